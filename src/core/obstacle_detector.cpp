#include "icanc/core/obstacle_detector.hpp"

#include <chrono>

namespace icanc {

std::string validate(const ObstacleDetectorParams& params) {
  for (const std::string& why : {validate(params.prep), validate(params.ground),
                                 validate(params.cluster), validate(params.tracker)}) {
    if (!why.empty()) return why;
  }
  return "";
}

ObstacleDetector::ObstacleDetector(const ObstacleDetectorParams& params)
    : params_(params), tracker_(params.tracker) {}

void ObstacleDetector::setParams(const ObstacleDetectorParams& params) {
  params_ = params;
  tracker_.setParams(params.tracker);
}

MultiObjectTracker::UpdateResult ObstacleDetector::process(double stamp_s, const Cloud& cloud,
                                                           StageTimes* times) {
  // Wall clock only measures how long the stages take; results depend on stamp_s alone.
  using Clock = std::chrono::steady_clock;
  const auto ms = [](Clock::time_point a, Clock::time_point b) {
    return std::chrono::duration<double, std::milli>(b - a).count();
  };
  const auto t0 = Clock::now();
  prepareCloud(cloud, params_.prep, prepared_);
  const auto t1 = Clock::now();
  ground_ = removeGround(prepared_, params_.ground, nonground_);
  const auto t2 = Clock::now();
  detections_ = clusterBoxes(nonground_, params_.cluster);
  const auto t3 = Clock::now();
  const auto result = tracker_.update(stamp_s, detections_);
  const auto t4 = Clock::now();
  if (times) {
    times->prep_ms = ms(t0, t1);
    times->ground_ms = ms(t1, t2);
    times->cluster_ms = ms(t2, t3);
    times->track_ms = ms(t3, t4);
  }
  return result;
}

}  // namespace icanc
