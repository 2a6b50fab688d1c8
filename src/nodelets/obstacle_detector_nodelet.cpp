// icanc/ObstacleDetector: PointCloud2 in, icanc/ObstacleArray out. Glue only: decoding checks,
// tf2, parameters and diagnostics here; every algorithm is in icanc::ObstacleDetector.
#include <cstdio>
#include <limits>
#include <map>
#include <memory>
#include <mutex>

#include <boost/make_shared.hpp>
#include <nodelet/nodelet.h>
#include <pcl/common/transforms.h>
#include <pcl_conversions/pcl_conversions.h>
#include <pluginlib/class_list_macros.hpp>
#include <sensor_msgs/PointCloud2.h>
#include <tf2_eigen/tf2_eigen.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>

#include "icanc/ObstacleArray.h"
#include "icanc/ObstacleDetectorConfig.h"
#include "icanc/core/perception/cloud_decode.hpp"
#include "icanc/core/motion/ego_motion.hpp"
#include "icanc/core/perception/obstacle_detector.hpp"
#include "icanc/ros/cloud_input_checks.hpp"
#include "icanc/ros/conversions.hpp"
#include "icanc/ros/ego_pose_source.hpp"
#include "icanc/ros/live_params.hpp"
#include "icanc/ros/nodelet_support.hpp"
#include "icanc/ros/zero_copy.hpp"

namespace icanc {

class ObstacleDetectorNodelet : public nodelet::Nodelet {
 private:
  void onInit() override {
    ros::NodeHandle& nh = getNodeHandle();
    ros::NodeHandle& pnh = getPrivateNodeHandle();

    ParamReader reader(pnh);
    ObstacleDetectorParams params;
    readParams(reader, params);
    reader.read("target_frame", target_frame_);
    reader.read("max_points", max_points_);
    const std::string rate_problem = readExpectedRate(reader, expected_rate_hz_);
    reader.read("trace_publications", trace_unused_);  // read by ZeroCopyPublisher
    std::string why = validate(params);
    if (why.empty() && max_points_ <= 0) why = "max_points must be > 0";
    if (why.empty()) why = rate_problem;
    checks_ = CloudInputChecks(getName());
    const std::string checks_problem = checks_.load(reader);  // stamp_check/*, sensor_health/*
    if (why.empty()) why = checks_problem;
    acceptReconfigureKeys<ObstacleDetectorConfig>(reader);
    if (!checkParams(getName(), reader, why)) return;
    // The vehicle's own motion: the namespace's ego_motion section, shared with LidarOdometry.
    ParamReader ego_reader(ros::NodeHandle(nh, "ego_motion"));
    EgoMotionParams ego_params;
    std::string source = toString(ego_params.source);
    ego_reader.read("source", source);
    ego_params.source = parseEgoMotionSource(source);
    ego_reader.read("fixed_frame", fixed_frame_);
    ego_reader.read("max_speed_mps", ego_params.max_speed_mps);
    ego_reader.read("max_yaw_rate_rad_s", ego_params.max_yaw_rate_rad_s);
    ego_reader.read("max_wait_s", ego_params.max_wait_s);
    ego_reader.read("replay_max_wait_s", ego_params.replay_max_wait_s);
    ego_reader.read("max_extrapolation_s", ego_params.max_extrapolation_s);
    ego_reader.accept("publish_tf");  // LidarOdometry's
    std::string ego_why = validate(ego_params);
    if (ego_why.empty() && fixed_frame_.empty()) ego_why = "ego_motion/fixed_frame must not be empty";
    if (ego_why.empty() && ego_params.source != EgoMotionSource::kNone && target_frame_.empty())
      ego_why = "ego_motion/source " + source + " needs ~target_frame (the vehicle frame)";
    if (!checkParams(getName(), ego_reader, ego_why)) return;
    ego_.setParams(ego_params);

    detector_.reset(new ObstacleDetector(params));
    tf_buffer_.reset(new tf2_ros::Buffer());
    tf_listener_.reset(new tf2_ros::TransformListener(*tf_buffer_, nh));
    // (Its odometry subscription runs on a thread of its own: it arrives while a cloud waits.)
    ego_source_.reset(new EgoPoseSource(nh, ego_params.source, fixed_frame_, *tf_buffer_));

    // Before the diagnostics: their 1 Hz timer may call diagnose() (which reads live_) while
    // onInit is still running on a loaded machine.
    live_.reset(new LiveParams<ObstacleDetectorConfig, ObstacleDetectorParams>(pnh, params, getName()));
    diagnostics_.reset(new Diagnostics(nh, pnh, getName(), "lidar"));
    diagnostics_->updater().add("obstacle detector", this, &ObstacleDetectorNodelet::diagnose);

    pub_.advertise<ObstacleArray>(nh, pnh, "obstacles", 5);
    ground_pub_ = pnh.advertise<sensor_msgs::PointCloud2>("ground_points", 2);
    obstacle_pub_ = pnh.advertise<sensor_msgs::PointCloud2>("obstacle_points", 2);
    moving_pub_ = pnh.advertise<sensor_msgs::PointCloud2>("moving_points", 2);
    sub_ = nh.subscribe("points", 2, &ObstacleDetectorNodelet::onCloud, this);
    input_.reset(new InputMonitor(diagnostics_->updater(), sub_.getTopic(), expected_rate_hz_));
    NODELET_INFO("ObstacleDetector on %s -> %s (boxes in '%s', ego motion: %s%s%s)",
                 sub_.getTopic().c_str(), nh.resolveName("obstacles").c_str(),
                 target_frame_.empty() ? "<cloud frame>" : target_frame_.c_str(),
                 toString(ego_params.source),
                 ego_params.source == EgoMotionSource::kNone ? "" : ", tracks in ",
                 ego_params.source == EgoMotionSource::kNone ? "" : fixed_frame_.c_str());
  }

