#include "icanc/ros/cloud_transform_queue.hpp"

#include <algorithm>

#include <boost/make_shared.hpp>
#include <ros/callback_queue_interface.h>
#include <tf2_eigen/tf2_eigen.h>

namespace icanc {

class CloudTransformQueue::DrainCallback : public ros::CallbackInterface {
 public:
  explicit DrainCallback(CloudTransformQueue* queue) : queue_(queue) {}
  CallResult call() override {
    {
      std::lock_guard<std::mutex> lock(queue_->post_mutex_);
      queue_->posted_ = false;
    }
    std::lock_guard<std::mutex> lock(queue_->mutex_);
    queue_->drain();
    return Success;
  }

 private:
  CloudTransformQueue* queue_;
};

CloudTransformQueue::CloudTransformQueue(ros::NodeHandle& nh, tf2_ros::Buffer& tf, EgoPoseSource& ego,
                                         const std::string& target_frame, double wait_s,
                                         Handler handler)
    : callbacks_(nh.getCallbackQueue()),
      tf_(tf),
      ego_(ego),
      target_frame_(target_frame),
      wait_s_(wait_s),
      handler_(std::move(handler)) {
  timer_ = nh.createWallTimer(ros::WallDuration(wait_s_), [this](const ros::WallTimerEvent&) {
    std::lock_guard<std::mutex> lock(mutex_);
    drain();
  }, /*oneshot=*/true, /*autostart=*/false);
  tf_changed_ = tf_._addTransformsChangedListener([this] { post(); });
  ego_.setOnPose([this] { post(); });
}

CloudTransformQueue::~CloudTransformQueue() {
  ego_.setOnPose(nullptr);
  tf_._removeTransformsChangedListener(tf_changed_);
  {
    std::lock_guard<std::mutex> lock(post_mutex_);
    alive_ = false;  // a tf callback still running posts nothing more
  }
  timer_.stop();
  callbacks_->removeByID(reinterpret_cast<uint64_t>(this));  // waits for a drain running
}

void CloudTransformQueue::post() {
  std::lock_guard<std::mutex> lock(post_mutex_);
  if (!alive_ || posted_ || stats_.waiting == 0) return;
  posted_ = true;
  callbacks_->addCallback(boost::make_shared<DrainCallback>(this), reinterpret_cast<uint64_t>(this));
}

void CloudTransformQueue::push(Cloud cloud) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (first_received_.isZero()) first_received_ = cloud.received;
  queue_.push_back(std::move(cloud));
  drain();
}

CloudTransformQueue::Stats CloudTransformQueue::stats(bool reset_max) {
  std::lock_guard<std::mutex> lock(post_mutex_);
  const Stats stats = stats_;
  if (reset_max) stats_.max_wait_ms = 0.0;
  return stats;
}

bool CloudTransformQueue::needsMount(const Cloud& cloud) const {
  return !target_frame_.empty() && target_frame_ != cloud.msg->header.frame_id;
}

void CloudTransformQueue::drain() {
  const bool with_pose = ego_.source() != EgoMotionSource::kNone;
  while (!queue_.empty()) {
    const Cloud& front = queue_.front();
    const ros::Time& stamp = front.msg->header.stamp;
    const ros::WallTime now = ros::WallTime::now();
    const bool full = queue_.size() > kMaxQueued;
    ros::WallTime deadline;
    bool ready;
    if (needsMount(front) && !tf_.canTransform(target_frame_, front.msg->header.frame_id, stamp)) {
      const double startup_s = kMountStartupWaitS - (front.received - first_received_).toSec();
      deadline = front.received + ros::WallDuration(mount_seen_ ? wait_s_ : std::max(wait_s_, startup_s));
      ready = false;
    } else {
      deadline = front.received + ros::WallDuration(ego_.worthWaiting() ? wait_s_ : 0.0);
      ready = !with_pose || ego_.available(stamp, target_frame_);
    }
    if (!ready && !full && now < deadline) {
      timer_.stop();
      timer_.setPeriod(deadline - now);
      timer_.start();
      break;
    }
    const Cloud cloud = std::move(queue_.front());
    queue_.pop_front();
    Transforms transforms = release(cloud, !ready);
    {
      std::lock_guard<std::mutex> lock(post_mutex_);
      if (transforms.mount_missing) ++stats_.mount_missing;
      if (transforms.timed_out) ++stats_.timed_out;
      if (!ready && full) ++stats_.pushed_out;
      stats_.max_wait_ms = std::max(stats_.max_wait_ms, transforms.waited_s * 1e3);
    }
    handler_(cloud, transforms);
  }
  std::lock_guard<std::mutex> lock(post_mutex_);
  stats_.waiting = queue_.size();
}

CloudTransformQueue::Transforms CloudTransformQueue::release(const Cloud& cloud, bool timed_out) {
  Transforms out;
  const std_msgs::Header& header = cloud.msg->header;
  out.waited_s = (ros::WallTime::now() - cloud.received).toSec();
  out.frame = header.frame_id;
  if (needsMount(cloud)) {
    try {
      out.to_frame = tf2::transformToEigen(
          tf_.lookupTransform(target_frame_, header.frame_id, header.stamp)).cast<float>();
      out.frame = target_frame_;
      mount_seen_ = true;
    } catch (const tf2::TransformException& e) {
      out.mount_missing = true;
      out.mount_why = e.what();
    }
  } else if (!target_frame_.empty()) {
    out.frame = target_frame_;
  }
  bool pose_waited = false;
  if (ego_.source() == EgoMotionSource::kNone) {
    out.pose_why = "no ego motion source";
  } else if (out.frame != target_frame_) {
    out.pose_why = "boxes are not in the vehicle frame " + target_frame_;
  } else {
    pose_waited = ego_.worthWaiting() && wait_s_ > 0.0;
    out.has_pose = ego_.lookup(header.stamp, target_frame_, out.pose, out.pose_why);
  }
  out.timed_out = timed_out && (out.mount_missing || (!out.has_pose && pose_waited));
  return out;
}

}  // namespace icanc
