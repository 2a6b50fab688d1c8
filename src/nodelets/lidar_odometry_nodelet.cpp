// icanc/LidarOdometry: PointCloud2 in (the detector's `points`, shared in the manager), tf
// odom_frame -> base_frame at the cloud's stamp and nav_msgs/Odometry on `lidar_odom` out. Glue
// only: decoding checks, tf2, parameters and diagnostics here; the registration is
// icanc::LidarOdometry. Idle (no subscription) unless the namespace parameter ego_motion/source is
// "lidar", so icanc.launch can always load it. With ~twist_topic (geometry_msgs/TwistStamped: the
// vehicle's forward speed in twist.linear.x, wheel speed on CAN; with ~twist_yaw_rate its gyro's
// yaw rate in twist.angular.z), frames whose scene fixes no motion take that motion
// (LidarOdometry::seedTwist) instead of "as before".
#include <map>
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
#include "icanc/core/motion/lidar_odometry.hpp"
#include "icanc/core/motion/measured_twist.hpp"
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
    reader.read("base_frame", base_frame_);
    reader.read("odom_frame", odom_frame_);
    reader.read("max_points", max_points_);
    reader.read("twist_topic", twist_topic_);
    reader.read("twist_max_age_s", twist_max_age_s_);
    reader.read("twist_yaw_rate", twist_yaw_rate_);
    const std::string rate_problem = readExpectedRate(reader, expected_rate_hz_);
    std::string why = validate(params);
    if (why.empty() && max_points_ <= 0) why = "max_points must be > 0";
    if (why.empty() && (base_frame_.empty() || odom_frame_.empty()))
      why = "base_frame and odom_frame must not be empty";
    if (why.empty() && base_frame_ == odom_frame_) why = "base_frame must differ from odom_frame";
    if (why.empty() && !(twist_max_age_s_ > 0.0 && twist_max_age_s_ <= 1.0))
      why = "twist_max_age_s must be in (0, 1]";
    if (why.empty()) why = rate_problem;
    if (!checkParams(getName(), reader, why)) return;

    std::string source;
    nh.param<std::string>("ego_motion/source", source, "");
    if (source != "lidar") {
      NODELET_INFO("LidarOdometry idle: %s is '%s', not 'lidar'",
                   nh.resolveName("ego_motion/source").c_str(), source.c_str());
      return;
    }

    odometry_.reset(new LidarOdometry(params));
    tf_buffer_.reset(new tf2_ros::Buffer());
    tf_listener_.reset(new tf2_ros::TransformListener(*tf_buffer_, nh));
    diagnostics_.reset(new Diagnostics(nh, pnh, getName(), "lidar"));
    diagnostics_->updater().add("lidar odometry", this, &LidarOdometryNodelet::diagnose);
    odom_pub_ = nh.advertise<nav_msgs::Odometry>("lidar_odom", 5);
    sub_ = nh.subscribe("points", 2, &LidarOdometryNodelet::onCloud, this);
    if (!twist_topic_.empty()) {
      twist_sub_ = nh.subscribe(twist_topic_, 50, &LidarOdometryNodelet::onSpeed, this);
      NODELET_INFO("LidarOdometry: the vehicle's speed%s from %s (twist.linear.x%s) where the "
                   "scene fixes no motion", twist_yaw_rate_ ? " and yaw rate" : "",
                   twist_sub_.getTopic().c_str(), twist_yaw_rate_ ? ", angular.z" : "");
    }
    input_.reset(new InputMonitor(diagnostics_->updater(), sub_.getTopic(), expected_rate_hz_));
    NODELET_INFO("LidarOdometry on %s -> tf %s -> %s, %s", sub_.getTopic().c_str(),
                 odom_frame_.c_str(), base_frame_.c_str(), nh.resolveName("lidar_odom").c_str());
  }

  // Cloud frame -> base_frame (the sensor mount, normally static): at the stamp, else the latest.
  bool lookupMount(const std_msgs::Header& header, Eigen::Affine3f& mount) {
    mount.setIdentity();
    if (header.frame_id == base_frame_) return true;
    try {
      mount = tf2::transformToEigen(
          lookupAtStampOrLatest(*tf_buffer_, base_frame_, header.frame_id, header.stamp)).cast<float>();
      return true;
    } catch (const tf2::TransformException& e) {
      ++tf_failures_;
      NODELET_WARN_THROTTLE(5.0, "no transform %s -> %s (%s): cloud skipped, no odometry",
                            header.frame_id.c_str(), base_frame_.c_str(), e.what());
      return false;
    }
  }

  void onSpeed(const geometry_msgs::TwistStamped::ConstPtr& msg) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (msg->header.stamp.isZero()) {  // an unstamped driver: nothing to match a cloud's stamp to
      ++invalid_speeds_;
      NODELET_ERROR_THROTTLE(1.0, "vehicle twist on %s dropped: header.stamp is 0 (it is matched to "
                             "each cloud's stamp; stamp it when measured)", twist_sub_.getTopic().c_str());
      return;
    }
    MeasuredTwist twist = measuredTwist(msg->twist.linear.x);
    if (twist_yaw_rate_) twist.yaw_rate_rad_s = msg->twist.angular.z;
    const TwistHistory::Added added = speeds_.add(msg->header.stamp.toSec(), twist);
    if (added == TwistHistory::Added::kInvalid) {
      ++invalid_speeds_;
      NODELET_ERROR_THROTTLE(1.0, "vehicle twist on %s dropped: %g m/s, %g rad/s at stamp %.3f is "
                             "no measurement", twist_sub_.getTopic().c_str(), msg->twist.linear.x,
                             msg->twist.angular.z, msg->header.stamp.toSec());
    } else if (added == TwistHistory::Added::kRestarted) {
      ++speed_restarts_;
      NODELET_WARN_THROTTLE(1.0, "vehicle speed stamp went backwards on %s (bag loop?): history "
                            "restarted", twist_sub_.getTopic().c_str());
    }
  }

  // The vehicle's measured twist at the cloud's stamp, handed to the odometry for this frame.
  void seedTwist(const ros::Time& stamp) {
    if (twist_topic_.empty()) return;
    MeasuredTwist twist;
    if (speeds_.at(stamp.toSec(), twist_max_age_s_, twist)) {
      odometry_->seedTwist(twist);
      return;
    }
    ++speed_missing_;
    NODELET_WARN_THROTTLE(5.0, "no vehicle speed on %s within %.2f s of the cloud at %.3f: the "
                          "LiDAR alone for this frame", twist_sub_.getTopic().c_str(),
                          twist_max_age_s_, stamp.toSec());
  }

  void onCloud(const sensor_msgs::PointCloud2::ConstPtr& msg) {
    const ros::WallTime received = ros::WallTime::now();
    std::lock_guard<std::mutex> lock(mutex_);
    input_->received(msg->header.stamp.toSec());
    ++received_;
    const RawCloud raw = toRawCloud(*msg);
    DecodePlan plan;
    const DecodeError error = planDecode(raw, static_cast<std::size_t>(max_points_), plan);
    if (error != DecodeError::kNone) {
      ++invalid_[error];
      input_->invalid();
      NODELET_ERROR_THROTTLE(1.0, "dropping cloud (frame '%s', %ux%u, %zu bytes): %s",
                             msg->header.frame_id.c_str(), msg->width, msg->height,
                             msg->data.size(), toString(error));
      return;  // no transform for this stamp: consumers see the gap (bounded wait)
    }
    Eigen::Affine3f mount;
    if (!lookupMount(msg->header, mount)) return;

    seedTwist(msg->header.stamp);
    // The points input_stride skips are not decoded at all.
    const DecodePlan thinned =
        everyNthPoint(plan, odometry_->params().input_stride, odometry_->sourcePhase());
    const Eigen::Isometry3d pose = odometry_->registerFrom(
        msg->header.stamp.toSec(), [&](auto&& sink) { forEachXYZ(raw, thinned, mount, sink); },
        LidarOdometry::Thinning::kBySource);
    const LidarOdometryStats& stats = odometry_->lastStats();
    using Result = LidarOdometryStats::Result;
    if (stats.result == Result::kReset) {
      NODELET_WARN_THROTTLE(
          1.0, "cloud stamp went backwards (bag loop?): odometry restarted at identity");
    } else if (stats.result == Result::kDegenerate && stats.speed_seeded) {
      // Expected on a flat road or between walls; the vehicle's speed carries the pose.
      NODELET_INFO_THROTTLE(10.0, "registration degenerate (horizontal observability %.3f, at "
                            "least %.3f wanted): pose from the vehicle's measured motion",
                            stats.horizontal_observability,
                            odometry_->params().min_horizontal_observability);
    } else if (stats.result == Result::kDegenerate) {
      NODELET_WARN_THROTTLE(1.0,
                            "registration degenerate (%zu of %zu points matched, horizontal "
                            "observability %.3f, at least %.3f wanted): pose from the motion prior",
                            stats.correspondences, stats.registration_points,
                            stats.horizontal_observability,
                            odometry_->params().min_horizontal_observability);
    } else if (stats.result == Result::kExtrapolated) {
      NODELET_WARN_THROTTLE(1.0, "cloud with %zu usable points (< %d): pose from the %s",
                            stats.registration_points, odometry_->params().min_points,
                            stats.speed_seeded ? "vehicle's measured motion" : "motion prior");
    }
    publish(msg->header.stamp, pose, stats.result);
    last_ms_ = (ros::WallTime::now() - received).toSec() * 1e3;
    input_->processed(last_ms_);
  }

  void publish(const ros::Time& stamp, const Eigen::Isometry3d& pose,
               LidarOdometryStats::Result result) {
    geometry_msgs::TransformStamped tf = tf2::eigenToTransform(pose);
    tf.header.stamp = stamp;
    tf.header.frame_id = odom_frame_;
    tf.child_frame_id = base_frame_;
    broadcaster_.sendTransform(tf);

    auto odom = boost::make_shared<nav_msgs::Odometry>();
    odom->header = tf.header;
    odom->child_frame_id = base_frame_;
    odom->pose.pose = tf2::toMsg(pose);
    const Eigen::Vector3d v = odometry_->linearVelocity(), w = odometry_->angularVelocity();
    odom->twist.twist.linear.x = v.x();
    odom->twist.twist.linear.y = v.y();
    odom->twist.twist.linear.z = v.z();
    odom->twist.twist.angular.x = w.x();
    odom->twist.twist.angular.y = w.y();
    odom->twist.twist.angular.z = w.z();
    // Diagonal covariances (x y z roll pitch yaw). Registered: the centimetre-level agreement
    // measured on KITTI (docs/lidar_odometry.md); from the motion prior: a metre and 0.1 rad,
    // so a fusing filter trusts it little.
    const bool measured = result == LidarOdometryStats::Result::kRegistered ||
                          result == LidarOdometryStats::Result::kHeld ||
                          result == LidarOdometryStats::Result::kAtRest ||
                          result == LidarOdometryStats::Result::kFirstFrame ||
                          result == LidarOdometryStats::Result::kReset;
    const double pos_var = measured ? 0.05 * 0.05 : 1.0, rot_var = measured ? 0.01 * 0.01 : 0.01;
    const double vel_var = measured ? 0.2 * 0.2 : 4.0, rate_var = measured ? 0.02 * 0.02 : 0.04;
    for (int i = 0; i < 3; ++i) {
      odom->pose.covariance[i * 7] = pos_var;
      odom->pose.covariance[(i + 3) * 7] = rot_var;
      odom->twist.covariance[i * 7] = vel_var;
      odom->twist.covariance[(i + 3) * 7] = rate_var;
    }
    odom_pub_.publish(nav_msgs::Odometry::ConstPtr(odom));
    ++published_;
  }

  void diagnose(diagnostic_updater::DiagnosticStatusWrapper& stat) {
    std::lock_guard<std::mutex> lock(mutex_);
    std::uint64_t invalid = 0;
    for (const auto& kv : invalid_) {
      invalid += kv.second;
      stat.add(std::string("invalid clouds: ") + toString(kv.first), kv.second);
    }
    const LidarOdometryCounters& c = odometry_->counters();
    if (invalid > reported_invalid_)
      stat.summary(diagnostic_msgs::DiagnosticStatus::WARN, "invalid clouds dropped");
    else if (tf_failures_ > reported_tf_failures_)
      stat.summary(diagnostic_msgs::DiagnosticStatus::WARN, "transform to base frame missing");
    else if (invalid_speeds_ > reported_invalid_speeds_ || speed_missing_ > reported_speed_missing_)
      stat.summary(diagnostic_msgs::DiagnosticStatus::WARN, "vehicle speed invalid or missing");
    else if (c.degenerate + c.extrapolated > reported_prior_)
      stat.summary(diagnostic_msgs::DiagnosticStatus::WARN, "poses from the motion prior");
    else
      stat.summary(diagnostic_msgs::DiagnosticStatus::OK, "ok");
    reported_invalid_ = invalid;
    reported_tf_failures_ = tf_failures_;
    reported_prior_ = c.degenerate + c.extrapolated;
    reported_invalid_speeds_ = invalid_speeds_;
    reported_speed_missing_ = speed_missing_;
    const LidarOdometryStats& s = odometry_->lastStats();
    stat.add("clouds received", received_);
    stat.add("odometry published", published_);
    stat.add("invalid clouds", invalid);
    stat.add("transform failures", tf_failures_);
    stat.add("frames", c.frames);
    stat.add("registered", c.registered);
    stat.add("at rest (the scan fits no motion)", c.at_rest);
    stat.add("degenerate (motion prior)", c.degenerate);
    stat.add("of those, registered along-track held (speed only)", c.held);
    stat.add("too few points (motion prior)", c.extrapolated);
    stat.add("resets: time backwards", c.resets);
    stat.add("gaps above max_dt_s", c.gaps);
    stat.add("non-finite points", c.nonfinite_points);
    stat.add("twist topic", twist_topic_.empty() ? std::string("none") : twist_sub_.getTopic());
    stat.add("poses from the measured twist (scene degenerate)", c.speed_seeded);
    stat.add("clouds without a vehicle speed", speed_missing_);
    stat.add("invalid vehicle speeds", invalid_speeds_);
    stat.add("vehicle speed restarts: time backwards", speed_restarts_);
    stat.add("last result", toString(s.result));
    stat.add("registration points", s.registration_points);
    stat.add("correspondences", s.correspondences);
    stat.add("iterations", s.iterations);
    stat.add("threshold m", s.threshold_m);
    stat.add("map points", s.map_points);
    stat.add("downsample ms", s.downsample_ms);
    stat.add("registration ms", s.register_ms);
    stat.add("map ms", s.map_ms);
    stat.add("processing ms (last frame)", last_ms_);
  }

  std::unique_ptr<LidarOdometry> odometry_;
  std::unique_ptr<tf2_ros::Buffer> tf_buffer_;
  std::unique_ptr<tf2_ros::TransformListener> tf_listener_;
  tf2_ros::TransformBroadcaster broadcaster_;
  std::unique_ptr<Diagnostics> diagnostics_;
  std::unique_ptr<InputMonitor> input_;
  ros::Publisher odom_pub_;
  ros::Subscriber sub_, twist_sub_;

  std::string base_frame_ = "base_link";
  std::string odom_frame_ = "odom";
  int max_points_ = 2000000;
  double expected_rate_hz_ = 10.0;
  std::string twist_topic_;         // "": no vehicle speed
  double twist_max_age_s_ = 0.2;    // a speed this far from the cloud's stamp is not used [s]
  bool twist_yaw_rate_ = false;     // twist.angular.z is the vehicle's yaw rate (a gyro)
  TwistHistory speeds_;

  std::mutex mutex_;  // the cloud callback and the diagnostics timer
  std::map<DecodeError, std::uint64_t> invalid_;
  std::uint64_t received_ = 0, published_ = 0, tf_failures_ = 0;
  std::uint64_t reported_invalid_ = 0, reported_tf_failures_ = 0, reported_prior_ = 0;
  std::uint64_t invalid_speeds_ = 0, speed_missing_ = 0, speed_restarts_ = 0;
  std::uint64_t reported_invalid_speeds_ = 0, reported_speed_missing_ = 0;
  double last_ms_ = 0.0;
};

}  // namespace icanc

PLUGINLIB_EXPORT_CLASS(icanc::LidarOdometryNodelet, nodelet::Nodelet)
