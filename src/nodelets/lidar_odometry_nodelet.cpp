// icanc/LidarOdometry: PointCloud2 in (the detector's `points`, shared in the manager), tf
// odom_frame -> base_frame at the cloud's stamp and nav_msgs/Odometry on `lidar_odom` out. Glue
// only: decoding checks, tf2, parameters and diagnostics here; the registration is
// icanc::LidarOdometry. Idle (no subscription) unless the namespace parameter ego_motion/source is
// "lidar", so icanc.launch can always load it. What is counted, logged and reported is
// icanc::OdometryFeed's. With ~twist_topic (geometry_msgs/TwistStamped: the
// vehicle's forward speed in twist.linear.x, wheel speed on CAN; with ~twist_yaw_rate its gyro's
// yaw rate in twist.angular.z), frames whose scene fixes no motion take that motion
// (LidarOdometry::seedTwist) instead of "as before".
#include <memory>
#include <mutex>

#include <boost/make_shared.hpp>
#include <geometry_msgs/TransformStamped.h>
#include <geometry_msgs/TwistStamped.h>
#include <nav_msgs/Odometry.h>
#include <nodelet/nodelet.h>
#include <pluginlib/class_list_macros.hpp>
#include <sensor_msgs/PointCloud2.h>
#include <tf2_eigen/tf2_eigen.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_broadcaster.h>
#include <tf2_ros/transform_listener.h>

#include "icanc/core/perception/cloud_decode.hpp"
#include "icanc/core/motion/odometry_feed.hpp"
#include "icanc/ros/conversions.hpp"
#include "icanc/ros/nodelet_support.hpp"

namespace icanc {

class LidarOdometryNodelet : public nodelet::Nodelet {
 private:
  void onInit() override {
    ros::NodeHandle& nh = getNodeHandle();
    ros::NodeHandle& pnh = getPrivateNodeHandle();

    ParamReader reader(pnh);
    LidarOdometryParams params;
    visitParams(reader, params);
    OdometryFeedParams feed;
    reader.read("base_frame", feed.base_frame);
    reader.read("odom_frame", feed.odom_frame);
    reader.read("max_points", feed.max_points);
    reader.read("twist_topic", feed.twist_topic);
    reader.read("twist_max_age_s", feed.twist_max_age_s);
    reader.read("twist_yaw_rate", feed.twist_yaw_rate);
    const std::string rate_problem = readExpectedRate(reader, expected_rate_hz_);
    std::string why = validate(params);
    if (why.empty()) why = validate(feed);
    if (why.empty()) why = rate_problem;
    if (!checkParams(getName(), reader, why)) return;

    std::string source;
    nh.param<std::string>("ego_motion/source", source, "");
    if (source != "lidar") {
      NODELET_INFO("LidarOdometry idle: %s is '%s', not 'lidar'",
                   nh.resolveName("ego_motion/source").c_str(), source.c_str());
      return;
    }

    feed_.reset(new OdometryFeed(params, feed, feed.twist_topic.empty() ? "" : nh.resolveName(feed.twist_topic)));
    tf_buffer_.reset(new tf2_ros::Buffer());
    // /tf on this nodelet's own callback queue: no thread polling for it.
    tf_listener_.reset(new tf2_ros::TransformListener(*tf_buffer_, nh, /*spin_thread=*/false));
    diagnostics_.reset(new Diagnostics(nh, pnh, getName(), "lidar"));
    diagnostics_->updater().add("lidar odometry", [this](diagnostic_updater::DiagnosticStatusWrapper& stat) {
      std::lock_guard<std::mutex> lock(mutex_);
      report(stat, feed_->report(last_ms_));
    });
    odom_pub_ = nh.advertise<nav_msgs::Odometry>("lidar_odom", 5);
    sub_ = nh.subscribe("points", 2, &LidarOdometryNodelet::onCloud, this);
    if (!feed.twist_topic.empty()) {
      twist_sub_ = nh.subscribe(feed.twist_topic, 50, &LidarOdometryNodelet::onSpeed, this);
      NODELET_INFO("LidarOdometry: the vehicle's speed%s from %s (twist.linear.x%s) where the "
                   "scene fixes no motion", feed.twist_yaw_rate ? " and yaw rate" : "",
                   twist_sub_.getTopic().c_str(), feed.twist_yaw_rate ? ", angular.z" : "");
    }
    input_.reset(new InputMonitor(diagnostics_->updater(), sub_.getTopic(), expected_rate_hz_));
    NODELET_INFO("LidarOdometry on %s -> tf %s -> %s, %s", sub_.getTopic().c_str(),
                 feed.odom_frame.c_str(), feed.base_frame.c_str(), nh.resolveName("lidar_odom").c_str());
  }

  // Cloud frame -> base_frame (the sensor mount, normally static): at the stamp, else the latest.
  bool lookupMount(const std_msgs::Header& header, Eigen::Affine3f& mount) {
    mount.setIdentity();
    const std::string& base_frame = feed_->params().base_frame;
    if (header.frame_id == base_frame) return true;
    try {
      mount = tf2::transformToEigen(
          lookupAtStampOrLatest(*tf_buffer_, base_frame, header.frame_id, header.stamp)).cast<float>();
      return true;
    } catch (const tf2::TransformException& e) {
      feed_->onTransformFailure(header.frame_id, e.what(), ros::Time::now().toSec(), logs_);
      return false;
    }
  }

