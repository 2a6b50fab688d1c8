// What the LightBridge nodelet decides above the protocol (LightBridgeSession), without I/O:
// when to open the port again and to check it is still there, the port's bookkeeping (opens,
// losses, open failures, the last error), which of the session's events reach the log (device
// lines at most 20 per second, device errors throttled per kind, wire faults once a second), when
// link_up and lamp_status are republished, the command latency and the diagnostics report.
// Time is the nodelet's steady clock [s], an argument.
#pragma once

#include <cstdint>
#include <deque>
#include <string>
#include <vector>

#include "icanc/core/bridge/rosserial_session.hpp"
#include "icanc/core/common/log_line.hpp"
#include "icanc/core/common/status_report.hpp"

namespace icanc {

// The port's own parameters (~port, ~baud, ~reconnect_period_s); "" or the problem.
std::string validatePort(const std::string& port, int baud, double reconnect_period_s);

// Two time requests of a stock ros_lib device (2.5 s apart) [s].
constexpr double kStockLinkTimeoutS = 5.0;
// The warning for a link_timeout_s that drops a stock device between its time requests, or "".
std::string linkTimeoutWarning(const LightBridgeParams& params);

// Lamp levels 0..1 as the device's 0..255 (clamped); not a number is ON (255).
std::vector<std::uint8_t> deviceLevels(const std::vector<float>& levels);

// What lamp_status says (icanc/LampState).
struct LampStatusSnapshot {
  LampStatus status = LampStatus::kUnknownFailSafe;
  bool link_up = false;
  bool commanded_on = true;
};

// What the nodelet does after a step, in this order: log, publish lamp_state, link_up, lamp_status.
struct HostActions {
  std::vector<LogLine> logs;
  std::vector<bool> lamp_states;  // the device's reports, for lamp_state
  bool publish_link = false;      // link_up changed: publish link_up
  bool link_up = false;
  bool publish_status = false;    // publish `status` on lamp_status
  LampStatusSnapshot status;
};

class LightBridgeHost {
 public:
  static constexpr double kErrorPeriodS = 10.0;  // per-kind throttle of device errors [s]

  LightBridgeHost(const LightBridgeParams& params, const std::string& port, int baud,
                  double reconnect_period_s);

  LightBridgeSession& session() { return session_; }
  const LightBridgeSession& session() const { return session_; }

  // The port is closed: true when an attempt to open it is due at `now` (then the next one is
  // reconnect_period_s later, and so is the first presence check).
  bool openDue(double now);
  // The port is open: true when checking that its path still names the device is due.
  bool presenceCheckDue(double now);

  void onOpenFailed(const std::string& error, double now, HostActions& actions);
  void onOpened(double now, SessionOutput& out, HostActions& actions);
  // The port was lost (I/O error, unplugged): the next open is due at once.
  void onLost(const std::string& why, double now, SessionOutput& out, HostActions& actions);

  // lamp_cmd and lamp_command (levels 0..1) from ROS.
  void onCommand(bool on, double now, SessionOutput& out);
  void onLevels(const std::vector<float>& levels, double now, SessionOutput& out);

  void onWritten(std::size_t bytes) { tx_bytes_ += bytes; }
  // lamp_cmd callback -> its frame written and drained [ms] (the last 1000 kept).
  void onCommandLatency(double ms);

  // After the session's output (its bytes written): its events as log lines and lamp_state
  // reports, and whether link_up, lamp_status and a wire-fault line are due.
  void afterStep(const SessionOutput& out, double now, HostActions& actions);
  // lamp_status as of `now`, recorded as published (at startup).
  LampStatusSnapshot statusPublished(double now);

  StatusReport report(double now) const;

 private:
  void deviceLog(const SessionEvent& e, double now, HostActions& actions);

  LightBridgeSession session_;
  std::string port_;
  int baud_;
  double reconnect_period_s_;

  double next_open_s_ = 0.0, next_presence_check_s_ = 0.0;
  std::string last_error_;
  std::uint64_t port_opens_ = 0, port_losses_ = 0, open_failures_ = 0, lamp_cmds_ = 0, tx_bytes_ = 0;
  std::uint64_t level_cmds_ = 0;
  std::deque<double> latencies_ms_;

  ErrorThrottle error_throttle_{kErrorPeriodS};
  LogThrottle open_failure_throttle_{10.0};
  LogThrottle info_throttle_{60.0};
  bool link_published_ = false;
  LampStatus status_published_ = LampStatus::kUnknownFailSafe;
  bool commanded_published_ = true;
  double status_published_s_ = -1e9;
  rosserial::ParserCounters logged_faults_;
  double last_fault_log_s_ = -1e9;
  double log_window_start_s_ = -1e9;
  unsigned log_window_count_ = 0;
  unsigned long dropped_logs_ = 0;
};

}  // namespace icanc
