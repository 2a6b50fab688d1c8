// The host side of a rosserial link to the headlight device (icanc/LightBridge), without I/O:
// bytes in, bytes out, events out, time as an argument.
//
//   port opened --> kNegotiating: "request topics" now and every negotiation_retry_s
//   device announces a std_msgs/Bool subscriber named device_cmd_topic (TopicInfo on id 1)
//       md5 and type match --> kSynced: the lamp command is sent on every change and repeated at
//                              heartbeat_hz; the device's publisher device_state_topic is
//                              republished (kLampState events)
//       anything else       --> kMismatch: no command is ever sent; an error names both types
//   no good frame from the device for link_timeout_s --> kLinkLost event, back to kNegotiating
//       (any frame is life: a stock subscribe-only ros_lib device sends only its time requests,
//       one every 2.5 s, so the default timeout spans two of them)
//   a synced device re-announces the command topic with another type --> kLinkLost, kMismatch
//   port closed --> kClosed
//
// Also served: time requests (id 10, answered with std_msgs/Time = ros_now), device logs (id 7,
// kDeviceLog events), parameter requests (id 6, answered empty so the device's getParam fails
// fast), TX-stop from the host on shutdown (txStop()).
//
// Fail-safe: when no lamp command has come from ROS for cmd_stale_timeout_s (or none yet), the
// heartbeat commands the lamp ON.
//
// Segmented lamp (optional): when device_levels_topic is set and the device subscribes
// it as std_msgs/UInt8MultiArray, the segment levels (0..255 per segment, onLevels) go with every
// lamp command (changes and heartbeats) and at once when they change; when the lamp command or
// the levels are stale (cmd_stale_timeout_s, or none yet) every segment is sent at 255. A device
// with another type there is an error; the binary command goes on.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "icanc/core/bridge/rosserial_protocol.hpp"

namespace icanc {

struct LightBridgeParams {
  std::string device_cmd_topic = "lamp_cmd";      // the device's std_msgs/Bool subscriber
  std::string device_state_topic = "lamp_state";  // the device's std_msgs/Bool publisher ("" = none)
  std::string device_levels_topic;  // the device's std_msgs/UInt8MultiArray subscriber ("" = none)
  double heartbeat_hz = 10.0;          // command repeated at this rate even when unchanged [Hz]
  // No frame (of any kind, time requests included) from a synced device this long: link lost [s].
  // ros_lib requests the time every 2.5 s (SYNC_SECONDS * 500 ms) and may send nothing else;
  // rosserial_python waits 15 s. 6 s tolerates one lost time request.
  double link_timeout_s = 6.0;
  double negotiation_retry_s = 1.0;    // "request topics" repeated this often until synced [s]
  double cmd_stale_timeout_s = 1.0;    // no lamp_cmd from ROS this long: command ON [s]
  // A device that reported its lamp state and then reports nothing this long: lamp status
  // unknown (fail-safe) at once, not after link_timeout_s. The sketch reports every 100 ms and
  // turns its lamp ON after 500 ms without a command (COMMAND_TIMEOUT_MS), so a silent board
  // is, by then, ON or not running at all [s]; in (0, link_timeout_s].
  double lamp_report_timeout_s = 0.5;
  double frame_timeout_s = 0.1;        // a frame stalled this long mid-way is abandoned [s]
  int max_payload_bytes = 512;         // larger announced lengths are rejected (device buffer)
};

std::string validate(const LightBridgeParams& params);

// The parameter keys (the LightBridge nodelet's private parameters), for the ROS reader.
template <class Reader>
void visitParams(Reader& r, LightBridgeParams& p) {
  r("device_cmd_topic", p.device_cmd_topic);
  r("device_state_topic", p.device_state_topic);
  r("device_levels_topic", p.device_levels_topic);
  r("heartbeat_hz", p.heartbeat_hz);
  r("link_timeout_s", p.link_timeout_s);
  r("negotiation_retry_s", p.negotiation_retry_s);
  r("cmd_stale_timeout_s", p.cmd_stale_timeout_s);
  r("lamp_report_timeout_s", p.lamp_report_timeout_s);
  r("frame_timeout_s", p.frame_timeout_s);
  r("max_payload_bytes", p.max_payload_bytes);
}

enum class LinkState : std::uint8_t { kClosed = 0, kNegotiating = 1, kSynced = 2, kMismatch = 3 };
const char* toString(LinkState state);

// What an error event is about. The nodelet throttles each kind on its own (ErrorThrottle), so
// one repeated fault (a malformed TopicInfo every negotiation) cannot hide another (a command
// subscriber of the wrong type).
enum class SessionError : std::uint8_t {
  kNone = 0,
  kMalformedTopicInfo,
  kMalformedLog,
  kMalformedLampState,
  kCommandTypeMismatch,
  kStateTypeMismatch,
  kNoCommandSubscriber,
  kLevelsTypeMismatch,
  kCount
};

// The lamp as the host knows it (icanc/LampState's constants).
enum class LampStatus : std::uint8_t {
  kOff = 0,
  kOn = 1,
  kUnknownFailSafe = 2,  // link down, or the device's reports stopped (lamp_report_timeout_s):
                         // no report; the device's command timeout turns the lamp ON
  kNotReported = 3,      // link up, but the device publishes no lamp state (subscribe-only)
};
const char* toString(LampStatus status);

struct SessionEvent {
  enum Kind : std::uint8_t {
    kDeviceLog,   // level (rosserial_msgs/Log level), text
    kLampState,   // value: the lamp state the device reports
    kLinkUp,      // text: what was negotiated
    kLinkLost,    // text: why
    kError,       // text (type mismatch, malformed payload, ...)
    kWarning,     // text
    kInfo,        // text
  };
  Kind kind;
  std::string text;
  std::uint8_t level = 0;
  bool value = false;
  SessionError error = SessionError::kNone;  // kError events: what the error is about
};

// Per-kind throttle of error lines: the first error of a kind passes, then at most one per
// period_s of that kind; the ones held back are counted and reported with the next line.
class ErrorThrottle {
 public:
  explicit ErrorThrottle(double period_s) : period_s_(period_s) {}
  // True when a line may be printed at `now` [s]; `suppressed` is then the number of errors of
  // this kind held back since its previous line.
  bool allow(SessionError kind, double now, std::uint64_t& suppressed);