  void onSpeed(const geometry_msgs::TwistStamped::ConstPtr& msg) {
    std::lock_guard<std::mutex> lock(mutex_);
    feed_->onTwist(msg->header.stamp.isZero() ? 0.0 : msg->header.stamp.toSec(), msg->twist.linear.x,
                   msg->twist.angular.z, ros::Time::now().toSec(), logs_);
    flushLogs();
  }

  // With mutex_ held: the core's log lines under this nodelet's name.
  void flushLogs() {
    for (const LogLine& line : logs_) log(getName(), line);
    logs_.clear();
  }

  void onCloud(const sensor_msgs::PointCloud2::ConstPtr& msg) {
    const ros::WallTime received = ros::WallTime::now();
    std::lock_guard<std::mutex> lock(mutex_);
    input_->received(msg->header.stamp.toSec());
    feed_->onCloud();
    const double now = ros::Time::now().toSec();  // paces the log lines
    const RawCloud raw = toRawCloud(*msg);
    DecodePlan plan;
    const DecodeError error = planDecode(raw, static_cast<std::size_t>(feed_->params().max_points), plan);
    if (error != DecodeError::kNone) {
      input_->invalid();
      feed_->onInvalidCloud(error, msg->header.frame_id, msg->width, msg->height, msg->data.size(), now, logs_);
      flushLogs();
      return;  // no transform for this stamp: consumers see the gap (bounded wait)
    }
    Eigen::Affine3f mount;
    if (!lookupMount(msg->header, mount)) {
      flushLogs();
      return;
    }
    feed_->seedTwist(msg->header.stamp.toSec(), now, logs_);
    LidarOdometry& odometry = feed_->odometry();
    // The points input_stride skips are not decoded at all.
    const DecodePlan thinned = everyNthPoint(plan, odometry.params().input_stride, odometry.sourcePhase());
    const Eigen::Isometry3d pose = odometry.registerFrom(
        msg->header.stamp.toSec(), [&](auto&& sink) { forEachXYZ(raw, thinned, mount, sink); },
        LidarOdometry::Thinning::kBySource);
    feed_->onRegistered(now, logs_);
    flushLogs();
    publish(msg->header.stamp, pose, odometry.lastStats().result);
    last_ms_ = (ros::WallTime::now() - received).toSec() * 1e3;
    input_->processed(last_ms_);
  }

  void publish(const ros::Time& stamp, const Eigen::Isometry3d& pose,
               LidarOdometryStats::Result result) {
    geometry_msgs::TransformStamped tf = tf2::eigenToTransform(pose);
    tf.header.stamp = stamp;
    tf.header.frame_id = feed_->params().odom_frame;
    tf.child_frame_id = feed_->params().base_frame;
    broadcaster_.sendTransform(tf);

    auto odom = boost::make_shared<nav_msgs::Odometry>();
    odom->header = tf.header;
    odom->child_frame_id = tf.child_frame_id;
    odom->pose.pose = tf2::toMsg(pose);
    const Eigen::Vector3d v = feed_->odometry().linearVelocity(), w = feed_->odometry().angularVelocity();
    odom->twist.twist.linear.x = v.x();
    odom->twist.twist.linear.y = v.y();
    odom->twist.twist.linear.z = v.z();
    odom->twist.twist.angular.x = w.x();
    odom->twist.twist.angular.y = w.y();
    odom->twist.twist.angular.z = w.z();
    const OdometryVariances var = odometryVariances(result);  // diagonal: x y z roll pitch yaw
    for (int i = 0; i < 3; ++i) {
      odom->pose.covariance[i * 7] = var.position;
      odom->pose.covariance[(i + 3) * 7] = var.rotation;
      odom->twist.covariance[i * 7] = var.velocity;
      odom->twist.covariance[(i + 3) * 7] = var.rate;
    }
    odom_pub_.publish(nav_msgs::Odometry::ConstPtr(odom));
    feed_->onPublished();
  }

  std::unique_ptr<OdometryFeed> feed_;
  std::unique_ptr<tf2_ros::Buffer> tf_buffer_;
  std::unique_ptr<tf2_ros::TransformListener> tf_listener_;
  tf2_ros::TransformBroadcaster broadcaster_;
  std::unique_ptr<Diagnostics> diagnostics_;
  std::unique_ptr<InputMonitor> input_;
  ros::Publisher odom_pub_;
  ros::Subscriber sub_, twist_sub_;
  double expected_rate_hz_ = 10.0;

  std::mutex mutex_;  // the cloud and twist callbacks and the diagnostics timer
  std::vector<LogLine> logs_;  // the core's lines of this callback
  double last_ms_ = 0.0;
};

}  // namespace icanc

PLUGINLIB_EXPORT_CLASS(icanc::LidarOdometryNodelet, nodelet::Nodelet)
