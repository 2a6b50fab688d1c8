// icanc/DangerDetector: marks each obstacle with the danger model of ~model (icanc/danger.hpp:
// "paper" = Listing 1, "predictive" = corridor prediction with per-track hysteresis) and
// republishes the array with num_dangerous, and rviz markers (boxes, labels, velocity, sections)
// on `markers` while someone listens. Glue only.
//
//   ~vehicle_frame (string, "base_link")  the frame the rules are written in (x forward, y left,
//       origin on the vehicle). An array in any other frame (the ObstacleDetector could not
//       transform, a misconfigured target_frame) is refused: counted, a throttled ERROR,
//       diagnostics ERROR, and nothing is published for it, so the LightController's watchdog
//       lights the lamp rather than judging sensor-frame boxes by vehicle-frame rules.
//   ~predictive/path_topic (string, "")  the planner's path (nav_msgs/Path, any frame tf brings
//       into vehicle_frame): the predictive model predicts the vehicle along it instead of along
//       the constant turn of its twist ("" = no planner). ~predictive/path_max_age_s (1.0) and
//       ~predictive/path_max_offset_m (2.0): a path farther in time from the obstacles, or one the
//       vehicle is farther from, is not used (counted; the twist then, as without a planner).
#include <memory>
#include <mutex>

#include <boost/make_shared.hpp>
#include <nodelet/nodelet.h>
#include <pluginlib/class_list_macros.hpp>

#include "icanc/DangerDetectorConfig.h"
#include "icanc/ObstacleArray.h"
#include "icanc/core/danger/danger.hpp"
#include "icanc/ros/conversions.hpp"
#include "icanc/ros/live_params.hpp"
#include "icanc/ros/markers.hpp"
#include "icanc/ros/nodelet_support.hpp"
#include "icanc/ros/planned_path_source.hpp"
#include "icanc/ros/zero_copy.hpp"

namespace icanc {

class DangerDetectorNodelet : public nodelet::Nodelet {
 private:
  void onInit() override {
    ros::NodeHandle& nh = getNodeHandle();
    ros::NodeHandle& pnh = getPrivateNodeHandle();
    ParamReader reader(pnh);
    readParams(reader, params_);
    bool trace = false;
    reader.read("trace_publications", trace);  // read by ZeroCopyPublisher
    const std::string rate_problem = readExpectedRate(reader, expected_rate_hz_);
    reader.read("marker_lifetime_s", marker_style_.lifetime_s);
    reader.read("marker_section_length_m", marker_style_.section_length_m);
    reader.read("vehicle_frame", vehicle_frame_);
    PlannedPathSource::Params path_params;
    reader.read("predictive/path_topic", path_params.topic);
    reader.read("predictive/path_max_age_s", path_params.max_age_s);
    reader.read("predictive/path_max_offset_m", path_params.max_offset_m);
    std::string why = validate(params_);
    if (why.empty()) why = PlannedPathSource::validate(path_params);
    if (why.empty() && bareFrame(vehicle_frame_).empty())
      why = "vehicle_frame must name the frame the obstacles come in (e.g. base_link)";
    acceptReconfigureKeys<DangerDetectorConfig>(reader);
    if (!checkParams(getName(), reader, why.empty() ? rate_problem : why)) return;
    hysteresis_.reset(new DangerHysteresis(params_));
    planned_path_.reset(new PlannedPathSource(nh, path_params, getName()));

    // Before the diagnostics: their 1 Hz timer may call diagnose() (which reads live_) while
    // onInit is still running on a loaded machine.
    live_.reset(new LiveParams<DangerDetectorConfig, DangerParams>(pnh, params_, getName()));
    diagnostics_.reset(new Diagnostics(nh, pnh, getName(), "danger"));
    diagnostics_->updater().add("danger detector", this, &DangerDetectorNodelet::diagnose);
    pub_.advertise<ObstacleArray>(nh, pnh, "obstacles_danger", 5);
    marker_pub_ = nh.advertise<visualization_msgs::MarkerArray>("markers", 5);
    sub_ = nh.subscribe("obstacles", 5, &DangerDetectorNodelet::onObstacles, this);
    input_.reset(new InputMonitor(diagnostics_->updater(), sub_.getTopic(), expected_rate_hz_));
    NODELET_INFO("DangerDetector: model %s, half_width %.2f m, reaction_time %.2f s, frame %s, "
                 "planned path %s",
                 toString(params_.model), params_.half_width_m, params_.reaction_time_s,
                 vehicle_frame_.c_str(), path_params.topic.empty() ? "none" : path_params.topic.c_str());
  }