  // Sensor -> target frame at the cloud's stamp (latest transform as a fallback). On failure,
  // boxes stay in the sensor frame, with a throttled warning (the DangerDetector refuses them: no
  // danger is judged in the wrong frame, and its watchdog lights the lamp).
  std::string lookupTransform(const std_msgs::Header& header, Eigen::Affine3f& transform) {
    transform.setIdentity();
    if (target_frame_.empty() || target_frame_ == header.frame_id) return header.frame_id;
    waitForMountAtStartup(header.frame_id);
    try {
      transform = tf2::transformToEigen(
          lookupAtStampOrLatest(*tf_buffer_, target_frame_, header.frame_id, header.stamp)).cast<float>();
      mount_seen_ = true;
      return target_frame_;
    } catch (const tf2::TransformException& e) {
      ++tf_failures_;
      NODELET_WARN_THROTTLE(5.0, "no transform %s -> %s (%s): publishing boxes in %s",
                            header.frame_id.c_str(), target_frame_.c_str(), e.what(),
                            header.frame_id.c_str());
      return header.frame_id;
    }
  }

  // The first clouds may come before the sensor's mount on /tf_static (a driver started before the
  // robot_state_publisher, a bag whose latched transform arrives a moment later): wait for it, up
  // to kMountStartupWaitS of wall time in all, instead of publishing the first boxes in the
  // sensor's frame. Once a transform was found, or the budget is spent, no more waiting.
  void waitForMountAtStartup(const std::string& sensor_frame) {
    if (mount_seen_ || mount_wait_left_s_ <= 0.0) return;
    const ros::WallTime start = ros::WallTime::now();
    while (!tf_buffer_->canTransform(target_frame_, sensor_frame, ros::Time(0)) && ros::ok()) {
      if ((ros::WallTime::now() - start).toSec() >= mount_wait_left_s_) break;
      ros::WallDuration(0.005).sleep();
    }
    mount_wait_left_s_ -= (ros::WallTime::now() - start).toSec();
    if (mount_wait_left_s_ <= 0.0)
      NODELET_WARN("no transform %s -> %s within %.1f s of the first cloud: is the sensor's mount "
                   "published (static_transform_publisher, robot_state_publisher)?",
                   sensor_frame.c_str(), target_frame_.c_str(), kMountStartupWaitS);
  }

