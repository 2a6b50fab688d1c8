// icanc/LightController: the paper's timer state machine (icanc/light_controller.hpp) over the
// DangerDetector's output, with the segmented lamp, both fed by icanc/lamp_control.hpp. Publishes
// icanc/LightState and std_msgs/Bool on every change and at a steady rate, and the lamp as rviz
// markers on `markers` while someone listens (icanc/lamp_publisher.hpp). Time is ROS time (sim
// time during replay).
// Beside it, the segmented lamp (icanc/segmented_light_controller.hpp): the dangerous
// boxes of the same ObstacleArray light the segments that see them; icanc/LampCommand on
// `lamp_command`, wedges on `~lamp_segments` while someone listens. `lamp_cmd` stays the paper's
// binary lamp (with the default one-segment lamp it is exactly "any segment on").
#include <memory>
#include <mutex>
#include <vector>

#include <nodelet/nodelet.h>
#include <pluginlib/class_list_macros.hpp>

#include "icanc/IlluminationState.h"
#include "icanc/LightControllerConfig.h"
#include "icanc/ObstacleArray.h"
#include "icanc/core/light/lamp_control.hpp"
#include "icanc/ros/conversions.hpp"
#include "icanc/ros/lamp_publisher.hpp"
#include "icanc/ros/live_params.hpp"
#include "icanc/ros/nodelet_settings.hpp"
#include "icanc/ros/nodelet_support.hpp"

namespace icanc {

// The earliest a rearmed timer fires after now (s).
constexpr double kSoonestRearmS = 1e-4;

class LightControllerNodelet : public nodelet::Nodelet {
 private:
  void onInit() override {
    ros::NodeHandle& nh = getNodeHandle();
    ros::NodeHandle& pnh = getPrivateNodeHandle();
    ParamReader reader(pnh);
    LightControllerSettings settings;
    const std::string why = loadSettings(reader, settings);
    const LightControllerParams& params = settings.params;
    fault_levels_ = faultLevels(settings.lamp);
    publish_rate_hz_ = settings.publish_rate_hz;
    if (!checkParams(getName(), reader, why)) {
      startFault(reader.error().empty() ? why : reader.error());
      return;
    }
    control_.reset(new LampControl(params, settings.lamp));

    // Before the diagnostics: their 1 Hz timer may call diagnose() (which reads live_) while
    // onInit is still running on a loaded machine.
    live_.reset(new LiveParams<LightControllerConfig, LightControllerParams>(pnh, params, getName()));
    diagnostics_.reset(new Diagnostics(nh, pnh, getName(), "headlight"));
    diagnostics_->updater().add("light controller", [this](diagnostic_updater::DiagnosticStatusWrapper& stat) {
      std::lock_guard<std::mutex> lock(mutex_);
      report(stat, control_->report());
      live_->addTo(stat);
    });
    lamp_.advertise(nh, pnh, true, settings.marker_style);
    sub_ = nh.subscribe("obstacles_danger", 5, &LightControllerNodelet::onDanger, this);
    input_.reset(new InputMonitor(diagnostics_->updater(), sub_.getTopic(), settings.expected_rate_hz));
    // No fixed tick: one timer whose next expiry rearm moves to the lamp's next event or the next
    // steady publication, whichever comes first, so the manager wakes only when there is work.
    // Periodic, not one-shot: roscpp parks a one-shot timer for ever after its callback, which
    // would undo a rearm made inside it; the period left behind is only a fallback.
    timer_ = nh.createTimer(ros::Duration(1.0 / publish_rate_hz_), &LightControllerNodelet::onTimer, this);
    if (params.illumination_enabled) {  // camera illumination gate (IlluminationMonitor)
      illumination_sub_ = nh.subscribe("illumination", 5, &LightControllerNodelet::onIllumination, this);
      NODELET_INFO("LightController: illumination gate on %s (no danger lamp in daylight)",
                   illumination_sub_.getTopic().c_str());
    }
    NODELET_INFO("LightController: tau %.2f s, recheck below %.2f s, watchdog %.2f s, %zu lamp "
                 "segment(s)", params.tau_s, params.recheck_below_s, params.stale_timeout_s,
                 control_->segmented().segments().size());
    if (!params.watchdog_enabled)
      NODELET_WARN("LightController: watchdog_enabled is false: no fail-safe lamp when the input "
                   "stops (offline use only)");
  }

  // Invalid parameters: no state machine, but the lamp side still hears from the controller.
  // Lamp ON (REASON_FAULT) at publish_rate_hz and an ERROR in diagnostics naming the problem,
  // so a typo in a profile is a lit lamp and a message, not a silent graph.
  void startFault(const std::string& why) {
    ros::NodeHandle& nh = getNodeHandle();
    ros::NodeHandle& pnh = getPrivateNodeHandle();
    fault_ = why;
    diagnostics_.reset(new Diagnostics(nh, pnh, getName(), "headlight"));
    diagnostics_->updater().add("light controller", [this](diagnostic_updater::DiagnosticStatusWrapper& stat) {
      report(stat, faultReport(fault_));
    });
    lamp_.advertise(nh, pnh, false);
    timer_ = nh.createTimer(ros::Duration(1.0 / faultPublishRate(publish_rate_hz_)), [this](const ros::TimerEvent&) {
      std::lock_guard<std::mutex> lock(mutex_);
      publish(ros::Time::now(), false);
    });
    NODELET_ERROR("LightController cannot start (%s): publishing lamp ON (reason fault)", why.c_str());
  }