  // An array not in the vehicle frame: nothing is published (the watchdog lights the lamp).
  bool refuseFrame(const ObstacleArray& msg) {
    if (bareFrame(msg.header.frame_id) == bareFrame(vehicle_frame_)) {
      std::lock_guard<std::mutex> lock(mutex_);
      last_refused_ = false;
      return false;
    }
    {
      std::lock_guard<std::mutex> lock(mutex_);
      ++wrong_frame_;
      last_refused_ = true;
      refused_since_report_ = true;
      last_wrong_frame_ = msg.header.frame_id;
    }
    NODELET_ERROR_THROTTLE(5.0, "obstacles in frame '%s', expected vehicle_frame '%s': array "
                           "refused, nothing published (the lamp's watchdog turns it ON); check "
                           "the ObstacleDetector's target_frame and tf",
                           msg.header.frame_id.c_str(), vehicle_frame_.c_str());
    return true;
  }

  void onObstacles(const ObstacleArray::ConstPtr& msg) {
    const ros::WallTime received = ros::WallTime::now();
    input_->received(msg->header.stamp.toSec());
    if (refuseFrame(*msg)) {
      input_->processed((ros::WallTime::now() - received).toSec() * 1e3);
      return;
    }
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (live_->take(params_)) hysteresis_->setParams(params_);
    }
    auto out = boost::make_shared<ObstacleArray>(*msg);
    std::uint32_t dangerous = 0;
    const bool predictive = params_.model == DangerModel::kPredictive;
    const double now = msg->header.stamp.toSec();
    // The planner's path, looked up only when the model follows it (moving forward).
    const bool follows = alongPlannedPath(Eigen::Vector2d(msg->ego_twist.linear.x, msg->ego_twist.linear.y));
    const std::shared_ptr<const EgoPath> path =
        predictive && follows && !out->obstacles.empty() ? planned_path_->at(msg->header.stamp, vehicle_frame_)
                                                         : nullptr;
    for (Obstacle& o : out->obstacles) {
      ObjectKinematics k = toKinematics(o, msg->ego_twist);
      k.ego_path = path;
      const DangerAssessment a = assessDanger(k, params_);
      o.section = static_cast<std::uint8_t>(a.section);
      o.closest_distance = static_cast<float>(a.distance_m);
      o.moving_toward = a.moving_toward;
      // The paper's rule is per frame, as published; the predictive model is smoothed per track.
      o.dangerous = predictive ? hysteresis_->update(o.id, a, now) : a.dangerous;
      dangerous += o.dangerous;
    }
    out->num_dangerous = dangerous;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      ++messages_;
      dangerous_total_ += dangerous;
      last_dangerous_ = dangerous;
      last_obstacles_ = out->obstacles.size();
    }
    pub_.publish(ObstacleArray::ConstPtr(out));
    if (marker_pub_.getNumSubscribers() > 0) marker_pub_.publish(dangerMarkers(*out, params_, marker_style_));
    input_->processed((ros::WallTime::now() - received).toSec() * 1e3);
  }

  void diagnose(diagnostic_updater::DiagnosticStatusWrapper& stat) {
    std::lock_guard<std::mutex> lock(mutex_);
    // ERROR at least once per refusal, even when good arrays follow before the next report.
    if (last_refused_ || refused_since_report_)
      stat.summary(diagnostic_msgs::DiagnosticStatus::ERROR,
                   "obstacles in frame '" + last_wrong_frame_ + "', not " + vehicle_frame_ +
                       ": refused");
    else
      stat.summary(diagnostic_msgs::DiagnosticStatus::OK, "ok");
    refused_since_report_ = false;
    stat.add("vehicle_frame", vehicle_frame_);
    stat.add("arrays refused: wrong frame", wrong_frame_);
    stat.add("last wrong frame", last_wrong_frame_);
    stat.add("arrays processed", messages_);
    stat.add("dangerous object-frames", dangerous_total_);
    stat.add("obstacles (last array)", last_obstacles_);
    stat.add("dangerous (last array)", last_dangerous_);
    stat.add("model", toString(params_.model));
    stat.add("half_width_m", params_.half_width_m);
    stat.add("reaction_time_s", params_.reaction_time_s);
    planned_path_->addTo(stat);
    live_->addTo(stat);
  }

  DangerParams params_;
  std::unique_ptr<DangerHysteresis> hysteresis_;
  std::unique_ptr<PlannedPathSource> planned_path_;
  std::unique_ptr<Diagnostics> diagnostics_;
  std::unique_ptr<InputMonitor> input_;
  double expected_rate_hz_ = 10.0;
  std::unique_ptr<LiveParams<DangerDetectorConfig, DangerParams>> live_;
  MarkerStyle marker_style_;
  ZeroCopyPublisher pub_;
  ros::Publisher marker_pub_;
  ros::Subscriber sub_;
  std::mutex mutex_;
  std::string vehicle_frame_ = "base_link";
  std::uint64_t messages_ = 0, dangerous_total_ = 0, wrong_frame_ = 0;
  bool last_refused_ = false;  // the last array was in the wrong frame: diagnostics ERROR
  bool refused_since_report_ = false;
  std::string last_wrong_frame_;
  std::size_t last_obstacles_ = 0, last_dangerous_ = 0;
};

}  // namespace icanc

PLUGINLIB_EXPORT_CLASS(icanc::DangerDetectorNodelet, nodelet::Nodelet)
