// DetectorPipeline: one frame as the ObstacleDetector nodelet runs it. Invalid layouts are
// counted by reason; a scan fed with its transform gives confirmed tracks in the output frame by
// either method; a change of output frame (a transform that did not come) restarts the tracks and
// is counted; the ego motion is measured from the poses fed, extrapolated without them, then lost
// (the tracks restart once, relative from then on); source none steps nothing and counts nothing.
// The blind-sensor check's returns are counted in the same pass, as a pass of their own counts them.
#include "icanc/core/perception/detector_pipeline.hpp"

#include <random>

#include <gtest/gtest.h>

#include "icanc/sim/lidar_sim.hpp"
#include "scene_objects.hpp"

namespace icanc {
namespace {

constexpr float kMountZ = 1.73f;  // the sensor above base_link (the road)

struct Scan {
  Cloud cloud;  // organized, in the sensor's frame
  RawCloud raw;
};

Scan render() {
  sim::Scene scene;
  scene.ground_z = 0.0f;
  scene.objects = {test_scene::block("car", {4.5f, 1.8f, 1.5f}, {15.0f, 3.0f, 0.0f}),
                   test_scene::cylinder("pedestrian", 0.5f, 1.7f, {8.0f, -4.0f, 0.0f})};
  std::mt19937_64 rng(7);
  Eigen::Isometry3f pose = Eigen::Isometry3f::Identity();
  pose.translation().z() = kMountZ;
  Scan s;
  sim::renderScan(scene, 0.0, pose, sim::LidarModel::hdl64e(), sim::NoiseParams(), rng, s.cloud);
  s.raw.width = s.cloud.width;
  s.raw.height = s.cloud.height;
  s.raw.point_step = sizeof(Point);
  s.raw.row_step = s.raw.width * s.raw.point_step;
  s.raw.fields = {{"x", 0, 7, 1}, {"y", 4, 7, 1}, {"z", 8, 7, 1}};
  s.raw.data = reinterpret_cast<const std::uint8_t*>(s.cloud.points.data());
  s.raw.data_size = s.cloud.size() * sizeof(Point);
  return s;
}

ObstacleDetectorParams detectorParams(DetectorMethod method) {
  ObstacleDetectorParams params;
  params.method = method;
  params.prep.roi_min = {-20.0f, -20.0f, -1.0f};
  params.prep.roi_max = {60.0f, 20.0f, 4.0f};
  return params;
}

std::size_t confirmed(const DetectorPipeline& p) {
  std::size_t n = 0;
  for (const Track& t : p.detector().tracks()) n += t.confirmed;
  return n;
}

class Frames {
 public:
  Frames(DetectorPipeline& pipeline, const Scan& scan) : pipeline_(pipeline), scan_(scan) {
    EXPECT_EQ(pipeline_.plan(scan_.raw, plan_), DecodeError::kNone);
  }
  // One frame at `stamp_s` in base_link (through the mount), or in the sensor's own frame.
  DetectorPipelineResult run(double stamp_s, bool mounted = true, const Eigen::Isometry3d* pose = nullptr) {
    DetectorPipelineInput in;
    in.stamp_s = stamp_s;
    in.raw = &scan_.raw;
    in.plan = &plan_;
    in.frame = mounted ? "base_link" : "lidar";
    if (mounted) in.to_frame = Eigen::Translation3f(0.0f, 0.0f, kMountZ);
    in.fixed_T_vehicle = pose;
    return pipeline_.process(in);
  }

