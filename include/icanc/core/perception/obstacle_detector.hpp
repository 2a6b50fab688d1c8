// The Obstacle Detector of the paper as one ROS-free pipeline: preparation -> RANSAC ground ->
// Euclidean clusters and boxes -> tracking (Hungarian + Kalman), with per-stage timings.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "icanc/core/motion/free_space.hpp"
#include "icanc/core/perception/box.hpp"
#include "icanc/core/perception/cloud_prep.hpp"
#include "icanc/core/perception/clustering.hpp"
#include "icanc/core/perception/fast_detector.hpp"
#include "icanc/core/perception/ground_removal.hpp"
#include "icanc/core/tracking/tracker.hpp"
#include "icanc/core/common/types.hpp"

namespace icanc {

// "classic": the paper's PCL chain (voxel grid, RANSAC plane, k-d tree Euclidean clusters).
// "fast": FastDetector (polar-grid ground that follows slopes, BEV grid connected components);
// it uses prep's ROI and ego box, not its voxel grid, nor the ground and cluster sections.
enum class DetectorMethod : std::uint8_t { kClassic, kFast, kInvalid };
const char* toString(DetectorMethod method);
DetectorMethod parseDetectorMethod(const std::string& name);  // kInvalid for anything else

struct ObstacleDetectorParams {
  DetectorMethod method = DetectorMethod::kClassic;
  // Each box carries its footprint as tight boxes per occupied cell of this grid
  // (Box3D::footprint), both methods [m]; 0: none (the axis-aligned box is the footprint).
  float footprint_cell_m = 1.0f;
  FastDetectorParams fast;
  CloudPrepParams prep;
  GroundParams ground;
  ClusterParams cluster;
  TrackerParams tracker;
  FreeSpaceParams free_space;  // motion read from free space (needs the vehicle's motion)
};

// First problem found, or "" when every part is valid.
std::string validate(const ObstacleDetectorParams& params);

struct StageTimes {
  double prep_ms = 0.0;
  double ground_ms = 0.0;
  double cluster_ms = 0.0;
  double motion_ms = 0.0;  // free-space motion: the frame's range image and the boxes' tests
  double track_ms = 0.0;
  double total_ms() const { return prep_ms + ground_ms + cluster_ms + motion_ms + track_ms; }
};

class ObstacleDetector {
 public:
  explicit ObstacleDetector(const ObstacleDetectorParams& params = ObstacleDetectorParams());

  // Processes one frame already in the vehicle frame, stamped `stamp_s` (header stamp).
  MultiObjectTracker::UpdateResult process(double stamp_s, const Cloud& cloud,
                                           StageTimes* times = nullptr);

  // Same, with the points from `source(sink)` (sink(x, y, z) per point, already in the vehicle
  // frame), e.g. straight from a PointCloud2 decoder: the fast path reads them in its first
  // pass; the classic one collects them into a cloud first.
  template <class Source>
  MultiObjectTracker::UpdateResult processFrom(double stamp_s, Source&& source,
                                               StageTimes* times = nullptr);

  const std::vector<Box3D>& detections() const { return detections_; }  // this frame's clusters
  const std::vector<Track>& tracks() const { return tracker_.tracks(); }
  const GroundResult& ground() const { return ground_; }  // classic path only
  const FastDetector* fast() const { return fast_.get(); }  // null unless method is kFast

  // The last frame's points as the detector split them, in the frame the clouds were given in
  // (both cleared first; for debug clouds, built only when called). classic: the prepared
  // (voxel-grid) points, `ground` the RANSAC plane's inliers, `obstacles` the rest, which the
  // clusters are made of; fast: FastDetector::splitPoints.
  void splitPoints(Cloud& ground, Cloud& obstacles) const;

  // Where the sensor is in the frame the clouds are given in (the vehicle frame): the tracker
  // measures the faces of each box nearest it (TrackAnchor). Default: the frame's origin. The
  // nodelet sets it from the cloud's transform every frame.
  // The fast path's range split lays its rays out as seen from here too.
  void setSensorOrigin(const Eigen::Vector3f& origin) {
    sensor_origin_ = origin;
    if (fast_) fast_->setSensorOrigin(origin);
  }

  // How the vehicle moved since the previous frame (EgoStep::motion), for the next frame only: the
  // tracker re-expresses its tracks by it, so their velocities are over ground. Not set: the
  // vehicle is taken to stand still (velocities relative to it, the paper's behaviour).
  // `known` false: no pose (ego motion source none, or lost): the tracks' velocities are relative
  // and free space tells nothing (every obstacle's motion unknown, the past images dropped).
  void setFrameMotion(const Eigen::Isometry3d& motion, bool known = true) {
    frame_motion_ = motion;
    motion_known_ = known;
  }
  // Keep the returns found in free space each frame (FreeSpaceMotion::freePoints; a debug cloud).
  void setCollectMovingPoints(bool collect) { motion_.setCollectFree(collect); }
  const Cloud& movingPoints() const { return motion_.freePoints(); }

  // Takes effect on the next frame; the tracks are kept.
  void setParams(const ObstacleDetectorParams& params);
  const ObstacleDetectorParams& params() const { return params_; }
  void reset() { tracker_.reset(); }

 private:
  MultiObjectTracker::UpdateResult track(double stamp_s, StageTimes* times);
  void beginMotion(double stamp_s);

  ObstacleDetectorParams params_;
  std::unique_ptr<FastDetector> fast_;
  MultiObjectTracker tracker_;
  Cloud collected_;
  Cloud prepared_;
  Cloud nonground_;
  GroundResult ground_;
  std::vector<Box3D> detections_;
  Eigen::Vector3f sensor_origin_ = Eigen::Vector3f::Zero();
  Eigen::Isometry3d frame_motion_ = Eigen::Isometry3d::Identity();
  bool motion_known_ = true;
  FreeSpaceMotion motion_;
};

template <class Source>
MultiObjectTracker::UpdateResult ObstacleDetector::processFrom(double stamp_s, Source&& source,
                                                               StageTimes* times) {
  if (!fast_) {
    collected_.clear();
    source([this](float x, float y, float z) { collected_.push_back(Point(x, y, z)); });
    return process(stamp_s, collected_, times);
  }
  beginMotion(stamp_s);
  FastStageTimes fast_times;
  if (motion_known_) {
    // Every return also goes into the frame's range image, in the same pass.
    fast_->detectFrom(
        [&](auto&& sink) {
          source([&](float x, float y, float z) {
            motion_.addPoint(x, y, z);
            sink(x, y, z);
          });
        },
        detections_, &fast_times);
  } else {
    fast_->detectFrom(std::forward<Source>(source), detections_, &fast_times);
  }
  if (times) {
    times->prep_ms = fast_times.prep_ms;
    times->ground_ms = fast_times.ground_ms;
    times->cluster_ms = fast_times.cluster_ms;
  }
  return track(stamp_s, times);
}

}  // namespace icanc