 private:
  static constexpr std::size_t kKinds = static_cast<std::size_t>(SessionError::kCount);
  double period_s_;
  double last_s_[kKinds] = {};
  bool printed_[kKinds] = {};
  std::uint64_t held_[kKinds] = {};
};

struct SessionOutput {
  std::vector<std::uint8_t> tx;        // bytes to write to the port, in order
  std::vector<SessionEvent> events;
  bool command_sent = false;           // tx holds a lamp command frame
};

struct SessionCounters {
  std::uint64_t topic_requests = 0;
  std::uint64_t commands_sent = 0;       // lamp command frames (changes + heartbeats)
  std::uint64_t levels_sent = 0;         // segment level frames
  std::uint64_t stale_commands = 0;      // heartbeats that commanded ON for want of lamp_cmd
  std::uint64_t time_replies = 0;
  std::uint64_t device_logs = 0;
  std::uint64_t lamp_reports = 0;
  std::uint64_t overdue_reports = 0;     // times the device's lamp reports stopped (status unknown)
  std::uint64_t link_ups = 0;
  std::uint64_t link_losses = 0;
  std::uint64_t type_mismatches = 0;     // announced topics refused for their type/md5
  std::uint64_t bad_payloads = 0;        // good frame, undecodable payload
  std::uint64_t unknown_topics = 0;      // frames on ids the device never announced
  std::uint64_t unsupported = 0;         // services, parameters
};

class LightBridgeSession {
 public:
  explicit LightBridgeSession(const LightBridgeParams& params = LightBridgeParams());

