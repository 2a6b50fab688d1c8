// icanc/LightBridge: the lamp command (lamp_cmd, std_msgs/Bool) to a rosserial (ros_lib) device on
// a serial port, and the lamp state the device reports back (lamp_state, std_msgs/Bool). The
// protocol and the link's state machine are the core's (icanc/rosserial_session.hpp); this
// nodelet only does I/O: one thread owns the port (open, reopen after an unplug, read, tick),
// lamp_cmd callbacks write their frame at once. Wall (steady) time drives the link; ROS time
// answers the device's time requests.
//
//   ~port (string, required)        serial device, e.g. /dev/ttyACM0 or a /dev/serial/by-id link
//   ~baud (int, 57600)              9600 ... 921600 (the sketch uses 57600; 115200 supported)
//   ~device_cmd_topic, ~device_state_topic, ~heartbeat_hz, ~link_timeout_s, ~negotiation_retry_s,
//   ~cmd_stale_timeout_s, ~lamp_report_timeout_s, ~frame_timeout_s, ~max_payload_bytes
//                                   see LightBridgeParams
//   ~reconnect_period_s (1.0)       reopening attempts while the port is missing [s]
//   ~device_levels_topic ("")       a segmented lamp (issue 23): lamp_command (icanc/LampCommand)
//       levels, as 0..255, to the device's std_msgs/UInt8MultiArray subscriber of this name
//   ~link_up (std_msgs/Bool, latched)  true while the device is synced (false on a type mismatch)
//   lamp_status (icanc/LampState, latched)  stamped: ON / OFF as reported, UNKNOWN_FAILSAFE while
//       the link is down or the device's reports are overdue (lamp_report_timeout_s; the device's
//       command timeout turns it ON), NOT_REPORTED for a device without a lamp_state publisher;
//       on every report and change, 1 Hz while unknown
// Device errors are throttled per kind (10 s each), so one repeated fault cannot hide another.
#include <algorithm>
#include <atomic>
#include <cmath>
#include <chrono>
#include <condition_variable>
#include <deque>
#include <memory>
#include <mutex>
#include <thread>

#include <boost/make_shared.hpp>
#include <nodelet/nodelet.h>
#include <pluginlib/class_list_macros.hpp>
#include <std_msgs/Bool.h>

#include "icanc/LampCommand.h"
#include "icanc/LampState.h"
#include "icanc/core/bridge/rosserial_session.hpp"
#include "icanc/core/bridge/serial_port.hpp"
#include "icanc/core/common/percentile.hpp"
#include "icanc/ros/nodelet_support.hpp"

namespace icanc {

namespace {

using icanc::percentile;

double steadyNow() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

rosserial::Stamp rosNow() {
  const ros::Time t = ros::Time::now();
  return rosserial::Stamp{t.sec, t.nsec};
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
    if (session_ && port_.isOpen()) {
      SessionOutput out;
      session_->txStop(out);  // the device drops its configuration: lamp fail-safe ON
      std::string error;
      port_.write(out.tx.data(), out.tx.size(), true, error);
    }
    port_.close();
  }