  void onCloud(const sensor_msgs::PointCloud2::ConstPtr& msg) {
    const ros::WallTime received = ros::WallTime::now();
    std::lock_guard<std::mutex> lock(mutex_);
    input_->received(msg->header.stamp.toSec());
    ++received_;
    ObstacleDetectorParams tuned;
    if (live_->take(tuned)) detector_->setParams(tuned);

    Eigen::Affine3f to_target;
    const std::string frame = lookupTransform(msg->header, to_target);
    // The fast detector reads the message in its own first pass (forEachXYZ); the classic one
    // gets a decoded cloud. The layout checks are the same either way.
    const RawCloud raw = toRawCloud(*msg);
    DecodePlan plan;
    DecodeStats stats;
    const DecodeError error = planDecode(raw, static_cast<std::size_t>(max_points_), plan);
    if (error != DecodeError::kNone) {
      ++invalid_[error];
      input_->invalid();
      NODELET_ERROR_THROTTLE(1.0, "dropping cloud (frame '%s', %ux%u, %zu bytes): %s",
                             msg->header.frame_id.c_str(), msg->width, msg->height,
                             msg->data.size(), toString(error));
      return;  // not valid input: the light controller's watchdog sees the gap
    }

    // Zero, repeated, backwards or jumping stamps are no valid input (dt = 0 hides every speed);
    // a blind sensor (too few valid returns) is flagged in the output: both light the lamp.
    if (!checks_.stampValid(msg->header.stamp, *input_)) return;
    const std::size_t valid_points = checks_.checkHealth(raw, plan);

    if (!last_frame_.empty() && frame != last_frame_) {
      ++frame_changes_;
      NODELET_WARN("output frame changed from '%s' to '%s': tracker reset", last_frame_.c_str(),
                   frame.c_str());
      detector_->reset();
    }
    last_frame_ = frame;

    const double stamp_s = msg->header.stamp.toSec();
    const EgoStep ego = egoStep(msg->header.stamp, frame);
    detector_->setFrameMotion(ego.motion, ego.status != EgoStep::Status::kNone &&
                                              ego.status != EgoStep::Status::kLost);
    detector_->setCollectMovingPoints(moving_pub_.getNumSubscribers() > 0);

    StageTimes times;
    detector_->setSensorOrigin(to_target.translation());  // the cloud frame's origin
    MultiObjectTracker::UpdateResult result;
    if (detector_->fast()) {
      result = detector_->processFrom(
          stamp_s, [&](auto&& sink) { stats = forEachXYZ(raw, plan, to_target, sink); }, &times);
    } else {
      decodeXYZ(raw, to_target, static_cast<std::size_t>(max_points_), cloud_, &stats);
      result = detector_->process(stamp_s, cloud_, &times);
      checkGround(frame);
    }
    dropped_points_ += stats.dropped_nonfinite + stats.dropped_zero;
    if (result == MultiObjectTracker::UpdateResult::kResetTimeBackwards) {
      ++time_resets_;
      NODELET_WARN_THROTTLE(1.0, "cloud stamp went backwards (bag loop?): tracker reset");
    } else if (result == MultiObjectTracker::UpdateResult::kResetGap) {
      ++gap_resets_;
      NODELET_WARN_THROTTLE(1.0, "gap between clouds above tracker/max_dt_s: tracker reset");
    }

    auto out = boost::make_shared<ObstacleArray>();
    out->header.stamp = msg->header.stamp;
    out->header.frame_id = frame;
    out->cloud_receive_time.fromNSec(received.toNSec());
    out->ego_motion_source = toString(ego_.params().source);
    out->ego_motion_status = toString(ego.status);
    out->ego_twist = toTwistMsg(ego);
    out->sensor_blind = checks_.blind();
    out->valid_points = static_cast<std::uint32_t>(valid_points);
    for (const Track& track : detector_->tracks()) {
      if (!track.confirmed) continue;
      out->obstacles.emplace_back();
      toObstacleMsg(track, ego, out->obstacles.back());
    }
    out->processing_ms = static_cast<float>((ros::WallTime::now() - received).toSec() * 1e3);
    last_times_ = times;
    last_obstacles_ = out->obstacles.size();
    last_processing_ms_ = out->processing_ms;
    input_->processed(out->processing_ms);
    ++published_;
    pub_.publish(ObstacleArray::ConstPtr(out));
    publishPoints(msg->header, to_target);
  }

