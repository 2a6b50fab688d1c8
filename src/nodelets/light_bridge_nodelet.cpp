// icanc/LightBridge: the lamp command (lamp_cmd, std_msgs/Bool) to a rosserial (ros_lib) device on
// a serial port, and the lamp state the device reports back (lamp_state, std_msgs/Bool). The
// protocol and the link's state machine are the core's (icanc/rosserial_session.hpp), and so are
// what is logged, republished and reported (icanc/light_bridge_host.hpp) and the port's handling
// (icanc/light_bridge_link.hpp); this nodelet only runs them: one thread owns the port (open,
// reopen after an unplug, read, tick), lamp_cmd callbacks write their frame at once. Wall (steady)
// time drives the link; ROS time answers the device's time requests.
//
//   ~port (string, required)        serial device, e.g. /dev/ttyACM0 or a /dev/serial/by-id link
//   ~baud (int, 57600)              9600 ... 921600 (the sketch uses 57600; 115200 supported)
//   ~device_cmd_topic, ~device_state_topic, ~heartbeat_hz, ~link_timeout_s, ~negotiation_retry_s,
//   ~cmd_stale_timeout_s, ~lamp_report_timeout_s, ~frame_timeout_s, ~max_payload_bytes
//                                   see LightBridgeParams
//   ~reconnect_period_s (1.0)       reopening attempts while the port is missing [s]
//   ~device_levels_topic ("")       a segmented lamp: lamp_command (icanc/LampCommand)
//       levels, as 0..255, to the device's std_msgs/UInt8MultiArray subscriber of this name
//   ~link_up (std_msgs/Bool, latched)  true while the device is synced (false on a type mismatch)
//   lamp_status (icanc/LampState, latched)  stamped: ON / OFF as reported, UNKNOWN_FAILSAFE while
//       the link is down or the device's reports are overdue (lamp_report_timeout_s; the device's
//       command timeout turns it ON), NOT_REPORTED for a device without a lamp_state publisher;
//       on every report and change, 1 Hz while unknown
// Device errors are throttled per kind (10 s each), so one repeated fault cannot hide another.
#include <chrono>
#include <condition_variable>
#include <memory>
#include <mutex>
#include <thread>

#include <nodelet/nodelet.h>
#include <pluginlib/class_list_macros.hpp>
#include <std_msgs/Bool.h>

#include "icanc/LampCommand.h"
#include "icanc/LampState.h"
#include "icanc/core/bridge/light_bridge_link.hpp"
#include "icanc/ros/conversions.hpp"
#include "icanc/ros/nodelet_settings.hpp"
#include "icanc/ros/nodelet_support.hpp"

namespace icanc {

namespace {

double steadyNow() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

}  // namespace

class LightBridgeNodelet : public nodelet::Nodelet {
 public:
  ~LightBridgeNodelet() override {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      running_ = false;
    }
    wake_.notify_all();
    if (thread_.joinable()) thread_.join();
    std::lock_guard<std::mutex> lock(mutex_);
    if (link_) link_->stop();  // the device drops its configuration: lamp fail-safe ON
  }

 private:
  void onInit() override {
    ros::NodeHandle& nh = getNodeHandle();
    ros::NodeHandle& pnh = getPrivateNodeHandle();
    ParamReader reader(pnh);
    LightBridgeSettings settings;
    if (!checkParams(getName(), reader, loadSettings(reader, settings))) return;
    const LightBridgeParams& params = settings.params;
    const std::string timeout_warning = linkTimeoutWarning(params);
    if (!timeout_warning.empty()) NODELET_WARN("%s", timeout_warning.c_str());
    link_.reset(new LightBridgeLink(params, settings.port, settings.baud, settings.reconnect_period_s));

    diagnostics_.reset(new Diagnostics(nh, pnh, getName(), "headlight bridge " + settings.port));
    diagnostics_->updater().add("light bridge", [this](diagnostic_updater::DiagnosticStatusWrapper& stat) {
      std::lock_guard<std::mutex> lock(mutex_);
      report(stat, link_->host().report(steadyNow()));
    });
    state_pub_ = nh.advertise<std_msgs::Bool>("lamp_state", 10);
    link_pub_ = pnh.advertise<std_msgs::Bool>("link_up", 1, true);
    status_pub_ = nh.advertise<LampState>("lamp_status", 1, true);
    publishBool(link_pub_, false);
    publishStatus(link_->host().statusPublished(steadyNow()));
    sub_ = nh.subscribe("lamp_cmd", 10, &LightBridgeNodelet::onCommand, this, ros::TransportHints().tcpNoDelay());
    input_.reset(new InputMonitor(diagnostics_->updater(), sub_.getTopic(), settings.expected_rate_hz));
    if (!params.device_levels_topic.empty())  // a segmented lamp: its levels too
      levels_sub_ = nh.subscribe("lamp_command", 10, &LightBridgeNodelet::onLevels, this,
                                 ros::TransportHints().tcpNoDelay());
    running_ = true;
    thread_ = std::thread(&LightBridgeNodelet::ioLoop, this);
    NODELET_INFO("LightBridge: %s at %d baud, device topics '%s' (commands, %.1f Hz heartbeat) and "
                 "'%s' (lamp state), link timeout %.2f s",
                 settings.port.c_str(), settings.baud, params.device_cmd_topic.c_str(), params.heartbeat_hz,
                 params.device_state_topic.c_str(), params.link_timeout_s);
  }