 private:
  void onInit() override {
    ros::NodeHandle& nh = getNodeHandle();
    ros::NodeHandle& pnh = getPrivateNodeHandle();
    ParamReader reader(pnh);
    LightBridgeParams params;
    reader.read("port", port_name_);
    reader.read("baud", baud_);
    reader.read("reconnect_period_s", reconnect_period_s_);
    reader.read("device_cmd_topic", params.device_cmd_topic);
    reader.read("device_state_topic", params.device_state_topic);
    reader.read("device_levels_topic", params.device_levels_topic);
    reader.read("heartbeat_hz", params.heartbeat_hz);
    reader.read("link_timeout_s", params.link_timeout_s);
    reader.read("negotiation_retry_s", params.negotiation_retry_s);
    reader.read("cmd_stale_timeout_s", params.cmd_stale_timeout_s);
    reader.read("lamp_report_timeout_s", params.lamp_report_timeout_s);
    reader.read("frame_timeout_s", params.frame_timeout_s);
    reader.read("max_payload_bytes", params.max_payload_bytes);
    const std::string rate_problem = readExpectedRate(reader, expected_rate_hz_);
    std::string why = validate(params);
    if (why.empty()) why = rate_problem;
    if (why.empty() && port_name_.empty()) why = "port must be set (e.g. /dev/ttyACM0)";
    if (why.empty() && !SerialPort::baudSupported(baud_))
      why = "baud " + std::to_string(baud_) + " is not supported (9600 ... 921600; 57600 default)";
    if (why.empty() && !(reconnect_period_s_ > 0.0)) why = "reconnect_period_s must be > 0";
    if (!checkParams(getName(), reader, why)) return;
    if (params.link_timeout_s < kStockLinkTimeoutS)
      NODELET_WARN("link_timeout_s %.2f s is shorter than two time requests of a stock ros_lib "
                   "device (2.5 s apart, %.1f s or more advised): a device that publishes nothing "
                   "else will be dropped and resynced", params.link_timeout_s, kStockLinkTimeoutS);
    session_.reset(new LightBridgeSession(params));

    diagnostics_.reset(new Diagnostics(nh, pnh, getName(), "headlight bridge " + port_name_));
    diagnostics_->updater().add("light bridge", this, &LightBridgeNodelet::diagnose);
    state_pub_ = nh.advertise<std_msgs::Bool>("lamp_state", 10);
    link_pub_ = pnh.advertise<std_msgs::Bool>("link_up", 1, true);
    status_pub_ = nh.advertise<LampState>("lamp_status", 1, true);
    publishLink(false);
    publishStatus(steadyNow());
    sub_ = nh.subscribe("lamp_cmd", 10, &LightBridgeNodelet::onCommand, this, ros::TransportHints().tcpNoDelay());
    input_.reset(new InputMonitor(diagnostics_->updater(), sub_.getTopic(), expected_rate_hz_));
    if (!params.device_levels_topic.empty())  // a segmented lamp (issue 23): its levels too
      levels_sub_ = nh.subscribe("lamp_command", 10, &LightBridgeNodelet::onLevels, this,
                                 ros::TransportHints().tcpNoDelay());
    running_ = true;
    thread_ = std::thread(&LightBridgeNodelet::ioLoop, this);
    NODELET_INFO("LightBridge: %s at %d baud, device topics '%s' (commands, %.1f Hz heartbeat) and "
                 "'%s' (lamp state), link timeout %.2f s",
                 port_name_.c_str(), baud_, params.device_cmd_topic.c_str(), params.heartbeat_hz,
                 params.device_state_topic.c_str(), params.link_timeout_s);
  }

  void onCommand(const std_msgs::Bool::ConstPtr& msg) {
    const double t0 = steadyNow();
    input_->received();
    std::lock_guard<std::mutex> lock(mutex_);
    ++lamp_cmds_;
    SessionOutput out;
    session_->onCommand(msg->data, t0, out);
    handle(out, t0);
    if (out.command_sent && port_.isOpen() && write_error_.empty()) {
      latencies_ms_.push_back((steadyNow() - t0) * 1000.0);
      if (latencies_ms_.size() > 1000) latencies_ms_.pop_front();
    }
    input_->processed((steadyNow() - t0) * 1000.0);
  }

  // icanc/LampCommand levels (0..1) as 0..255 to the device's device_levels_topic.
  void onLevels(const LampCommand::ConstPtr& msg) {
    const double now = steadyNow();
    std::vector<std::uint8_t> levels(msg->levels.size());
    for (std::size_t i = 0; i < levels.size(); ++i) {
      const float l = msg->levels[i];
      levels[i] = std::isfinite(l) ? static_cast<std::uint8_t>(std::lround(255.0f * std::min(std::max(l, 0.0f), 1.0f)))
                                   : 255;  // not a number: ON
    }
    std::lock_guard<std::mutex> lock(mutex_);
    ++level_cmds_;
    SessionOutput out;
    session_->onLevels(levels, now, out);
    handle(out, now);
  }

