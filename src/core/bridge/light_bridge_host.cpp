#include "icanc/core/bridge/light_bridge_host.hpp"

#include <algorithm>
#include <cmath>

#include "icanc/core/bridge/serial_port.hpp"
#include "icanc/core/common/percentile.hpp"

namespace icanc {

std::string validatePort(const std::string& port, int baud, double reconnect_period_s) {
  if (port.empty()) return "port must be set (e.g. /dev/ttyACM0)";
  if (!SerialPort::baudSupported(baud))
    return "baud " + std::to_string(baud) + " is not supported (9600 ... 921600; 57600 default)";
  if (!(reconnect_period_s > 0.0)) return "reconnect_period_s must be > 0";
  return "";
}

std::string linkTimeoutWarning(const LightBridgeParams& params) {
  if (!(params.link_timeout_s < kStockLinkTimeoutS)) return "";
  return formatText("link_timeout_s %.2f s is shorter than two time requests of a stock ros_lib "
                    "device (2.5 s apart, %.1f s or more advised): a device that publishes nothing "
                    "else will be dropped and resynced", params.link_timeout_s, kStockLinkTimeoutS);
}

std::vector<std::uint8_t> deviceLevels(const std::vector<float>& levels) {
  std::vector<std::uint8_t> out(levels.size());
  for (std::size_t i = 0; i < levels.size(); ++i) {
    const float l = levels[i];
    out[i] = std::isfinite(l) ? static_cast<std::uint8_t>(std::lround(255.0f * std::min(std::max(l, 0.0f), 1.0f)))
                              : 255;  // not a number: ON
  }
  return out;
}

LightBridgeHost::LightBridgeHost(const LightBridgeParams& params, const std::string& port, int baud,
                                 double reconnect_period_s)
    : session_(params), port_(port), baud_(baud), reconnect_period_s_(reconnect_period_s) {}

bool LightBridgeHost::openDue(double now) {
  if (now < next_open_s_) return false;
  next_open_s_ = now + reconnect_period_s_;
  next_presence_check_s_ = now + reconnect_period_s_;
  return true;
}

bool LightBridgeHost::presenceCheckDue(double now) {
  if (now < next_presence_check_s_) return false;
  next_presence_check_s_ = now + reconnect_period_s_;
  return true;
}

void LightBridgeHost::onOpenFailed(const std::string& error, double now, HostActions& actions) {
  ++open_failures_;
  last_error_ = error;
  if (open_failure_throttle_.allow(now))
    actions.logs.push_back({LogSeverity::kWarn,
                            formatText("cannot open the headlight port: %s (retrying every %.1f s; the "
                                       "device keeps its lamp ON meanwhile)", error.c_str(), reconnect_period_s_)});
}

void LightBridgeHost::onOpened(double now, SessionOutput& out, HostActions& actions) {
  ++port_opens_;
  actions.logs.push_back({LogSeverity::kInfo, formatText("opened %s at %d baud: requesting the device's topics",
                                                         port_.c_str(), baud_)});
  session_.onOpened(now, out);
}

void LightBridgeHost::onLost(const std::string& why, double now, SessionOutput& out, HostActions& actions) {
  ++port_losses_;
  last_error_ = why;
  actions.logs.push_back({LogSeverity::kError,
                          formatText("headlight port %s lost: %s; reopening every %.1f s (the device fails safe ON)",
                                     port_.c_str(), why.c_str(), reconnect_period_s_)});
  session_.onClosed(now, out);
  next_open_s_ = now;  // try at once: a replugged device may already be back
}

void LightBridgeHost::onCommand(bool on, double now, SessionOutput& out) {
  ++lamp_cmds_;
  session_.onCommand(on, now, out);
}

void LightBridgeHost::onLevels(const std::vector<float>& levels, double now, SessionOutput& out) {
  ++level_cmds_;
  session_.onLevels(deviceLevels(levels), now, out);
}

void LightBridgeHost::onCommandLatency(double ms) {
  latencies_ms_.push_back(ms);
  if (latencies_ms_.size() > 1000) latencies_ms_.pop_front();
}

void LightBridgeHost::afterStep(const SessionOutput& out, double now, HostActions& actions) {
  bool reported = false;
  for (const SessionEvent& e : out.events) {
    switch (e.kind) {
      case SessionEvent::kLampState:
        actions.lamp_states.push_back(e.value);
        reported = true;
        break;
      case SessionEvent::kDeviceLog: deviceLog(e, now, actions); break;
      case SessionEvent::kLinkUp:
        actions.logs.push_back({LogSeverity::kInfo, "headlight device synced on " + port_ + ": " + e.text});
        break;
      case SessionEvent::kLinkLost:
        actions.logs.push_back({LogSeverity::kError, "headlight link lost: " + e.text});
        break;
      case SessionEvent::kError: {
        std::uint64_t held = 0;
        if (!error_throttle_.allow(e.error, now, held)) break;
        actions.logs.push_back(
            {LogSeverity::kError,
             held > 0 ? formatText("headlight device: %s (and %lu more of this kind in the last %.0f s)",
                                   e.text.c_str(), static_cast<unsigned long>(held), kErrorPeriodS)
                      : "headlight device: " + e.text});
        break;
      }
      case SessionEvent::kWarning:
        actions.logs.push_back({LogSeverity::kWarn, "headlight device: " + e.text});
        break;
      case SessionEvent::kInfo:
        if (info_throttle_.allow(now)) actions.logs.push_back({LogSeverity::kInfo, "headlight device: " + e.text});
        break;
    }
  }
  // link_up and lamp_status follow the session's state, whatever event changed it.
  const bool up = session_.synced();
  if (up != link_published_) {
    actions.publish_link = true;
    actions.link_up = link_published_ = up;
  }
  const LampStatus status = session_.lampStatus();
  const bool commanded = session_.commandInForce(now);
  if (reported || status != status_published_ || commanded != commanded_published_ ||
      (status == LampStatus::kUnknownFailSafe && now - status_published_s_ >= 1.0)) {
    actions.publish_status = true;
    actions.status = statusPublished(now);
  }
  // Wire faults: one line per second at most, naming what happened since the last line.
  const rosserial::ParserCounters& c = session_.parserCounters();
  if ((c.faults() != logged_faults_.faults() || c.garbage_bytes != logged_faults_.garbage_bytes) &&
      now - last_fault_log_s_ >= 1.0) {
    actions.logs.push_back(
        {LogSeverity::kWarn, formatText("rosserial link %s: %s (the parser resynchronised; totals in /diagnostics)",
                                        port_.c_str(), rosserial::describeNewFaults(logged_faults_, c).c_str())});
    logged_faults_ = c;
    last_fault_log_s_ = now;
  }
}

LampStatusSnapshot LightBridgeHost::statusPublished(double now) {
  status_published_ = session_.lampStatus();
  commanded_published_ = session_.commandInForce(now);
  status_published_s_ = now;
  return LampStatusSnapshot{status_published_, session_.synced(), commanded_published_};
}

void LightBridgeHost::deviceLog(const SessionEvent& e, double now, HostActions& actions) {
  // At most 20 device lines per second: a chatty sketch must not flood rosout.
  if (now - log_window_start_s_ >= 1.0) {
    if (dropped_logs_ > 0)
      actions.logs.push_back({LogSeverity::kWarn, formatText("[device] %lu log lines dropped (over 20/s)", dropped_logs_)});
    log_window_start_s_ = now;
    log_window_count_ = 0;
    dropped_logs_ = 0;
  }
  if (++log_window_count_ > 20) {
    ++dropped_logs_;
    return;
  }
  LogSeverity severity = LogSeverity::kFatal;
  switch (e.level) {
    case rosserial::LogMessage::kDebug: severity = LogSeverity::kDebug; break;
    case rosserial::LogMessage::kInfo: severity = LogSeverity::kInfo; break;
    case rosserial::LogMessage::kWarn: severity = LogSeverity::kWarn; break;
    case rosserial::LogMessage::kError: severity = LogSeverity::kError; break;
    default: break;
  }
  actions.logs.push_back({severity, "[device] " + e.text});
}

StatusReport LightBridgeHost::report(double now) const {
  StatusReport stat;
  const LightBridgeSession& session = session_;
  const LinkState state = session.state();
  const bool cmd_on = session.commandInForce(now);
  switch (state) {
    case LinkState::kClosed:
      stat.summary(StatusLevel::kError, "port " + port_ + " not open: " + last_error_ + " (device lamp fails safe ON)");
      break;
    case LinkState::kNegotiating:
      stat.summary(StatusLevel::kWarn, "negotiating with the device (no answer yet)");
      break;
    case LinkState::kMismatch:
      stat.summary(StatusLevel::kError, "device command topic has the wrong type: commands refused");
      break;
    case LinkState::kSynced:
      if (session.lampReportOverdue())
        stat.summary(StatusLevel::kError, "device silent: lamp state unknown (it fails safe ON)");
      else if (!session.hasLampReport() && !session.params().device_state_topic.empty())
        stat.summary(StatusLevel::kWarn, "synced, but the device reports no lamp state");
      else if (session.commandStale(now))
        stat.summary(StatusLevel::kWarn, "synced; no lamp_cmd: commanding the lamp ON (fail-safe)");
      else
        stat.summary(StatusLevel::kOk, std::string("synced: lamp commanded ") + (cmd_on ? "ON" : "OFF"));
      break;
  }
  const SessionCounters& s = session.counters();
  const rosserial::ParserCounters& p = session.parserCounters();
  const std::vector<double> lat(latencies_ms_.begin(), latencies_ms_.end());
  stat.add("port", port_);
  stat.add("baud", baud_);
  stat.add("link state", std::string(toString(state)));
  stat.add("command in force", std::string(cmd_on ? "ON" : "OFF"));
  stat.add("lamp status", std::string(toString(session.lampStatus())));
  stat.add("device lamp state",
           std::string(session.hasLampReport() ? (session.lampReport() ? "ON" : "OFF") : "unknown"));
  stat.add("lamp report age [s]", session.hasLampReport() ? now - session.lastLampReportTime() : -1.0);
  stat.add("last error", last_error_);
  stat.add("port opens", port_opens_);
  stat.add("port losses", port_losses_);
  stat.add("open failures", open_failures_);
  stat.add("link ups", s.link_ups);
  stat.add("link losses", s.link_losses);
  stat.add("topic requests", s.topic_requests);
  stat.add("lamp_cmd received", lamp_cmds_);
  if (!session.params().device_levels_topic.empty()) {
    stat.add("lamp_command (segment levels) received", level_cmds_);
    stat.add("segment level frames sent", s.levels_sent);
    stat.add("device levels topic id", session.levelsTopicId());
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
  return stat;
}

}  // namespace icanc
