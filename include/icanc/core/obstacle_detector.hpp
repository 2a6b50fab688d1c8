// The Obstacle Detector of the paper as one ROS-free pipeline: preparation -> RANSAC ground ->
// Euclidean clusters and boxes -> tracking (Hungarian + Kalman), with per-stage timings.
#pragma once

#include <string>
#include <vector>

#include "icanc/core/box.hpp"
#include "icanc/core/cloud_prep.hpp"
#include "icanc/core/clustering.hpp"
#include "icanc/core/ground_removal.hpp"
#include "icanc/core/tracker.hpp"
#include "icanc/core/types.hpp"

namespace icanc {

struct ObstacleDetectorParams {
  CloudPrepParams prep;
  GroundParams ground;
  ClusterParams cluster;
  TrackerParams tracker;
};

// First problem found, or "" when every part is valid.
std::string validate(const ObstacleDetectorParams& params);

struct StageTimes {
  double prep_ms = 0.0;
  double ground_ms = 0.0;
  double cluster_ms = 0.0;
  double track_ms = 0.0;
  double total_ms() const { return prep_ms + ground_ms + cluster_ms + track_ms; }
};

class ObstacleDetector {
 public:
  explicit ObstacleDetector(const ObstacleDetectorParams& params = ObstacleDetectorParams());

  // Processes one frame already in the vehicle frame, stamped `stamp_s` (header stamp).
  MultiObjectTracker::UpdateResult process(double stamp_s, const Cloud& cloud,
                                           StageTimes* times = nullptr);

  const std::vector<Box3D>& detections() const { return detections_; }  // this frame's clusters
  const std::vector<Track>& tracks() const { return tracker_.tracks(); }
  const GroundResult& ground() const { return ground_; }

  // Takes effect on the next frame; the tracks are kept.
  void setParams(const ObstacleDetectorParams& params);
  const ObstacleDetectorParams& params() const { return params_; }
  void reset() { tracker_.reset(); }

 private:
  ObstacleDetectorParams params_;
  MultiObjectTracker tracker_;
  Cloud prepared_;
  Cloud nonground_;
  GroundResult ground_;
  std::vector<Box3D> detections_;
};

}  // namespace icanc
