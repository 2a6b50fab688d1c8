// DetectorStatus::addTo (src/ros/detector_status.cpp): the ObstacleDetector's diagnostics from the
// pipeline's counters, the transform queue's and the nodelet's own counts.
#include <string>

#include <gtest/gtest.h>

#include "icanc/ros/detector_status.hpp"

namespace icanc {
namespace {

std::string value(const diagnostic_updater::DiagnosticStatusWrapper& stat, const std::string& key) {
  for (const auto& kv : stat.values)
    if (kv.key == key) return kv.value;
  return "<absent>";
}

TEST(DetectorStatus, InvalidCloudsAreListedByKindSummedAndNameTheWarning) {
  DetectorStatus status;
  DetectorPipelineCounters c;
  c.invalid[DecodeError::kMissingXYZ] = 2;
  c.invalid[DecodeError::kTruncatedData] = 1;
  diagnostic_updater::DiagnosticStatusWrapper stat;
  status.addTo(stat, c, EgoMotionSource::kNone, CloudTransformQueue::Stats());
  EXPECT_EQ(stat.level, diagnostic_msgs::DiagnosticStatus::WARN);
  EXPECT_EQ(stat.message, "invalid clouds dropped");
  EXPECT_EQ(value(stat, std::string("invalid clouds: ") + toString(DecodeError::kMissingXYZ)), "2");
  EXPECT_EQ(value(stat, std::string("invalid clouds: ") + toString(DecodeError::kTruncatedData)), "1");
  EXPECT_EQ(value(stat, "invalid clouds"), "3");
  // The ego motion's faults are listed even at zero.
  EXPECT_EQ(value(stat, std::string("ego motion frames: ") + toString(EgoStep::Status::kLost)), "0");

  diagnostic_updater::DiagnosticStatusWrapper again;  // nothing grew since: OK
  status.addTo(again, c, EgoMotionSource::kNone, CloudTransformQueue::Stats());
  EXPECT_EQ(again.level, diagnostic_msgs::DiagnosticStatus::OK);
  EXPECT_EQ(again.message, "ok");
}

TEST(DetectorStatus, TheNodeletsCountsFollowThePipelines) {
  DetectorStatus status;
  status.onReceived();
  status.onReceived();
  status.onDebugFrame();
  StageTimes times;
  times.prep_ms = 1.5;
  times.track_ms = 0.25;
  status.onPublished(4, 12.5, times);
  diagnostic_updater::DiagnosticStatusWrapper stat;
  status.addTo(stat, DetectorPipelineCounters(), EgoMotionSource::kTf, CloudTransformQueue::Stats());
  EXPECT_EQ(stat.message, "ok");
  EXPECT_EQ(value(stat, "ego motion source"), "tf");
  EXPECT_EQ(value(stat, "clouds received"), "2");
  EXPECT_EQ(value(stat, "obstacle arrays published"), "1");
  EXPECT_EQ(value(stat, "obstacles (last frame)"), "4");
  EXPECT_EQ(value(stat, "frames with ground/obstacle points published"), "1");
  EXPECT_EQ(value(stat, "processing ms (last frame)"), "12.5");
  EXPECT_EQ(value(stat, "prep ms"), "1.5");
  EXPECT_EQ(value(stat, "track ms"), "0.25");
  // After the pipeline's counters, as the nodelet reported them.
  EXPECT_EQ(stat.values.back().key, "track ms");
}

}  // namespace
}  // namespace icanc
