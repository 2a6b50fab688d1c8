#include "icanc/core/bridge/rosserial_session.hpp"

#include <algorithm>
#include <sstream>

namespace icanc {

using rosserial::Frame;
using rosserial::TopicInfo;

std::string validate(const LightBridgeParams& p) {
  std::ostringstream why;
  if (p.device_cmd_topic.empty())
    why << "device_cmd_topic must not be empty";
  else if (!(p.heartbeat_hz >= 1.0 && p.heartbeat_hz <= 1000.0))
    why << "heartbeat_hz must be in [1, 1000] (got " << p.heartbeat_hz << ")";
  else if (!(p.link_timeout_s > 1.0 / p.heartbeat_hz))
    why << "link_timeout_s must be > 1 / heartbeat_hz (got " << p.link_timeout_s << ")";
  else if (!(p.negotiation_retry_s > 0.0))
    why << "negotiation_retry_s must be > 0 (got " << p.negotiation_retry_s << ")";
  else if (!(p.cmd_stale_timeout_s > 0.0))
    why << "cmd_stale_timeout_s must be > 0 (got " << p.cmd_stale_timeout_s << ")";
  else if (!(p.lamp_report_timeout_s > 0.0 && p.lamp_report_timeout_s <= p.link_timeout_s))
    why << "lamp_report_timeout_s must be in (0, link_timeout_s] (got " << p.lamp_report_timeout_s << ")";
  else if (!(p.frame_timeout_s > 0.0 && p.frame_timeout_s < p.link_timeout_s))
    why << "frame_timeout_s must be in (0, link_timeout_s) (got " << p.frame_timeout_s << ")";
  else if (!(p.max_payload_bytes >= 64 && p.max_payload_bytes <= 65535))
    why << "max_payload_bytes must be in [64, 65535] (got " << p.max_payload_bytes << ")";
  else if (!p.device_levels_topic.empty() &&
           (p.device_levels_topic == p.device_cmd_topic || p.device_levels_topic == p.device_state_topic))
    why << "device_levels_topic must differ from device_cmd_topic and device_state_topic (got '"
        << p.device_levels_topic << "')";
  return why.str();
}

const char* toString(LinkState state) {
  switch (state) {
    case LinkState::kClosed: return "port closed";
    case LinkState::kNegotiating: return "negotiating";
    case LinkState::kSynced: return "synced";
    case LinkState::kMismatch: return "type mismatch";
  }
  return "unknown";
}

const char* toString(LampStatus status) {
  switch (status) {
    case LampStatus::kOff: return "OFF";
    case LampStatus::kOn: return "ON";
    case LampStatus::kUnknownFailSafe: return "unknown (link down or device silent: it fails safe ON)";
    case LampStatus::kNotReported: return "not reported by the device";
  }
  return "unknown";
}

bool ErrorThrottle::allow(SessionError kind, double now, std::uint64_t& suppressed) {
  const std::size_t i = std::min(static_cast<std::size_t>(kind), kKinds - 1);
  if (printed_[i] && now - last_s_[i] < period_s_) {
    ++held_[i];
    return false;
  }
  suppressed = held_[i];
  held_[i] = 0;
  printed_[i] = true;
  last_s_[i] = now;
  return true;
}

namespace {

std::string stripSlash(const std::string& name) {
  return !name.empty() && name[0] == '/' ? name.substr(1) : name;
}

bool isBool(const TopicInfo& t) {
  return t.message_type == rosserial::kBoolType && t.md5sum == rosserial::kBoolMd5;
}

std::string describe(const TopicInfo& t) {
  std::ostringstream s;
  s << "'" << t.topic_name << "' (" << t.message_type << ", md5 " << t.md5sum << ", id " << t.topic_id << ")";
  return s.str();
}

}  // namespace

LightBridgeSession::LightBridgeSession(const LightBridgeParams& params)
    : params_(params),
      parser_(static_cast<std::size_t>(params.max_payload_bytes), params.frame_timeout_s) {}

void LightBridgeSession::event(SessionOutput& out, SessionEvent::Kind kind, std::string text) {
  SessionEvent e;
  e.kind = kind;
  e.text = std::move(text);
  out.events.push_back(std::move(e));
}

void LightBridgeSession::error(SessionOutput& out, SessionError kind, std::string text) {
  event(out, SessionEvent::kError, std::move(text));
  out.events.back().error = kind;
}

void LightBridgeSession::loseLink(const std::string& why, LinkState next, SessionOutput& out) {
  if (state_ == LinkState::kSynced) {
    ++counters_.link_losses;
    event(out, SessionEvent::kLinkLost, why);
  }
  state_ = next;
  has_lamp_report_ = false;  // what the device said on this link is no longer known
  report_overdue_ = false;
}

LampStatus LightBridgeSession::lampStatus() const {
  if (state_ != LinkState::kSynced || report_overdue_) return LampStatus::kUnknownFailSafe;
  if (state_id_ == 0 || !has_lamp_report_) return LampStatus::kNotReported;
  return lamp_report_ ? LampStatus::kOn : LampStatus::kOff;
}

void LightBridgeSession::send(std::uint16_t topic, const std::vector<std::uint8_t>& payload,
                              SessionOutput& out) {
  rosserial::appendFrame(topic, payload.data(), payload.size(), out.tx);
}

void LightBridgeSession::onOpened(double now, SessionOutput& out) {
  parser_.reset();
  state_ = LinkState::kNegotiating;
  has_lamp_report_ = false;
  report_overdue_ = false;
  last_rx_s_ = now;
  requestTopics(now, out);
}

void LightBridgeSession::onClosed(double now, SessionOutput& out) {
  loseLink("serial port closed", LinkState::kClosed, out);
  parser_.reset();
  announced_.clear();
  cmd_id_ = state_id_ = levels_id_ = 0;
}

void LightBridgeSession::requestTopics(double now, SessionOutput& out) {
  if (state_ != LinkState::kSynced) {  // a synced device re-announces the same ids
    announced_.clear();
    cmd_id_ = state_id_ = levels_id_ = 0;
  }
  send(rosserial::kIdPublisher, {}, out);
  ++counters_.topic_requests;
  last_request_s_ = now;
}

bool LightBridgeSession::commandStale(double now) const {
  return !has_command_ || !(now - last_command_s_ < params_.cmd_stale_timeout_s);
}

bool LightBridgeSession::levelsStale(double now) const {
  return levels_.empty() || !(now - last_levels_s_ < params_.cmd_stale_timeout_s);
}

bool LightBridgeSession::commandInForce(double now) const { return commandStale(now) || command_; }

void LightBridgeSession::sendCommand(double now, SessionOutput& out) {
  const bool stale = commandStale(now);
  if (stale) ++counters_.stale_commands;
  std::vector<std::uint8_t> payload;
  rosserial::serializeBool(stale ? true : command_, payload);
  send(cmd_id_, payload, out);
  ++counters_.commands_sent;
  out.command_sent = true;
  last_heartbeat_s_ = now;
  sendLevels(now, out);
}

void LightBridgeSession::sendLevels(double now, SessionOutput& out) {
  if (levels_id_ == 0) return;
  const bool stale = commandStale(now) || levelsStale(now);
  std::vector<std::uint8_t> payload;
  rosserial::serializeUInt8Array(stale ? std::vector<std::uint8_t>(std::max<std::size_t>(1, levels_.size()), 255)
                                       : levels_, payload);
  send(levels_id_, payload, out);
  ++counters_.levels_sent;
}

void LightBridgeSession::onLevels(const std::vector<std::uint8_t>& levels, double now, SessionOutput& out) {
  // Changed, or back after the fail-safe's 255s: sent at once; else with the next heartbeat.
  const bool changed = levelsStale(now) || levels != levels_;
  levels_ = levels;
  last_levels_s_ = now;
  if (changed && state_ == LinkState::kSynced) sendLevels(now, out);
}

void LightBridgeSession::onCommand(bool on, double now, SessionOutput& out) {
  has_command_ = true;
  command_ = on;
  last_command_s_ = now;
  if (state_ == LinkState::kSynced) sendCommand(now, out);
}

void LightBridgeSession::txStop(SessionOutput& out) {
  if (state_ == LinkState::kClosed) return;
  send(rosserial::kIdTxStop, {}, out);
}

void LightBridgeSession::onBytes(const std::uint8_t* data, std::size_t size, double now,
                                 const rosserial::Stamp& ros_now, SessionOutput& out) {
  if (state_ == LinkState::kClosed) return;
  std::vector<Frame> frames;
  parser_.feed(data, size, now, frames);
  for (const Frame& f : frames) handleFrame(f, now, ros_now, out);
}

void LightBridgeSession::tick(double now, const rosserial::Stamp& ros_now, SessionOutput& out) {
  if (state_ == LinkState::kClosed) return;
  std::vector<Frame> frames;
  parser_.poll(now, frames);
  for (const Frame& f : frames) handleFrame(f, now, ros_now, out);

  if (state_ == LinkState::kSynced) {
    if (!(now - last_rx_s_ < params_.link_timeout_s)) {
      std::ostringstream s;
      s << "no frame from the device for " << (now - last_rx_s_) << " s (link_timeout_s "
        << params_.link_timeout_s << "): device lost, requesting its topics again";
      loseLink(s.str(), LinkState::kNegotiating, out);
      requestTopics(now, out);
      return;
    }
    const bool overdue = has_lamp_report_ && !(now - last_lamp_report_s_ < params_.lamp_report_timeout_s);
    if (overdue && !report_overdue_) {
      ++counters_.overdue_reports;
      std::ostringstream s;
      s << "no lamp state from the device for " << (now - last_lamp_report_s_)
        << " s (lamp_report_timeout_s " << params_.lamp_report_timeout_s
        << "): lamp status unknown, the device fails safe ON";
      event(out, SessionEvent::kWarning, s.str());
    }
    report_overdue_ = overdue;
    if (now - last_heartbeat_s_ >= 1.0 / params_.heartbeat_hz - 1e-9) sendCommand(now, out);
    return;
  }
  if (now - last_request_s_ >= params_.negotiation_retry_s) {
    if (state_ == LinkState::kNegotiating && !announced_.empty() && cmd_id_ == 0) {
      std::ostringstream s;
      s << "the device announced " << announced_.size() << " topic(s) but no subscriber '"
        << params_.device_cmd_topic << "':";
      for (const auto& kv : announced_) s << ' ' << describe(kv.second);
      s << "; set ~device_cmd_topic or reflash the device";
      error(out, SessionError::kNoCommandSubscriber, s.str());
    }
    requestTopics(now, out);
  }
}

void LightBridgeSession::handleFrame(const Frame& f, double now, const rosserial::Stamp& ros_now,
                                     SessionOutput& out) {
  last_rx_s_ = now;
  switch (f.topic) {
    case rosserial::kIdPublisher:
    case rosserial::kIdSubscriber:
    case rosserial::kIdServiceServer:
    case rosserial::kIdServiceServer + 1:
    case rosserial::kIdServiceClient:
    case rosserial::kIdServiceClient + 1:
      handleTopicInfo(f, now, out);
      return;
    case rosserial::kIdLog: {
      rosserial::LogMessage log;
      if (!rosserial::deserialize(f.payload.data(), f.payload.size(), log)) {
        ++counters_.bad_payloads;
        error(out, SessionError::kMalformedLog,
              "malformed rosserial_msgs/Log payload from the device");
        return;
      }
      ++counters_.device_logs;
      SessionEvent e;
      e.kind = SessionEvent::kDeviceLog;
      e.level = log.level;
      e.text = std::move(log.msg);
      out.events.push_back(std::move(e));
      return;
    }
    case rosserial::kIdTime: {
      std::vector<std::uint8_t> payload;
      rosserial::serialize(ros_now, payload);
      send(rosserial::kIdTime, payload, out);
      ++counters_.time_replies;
      return;
    }
    case rosserial::kIdParameterRequest: {
      ++counters_.unsupported;
      if (!warned_unsupported_) {
        warned_unsupported_ = true;
        event(out, SessionEvent::kWarning,
              "the device requested a parameter: parameters are not served, it gets an empty answer");
      }
      // rosserial_msgs/RequestParamResponse with no ints, floats or strings.
      send(rosserial::kIdParameterRequest, std::vector<std::uint8_t>(12, 0), out);
      return;
    }
    case rosserial::kIdTxStop:
      loseLink("the device sent TX stop", LinkState::kNegotiating, out);
      requestTopics(now, out);
      return;
    default:
      break;
  }
  if (state_id_ != 0 && f.topic == state_id_) {
    bool on = true;
    if (!rosserial::deserializeBool(f.payload.data(), f.payload.size(), on)) {
      ++counters_.bad_payloads;
      error(out, SessionError::kMalformedLampState, "malformed std_msgs/Bool payload on '" +
                                           params_.device_state_topic + "' (" +
                                           std::to_string(f.payload.size()) + " bytes)");
      return;
    }
    ++counters_.lamp_reports;
    has_lamp_report_ = true;
    report_overdue_ = false;
    lamp_report_ = on;
    last_lamp_report_s_ = now;
    SessionEvent e;
    e.kind = SessionEvent::kLampState;
    e.value = on;
    out.events.push_back(std::move(e));
    return;
  }
  if (announced_.count(f.topic)) return;  // a device topic the bridge does not serve
  ++counters_.unknown_topics;
  if (state_ == LinkState::kSynced && now - last_request_s_ >= params_.negotiation_retry_s) {
    event(out, SessionEvent::kWarning, "frame on topic id " + std::to_string(f.topic) +
                                           " that the device never announced: requesting its topics");
    requestTopics(now, out);
  }
}

void LightBridgeSession::handleTopicInfo(const Frame& f, double now, SessionOutput& out) {
  TopicInfo t;
  if (!rosserial::deserialize(f.payload.data(), f.payload.size(), t) || t.topic_id < rosserial::kFirstUserTopic) {
    ++counters_.bad_payloads;
    error(out, SessionError::kMalformedTopicInfo,
          "malformed rosserial_msgs/TopicInfo from the device (" +
                                         std::to_string(f.payload.size()) + " bytes)");
    return;
  }
  const std::string name = stripSlash(t.topic_name);
  announced_[t.topic_id] = t;
  if (f.topic != rosserial::kIdPublisher && f.topic != rosserial::kIdSubscriber) {
    ++counters_.unsupported;
    if (!warned_unsupported_) {
      warned_unsupported_ = true;
      event(out, SessionEvent::kWarning, "the device announced service " + describe(t) +
                                             ": services are not served by the bridge");
    }
    return;
  }
  if (f.topic == rosserial::kIdSubscriber && name == stripSlash(params_.device_cmd_topic)) {
    if (!isBool(t)) {
      ++counters_.type_mismatches;
      cmd_id_ = 0;
      // A synced device re-announcing another type (reflashed, or another device on the port):
      // the link is down, not up with commands refused.
      loseLink("the device's command topic changed type", LinkState::kMismatch, out);
      error(out, SessionError::kCommandTypeMismatch,
            "the device subscribes " + describe(t) + " but the bridge serves " + rosserial::kBoolType +
                " (md5 " + rosserial::kBoolMd5 + "): refusing to send lamp commands; reflash the "
                "device with a std_msgs::Bool subscriber");
      return;
    }
    cmd_id_ = t.topic_id;
    if (state_ != LinkState::kSynced) {
      state_ = LinkState::kSynced;
      ++counters_.link_ups;
      last_rx_s_ = now;
      event(out, SessionEvent::kLinkUp, "device subscriber " + describe(t) + " negotiated");
      sendCommand(now, out);  // the device leaves its power-up fail-safe as soon as it may
    }
    return;
  }
  if (f.topic == rosserial::kIdSubscriber && !params_.device_levels_topic.empty() &&
      name == stripSlash(params_.device_levels_topic)) {
    if (t.message_type != rosserial::kUInt8ArrayType || t.md5sum != rosserial::kUInt8ArrayMd5) {
      ++counters_.type_mismatches;
      levels_id_ = 0;
      error(out, SessionError::kLevelsTypeMismatch,
            "the device subscribes " + describe(t) + " but the bridge sends segment levels as " +
                rosserial::kUInt8ArrayType + ": no levels sent (the binary command goes on)");
      return;
    }
    levels_id_ = t.topic_id;
    if (state_ == LinkState::kSynced) sendLevels(now, out);
    return;
  }
  if (f.topic == rosserial::kIdPublisher && !params_.device_state_topic.empty() &&
      name == stripSlash(params_.device_state_topic)) {
    if (!isBool(t)) {
      ++counters_.type_mismatches;
      state_id_ = 0;
      error(out, SessionError::kStateTypeMismatch,
            "the device publishes " + describe(t) + " but the bridge expects " + rosserial::kBoolType +
                " (md5 " + rosserial::kBoolMd5 + "): its lamp state is not republished");
      return;
    }
    state_id_ = t.topic_id;
    return;
  }
  event(out, SessionEvent::kInfo, std::string("the device ") +
                                      (f.topic == rosserial::kIdPublisher ? "publishes " : "subscribes ") +
                                      describe(t) + ", which the bridge does not serve");
}

}  // namespace icanc
