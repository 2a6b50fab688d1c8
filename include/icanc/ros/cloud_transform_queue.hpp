// The ObstacleDetector's clouds wait here, in their order, for what they need at their stamp: the
// sensor -> target_frame transform (tf2) and, with an ego motion source, the vehicle's pose in the
// fixed frame (EgoPoseSource). Nothing blocks: push() returns at once, and a cloud goes on (the
// handler, on the nodelet's callback queue) as soon as it has both, which tf2 and the odometry
// announce as they arrive, or at its deadline without what is missing: wait_s after it arrived
// (ego_motion/max_wait_s live, replay_max_wait_s on sim time), for the mount at start-up until
// kMountStartupWaitS after the first cloud, and not at all for a pose source that went silent
// (EgoPoseSource::worthWaiting). The transform is taken at the stamp or not at all, never the
// latest one. At most kMaxQueued clouds wait: one more sends the oldest on at once.
#pragma once

#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <string>

#include <Eigen/Geometry>
#include <boost/signals2/connection.hpp>
#include <ros/node_handle.h>
#include <ros/wall_timer.h>
#include <sensor_msgs/PointCloud2.h>
#include <tf2_ros/buffer.h>

#include "icanc/core/perception/cloud_decode.hpp"
#include "icanc/ros/ego_pose_source.hpp"

namespace icanc {

class CloudTransformQueue {
 public:
  struct Cloud {
    sensor_msgs::PointCloud2::ConstPtr msg;
    ros::WallTime received;
    DecodePlan plan;  // planDecode's, done on arrival
  };
  // What a cloud goes on with.
  struct Transforms {
    std::string frame;  // target_frame, or the cloud's own frame when its transform is missing
    Eigen::Affine3f to_frame = Eigen::Affine3f::Identity();  // cloud frame -> frame
    bool mount_missing = false;  // no target_frame <- cloud frame at the stamp: boxes in the cloud's
    std::string mount_why;
    bool has_pose = false;  // the vehicle's pose in the fixed frame at the stamp
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    std::string pose_why;   // why there is none
    bool timed_out = false;   // went on at its deadline (or pushed out) without all it waited for
    double waited_s = 0.0;    // wall time it waited
  };
  using Handler = std::function<void(const Cloud&, const Transforms&)>;
  struct Stats {
    std::uint64_t mount_missing = 0;  // clouds that went on in their own frame
    std::uint64_t timed_out = 0;   // clouds that went on without a transform they waited for
    std::uint64_t pushed_out = 0;  // of which sent on early: kMaxQueued were waiting
    std::size_t waiting = 0;       // clouds waiting now
    double max_wait_ms = 0.0;      // longest wait since the last stats(true)
  };

  static constexpr std::size_t kMaxQueued = 10;
  static constexpr double kMountStartupWaitS = 2.0;

  // `ego` and `tf` outlive the queue; the handler runs under the queue's lock, one cloud at a time.
  CloudTransformQueue(ros::NodeHandle& nh, tf2_ros::Buffer& tf, EgoPoseSource& ego,
                      const std::string& target_frame, double wait_s, Handler handler);
  ~CloudTransformQueue();

  void push(Cloud cloud);
  Stats stats(bool reset_max);

 private:
  void post();   // a drain on the nodelet's callback queue (from tf's and the odometry's threads)
  void drain();  // under mutex_
  bool needsMount(const Cloud& cloud) const;
  Transforms release(const Cloud& cloud, bool timed_out);

  class DrainCallback;
  ros::CallbackQueueInterface* callbacks_;
  tf2_ros::Buffer& tf_;
  EgoPoseSource& ego_;
  std::string target_frame_;
  double wait_s_;
  Handler handler_;

  std::mutex mutex_;  // the queue and everything the handler touches
  std::deque<Cloud> queue_;
  bool mount_seen_ = false;
  ros::WallTime first_received_;
  ros::WallTimer timer_;  // one shot, at the front cloud's deadline

  std::mutex post_mutex_;  // a leaf: posting, and the stats
  bool alive_ = true, posted_ = false;
  Stats stats_;
  boost::signals2::connection tf_changed_;
};

}  // namespace icanc