  void onCommand(const std_msgs::Bool::ConstPtr& msg) {
    const double t0 = steadyNow();
    input_->received();
    std::lock_guard<std::mutex> lock(mutex_);
    SessionOutput out;
    link_->host().onCommand(msg->data, t0, out);
    handle(out, t0);
    if (link_->commandWritten(out)) link_->host().onCommandLatency((steadyNow() - t0) * 1000.0);
    input_->processed((steadyNow() - t0) * 1000.0);
  }

  // icanc/LampCommand levels (0..1), as 0..255, to the device's device_levels_topic.
  void onLevels(const LampCommand::ConstPtr& msg) {
    const double now = steadyNow();
    std::lock_guard<std::mutex> lock(mutex_);
    SessionOutput out;
    link_->host().onLevels(msg->levels, now, out);
    handle(out, now);
  }

  void ioLoop() {
    std::vector<std::uint8_t> buf(1024);
    while (true) {
      {
        std::unique_lock<std::mutex> lock(mutex_);
        if (!running_) return;
        if (!link_->isOpen()) {
          const double now = steadyNow();
          SessionOutput out;
          HostActions actions;
          link_->openIfDue(now, out, actions);
          handle(out, now, actions);  // keeps lamp_status fresh (UNKNOWN_FAILSAFE at 1 Hz)
          if (!link_->isOpen()) {
            wake_.wait_for(lock, std::chrono::milliseconds(20));
            continue;
          }
        }
      }
      // Only this thread opens and closes the port, so reading outside the lock is safe.
      std::string error;
      const long n = link_->read(buf.data(), buf.size(), 0.01, error);
      std::lock_guard<std::mutex> lock(mutex_);
      const double now = steadyNow();
      SessionOutput out;
      HostActions actions;
      link_->afterRead(n, error, buf.data(), now, toStamp(ros::Time::now()), out, actions);
      handle(out, now, actions);
    }
  }

  // Writes the session's bytes, then logs and publishes what the host decides. With mutex_ held.
  void handle(SessionOutput& out, double now, HostActions actions = HostActions()) {
    link_->finish(out, now, actions);
    for (const LogLine& line : actions.logs) log(getName(), line);
    for (bool on : actions.lamp_states) publishBool(state_pub_, on);
    if (actions.publish_link) publishBool(link_pub_, actions.link_up);
    if (actions.publish_status) publishStatus(actions.status);
  }

  void publishStatus(const LampStatusSnapshot& status) {
    status_pub_.publish(toLampStateMsg(status, ros::Time::now()));
  }

  std::unique_ptr<Diagnostics> diagnostics_;
  std::unique_ptr<InputMonitor> input_;  // lamp_cmd (the LightController publishes >= publish_rate_hz)
  ros::Publisher state_pub_, link_pub_, status_pub_;
  ros::Subscriber sub_, levels_sub_;
  std::thread thread_;
  std::condition_variable wake_;

  std::mutex mutex_;  // everything below: the I/O thread, lamp_cmd callbacks, diagnostics
  bool running_ = false;
  std::unique_ptr<LightBridgeLink> link_;  // the port and the host deciding over it
};

}  // namespace icanc

PLUGINLIB_EXPORT_CLASS(icanc::LightBridgeNodelet, nodelet::Nodelet)
