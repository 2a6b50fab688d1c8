// icanc/ObstacleDetector: PointCloud2 in, icanc/ObstacleArray out. Glue only: parameters, the
// layout and stamp checks on arrival, the wait for the cloud's transforms (CloudTransformQueue:
// the callback never blocks), logs, diagnostics and publishing; each frame's work is
// icanc::DetectorPipeline's.
#include <memory>
#include <mutex>

#include <boost/make_shared.hpp>
#include <nodelet/nodelet.h>
#include <pcl/common/transforms.h>
#include <pcl_conversions/pcl_conversions.h>
#include <pluginlib/class_list_macros.hpp>
#include <sensor_msgs/PointCloud2.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>

#include "icanc/ObstacleArray.h"
#include "icanc/ObstacleDetectorConfig.h"
#include "icanc/core/perception/detector_pipeline.hpp"
#include "icanc/ros/cloud_input_checks.hpp"
#include "icanc/ros/cloud_transform_queue.hpp"
#include "icanc/ros/conversions.hpp"
#include "icanc/ros/detector_status.hpp"
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
    int max_points = 2000000;
    double expected_rate_hz = 10.0;
    bool trace_unused = false;
    reader.read("target_frame", target_frame_);
    reader.read("max_points", max_points);
    const std::string rate_problem = readExpectedRate(reader, expected_rate_hz);
    reader.read("trace_publications", trace_unused);  // read by ZeroCopyPublisher
    std::string why = validate(params);
    if (why.empty() && max_points <= 0) why = "max_points must be > 0";
    if (why.empty()) why = rate_problem;
    checks_ = CloudInputChecks(getName());
    const std::string checks_problem = checks_.load(reader);  // stamp_check/*, sensor_health/*
    if (why.empty()) why = checks_problem;
    acceptReconfigureKeys<ObstacleDetectorConfig>(reader);
    if (!checkParams(getName(), reader, why)) return;
    // The vehicle's own motion: the namespace's ego_motion section, shared with LidarOdometry.
    ParamReader ego_reader(ros::NodeHandle(nh, "ego_motion"));
    EgoMotionSection ego_section;
    if (!checkParams(getName(), ego_reader, loadEgoMotion(ego_reader, target_frame_, ego_section))) return;
    const EgoMotionParams& ego = ego_section.params;
    const std::string& fixed_frame = ego_section.fixed_frame;

    status_ = DetectorStatus(getName(), target_frame_, fixed_frame);
    pipeline_.reset(new DetectorPipeline(params, ego, static_cast<std::size_t>(max_points)));
    tf_buffer_.reset(new tf2_ros::Buffer());
    // /tf on this nodelet's own callback queue: no thread polling for it.
    tf_listener_.reset(new tf2_ros::TransformListener(*tf_buffer_, nh, /*spin_thread=*/false));
    ego_source_.reset(new EgoPoseSource(nh, ego.source, fixed_frame, *tf_buffer_));
    // Before the diagnostics: their 1 Hz timer may call diagnose() while onInit still runs.
    live_.reset(new LiveParams<ObstacleDetectorConfig, ObstacleDetectorParams>(pnh, params, getName()));
    diagnostics_.reset(new Diagnostics(nh, pnh, getName(), "lidar"));
    diagnostics_->updater().add("obstacle detector", this, &ObstacleDetectorNodelet::diagnose);
    pub_.advertise<ObstacleArray>(nh, pnh, "obstacles", 5);
    for (int i = 0; i < 3; ++i)
      points_pub_[i] = pnh.advertise<sensor_msgs::PointCloud2>(kPointTopics[i], 2);
    const double wait_s = ros::Time::isSimTime() ? ego.replay_max_wait_s : ego.max_wait_s;
    queue_.reset(new CloudTransformQueue(nh, *tf_buffer_, *ego_source_, target_frame_, wait_s,
        [this](const CloudTransformQueue::Cloud& c, const CloudTransformQueue::Transforms& t) { onReady(c, t); }));
    sub_ = nh.subscribe("points", 2, &ObstacleDetectorNodelet::onCloud, this);
    input_.reset(new InputMonitor(diagnostics_->updater(), sub_.getTopic(), expected_rate_hz));
    NODELET_INFO("ObstacleDetector on %s -> %s (boxes in '%s', ego motion: %s%s%s)",
                 sub_.getTopic().c_str(), nh.resolveName("obstacles").c_str(),
                 target_frame_.empty() ? "<cloud frame>" : target_frame_.c_str(), toString(ego.source),
                 ego.source == EgoMotionSource::kNone ? "" : ", tracks in ",
                 ego.source == EgoMotionSource::kNone ? "" : fixed_frame.c_str());
  }

  // On arrival: counted, the layout and stamp checked (invalid input is dropped: the light
  // controller's watchdog sees the gap), then queued to wait for its transforms. Never blocks.
  void onCloud(const sensor_msgs::PointCloud2::ConstPtr& msg) {
    CloudTransformQueue::Cloud cloud{msg, ros::WallTime::now(), DecodePlan()};
    {
      std::lock_guard<std::mutex> lock(mutex_);
      input_->received(msg->header.stamp.toSec());
      status_.onReceived();
      const DecodeError error = pipeline_->plan(toRawCloud(*msg), cloud.plan);
      if (error != DecodeError::kNone) {
        input_->invalid();
        NODELET_ERROR_THROTTLE(1.0, "dropping cloud (frame '%s', %ux%u, %zu bytes): %s",
                               msg->header.frame_id.c_str(), msg->width, msg->height,
                               msg->data.size(), toString(error));
        return;
      }
      // Zero, repeated, backwards or jumping stamps are no valid input (dt = 0 hides every speed).
      if (!checks_.stampValid(msg->header.stamp, *input_)) return;
    }
    queue_->push(std::move(cloud));
  }

  // A cloud with its transforms, or without those that did not come in time: boxes in the sensor
  // frame (the DangerDetector refuses them, its watchdog lights the lamp), ego motion extrapolated.
  void onReady(const CloudTransformQueue::Cloud& cloud, const CloudTransformQueue::Transforms& t) {
    const sensor_msgs::PointCloud2& msg = *cloud.msg;
    const double stamp_s = msg.header.stamp.toSec();
    std::lock_guard<std::mutex> lock(mutex_);
    ObstacleDetectorParams tuned;
    if (live_->take(tuned)) pipeline_->setParams(tuned);
    const RawCloud raw = toRawCloud(msg);
    DetectorPipelineInput in;
    in.stamp_s = stamp_s;
    in.frame = t.frame;
    in.raw = &raw;
    in.plan = &cloud.plan;
    in.to_frame = t.to_frame;
    in.fixed_T_vehicle = t.has_pose ? &t.pose : nullptr;
    in.collect_moving_points = points_pub_[2].getNumSubscribers() > 0;
    in.returns = &checks_.beginCount();
    const DetectorPipelineResult r = pipeline_->process(in);
    // A blind sensor (too few valid returns) is flagged in the output: it lights the lamp.
    const std::size_t valid_points =
        checks_.checkHealth(static_cast<std::size_t>(raw.width) * raw.height);
    status_.logFrame(*pipeline_, r, t, msg.header.frame_id, stamp_s);

    auto out = boost::make_shared<ObstacleArray>();
    out->header.stamp = msg.header.stamp;
    out->header.frame_id = t.frame;
    out->cloud_receive_time.fromNSec(cloud.received.toNSec());
    out->ego_motion_source = toString(pipeline_->egoParams().source);
    out->ego_motion_status = toString(r.ego.status);
    out->ego_twist = toTwistMsg(r.ego);
    out->sensor_blind = checks_.blind();
    out->valid_points = static_cast<std::uint32_t>(valid_points);
    for (const Track& track : pipeline_->detector().tracks()) {
      if (!track.confirmed) continue;
      out->obstacles.emplace_back();
      toObstacleMsg(track, r.ego, out->obstacles.back());
    }
    out->processing_ms = static_cast<float>((ros::WallTime::now() - cloud.received).toSec() * 1e3);
    status_.onPublished(out->obstacles.size(), out->processing_ms, r.times);
    input_->processed(out->processing_ms);
    pub_.publish(ObstacleArray::ConstPtr(out));
    publishPoints(msg.header, t.to_frame);
  }

  // ~ground_points, ~obstacle_points and ~moving_points (returns in free space; rviz tuning), in
  // the cloud's own frame with its stamp, built only while someone subscribes.
  void publishPoints(const std_msgs::Header& header, const Eigen::Affine3f& to_target) {
    bool wanted[3];
    for (int i = 0; i < 3; ++i) wanted[i] = points_pub_[i].getNumSubscribers() > 0;
    if (!wanted[0] && !wanted[1] && !wanted[2]) return;
    if (wanted[0] || wanted[1]) pipeline_->detector().splitPoints(ground_cloud_, obstacle_cloud_);
    status_.onDebugFrame();
    const Cloud* clouds[3] = {&ground_cloud_, &obstacle_cloud_, &pipeline_->detector().movingPoints()};
    for (int i = 0; i < 3; ++i) {
      if (!wanted[i]) continue;
      pcl::transformPointCloud(*clouds[i], debug_cloud_, to_target.inverse());
      auto out = boost::make_shared<sensor_msgs::PointCloud2>();
      pcl::toROSMsg(debug_cloud_, *out);
      out->header = header;
      points_pub_[i].publish(sensor_msgs::PointCloud2::ConstPtr(out));
    }
  }

  void diagnose(diagnostic_updater::DiagnosticStatusWrapper& stat) {
    const CloudTransformQueue::Stats waits = queue_ ? queue_->stats(true) : CloudTransformQueue::Stats();
    std::lock_guard<std::mutex> lock(mutex_);
    status_.addTo(stat, pipeline_->counters(), pipeline_->egoParams().source, waits);
    live_->addTo(stat);
    checks_.addTo(stat);
  }

  static constexpr const char* kPointTopics[3] = {"ground_points", "obstacle_points", "moving_points"};
  std::string target_frame_ = "base_link";
  std::unique_ptr<DetectorPipeline> pipeline_;
  std::unique_ptr<tf2_ros::Buffer> tf_buffer_;
  std::unique_ptr<tf2_ros::TransformListener> tf_listener_;
  std::unique_ptr<EgoPoseSource> ego_source_;
  std::unique_ptr<Diagnostics> diagnostics_;
  std::unique_ptr<InputMonitor> input_;
  std::unique_ptr<LiveParams<ObstacleDetectorConfig, ObstacleDetectorParams>> live_;
  ZeroCopyPublisher pub_;
  ros::Publisher points_pub_[3];
  Cloud ground_cloud_, obstacle_cloud_, debug_cloud_;  // reused by publishPoints
  std::mutex mutex_;  // arrival checks, the frame's work and the diagnostics timer
  CloudInputChecks checks_;
  DetectorStatus status_;  // logs and the counters of the diagnostics
  ros::Subscriber sub_;
  std::unique_ptr<CloudTransformQueue> queue_;  // last: gone, and its callbacks done, first
};

}  // namespace icanc

PLUGINLIB_EXPORT_CLASS(icanc::ObstacleDetectorNodelet, nodelet::Nodelet)
