#include "icanc/ros/ego_pose_source.hpp"

#include <tf2_eigen/tf2_eigen.h>

namespace icanc {
namespace {

constexpr double kOdometryHistoryS = 5.0;  // odometry kept for lookups this far back

}  // namespace

std::string loadEgoMotion(ParamReader& reader, const std::string& target_frame, EgoMotionSection& section) {
  EgoMotionParams& ego = section.params;
  std::string source = toString(ego.source);
  reader.read("source", source);
  ego.source = parseEgoMotionSource(source);
  reader.read("fixed_frame", section.fixed_frame);
  reader.read("max_speed_mps", ego.max_speed_mps);
  reader.read("max_yaw_rate_rad_s", ego.max_yaw_rate_rad_s);
  reader.read("max_wait_s", ego.max_wait_s);
  reader.read("replay_max_wait_s", ego.replay_max_wait_s);
  reader.read("max_extrapolation_s", ego.max_extrapolation_s);
  reader.accept("publish_tf");  // LidarOdometry's
  std::string why = validate(ego);
  if (why.empty() && section.fixed_frame.empty()) why = "ego_motion/fixed_frame must not be empty";
  if (why.empty() && ego.source != EgoMotionSource::kNone && target_frame.empty())
    why = "ego_motion/source " + source + " needs ~target_frame (the vehicle frame)";
  return why;
}

EgoPoseSource::EgoPoseSource(ros::NodeHandle& nh, EgoMotionSource source,
                             const std::string& fixed_frame, tf2_ros::Buffer& tf)
    : source_(source), fixed_frame_(fixed_frame), tf_(tf), odometry_(kOdometryHistoryS) {
  if (source_ != EgoMotionSource::kOdometry) return;
  ros::SubscribeOptions options = ros::SubscribeOptions::create<nav_msgs::Odometry>(
      "odom", 50, [this](const nav_msgs::Odometry::ConstPtr& msg) { onOdometry(msg); }, ros::VoidPtr(),
      &odom_queue_);
  odom_sub_ = nh.subscribe(options);
  odom_spinner_.reset(new ros::AsyncSpinner(1, &odom_queue_));
  odom_spinner_->start();
}

bool EgoPoseSource::lookup(const ros::Time& stamp, const std::string& vehicle_frame,
                           Eigen::Isometry3d& pose, std::string& why) {
  bool found = false;
  switch (source_) {
    case EgoMotionSource::kTf:
    case EgoMotionSource::kLidar: found = lookupTf(stamp, vehicle_frame, pose, why); break;
    case EgoMotionSource::kOdometry: found = lookupOdometry(stamp, vehicle_frame, pose, why); break;
    case EgoMotionSource::kNone:
    case EgoMotionSource::kInvalid: why = "no ego motion source"; break;
  }
  consecutive_misses_ = found ? 0 : consecutive_misses_ + 1;
  return found;
}

bool EgoPoseSource::available(const ros::Time& stamp, const std::string& vehicle_frame) {
  switch (source_) {
    case EgoMotionSource::kTf:
    case EgoMotionSource::kLidar: return tf_.canTransform(fixed_frame_, vehicle_frame, stamp);
    case EgoMotionSource::kOdometry: {
      Eigen::Isometry3d pose;
      std::string child, why;
      return interpolateOdometry(stamp, pose, child, why);
    }
    case EgoMotionSource::kNone:
    case EgoMotionSource::kInvalid: break;
  }
  return true;  // nothing to wait for
}

void EgoPoseSource::setOnPose(std::function<void()> on_pose) {
  std::lock_guard<std::mutex> lock(mutex_);
  on_pose_ = std::move(on_pose);
}

bool EgoPoseSource::lookupTf(const ros::Time& stamp, const std::string& vehicle_frame,
                             Eigen::Isometry3d& pose, std::string& why) {
  try {
    pose = tf2::transformToEigen(tf_.lookupTransform(fixed_frame_, vehicle_frame, stamp));
    return true;
  } catch (const tf2::TransformException& e) {
    why = e.what();
    return false;
  }
}

void EgoPoseSource::onOdometry(const nav_msgs::Odometry::ConstPtr& msg) {
  Eigen::Isometry3d pose;
  tf2::fromMsg(msg->pose.pose, pose);
  std::lock_guard<std::mutex> lock(mutex_);
  if (!msg->child_frame_id.empty()) odometry_child_frame_ = msg->child_frame_id;
  odometry_.add(msg->header.stamp.toSec(), pose);  // an older stamp: the replay restarted
  if (on_pose_) on_pose_();
}

bool EgoPoseSource::interpolateOdometry(const ros::Time& stamp, Eigen::Isometry3d& pose,
                                        std::string& child, std::string& why) {
  std::lock_guard<std::mutex> lock(mutex_);
  child = odometry_child_frame_;
  if (odometry_.empty()) {
    why = "no odometry received";
    return false;
  }
  const double t = stamp.toSec();
  const auto around = odometry_.bracket(t);
  if (!around.at_or_before) {
    why = "stamp older than the odometry kept";
    return false;
  }
  const auto& before = *around.at_or_before;
  if (before.stamp_s == t) {  // on a sample: its pose as it came, not a slerp's round trip
    pose = before.value;
    return true;
  }
  if (!around.after) {
    why = "no odometry at the stamp yet";
    return false;
  }
  const auto& after = *around.after;
  const double a = (t - before.stamp_s) / (after.stamp_s - before.stamp_s);
  const Eigen::Quaterniond q0(before.value.linear()), q1(after.value.linear());
  pose.setIdentity();
  pose.linear() = q0.slerp(a, q1).toRotationMatrix();
  pose.translation() = (1.0 - a) * before.value.translation() + a * after.value.translation();
  return true;
}

bool EgoPoseSource::lookupOdometry(const ros::Time& stamp, const std::string& vehicle_frame,
                                   Eigen::Isometry3d& pose, std::string& why) {
  std::string child;
  if (!interpolateOdometry(stamp, pose, child, why)) return false;
  if (child.empty() || child == vehicle_frame) return true;
  // The odometry's child frame is not the frame the boxes are in: through the (static) mount.
  try {
    pose = pose * tf2::transformToEigen(tf_.lookupTransform(child, vehicle_frame, ros::Time(0)));
    return true;
  } catch (const tf2::TransformException& e) {
    why = "odometry child frame " + child + ": " + e.what();
    return false;
  }
}

}  // namespace icanc
