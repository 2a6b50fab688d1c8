#include "icanc/core/motion/ego_motion.hpp"

#include <cmath>
#include <sstream>

#include "icanc/core/common/planar_geometry.hpp"

namespace icanc {
namespace {

// The pose after moving for dt at the body velocity and yaw rate, as an isometry in the frame the
// motion started from.
Eigen::Isometry3d stepPose(const Eigen::Vector3d& velocity, double yaw_rate, double dt) {
  return predictEgoPose(velocity.head<2>(), yaw_rate, dt).toIsometry(velocity.z() * dt);
}

// Inverse of predictEgoPose's position: the body velocity that covers `chord` in t at yaw rate w.
Eigen::Vector2d bodyVelocityFromChord(const Eigen::Vector2d& chord, double w, double t) {
  const double yaw = w * t;
  if (std::abs(yaw) < 1e-9) return chord / t;
  const double s = std::sin(yaw), c = std::cos(yaw);
  Eigen::Matrix2d m;
  m << s, c - 1.0, 1.0 - c, s;
  return (w * m.inverse()) * chord;
}

}  // namespace

const char* toString(EgoMotionSource source) {
  switch (source) {
    case EgoMotionSource::kNone: return "none";
    case EgoMotionSource::kTf: return "tf";
    case EgoMotionSource::kOdometry: return "odometry";
    case EgoMotionSource::kLidar: return "lidar";
    case EgoMotionSource::kInvalid: break;
  }
  return "invalid";
}

EgoMotionSource parseEgoMotionSource(const std::string& name) {
  if (name == "none") return EgoMotionSource::kNone;
  if (name == "tf") return EgoMotionSource::kTf;
  if (name == "odometry") return EgoMotionSource::kOdometry;
  if (name == "lidar") return EgoMotionSource::kLidar;
  return EgoMotionSource::kInvalid;
}

const char* toString(EgoStep::Status status) {
  switch (status) {
    case EgoStep::Status::kNone: return "none";
    case EgoStep::Status::kFirst: return "first";
    case EgoStep::Status::kMeasured: return "measured";
    case EgoStep::Status::kExtrapolated: return "extrapolated";
    case EgoStep::Status::kJump: return "jump";
    case EgoStep::Status::kLost: return "lost";
  }
  return "invalid";
}

std::string validate(const EgoMotionParams& p) {
  std::ostringstream why;
  if (p.source == EgoMotionSource::kInvalid) {
    why << "ego_motion/source must be \"none\", \"tf\", \"odometry\" or \"lidar\"";
  } else if (!(p.max_speed_mps > 0.0) || !std::isfinite(p.max_speed_mps)) {
    why << "ego_motion/max_speed_mps must be > 0 (got " << p.max_speed_mps << ")";
  } else if (!(p.max_yaw_rate_rad_s > 0.0) || !std::isfinite(p.max_yaw_rate_rad_s)) {
    why << "ego_motion/max_yaw_rate_rad_s must be > 0 (got " << p.max_yaw_rate_rad_s << ")";
  } else if (!(p.max_wait_s >= 0.0 && p.max_wait_s <= 1.0)) {
    why << "ego_motion/max_wait_s must be in [0, 1] (got " << p.max_wait_s << ")";
  } else if (!(p.replay_max_wait_s >= 0.0 && p.replay_max_wait_s <= 4.0)) {
    why << "ego_motion/replay_max_wait_s must be in [0, 4] (got " << p.replay_max_wait_s << ")";
  } else if (!(p.max_extrapolation_s >= 0.0 && p.max_extrapolation_s <= 5.0)) {
    why << "ego_motion/max_extrapolation_s must be in [0, 5] (got " << p.max_extrapolation_s << ")";
  }
  return why.str();
}

void EgoMotion::reset() {
  has_pose_ = false;
  has_stamp_ = false;
  missing_s_ = 0.0;
  velocity_.setZero();
  yaw_rate_ = 0.0;
}

EgoStep EgoMotion::carryTwist(double dt, EgoStep::Status status) const {
  EgoStep step;
  step.status = status;
  step.dt_s = dt;
  step.linear_velocity = velocity_;
  step.yaw_rate_rad_s = yaw_rate_;
  step.motion = stepPose(velocity_, yaw_rate_, dt).inverse();
  return step;
}

EgoStep EgoMotion::update(double stamp_s, const Eigen::Isometry3d* fixed_T_vehicle) {
  EgoStep step;
  if (params_.source == EgoMotionSource::kNone) return step;
  const bool valid_pose = fixed_T_vehicle && fixed_T_vehicle->matrix().allFinite();
  double dt = 0.0;
  if (has_stamp_) {
    dt = stamp_s - last_stamp_s_;
    if (!(dt >= 0.0)) {  // time went backwards (a replay restarting), or a non-finite stamp
      reset();
      dt = 0.0;
    }
  }
  has_stamp_ = true;
  last_stamp_s_ = stamp_s;
  step.dt_s = dt;

  if (!valid_pose) {
    if (!has_pose_) return step;  // kNone: nothing known yet
    missing_s_ += dt;
    if (missing_s_ > params_.max_extrapolation_s) {
      // Lost: forget the motion; the next pose starts afresh (kFirst).
      has_pose_ = false;
      velocity_.setZero();
      yaw_rate_ = 0.0;
      step.status = EgoStep::Status::kLost;
      return step;
    }
    step = carryTwist(dt, EgoStep::Status::kExtrapolated);
    last_pose_ = last_pose_ * step.motion.inverse();
    return step;
  }

  if (!has_pose_) {
    has_pose_ = true;
    missing_s_ = 0.0;
    last_pose_ = *fixed_T_vehicle;
    velocity_.setZero();
    yaw_rate_ = 0.0;
    step.status = EgoStep::Status::kFirst;
    return step;
  }

  const Eigen::Isometry3d previous_T_now = last_pose_.inverse() * (*fixed_T_vehicle);
  const double yaw = yawOf(previous_T_now.linear());
  const double distance = previous_T_now.translation().norm();
  const bool jump = distance > params_.max_speed_mps * dt + 1e-6 ||
                    std::abs(yaw) > params_.max_yaw_rate_rad_s * dt + 1e-9;
  missing_s_ = 0.0;
  if (jump) {
    step = carryTwist(dt, EgoStep::Status::kJump);
    last_pose_ = *fixed_T_vehicle;  // re-based: the next step is measured from here
    return step;
  }
  step.status = EgoStep::Status::kMeasured;
  step.motion = previous_T_now.inverse();
  if (dt > 0.0) {
    // The constant body velocity and yaw rate that move the vehicle from the previous pose to this
    // one (the chord of a constant-turn arc, in the previous frame's axes, inverted exactly); the
    // body velocity is the same in both frames' axes, the frame the boxes are published in.
    yaw_rate_ = yaw / dt;
    velocity_ << bodyVelocityFromChord(previous_T_now.translation().head<2>(), yaw_rate_, dt),
        previous_T_now.translation().z() / dt;
  }
  step.linear_velocity = velocity_;
  step.yaw_rate_rad_s = yaw_rate_;
  last_pose_ = *fixed_T_vehicle;
  return step;
}

Eigen::Vector3d relativeVelocity(const Eigen::Vector3d& velocity_over_ground,
                                 const Eigen::Vector3d& position,
                                 const Eigen::Vector3d& ego_velocity, double ego_yaw_rate) {
  const Eigen::Vector3d frame_velocity =
      ego_velocity + Eigen::Vector3d(0.0, 0.0, ego_yaw_rate).cross(position);
  return velocity_over_ground - frame_velocity;
}

Eigen::Isometry3d PlanarPose::toIsometry(double z) const {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() << position, z;
  pose.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  return pose;
}

PlanarPose predictEgoPose(const Eigen::Vector2d& v, double w, double t) {
  PlanarPose p;
  p.yaw = w * t;
  if (std::abs(p.yaw) < 1e-9) {
    p.position = v * t;
    return p;
  }
  // Integral of R(w s) v over [0, t].
  const double s = std::sin(p.yaw), c = std::cos(p.yaw);
  p.position.x() = (v.x() * s + v.y() * (c - 1.0)) / w;
  p.position.y() = (v.x() * (1.0 - c) + v.y() * s) / w;
  return p;
}

}  // namespace icanc