  // ~ground_points, ~obstacle_points and ~moving_points (returns in free space; rviz tuning),
  // in the cloud's own frame with its stamp,
  // built only while someone subscribes, checked per cloud.
  void publishPoints(const std_msgs::Header& header, const Eigen::Affine3f& to_target) {
    const bool ground = ground_pub_.getNumSubscribers() > 0;
    const bool obstacles = obstacle_pub_.getNumSubscribers() > 0;
    const bool moving = moving_pub_.getNumSubscribers() > 0;
    if (!ground && !obstacles && !moving) return;
    if (ground || obstacles) detector_->splitPoints(ground_cloud_, obstacle_cloud_);
    ++debug_frames_;
    const Eigen::Affine3f to_cloud = to_target.inverse();
    const auto send = [&](ros::Publisher& pub, const Cloud& points) {
      pcl::transformPointCloud(points, debug_cloud_, to_cloud);
      auto out = boost::make_shared<sensor_msgs::PointCloud2>();
      pcl::toROSMsg(debug_cloud_, *out);
      out->header = header;
      pub.publish(sensor_msgs::PointCloud2::ConstPtr(out));
    };
    if (ground) send(ground_pub_, ground_cloud_);
    if (obstacles) send(obstacle_pub_, obstacle_cloud_);
    if (moving) send(moving_pub_, detector_->movingPoints());
  }

  // A wrong ground plane is never silent: a plane rejected as the road (its height, or points
  // below it), and a frame without any plausible road (every point kept: nothing is deleted as
  // ground), are counted and warned about once per second at most.
  void checkGround(const std::string& frame) {
    const GroundResult& ground = detector_->ground();
    const GroundParams& params = detector_->params().ground;
    if (ground.status == GroundStatus::kNoPlane) {
      ++ground_absent_;
      NODELET_WARN_THROTTLE(1.0, "no ground plane within %.1f deg of horizontal in %s: every point "
                            "kept as obstacle", params.max_slope_deg, frame.c_str());
      return;
    }
    if (ground.rejection == GroundRejection::kNone) return;
    last_rejected_height_m_ = ground.rejected_height_m;
    char what[160];
    if (ground.status == GroundStatus::kFoundOnRetry) {
      ++ground_retried_;
      std::snprintf(what, sizeof(what), "road found on retry at %.2f m", ground.height_m);
    } else {
      ++ground_rejected_;
      std::snprintf(what, sizeof(what), "no plausible road near %.2f m either (%s), every point "
                    "kept as obstacle", params.expected_height_m,
                    ground.retry_rejection == GroundRejection::kNone ? "no plane there"
                                                                     : toString(ground.retry_rejection));
    }
    NODELET_WARN_THROTTLE(1.0, "ground plane at %.2f m in %s rejected, %s (road expected at %.2f "
                          "+- %.2f m; %zu points on it, %zu under it): %s",
                          ground.rejected_height_m, frame.c_str(), toString(ground.rejection),
                          params.expected_height_m, params.max_height_error_m,
                          ground.rejected_inliers, ground.rejected_points_below, what);
  }