  // The port was opened at `now` [s]: forget the old device, request its topics.
  void onOpened(double now, SessionOutput& out);
  // The port is gone (unplugged, I/O error).
  void onClosed(double now, SessionOutput& out);
  // Bytes read from the port at `now`; `ros_now` answers time requests.
  void onBytes(const std::uint8_t* data, std::size_t size, double now, const rosserial::Stamp& ros_now,
               SessionOutput& out);
  // A lamp command from ROS: sent at once when synced and remembered for the heartbeat.
  void onCommand(bool on, double now, SessionOutput& out);
  // Segment levels from ROS (icanc/LampCommand as 0..255): sent at once when the device takes them.
  void onLevels(const std::vector<std::uint8_t>& levels, double now, SessionOutput& out);
  std::uint16_t levelsTopicId() const { return levels_id_; }
  // Advances the clock: heartbeat, link timeout, negotiation retries, stalled frames (a frame
  // found by the rescan of a stalled one may be a time request, answered with `ros_now`).
  void tick(double now, const rosserial::Stamp& ros_now, SessionOutput& out);
  // "Stop" for the device (sent on shutdown): it drops its configuration and fails safe ON.
  void txStop(SessionOutput& out);

  LinkState state() const { return state_; }
  bool synced() const { return state_ == LinkState::kSynced; }
  // What the lamp command in force is (the last lamp_cmd, or ON when stale / none yet).
  bool commandInForce(double now) const;
  // No lamp_cmd for cmd_stale_timeout_s, or none yet.
  bool commandStale(double now) const;
  // No lamp_command levels for cmd_stale_timeout_s, or none yet.
  bool levelsStale(double now) const;
  bool hasLampReport() const { return has_lamp_report_; }
  bool lampReport() const { return lamp_report_; }
  // Unknown (fail-safe) unless synced or while the reports are overdue (lamp_report_timeout_s,
  // as of the last tick); the report of this link only (forgotten when it drops).
  LampStatus lampStatus() const;
  bool lampReportOverdue() const { return report_overdue_; }
  double lastLampReportTime() const { return last_lamp_report_s_; }
  double lastRxTime() const { return last_rx_s_; }
  std::uint16_t cmdTopicId() const { return cmd_id_; }
  std::uint16_t stateTopicId() const { return state_id_; }
  const rosserial::ParserCounters& parserCounters() const { return parser_.counters(); }
  const SessionCounters& counters() const { return counters_; }
  const LightBridgeParams& params() const { return params_; }

 private:
  void handleFrame(const rosserial::Frame& frame, double now, const rosserial::Stamp& ros_now,
                   SessionOutput& out);
  void handleTopicInfo(const rosserial::Frame& frame, double now, SessionOutput& out);
  void requestTopics(double now, SessionOutput& out);
  void sendCommand(double now, SessionOutput& out);
  void sendLevels(double now, SessionOutput& out);
  void send(std::uint16_t topic, const std::vector<std::uint8_t>& payload, SessionOutput& out);
  static void event(SessionOutput& out, SessionEvent::Kind kind, std::string text);
  static void error(SessionOutput& out, SessionError kind, std::string text);
  // A synced link drops (kLinkLost event, counted, the lamp report forgotten); `next` is the state.
  void loseLink(const std::string& why, LinkState next, SessionOutput& out);

  LightBridgeParams params_;
  rosserial::FrameParser parser_;
  LinkState state_ = LinkState::kClosed;
  std::map<std::uint16_t, rosserial::TopicInfo> announced_;  // this negotiation's topics by id
  std::uint16_t cmd_id_ = 0;     // 0: not announced (0 is never a user topic)
  std::uint16_t state_id_ = 0;
  std::uint16_t levels_id_ = 0;
  std::vector<std::uint8_t> levels_;  // the last levels from ROS
  double last_levels_s_ = 0.0;
  double last_request_s_ = 0.0;
  double last_rx_s_ = 0.0;
  double last_heartbeat_s_ = 0.0;
  bool has_command_ = false;
  bool command_ = true;
  double last_command_s_ = 0.0;
  bool has_lamp_report_ = false;
  bool report_overdue_ = false;  // a device that reports went silent for lamp_report_timeout_s
  bool lamp_report_ = true;
  double last_lamp_report_s_ = 0.0;
  bool warned_unsupported_ = false;
  SessionCounters counters_;
};

}  // namespace icanc
