// The vehicle's own motion between LiDAR frames, from whichever source the vehicle has (REP-105:
// the pose of the vehicle frame in a fixed `odom` frame at each cloud's stamp). The tracker uses it
// to keep its state in the fixed frame (a parked car stands still whatever the vehicle does); the
// danger model uses the vehicle's twist to predict the vehicle along its own path.
// No ROS here: the ObstacleDetector nodelet looks the pose up (tf2, nav_msgs/Odometry or the
// LidarOdometry nodelet's tf) and hands it over with the frame's stamp.
#pragma once

#include <cstdint>
#include <string>

#include <Eigen/Geometry>

namespace icanc {

// Where the pose of the vehicle frame in the fixed frame comes from (parameter ego_motion/source).
// kNone: nothing; the vehicle is taken to stand still, velocities are relative to it (the paper).
enum class EgoMotionSource : std::uint8_t { kNone, kTf, kOdometry, kLidar, kInvalid };
const char* toString(EgoMotionSource source);
EgoMotionSource parseEgoMotionSource(const std::string& name);  // "none" | "tf" | "odometry" | "lidar"

struct EgoMotionParams {
  EgoMotionSource source = EgoMotionSource::kNone;
  // A pose step implying more than these is a jump (odometry reset, relocalisation), not motion:
  // the step is replaced by the last twist over the frame's dt and the pose re-based.
  double max_speed_mps = 70.0;          // [m/s]
  double max_yaw_rate_rad_s = 2.0;      // [rad/s]
  // How long the nodelet waits for the pose at a cloud's stamp before it extrapolates [s] (wall
  // clock) ...
  double max_wait_s = 0.1;
  // ... and how long under sim time (a bag replayed with /clock): there the pose is published
  // before the cloud (icanc bag replay, rosbag play) or computed from it (LidarOdometry), and a
  // loaded machine must not turn a measured frame into an extrapolated one (a replay that depends
  // on the CPU's load is not a regression test) [s].
  double replay_max_wait_s = 2.0;
  // A pose missing for longer than this (extrapolated frames in a row, in seconds of stamps) drops
  // the motion: the vehicle is taken to stand still again until poses come back [s].
  double max_extrapolation_s = 0.5;
};

std::string validate(const EgoMotionParams& params);  // first problem, "" when valid

// The vehicle's motion over one frame, in the vehicle frame at the frame's stamp.
struct EgoStep {
  enum class Status : std::uint8_t {
    kNone,          // no ego motion (source none, or none known yet): identity, zero twist
    kFirst,         // the first pose: nothing to compare with yet (identity, zero twist)
    kMeasured,      // from two poses
    kExtrapolated,  // pose missing: the last twist carried over dt
    kJump,          // the poses jumped: the last twist carried over dt, the pose re-based
    kLost,          // missing for longer than max_extrapolation_s: identity, zero twist
  };
  Status status = Status::kNone;
  // Maps a point of the previous frame's vehicle frame into this frame's: p_now = motion * p_prev.
  Eigen::Isometry3d motion = Eigen::Isometry3d::Identity();
  Eigen::Vector3d linear_velocity = Eigen::Vector3d::Zero();  // of the vehicle origin [m/s]
  double yaw_rate_rad_s = 0.0;                                // about the vehicle's z [rad/s]
  double dt_s = 0.0;
};
const char* toString(EgoStep::Status status);

// Turns the sequence of poses (one per frame, or none when the source had none in time) into the
// per-frame motion and twist, guarding against jumps and gaps.
class EgoMotion {
 public:
  explicit EgoMotion(const EgoMotionParams& params = EgoMotionParams()) : params_(params) {}

  // One frame at stamp_s with the vehicle's pose in the fixed frame (fixed_T_vehicle), or null when
  // none was available. Time going backwards resets (the first pose after it is kFirst).
  EgoStep update(double stamp_s, const Eigen::Isometry3d* fixed_T_vehicle);

  void reset();
  void setParams(const EgoMotionParams& params) { params_ = params; }
  const EgoMotionParams& params() const { return params_; }

 private:
  EgoStep carryTwist(double dt, EgoStep::Status status) const;

  EgoMotionParams params_;
  bool has_pose_ = false;
  bool has_stamp_ = false;
  double last_stamp_s_ = 0.0;
  double missing_s_ = 0.0;  // stamps' time since the last real pose
  Eigen::Isometry3d last_pose_ = Eigen::Isometry3d::Identity();  // fixed_T_vehicle, extrapolated
  Eigen::Vector3d velocity_ = Eigen::Vector3d::Zero();
  double yaw_rate_ = 0.0;
};

// The velocity of an object relative to the vehicle, in the vehicle frame: its velocity over
// ground minus the velocity of the vehicle-fixed point where it is (the vehicle's linear velocity
// plus yaw rate x position). A parked car seen from a car turning left sweeps to the right.
Eigen::Vector3d relativeVelocity(const Eigen::Vector3d& velocity_over_ground,
                                 const Eigen::Vector3d& position,
                                 const Eigen::Vector3d& ego_velocity, double ego_yaw_rate);

// The vehicle's own displacement and heading change after t seconds at a constant body velocity
// (vx, vy) and yaw rate (constant turn rate and velocity), in the vehicle frame at time 0.
struct PlanarPose {
  Eigen::Vector2d position = Eigen::Vector2d::Zero();
  double yaw = 0.0;
  // The same pose in 3D, at height z, turned about z by yaw.
  Eigen::Isometry3d toIsometry(double z = 0.0) const;
};
PlanarPose predictEgoPose(const Eigen::Vector2d& body_velocity, double yaw_rate, double t);

}  // namespace icanc