 private:
  DetectorPipeline& pipeline_;
  const Scan& scan_;
  DecodePlan plan_;
};

TEST(DetectorPipeline, InvalidLayoutsAreCountedByReason) {
  DetectorPipeline pipeline(ObstacleDetectorParams(), EgoMotionParams(), 1000);
  RawCloud empty;
  DecodePlan plan;
  EXPECT_EQ(pipeline.plan(empty, plan), DecodeError::kEmpty);
  EXPECT_EQ(pipeline.plan(empty, plan), DecodeError::kEmpty);
  const Scan scan = render();
  EXPECT_EQ(pipeline.plan(scan.raw, plan), DecodeError::kTooManyPoints);  // over max_points
  EXPECT_EQ(pipeline.counters().invalid.at(DecodeError::kEmpty), 2u);
  EXPECT_EQ(pipeline.counters().invalid.at(DecodeError::kTooManyPoints), 1u);
  EXPECT_EQ(pipeline.counters().frames, 0u);
}

TEST(DetectorPipeline, TracksInTheOutputFrameAndRestartsWhenItChanges) {
  const Scan scan = render();
  for (const DetectorMethod method : {DetectorMethod::kFast, DetectorMethod::kClassic}) {
    DetectorPipeline pipeline(detectorParams(method), EgoMotionParams(), 2000000);
    Frames frames(pipeline, scan);
    DetectorPipelineResult r;
    for (int i = 0; i < 3; ++i) r = frames.run(0.1 * i);
    EXPECT_EQ(r.ego.status, EgoStep::Status::kNone) << toString(method);
    EXPECT_TRUE(r.previous_frame.empty()) << toString(method);
    EXPECT_FALSE(r.ground_fault) << toString(method);  // the road at base_link's z = 0
    EXPECT_EQ(confirmed(pipeline), 2u) << toString(method);
    for (const Track& t : pipeline.detector().tracks())  // the boxes stand on base_link's road
      EXPECT_LT(t.box.center.z(), 1.2f) << toString(method);
    EXPECT_GT(pipeline.counters().dropped_points, 0u) << "the scan's NaN returns";

    // No transform: the sensor's frame, the tracks restart (counted), nothing confirmed yet.
    r = frames.run(0.3, /*mounted=*/false);
    EXPECT_EQ(r.previous_frame, "base_link") << toString(method);
    EXPECT_EQ(confirmed(pipeline), 0u) << toString(method);
    r = frames.run(0.4);
    EXPECT_EQ(r.previous_frame, "lidar") << toString(method);
    EXPECT_EQ(pipeline.counters().frame_changes, 2u) << toString(method);
    EXPECT_EQ(pipeline.counters().frames, 5u) << toString(method);
    EXPECT_TRUE(pipeline.counters().ego.empty()) << "source none counts no ego frames";

    r = frames.run(0.2);  // a stamp back in time: the tracker restarts, counted
    EXPECT_EQ(r.tracker, MultiObjectTracker::UpdateResult::kResetTimeBackwards) << toString(method);
    EXPECT_EQ(pipeline.counters().time_resets, 1u) << toString(method);
  }
}

// The blind-sensor check's returns, counted in the pipeline's pass over the cloud, are the counts
// of a pass of their own (countValidReturns), in the sensor's frame whatever the mount: a mount
// turned by 90 degrees would move every sector if they were counted after the transform.
TEST(DetectorPipeline, CountsTheReturnsInItsPassAsTheBlindCheckDoes) {
  const Scan scan = render();
  SensorHealthParams health;
  health.min_range_m = 5.0;  // the road under the sensor and the pedestrian are nearer: not valid
  health.max_range_m = 40.0;
  health.sectors = 12;
  DecodePlan plan;
  ASSERT_EQ(planDecode(scan.raw, 2000000, plan), DecodeError::kNone);
  SectorReturns expected;
  const std::size_t expected_valid = countValidReturns(scan.raw, plan, health, &expected);
  ASSERT_GT(expected_valid, 1000u);
  ASSERT_GT(expected.returned[3], expected.valid[3]) << "the road nearer than min_range_m";
  Eigen::Affine3f mount = Eigen::Translation3f(0.5f, 0.2f, kMountZ) *
                          Eigen::AngleAxisf(static_cast<float>(M_PI / 2), Eigen::Vector3f::UnitZ());
  for (const DetectorMethod method : {DetectorMethod::kFast, DetectorMethod::kClassic}) {
    DetectorPipeline pipeline(detectorParams(method), EgoMotionParams(), 2000000);
    ReturnCounter counter;
    counter.begin(health);
    DetectorPipelineInput in;
    in.raw = &scan.raw;
    in.plan = &plan;
    in.frame = "base_link";
    in.to_frame = mount;
    in.returns = &counter;
    pipeline.process(in);
    EXPECT_EQ(counter.valid(), expected_valid) << toString(method);
    EXPECT_EQ(counter.sectors().valid, expected.valid) << toString(method);
    EXPECT_EQ(counter.sectors().returned, expected.returned) << toString(method);
  }
}

TEST(DetectorPipeline, EgoMotionMeasuredThenExtrapolatedThenLostRestartsTheTracksOnce) {
  const Scan scan = render();
  EgoMotionParams ego;
  ego.source = EgoMotionSource::kTf;
  ego.max_extrapolation_s = 0.25;
  DetectorPipeline pipeline(detectorParams(DetectorMethod::kFast), ego, 2000000);
  Frames frames(pipeline, scan);
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  std::vector<EgoStep::Status> seen;
  for (int i = 0; i < 4; ++i) {
    pose.translation().x() = 0.2 * i;  // 2 m/s ahead
    seen.push_back(frames.run(0.1 * i, true, &pose).ego.status);
  }
  EXPECT_EQ(seen.front(), EgoStep::Status::kFirst);
  EXPECT_EQ(seen.back(), EgoStep::Status::kMeasured);
  pose.translation().x() = 0.8;
  EXPECT_NEAR(frames.run(0.4, true, &pose).ego.linear_velocity.x(), 2.0, 1e-6);
  EXPECT_EQ(confirmed(pipeline), 2u);

  // No pose: extrapolated for max_extrapolation_s, then lost (velocities relative: one restart).
  EXPECT_EQ(frames.run(0.5).ego.status, EgoStep::Status::kExtrapolated);
  EXPECT_EQ(frames.run(0.6).ego.status, EgoStep::Status::kExtrapolated);
  EXPECT_EQ(frames.run(0.7).ego.status, EgoStep::Status::kLost);
  EXPECT_EQ(confirmed(pipeline), 0u) << "the tracks restarted at the loss";
  EXPECT_EQ(frames.run(0.8).ego.status, EgoStep::Status::kNone);
  const DetectorPipelineCounters& c = pipeline.counters();
  EXPECT_EQ(c.ego.at(EgoStep::Status::kMeasured), 4u);
  EXPECT_EQ(c.ego.at(EgoStep::Status::kExtrapolated), 2u);
  EXPECT_EQ(c.ego.at(EgoStep::Status::kLost), 1u);
  EXPECT_EQ(c.ego_restarts, 1u);
}

}  // namespace
}  // namespace icanc