  // The vehicle's motion since the previous cloud, from the configured source at this stamp. A
  // missing pose is extrapolated from the last twist for a while, then the motion is dropped and
  // the tracks restart (their velocities would mix frames); a jump re-bases. Counted and warned.
  EgoStep egoStep(const ros::Time& stamp, const std::string& frame) {
    if (ego_.params().source == EgoMotionSource::kNone) return EgoStep();
    Eigen::Isometry3d pose;
    std::string why;
    const double wait_s = ros::Time::isSimTime() ? ego_.params().replay_max_wait_s
                                                 : ego_.params().max_wait_s;
    const bool found = frame == target_frame_ && ego_source_->lookup(stamp, frame, wait_s, pose, why);
    if (!found && why.empty()) why = "boxes are not in the vehicle frame " + target_frame_;
    const EgoStep step = ego_.update(stamp.toSec(), found ? &pose : nullptr);
    ++ego_counts_[step.status];
    switch (step.status) {
      case EgoStep::Status::kExtrapolated:
        NODELET_WARN_THROTTLE(1.0, "no pose of %s in %s at %.3f (%s): ego motion extrapolated",
                              frame.c_str(), fixed_frame_.c_str(), stamp.toSec(), why.c_str());
        break;
      case EgoStep::Status::kJump:
        NODELET_WARN_THROTTLE(1.0, "the pose of %s in %s jumped at %.3f (odometry reset?): "
                              "re-based on it", frame.c_str(), fixed_frame_.c_str(), stamp.toSec());
        break;
      case EgoStep::Status::kLost:
        NODELET_ERROR_THROTTLE(1.0, "no pose of %s in %s for more than %.2f s (%s): velocities are "
                               "relative to the vehicle until it comes back", frame.c_str(),
                               fixed_frame_.c_str(), ego_.params().max_extrapolation_s, why.c_str());
        break;
      case EgoStep::Status::kNone:
        NODELET_WARN_THROTTLE(5.0, "no pose of %s in %s yet (%s): velocities relative to the "
                              "vehicle", frame.c_str(), fixed_frame_.c_str(), why.c_str());
        break;
      case EgoStep::Status::kFirst:
      case EgoStep::Status::kMeasured: break;
    }
    // Tracks whose velocities were relative (no pose) must not continue over ground, nor the
    // other way round.
    const bool over_ground = step.status != EgoStep::Status::kNone &&
                             step.status != EgoStep::Status::kLost;
    if (ego_frames_ > 0 && over_ground != ego_over_ground_) {  // the first frame starts, not restarts
      if (detector_) detector_->reset();
      ++ego_restarts_;
    }
    ego_over_ground_ = over_ground;
    ++ego_frames_;
    return step;
  }

  void diagnose(diagnostic_updater::DiagnosticStatusWrapper& stat) {
    std::lock_guard<std::mutex> lock(mutex_);
    std::uint64_t invalid = 0;
    for (const auto& kv : invalid_) {
      invalid += kv.second;
      stat.add(std::string("invalid clouds: ") + toString(kv.first), kv.second);
    }
    const std::uint64_t ego_faults = ego_counts_[EgoStep::Status::kExtrapolated] +
                                     ego_counts_[EgoStep::Status::kJump] +
                                     ego_counts_[EgoStep::Status::kLost];
    const std::uint64_t ground_faults = ground_retried_ + ground_rejected_ + ground_absent_;
    if (invalid > reported_invalid_)
      stat.summary(diagnostic_msgs::DiagnosticStatus::WARN, "invalid clouds dropped");
    else if (tf_failures_ > reported_tf_failures_)
      stat.summary(diagnostic_msgs::DiagnosticStatus::WARN, "transform to target frame missing");
    else if (ego_faults > reported_ego_faults_)
      stat.summary(diagnostic_msgs::DiagnosticStatus::WARN, "ego motion extrapolated, jumped or lost");
    else if (ground_faults > reported_ground_faults_)
      stat.summary(diagnostic_msgs::DiagnosticStatus::WARN, "ground plane rejected or absent");
    else
      stat.summary(diagnostic_msgs::DiagnosticStatus::OK, "ok");
    reported_invalid_ = invalid;
    reported_tf_failures_ = tf_failures_;
    reported_ego_faults_ = ego_faults;
    reported_ground_faults_ = ground_faults;
    stat.add("ego motion source", toString(ego_.params().source));
    for (const auto& kv : ego_counts_)
      stat.add(std::string("ego motion frames: ") + toString(kv.first), kv.second);
    stat.add("ego motion restarts of the tracks", ego_restarts_);
    stat.add("clouds received", received_);
    stat.add("obstacle arrays published", published_);
    stat.add("invalid clouds", invalid);
    stat.add("points dropped (NaN/Inf/zero)", dropped_points_);
    stat.add("transform failures", tf_failures_);
    stat.add("tracker resets: time backwards", time_resets_);
    stat.add("tracker resets: gap", gap_resets_);
    stat.add("output frame changes", frame_changes_);
    stat.add("ground planes rejected, road found on retry", ground_retried_);
    stat.add("ground planes rejected, every point kept", ground_rejected_);
    stat.add("frames without a ground plane, every point kept", ground_absent_);
    stat.add("last rejected ground plane height m", last_rejected_height_m_);
    stat.add("obstacles (last frame)", last_obstacles_);
    stat.add("frames with ground/obstacle points published", debug_frames_);
    stat.add("processing ms (last frame)", last_processing_ms_);
    stat.add("prep ms", last_times_.prep_ms);
    stat.add("ground ms", last_times_.ground_ms);
    stat.add("cluster ms", last_times_.cluster_ms);
    stat.add("motion ms", last_times_.motion_ms);
    stat.add("track ms", last_times_.track_ms);
    live_->addTo(stat);
    checks_.addTo(stat);
  }

