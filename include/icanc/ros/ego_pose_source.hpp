// Where the ObstacleDetector nodelet gets the vehicle's pose in the fixed frame at a cloud's stamp
// (parameter ego_motion/source): tf (the vehicle's odom -> base_link, e.g. robot_localization or
// wheel odometry), lidar (the same lookup, of the tf the icanc/LidarOdometry nodelet publishes),
// odometry (a nav_msgs/Odometry topic, interpolated at the stamp), none. Glue only: what the poses
// mean is icanc::EgoMotion's.
#pragma once

#include <functional>
#include <memory>
#include <mutex>
#include <string>

#include <Eigen/Geometry>
#include <nav_msgs/Odometry.h>
#include <ros/callback_queue.h>
#include <ros/node_handle.h>
#include <ros/spinner.h>
#include <ros/subscriber.h>
#include <tf2_ros/buffer.h>

#include "icanc/core/common/stamped_history.hpp"
#include "icanc/core/motion/ego_motion.hpp"
#include "icanc/ros/param_reader.hpp"

namespace icanc {

// The namespace's ego_motion section, shared with LidarOdometry: the core's parameters and the
// fixed frame the poses are in.
struct EgoMotionSection {
  EgoMotionParams params;
  std::string fixed_frame = "odom";
};

// Reads the section with `reader` (a ParamReader over the namespace's ego_motion) and checks it:
// "" or the first problem. A source other than none needs `target_frame`, the vehicle frame.
std::string loadEgoMotion(ParamReader& reader, const std::string& target_frame, EgoMotionSection& section);

class EgoPoseSource {
 public:
  // For kOdometry it subscribes to `odom` in nh's namespace (remap it), on a queue and thread of
  // its own (below); the others use `tf`.
  EgoPoseSource(ros::NodeHandle& nh, EgoMotionSource source, const std::string& fixed_frame,
                tf2_ros::Buffer& tf);

  // The pose of vehicle_frame in the fixed frame at `stamp`, as it is now: never waits (the
  // cloud waited for it in CloudTransformQueue). False, with the reason, when there is none (the
  // caller extrapolates and counts).
  bool lookup(const ros::Time& stamp, const std::string& vehicle_frame,
              Eigen::Isometry3d& fixed_T_vehicle, std::string& why);

  // Whether lookup would find the pose now (what a waiting cloud is released on).
  bool available(const ros::Time& stamp, const std::string& vehicle_frame);

  // Whether a cloud should wait for its pose: after kMissesBeforeNoWait lookups in a row without
  // one it is not, until a pose comes again, so a source that is configured but silent costs no
  // latency on every cloud; the first cloud waits like the others (a replay's first frame must
  // not depend on which message arrived first).
  bool worthWaiting() const { return consecutive_misses_ < kMissesBeforeNoWait; }

  // Called (on the odometry's thread) after each odometry message: a cloud may wait for it.
  void setOnPose(std::function<void()> on_pose);

  EgoMotionSource source() const { return source_; }

  static constexpr int kMissesBeforeNoWait = 3;

 private:
  bool lookupTf(const ros::Time& stamp, const std::string& vehicle_frame, Eigen::Isometry3d& pose,
                std::string& why);
  bool lookupOdometry(const ros::Time& stamp, const std::string& vehicle_frame,
                      Eigen::Isometry3d& pose, std::string& why);
  bool interpolateOdometry(const ros::Time& stamp, Eigen::Isometry3d& pose, std::string& child,
                           std::string& why);
  void onOdometry(const nav_msgs::Odometry::ConstPtr& msg);

  EgoMotionSource source_;
  std::string fixed_frame_;
  tf2_ros::Buffer& tf_;
  std::mutex mutex_;
  StampedHistory<Eigen::Isometry3d> odometry_;  // by stamp (toSec()), the last few seconds
  std::string odometry_child_frame_;
  int consecutive_misses_ = 0;  // lookups in a row that found no pose
  std::function<void()> on_pose_;  // under mutex_
  // The odometry on a queue and a thread of its own, so that it arrives whatever the nodelet
  // manager's threads are busy with. Last: unsubscribed and joined before what the callback
  // touches goes.
  ros::CallbackQueue odom_queue_;
  std::unique_ptr<ros::AsyncSpinner> odom_spinner_;
  ros::Subscriber odom_sub_;
};

}  // namespace icanc