  void onDanger(const ObstacleArray::ConstPtr& msg) {
    const ros::WallTime received = ros::WallTime::now();
    input_->received(msg->header.stamp.toSec());
    std::lock_guard<std::mutex> lock(mutex_);
    applyTunedParams();
    const ros::Time now = ros::Time::now();
    dangerousBoxes(*msg, boxes_);
    const LampControl::InputResult result =
        control_->onInput(now.toSec(), msg->num_dangerous, msg->sensor_blind, boxes_);
    lamp_.onInput(*msg, result.triggered);
    if (result.unlocated)
      NODELET_ERROR_THROTTLE(5.0, "num_dangerous %u but %zu obstacles flagged dangerous: every lamp "
                             "segment on", msg->num_dangerous, boxes_.size());
    // Every input is answered (replay tools wait for it); changes are among them.
    publish(now, true);
    rearm(now);
    input_->processed((ros::WallTime::now() - received).toSec() * 1e3);
  }

  void onIllumination(const IlluminationState::ConstPtr& msg) {
    std::lock_guard<std::mutex> lock(mutex_);
    const ros::Time now = ros::Time::now();
    bool invalid = false;
    const bool changed = control_->onIllumination(now.toSec(), msg->state, invalid);
    if (invalid) NODELET_ERROR_THROTTLE(5.0, "illumination state %u is invalid: treated as unknown", msg->state);
    if (changed) publish(now, false);
    rearm(now);
  }

  void onTimer(const ros::TimerEvent&) {
    std::lock_guard<std::mutex> lock(mutex_);
    armed_at_ = ros::Time();  // it fired: rearm below whatever the instant
    applyTunedParams();
    const ros::Time now = ros::Time::now();
    bool stale_event = false;
    const bool changed = control_->tick(now.toSec(), stale_event);
    if (stale_event)
      NODELET_WARN("no input on %s for %.2f s: lamp ON (fail-safe)", sub_.getTopic().c_str(),
                   control_->binary().params().stale_timeout_s);
    if (changed || steadyPublicationDue(now) <= now) publish(now, false);
    rearm(now);
  }

  // When the steady publication is next due: publish_rate_hz after the last one (at once when
  // time went backwards, a bag loop). ROS durations, not differences of seconds: a replay's
  // publications fall on the same instants.
  ros::Time steadyPublicationDue(const ros::Time& now) const {
    const ros::Time last = lamp_.lastPublished();
    return now < last ? now : last + ros::Duration(1.0 / publish_rate_hz_);
  }

  // With mutex_ held: timer_ at the earlier of the lamp's next event and the next steady
  // publication; touched only when that instant moved.
  void rearm(const ros::Time& now) {
    ros::Time at = steadyPublicationDue(now);
    const double event = control_->nextEvent();
    if (event < at.toSec()) at.fromSec(event);
    // Never a zero period: a periodic timer would then fire without pause.
    const ros::Time soonest = now + ros::Duration(kSoonestRearmS);
    if (at < soonest) at = soonest;
    if (at == armed_at_) return;
    armed_at_ = at;
    timer_.setPeriod(at - now, true);
  }

  // With mutex_ held: a dynamic_reconfigure change, from this input or timer on.
  void applyTunedParams() {
    LightControllerParams tuned;
    if (live_->take(tuned)) control_->setParams(tuned);
  }

  // The lamp on every topic: the controller's, or every segment ON (REASON_FAULT) on the fault
  // path (no controller). With mutex_ held.
  void publish(const ros::Time& now, bool answers_input) {
    lamp_.publish(now, control_.get(), fault_levels_, answers_input);
  }

  std::unique_ptr<LampControl> control_;
  std::vector<Eigen::AlignedBox2d> boxes_;  // the input's dangerous boxes (reused)
  std::vector<float> fault_levels_;         // levels published by the fault path
  std::unique_ptr<Diagnostics> diagnostics_;
  std::unique_ptr<InputMonitor> input_;
  LampPublisher lamp_;  // the lamp's topics and what their messages carry besides the lamp
  std::unique_ptr<LiveParams<LightControllerConfig, LightControllerParams>> live_;
  ros::Subscriber sub_;
  ros::Subscriber illumination_sub_;
  ros::Timer timer_;       // moved by rearm (a plain publication timer on the fault path)
  ros::Time armed_at_;     // when timer_ fires next
  double publish_rate_hz_ = 10.0;

  std::mutex mutex_;  // subscriber, timer and diagnostics callbacks
  std::string fault_;  // why the controller could not start ("" when it runs)
};

}  // namespace icanc

PLUGINLIB_EXPORT_CLASS(icanc::LightControllerNodelet, nodelet::Nodelet)