  void ioLoop() {
    std::vector<std::uint8_t> buf(1024);
    double next_open = 0.0, next_presence_check = 0.0;
    while (true) {
      {
        std::unique_lock<std::mutex> lock(mutex_);
        if (!running_) return;
        if (!port_.isOpen()) {
          const double now = steadyNow();
          if (now >= next_open) {
            openPort(now);
            next_open = now + reconnect_period_s_;
            next_presence_check = now + reconnect_period_s_;
          }
          if (!port_.isOpen()) {
            SessionOutput none;
            handle(none, now);  // keeps lamp_status fresh (UNKNOWN_FAILSAFE at 1 Hz)
            wake_.wait_for(lock, std::chrono::milliseconds(20));
            continue;
          }
        }
      }
      // Only this thread opens and closes the port, so reading outside the lock is safe.
      std::string error;
      const long n = port_.read(buf.data(), buf.size(), 0.01, error);
      std::lock_guard<std::mutex> lock(mutex_);
      const double now = steadyNow();
      SessionOutput out;
      if (n < 0 || !write_error_.empty()) {
        lost(n < 0 ? error : write_error_, now, out);
        next_open = now;  // try at once: a replugged device may already be back
      } else if (now >= next_presence_check) {
        next_presence_check = now + reconnect_period_s_;
        if (!port_.stillPresent()) {
          lost("the path no longer names the opened device", now, out);
          next_open = now;
        }
      }
      if (port_.isOpen()) {
        const rosserial::Stamp ros_now = rosNow();
        if (n > 0) session_->onBytes(buf.data(), static_cast<std::size_t>(n), now, ros_now, out);
        session_->tick(now, ros_now, out);
      }
      handle(out, now);
    }
  }

  // With mutex_ held.
  void openPort(double now) {
    std::string error;
    if (!port_.open(port_name_, baud_, error)) {
      ++open_failures_;
      last_error_ = error;
      NODELET_WARN_THROTTLE(10.0, "cannot open the headlight port: %s (retrying every %.1f s; the "
                            "device keeps its lamp ON meanwhile)", error.c_str(), reconnect_period_s_);
      return;
    }
    ++port_opens_;
    NODELET_INFO("opened %s at %d baud: requesting the device's topics", port_name_.c_str(), baud_);
    SessionOutput out;
    session_->onOpened(now, out);
    handle(out, now);
  }

  // With mutex_ held.
  void lost(const std::string& why, double now, SessionOutput& out) {
    ++port_losses_;
    last_error_ = why;
    write_error_.clear();
    NODELET_ERROR("headlight port %s lost: %s; reopening every %.1f s (the device fails safe ON)",
                  port_name_.c_str(), why.c_str(), reconnect_period_s_);
    port_.close();
    session_->onClosed(now, out);
  }

  // Writes the session's bytes and acts on its events. With mutex_ held.
  void handle(SessionOutput& out, double now) {
    if (!out.tx.empty() && port_.isOpen() && write_error_.empty()) {
      std::string error;
      if (port_.write(out.tx.data(), out.tx.size(), true, error))
        tx_bytes_ += out.tx.size();
      else
        write_error_ = error;  // the I/O thread closes the port (it may be polling it now)
    }
    bool reported = false;
    for (const SessionEvent& e : out.events) {
      switch (e.kind) {
        case SessionEvent::kLampState: {
          auto msg = boost::make_shared<std_msgs::Bool>();
          msg->data = e.value;
          state_pub_.publish(std_msgs::Bool::ConstPtr(msg));
          reported = true;
          break;
        }
        case SessionEvent::kDeviceLog: deviceLog(e, now); break;
        case SessionEvent::kLinkUp:
          NODELET_INFO("headlight device synced on %s: %s", port_name_.c_str(), e.text.c_str());
          break;
        case SessionEvent::kLinkLost:
          NODELET_ERROR("headlight link lost: %s", e.text.c_str());
          break;
        case SessionEvent::kError: {
          std::uint64_t held = 0;
          if (!error_throttle_.allow(e.error, now, held)) break;
          if (held > 0)
            NODELET_ERROR("headlight device: %s (and %lu more of this kind in the last %.0f s)",
                          e.text.c_str(), static_cast<unsigned long>(held), kErrorPeriodS);
          else
            NODELET_ERROR("headlight device: %s", e.text.c_str());
          break;
        }
        case SessionEvent::kWarning: NODELET_WARN("headlight device: %s", e.text.c_str()); break;
        case SessionEvent::kInfo: NODELET_INFO_THROTTLE(60.0, "headlight device: %s", e.text.c_str()); break;
      }
    }
    // link_up and lamp_status follow the session's state, whatever event changed it.
    const bool up = session_->synced();
    if (up != link_published_) publishLink(up);
    const LampStatus status = session_->lampStatus();
    const bool commanded = session_->commandInForce(now);
    if (reported || status != status_published_ || commanded != commanded_published_ ||
        (status == LampStatus::kUnknownFailSafe && now - status_published_s_ >= 1.0))
      publishStatus(now);
    // Wire faults: one line per second at most, naming what happened since the last line.
    const rosserial::ParserCounters& c = session_->parserCounters();
    if ((c.faults() != logged_faults_.faults() || c.garbage_bytes != logged_faults_.garbage_bytes) &&
        now - last_fault_log_ >= 1.0) {
      NODELET_WARN("rosserial link %s: %s (the parser resynchronised; totals in /diagnostics)",
                   port_name_.c_str(), rosserial::describeNewFaults(logged_faults_, c).c_str());
      logged_faults_ = c;
      last_fault_log_ = now;
    }
  }

