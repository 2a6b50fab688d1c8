#include "icanc/core/perception/obstacle_detector.hpp"

#include <chrono>
#include <cmath>
#include <string>

namespace icanc {

const char* toString(DetectorMethod method) {
  switch (method) {
    case DetectorMethod::kClassic: return "classic";
    case DetectorMethod::kFast: return "fast";
    case DetectorMethod::kInvalid: break;
  }
  return "invalid";
}

DetectorMethod parseDetectorMethod(const std::string& name) {
  if (name == "classic") return DetectorMethod::kClassic;
  if (name == "fast") return DetectorMethod::kFast;
  return DetectorMethod::kInvalid;
}

std::string validate(const ObstacleDetectorParams& params) {
  if (params.method == DetectorMethod::kInvalid)
    return "method must be \"classic\" or \"fast\"";
  if (!(params.footprint_cell_m >= 0.0f) || !std::isfinite(params.footprint_cell_m))
    return "footprint_cell_m must be >= 0 (got " + std::to_string(params.footprint_cell_m) + ")";
  for (const std::string& why : {validate(params.prep), validate(params.ground),
                                 validate(params.cluster), validate(params.tracker),
                                 validate(params.fast), validate(params.free_space)}) {
    if (!why.empty()) return why;
  }
  if (params.method == DetectorMethod::kFast) {
    const Eigen::Vector3f extent = params.prep.roi_max - params.prep.roi_min;
    if (extent.x() / params.fast.cell_m * (extent.y() / params.fast.cell_m) > 64e6f)
      return "fast.cell_m is too small for the ROI (more than 64 million grid cells)";
  }
  return "";
}

ObstacleDetector::ObstacleDetector(const ObstacleDetectorParams& params)
    : params_(params), tracker_(params.tracker) {
  setParams(params);
}

void ObstacleDetector::setParams(const ObstacleDetectorParams& params) {
  params_ = params;
  tracker_.setParams(params.tracker);
  motion_.setParams(params.free_space);
  if (params.prep.remove_ego) motion_.setEgoBox(params.prep.ego_min, params.prep.ego_max);
  else motion_.setEgoBox(Eigen::Vector3f::Constant(1.0f), Eigen::Vector3f::Constant(-1.0f));
  fast_.reset(params.method == DetectorMethod::kFast
                  ? new FastDetector(params.prep, params.fast, params.footprint_cell_m)
                  : nullptr);
  if (fast_) fast_->setSensorOrigin(sensor_origin_);
}

MultiObjectTracker::UpdateResult ObstacleDetector::process(double stamp_s, const Cloud& cloud,
                                                           StageTimes* times) {
  // Wall clock only measures how long the stages take; results depend on stamp_s alone.
  using Clock = std::chrono::steady_clock;
  const auto ms = [](Clock::time_point a, Clock::time_point b) {
    return std::chrono::duration<double, std::milli>(b - a).count();
  };
  beginMotion(stamp_s);
  if (motion_known_) {
    for (const Point& p : cloud.points) motion_.addPoint(p.x, p.y, p.z);
  }
  if (fast_) {
    FastStageTimes fast_times;
    fast_->detect(cloud, detections_, &fast_times);
    if (times) {
      times->prep_ms = fast_times.prep_ms;
      times->ground_ms = fast_times.ground_ms;
      times->cluster_ms = fast_times.cluster_ms;
    }
    return track(stamp_s, times);
  }
  const auto t0 = Clock::now();
  prepareCloud(cloud, params_.prep, prepared_);
  const auto t1 = Clock::now();
  ground_ = removeGround(prepared_, params_.ground, nonground_);
  const auto t2 = Clock::now();
  detections_ = clusterBoxes(nonground_, params_.cluster, params_.footprint_cell_m);
  GrazingColumnParams grazing = params_.cluster.grazing;
  // One line of sight: the points (voxel centroids) of one column lie within half a voxel.
  if (params_.prep.voxel_leaf_m > 0.0f) grazing.thin_m = 0.5f * params_.prep.voxel_leaf_m;
  dropGrazingColumnBoxes(detections_, sensor_origin_.head<2>(), grazing);
  const auto t3 = Clock::now();
  if (times) {
    times->prep_ms = ms(t0, t1);
    times->ground_ms = ms(t1, t2);
    times->cluster_ms = ms(t2, t3);
  }
  return track(stamp_s, times);
}

void ObstacleDetector::splitPoints(Cloud& ground, Cloud& obstacles) const {
  if (fast_) {
    fast_->splitPoints(ground, obstacles);
    return;
  }
  // removeGround keeps the order of the points it does not remove: the ground is what the walk
  // along prepared_ does not find, in turn, in nonground_.
  ground.clear();
  obstacles = nonground_;
  std::size_t next = 0;
  for (const Point& p : prepared_.points) {
    if (next < nonground_.size()) {
      const Point& q = nonground_.points[next];
      if (p.x == q.x && p.y == q.y && p.z == q.z) {
        ++next;
        continue;
      }
    }
    ground.push_back(p);
  }
}

void ObstacleDetector::beginMotion(double stamp_s) {
  if (motion_known_) motion_.beginFrame(stamp_s, frame_motion_, sensor_origin_);
  else motion_.reset();
}

MultiObjectTracker::UpdateResult ObstacleDetector::track(double stamp_s, StageTimes* times) {
  const double m0 = fastNowMs();
  if (motion_known_) {  // else every box keeps the default evidence: unknown
    motion_.evaluate(detections_);
    motion_.endFrame();
  }
  const double t0 = fastNowMs();
  if (times) times->motion_ms = t0 - m0;
  // Faces at the region of interest's edge are cut there; a box edge lies up to one voxel (classic)
  // or one grid cell (fast) inside the last point.
  TrackerView view;
  view.origin = sensor_origin_.head<2>();
  view.region_min = params_.prep.roi_min.head<2>();
  view.region_max = params_.prep.roi_max.head<2>();
  view.region_tolerance_m = fast_ ? params_.fast.cell_m : params_.prep.voxel_leaf_m;
  const auto result = tracker_.update(stamp_s, detections_, view, frame_motion_);
  frame_motion_.setIdentity();
  if (times) times->track_ms = fastNowMs() - t0;
  return result;
}

}  // namespace icanc
