// One LiDAR frame through the ObstacleDetector, in the order its nodelet runs it: the cloud's
// layout is checked (planDecode), a change of output frame restarts the tracks, the vehicle's
// motion since the previous frame is stepped (EgoMotion), the detector runs on the cloud in the
// output frame, and its confirmed tracks are the answer. No ROS: the nodelet feeds each cloud with
// its transform and pose (or none), logs what the result reports and publishes it; the counters
// its diagnostics report live here.
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <map>
#include <memory>
#include <string>

#include <Eigen/Geometry>

#include "icanc/core/input/sensor_health.hpp"
#include "icanc/core/motion/ego_motion.hpp"
#include "icanc/core/perception/cloud_decode.hpp"
#include "icanc/core/perception/obstacle_detector.hpp"

namespace icanc {

struct DetectorPipelineCounters {
  std::map<DecodeError, std::uint64_t> invalid;     // clouds planDecode refused, by reason
  std::map<EgoStep::Status, std::uint64_t> ego;     // frames by ego motion status
  std::uint64_t ego_restarts = 0;                   // tracks restarted: over ground <-> relative
  std::uint64_t frames = 0, dropped_points = 0;     // frames processed; NaN/Inf/zero points
  std::uint64_t time_resets = 0, gap_resets = 0;    // tracker resets: stamp backwards, gap
  std::uint64_t frame_changes = 0;                  // output frame changed: tracks reset
  std::uint64_t ground_retried = 0, ground_rejected = 0, ground_absent = 0;  // classic path
  float last_rejected_height_m = std::numeric_limits<float>::quiet_NaN();
};

// A cloud planDecode accepted, in the frame its boxes go out in: the output frame (target) when
// its transform came, else the cloud's own frame with `to_frame` the identity.
struct DetectorPipelineInput {
  double stamp_s = 0.0;
  std::string frame;
  const RawCloud* raw = nullptr;
  const DecodePlan* plan = nullptr;
  Eigen::Affine3f to_frame = Eigen::Affine3f::Identity();  // cloud frame -> `frame`
  const Eigen::Isometry3d* fixed_T_vehicle = nullptr;     // the pose at the stamp; null: none
  bool collect_moving_points = false;
  // When given (begun by the caller), the frame's returns are counted into it for the
  // blind-sensor check: in the fast detector's own pass over the cloud, else in a pass of its own.
  ReturnCounter* returns = nullptr;
};

struct DetectorPipelineResult {
  EgoStep ego;
  std::string previous_frame;  // not empty when the output frame changed (tracks reset)
  MultiObjectTracker::UpdateResult tracker = MultiObjectTracker::UpdateResult::kOk;
  bool ground_fault = false;   // classic path: the ground plane was rejected or absent
  StageTimes times;
};

class DetectorPipeline {
 public:
  DetectorPipeline(const ObstacleDetectorParams& params, const EgoMotionParams& ego,
                   std::size_t max_points);

  // The layout checks (planDecode): kNone and `plan` filled, else counted by reason.
  DecodeError plan(const RawCloud& raw, DecodePlan& plan);

  // The frame, after `plan` accepted it. The ego step is EgoStep() for source kNone; a missing
  // pose (fixed_T_vehicle null) is extrapolated, then lost (EgoMotion); tracks whose velocities
  // are relative do not go on over ground, nor the other way round.
  DetectorPipelineResult process(const DetectorPipelineInput& in);

  void setParams(const ObstacleDetectorParams& params) { detector_.setParams(params); }
  ObstacleDetector& detector() { return detector_; }
  const ObstacleDetector& detector() const { return detector_; }
  const EgoMotionParams& egoParams() const { return ego_.params(); }
  const DetectorPipelineCounters& counters() const { return counters_; }

 private:
  EgoStep egoStep(double stamp_s, const Eigen::Isometry3d* pose);
  bool countGround();

  ObstacleDetector detector_;
  EgoMotion ego_;
  std::size_t max_points_;
  Cloud cloud_;  // the classic path's decoded cloud, reused
  std::string last_frame_;
  bool over_ground_ = false;
  std::uint64_t ego_frames_ = 0;  // frames through egoStep
  DetectorPipelineCounters counters_;
};

}  // namespace icanc