  void deviceLog(const SessionEvent& e, double now) {
    // At most 20 device lines per second: a chatty sketch must not flood rosout.
    if (now - log_window_start_ >= 1.0) {
      if (dropped_logs_ > 0) NODELET_WARN("[device] %lu log lines dropped (over 20/s)", dropped_logs_);
      log_window_start_ = now;
      log_window_count_ = 0;
      dropped_logs_ = 0;
    }
    if (++log_window_count_ > 20) {
      ++dropped_logs_;
      return;
    }
    switch (e.level) {
      case rosserial::LogMessage::kDebug: NODELET_DEBUG("[device] %s", e.text.c_str()); break;
      case rosserial::LogMessage::kInfo: NODELET_INFO("[device] %s", e.text.c_str()); break;
      case rosserial::LogMessage::kWarn: NODELET_WARN("[device] %s", e.text.c_str()); break;
      case rosserial::LogMessage::kError: NODELET_ERROR("[device] %s", e.text.c_str()); break;
      default: NODELET_FATAL("[device] %s", e.text.c_str()); break;
    }
  }

  void publishLink(bool up) {
    auto msg = boost::make_shared<std_msgs::Bool>();
    msg->data = up;
    link_pub_.publish(std_msgs::Bool::ConstPtr(msg));
    link_published_ = up;
  }

  // With mutex_ held (or before the I/O thread starts).
  void publishStatus(double now) {
    auto msg = boost::make_shared<LampState>();
    msg->header.stamp = ros::Time::now();
    status_published_ = session_->lampStatus();
    commanded_published_ = session_->commandInForce(now);
    status_published_s_ = now;
    msg->state = static_cast<std::uint8_t>(status_published_);
    msg->link_up = session_->synced();
    msg->commanded_on = commanded_published_;
    status_pub_.publish(LampState::ConstPtr(msg));
  }

