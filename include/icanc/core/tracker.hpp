// Multi-object tracker: gating by centre displacement and BEV IoU, optimal assignment
// (solveAssignmentByComponents), one ConstantVelocityKalman per track, birth / confirmation / deletion.
// Time is always the caller's (header stamps), never a clock.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "icanc/core/box.hpp"
#include "icanc/core/hungarian.hpp"
#include "icanc/core/kalman_cv.hpp"

namespace icanc {

struct TrackerParams {
  float gate_distance_m = 2.0f;        // max distance predicted centre -> detection centre (x/y)
  float iou_weight = 1.0f;             // cost = distance / gate + iou_weight * (1 - BEV IoU)
  int min_hits_to_confirm = 2;         // detections before a track is published
  int max_missed_frames = 2;           // a track survives this many consecutive misses
  double accel_std = 3.0;              // process noise, white acceleration [m/s^2]
  double measurement_std_m = 0.15;     // centre measurement noise [m]
  double initial_velocity_std = 5.0;   // velocity uncertainty of a new track [m/s]
  double max_dt_s = 1.0;               // a larger gap between frames resets the tracker
};

std::string validate(const TrackerParams& params);

struct Track {
  std::uint32_t id = 0;
  Box3D box;                  // last associated box, centre replaced by the filtered position
  ConstantVelocityKalman filter;
  int age = 0;                // frames since birth (1 on the birth frame)
  int hits = 0;               // frames with an associated detection
  int missed = 0;             // consecutive frames without one
  bool confirmed = false;     // hits >= min_hits_to_confirm (stays true once reached)

  Eigen::Vector3d velocity() const { return filter.velocity(); }
  // 1-sigma uncertainty of the planar velocity [m/s] (sqrt of the x/y velocity variance sum).
  double velocityStd() const;           // planar: sqrt(var vx + var vy)
  Eigen::Vector2d velocityStdXY() const;  // per axis: sqrt(var vx), sqrt(var vy)
};

class MultiObjectTracker {
 public:
  enum class UpdateResult {
    kOk,
    kResetTimeBackwards,  // stamp older than the previous frame: tracks dropped (bag loop)
    kResetGap,            // gap larger than max_dt_s: tracks dropped
  };

  explicit MultiObjectTracker(const TrackerParams& params = TrackerParams());

  // One frame: predict every track to `stamp_s`, associate, update, age, birth, delete.
  // The first frame after construction or reset() only starts tracks.
  UpdateResult update(double stamp_s, const std::vector<Box3D>& detections);

  // Drops all tracks; the next update() only starts tracks. Ids keep counting (never reused).
  void reset();
  void setParams(const TrackerParams& params) { params_ = params; }
  const TrackerParams& params() const { return params_; }

  // All live tracks (tentative ones too; check Track::confirmed).
  const std::vector<Track>& tracks() const { return tracks_; }

 private:
  TrackerParams params_;
  std::vector<Track> tracks_;
  std::uint32_t next_id_ = 1;
  double last_stamp_s_ = 0.0;
  bool has_stamp_ = false;

  // Per-frame scratch, kept to avoid allocating in steady state (grows only).
  Eigen::MatrixXd cost_;  // tracks x detections, used through its top-left corner
  ComponentWorkspace assignment_workspace_;  // solved per connected component of gated pairs
  std::vector<int> track_to_detection_;
  std::vector<char> detection_used_;
};

}  // namespace icanc