  std::unique_ptr<ObstacleDetector> detector_;
  std::unique_ptr<tf2_ros::Buffer> tf_buffer_;
  std::unique_ptr<tf2_ros::TransformListener> tf_listener_;
  std::unique_ptr<EgoPoseSource> ego_source_;
  static constexpr double kMountStartupWaitS = 2.0;
  bool mount_seen_ = false;                       // a sensor -> target transform was found
  double mount_wait_left_s_ = kMountStartupWaitS;  // start-up wait budget left [s]
  EgoMotion ego_;
  std::string fixed_frame_ = "odom";
  std::map<EgoStep::Status, std::uint64_t> ego_counts_;
  std::uint64_t ego_restarts_ = 0, reported_ego_faults_ = 0;
  bool ego_over_ground_ = false;
  std::uint64_t ego_frames_ = 0;  // frames through egoStep
  std::unique_ptr<Diagnostics> diagnostics_;
  std::unique_ptr<InputMonitor> input_;
  std::unique_ptr<LiveParams<ObstacleDetectorConfig, ObstacleDetectorParams>> live_;
  ZeroCopyPublisher pub_;
  ros::Publisher ground_pub_, obstacle_pub_, moving_pub_;
  Cloud ground_cloud_, obstacle_cloud_, debug_cloud_;  // reused by publishPoints
  std::uint64_t debug_frames_ = 0;
  ros::Subscriber sub_;

  std::string target_frame_ = "base_link";
  int max_points_ = 2000000;
  double expected_rate_hz_ = 10.0;
  bool trace_unused_ = false;

  std::mutex mutex_;  // the cloud callback and the diagnostics timer
  Cloud cloud_;
  std::string last_frame_;
  std::map<DecodeError, std::uint64_t> invalid_;
  std::uint64_t received_ = 0, published_ = 0, dropped_points_ = 0, tf_failures_ = 0;
  std::uint64_t time_resets_ = 0, gap_resets_ = 0, frame_changes_ = 0;
  std::uint64_t ground_retried_ = 0, ground_rejected_ = 0, ground_absent_ = 0;
  std::uint64_t reported_ground_faults_ = 0;
  float last_rejected_height_m_ = std::numeric_limits<float>::quiet_NaN();
  CloudInputChecks checks_;
  std::uint64_t reported_invalid_ = 0, reported_tf_failures_ = 0;
  std::size_t last_obstacles_ = 0;
  double last_processing_ms_ = 0.0;
  StageTimes last_times_;
};

}  // namespace icanc

PLUGINLIB_EXPORT_CLASS(icanc::ObstacleDetectorNodelet, nodelet::Nodelet)