  void diagnose(diagnostic_updater::DiagnosticStatusWrapper& stat) {
    std::lock_guard<std::mutex> lock(mutex_);
    using diagnostic_msgs::DiagnosticStatus;
    const double now = steadyNow();
    const LinkState state = session_->state();
    const bool cmd_on = session_->commandInForce(now);
    const bool stale = session_->commandStale(now);
    switch (state) {
      case LinkState::kClosed:
        stat.summary(DiagnosticStatus::ERROR, "port " + port_name_ + " not open: " + last_error_ +
                                                  " (device lamp fails safe ON)");
        break;
      case LinkState::kNegotiating:
        stat.summary(DiagnosticStatus::WARN, "negotiating with the device (no answer yet)");
        break;
      case LinkState::kMismatch:
        stat.summary(DiagnosticStatus::ERROR, "device command topic has the wrong type: commands refused");
        break;
      case LinkState::kSynced:
        if (session_->lampReportOverdue())
          stat.summary(DiagnosticStatus::ERROR, "device silent: lamp state unknown (it fails safe ON)");
        else if (!session_->hasLampReport() && !session_->params().device_state_topic.empty())
          stat.summary(DiagnosticStatus::WARN, "synced, but the device reports no lamp state");
        else if (stale)
          stat.summary(DiagnosticStatus::WARN, "synced; no lamp_cmd: commanding the lamp ON (fail-safe)");
        else
          stat.summary(DiagnosticStatus::OK, std::string("synced: lamp commanded ") + (cmd_on ? "ON" : "OFF"));
        break;
    }
    const SessionCounters& s = session_->counters();
    const rosserial::ParserCounters& p = session_->parserCounters();
    const std::vector<double> lat(latencies_ms_.begin(), latencies_ms_.end());
    stat.add("port", port_name_);
    stat.add("baud", baud_);
    stat.add("link state", toString(state));
    stat.add("command in force", cmd_on ? "ON" : "OFF");
    stat.add("lamp status", toString(session_->lampStatus()));
    stat.add("device lamp state", session_->hasLampReport() ? (session_->lampReport() ? "ON" : "OFF") : "unknown");
    stat.add("lamp report age [s]", session_->hasLampReport() ? now - session_->lastLampReportTime() : -1.0);
    stat.add("last error", last_error_);
    stat.add("port opens", port_opens_);
    stat.add("port losses", port_losses_);
    stat.add("open failures", open_failures_);
    stat.add("link ups", s.link_ups);
    stat.add("link losses", s.link_losses);
    stat.add("topic requests", s.topic_requests);
    stat.add("lamp_cmd received", lamp_cmds_);
    if (!session_->params().device_levels_topic.empty()) {
      stat.add("lamp_command (segment levels) received", level_cmds_);
      stat.add("segment level frames sent", s.levels_sent);
      stat.add("device levels topic id", session_->levelsTopicId());
    }
    stat.add("commands sent", s.commands_sent);
    stat.add("fail-safe ON commands (lamp_cmd stale)", s.stale_commands);
    stat.add("lamp reports", s.lamp_reports);
    stat.add("lamp reports overdue (status unknown)", s.overdue_reports);
    stat.add("time replies", s.time_replies);
    stat.add("device logs", s.device_logs);
    stat.add("tx bytes", tx_bytes_);
    stat.add("rx bytes", p.bytes);
    stat.add("rx frames", p.frames);
    stat.add("faults: garbage bytes", p.garbage_bytes);
    stat.add("faults: bad length checksum", p.bad_length_checksum);
    stat.add("faults: oversized length", p.oversize_length);
    stat.add("faults: bad message checksum", p.bad_message_checksum);
    stat.add("faults: truncated frames", p.truncated);
    stat.add("faults: bad payloads", s.bad_payloads);
    stat.add("faults: unknown topic ids", s.unknown_topics);
    stat.add("faults: type mismatches", s.type_mismatches);
    stat.add("unsupported requests", s.unsupported);
    stat.add("command latency samples", lat.size());
    stat.add("command latency p50 [ms]", percentile(lat, 0.5));
    stat.add("command latency p99 [ms]", percentile(lat, 0.99));
  }

  std::string port_name_;
  int baud_ = 57600;
  double reconnect_period_s_ = 1.0;

  std::unique_ptr<Diagnostics> diagnostics_;
  std::unique_ptr<InputMonitor> input_;  // lamp_cmd (the LightController publishes >= publish_rate_hz)
  double expected_rate_hz_ = 10.0;
  ros::Publisher state_pub_, link_pub_, status_pub_;
  ros::Subscriber sub_, levels_sub_;
  std::thread thread_;
  std::condition_variable wake_;

  std::mutex mutex_;  // everything below: the I/O thread, lamp_cmd callbacks, diagnostics
  bool running_ = false;
  std::unique_ptr<LightBridgeSession> session_;
  SerialPort port_;
  std::string last_error_;
  std::string write_error_;  // set by a failed write, the I/O thread then closes the port
  std::uint64_t port_opens_ = 0, port_losses_ = 0, open_failures_ = 0, lamp_cmds_ = 0, tx_bytes_ = 0;
  std::uint64_t level_cmds_ = 0;
  static constexpr double kStockLinkTimeoutS = 5.0;  // two ros_lib time-sync periods [s]
  static constexpr double kErrorPeriodS = 10.0;      // per-kind throttle of device errors [s]
  ErrorThrottle error_throttle_{kErrorPeriodS};
  bool link_published_ = false;
  LampStatus status_published_ = LampStatus::kUnknownFailSafe;
  bool commanded_published_ = true;
  double status_published_s_ = -1e9;
  std::deque<double> latencies_ms_;  // lamp_cmd callback -> frame written and drained
  rosserial::ParserCounters logged_faults_;
  double last_fault_log_ = -1e9;
  double log_window_start_ = -1e9;
  unsigned log_window_count_ = 0;
  unsigned long dropped_logs_ = 0;
};

}  // namespace icanc

PLUGINLIB_EXPORT_CLASS(icanc::LightBridgeNodelet, nodelet::Nodelet)
