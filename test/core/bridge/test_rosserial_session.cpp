// Pins the bridge's host session against an in-memory rosserial device (the same device model the
// pseudo-terminal emulator uses) with the sketch's fail-safe logic: negotiation, time replies,
// commands and heartbeat, staleness, link loss and recovery, device reset mid-frame, type
// mismatches refused, faults on the wire survived.
#include <gtest/gtest.h>

#include <algorithm>

#include "../../../firmware/icanc_headlight/headlight_logic.h"
#include "icanc/core/bridge/rosserial_device.hpp"
#include "icanc/core/bridge/rosserial_session.hpp"

namespace icanc {
namespace {

using rosserial::Stamp;
using Bytes = std::vector<std::uint8_t>;

const Bytes kRequestTopics = {0xFF, 0xFE, 0x00, 0x00, 0xFF, 0x00, 0x00, 0xFF};
const Bytes kBoolTrue100 = {0xFF, 0xFE, 0x01, 0x00, 0xFE, 0x64, 0x00, 0x01, 0x9A};
const Bytes kBoolFalse100 = {0xFF, 0xFE, 0x01, 0x00, 0xFE, 0x64, 0x00, 0x00, 0x9B};
const Bytes kTimeRequest = {0xFF, 0xFE, 0x08, 0x00, 0xF7, 0x0A, 0x00, 0, 0, 0, 0, 0, 0, 0, 0, 0xF5};
const Bytes kTimeReply = {0xFF, 0xFE, 0x08, 0x00, 0xF7, 0x0A, 0x00, 0x00, 0xF1, 0x53,
                          0x65, 0x00, 0x65, 0xCD, 0x1D, 0xFD};
constexpr const char* kInt32Md5 = "da5909fbe378aeaf85e547e830cc1bb7";

bool contains(const Bytes& hay, const Bytes& needle) {
  return std::search(hay.begin(), hay.end(), needle.begin(), needle.end()) != hay.end();
}

// The host session and an emulated icanc_headlight sketch, wired back to back, 10 ms steps.
struct Bench {
  explicit Bench(const std::string& cmd_type = rosserial::kBoolType,
                 const std::string& cmd_md5 = rosserial::kBoolMd5,
                 const std::string& state_type = rosserial::kBoolType,
                 const std::string& state_md5 = rosserial::kBoolMd5, bool with_cmd = true,
                 bool with_state = true)
      : host(params()), logic(500) {
    // Without a state publisher: a stock subscribe-only sketch, which sends only time requests.
    if (with_state) state_id = device.advertise("lamp_state", state_type, state_md5);
    if (with_cmd)
      device.subscribe("lamp_cmd", cmd_type, cmd_md5, [this](const std::uint8_t* d, std::size_t n) {
        ++device_commands;
        bool v = true;
        if (rosserial::deserializeBool(d, n, v)) {
          logic.onCommand(v, ms());
          device_values.push_back(v);
        }
      });
  }
  static LightBridgeParams params() { return LightBridgeParams(); }
  std::uint32_t ms() const { return static_cast<std::uint32_t>(now * 1000.0 + 0.5); }

  void collect(SessionOutput& out) {
    to_device.insert(to_device.end(), out.tx.begin(), out.tx.end());
    host_tx.insert(host_tx.end(), out.tx.begin(), out.tx.end());
    for (auto& e : out.events) events.push_back(e);
    out = SessionOutput();
  }
  void open() {
    SessionOutput out;
    host.onOpened(now, out);
    collect(out);
  }
  // One 10 ms step: host tick, device spin (with the sketch's loop), host reads.
  void step() {
    now += 0.01;
    SessionOutput out;
    host.tick(now, ros_now, out);
    collect(out);
    Bytes to_host;
    if (cable) device.receive(to_device.data(), to_device.size(), ms(), to_host);
    to_device.clear();
    device.spinOnce(ms(), to_host);
    lamp_on = logic.update(device.connected(), ms());
    if (state_id != 0 && ms() - last_state_ms >= 100) {
      device.publish(state_id, Bytes{static_cast<std::uint8_t>(lamp_on)}, to_host);
      last_state_ms = ms();
    }
    to_host.insert(to_host.begin(), inject.begin(), inject.end());
    inject.clear();
    if (cable) host.onBytes(to_host.data(), to_host.size(), now, ros_now, out);
    collect(out);
  }
  void run(double seconds) {
    const int n = static_cast<int>(seconds / 0.01 + 0.5);
    for (int i = 0; i < n; ++i) step();
  }
  void command(bool on) {
    SessionOutput out;
    host.onCommand(on, now, out);
    collect(out);
  }
  int count(SessionEvent::Kind kind) const {
    return static_cast<int>(std::count_if(events.begin(), events.end(), [&](const SessionEvent& e) { return e.kind == kind; }));
  }
  std::string allText(SessionEvent::Kind kind) const {
    std::string s;
    for (const auto& e : events)
      if (e.kind == kind) s += e.text + "\n";
    return s;
  }

  double now = 0.0;
  Stamp ros_now{1700000000u, 500000000u};
  LightBridgeSession host;
  rosserial::RosserialDevice device;
  icanc_fw::HeadlightLogic logic;
  std::uint16_t state_id = 0;
  bool cable = true;
  bool lamp_on = true;
  std::uint32_t last_state_ms = 0;
  int device_commands = 0;
  std::vector<bool> device_values;
  Bytes to_device, host_tx, inject;
  std::vector<SessionEvent> events;
};

TEST(LightBridgeSession, ValidateNamesTheBadParameter) {
  EXPECT_EQ(validate(LightBridgeParams()), "");
  LightBridgeParams p;
  p.heartbeat_hz = 0.0;
  EXPECT_NE(validate(p).find("heartbeat_hz"), std::string::npos);
  p = LightBridgeParams();
  p.link_timeout_s = 0.05;  // shorter than one heartbeat period
  EXPECT_NE(validate(p).find("link_timeout_s"), std::string::npos);
  p = LightBridgeParams();
  p.device_cmd_topic = "";
  EXPECT_NE(validate(p).find("device_cmd_topic"), std::string::npos);
  p = LightBridgeParams();
  p.max_payload_bytes = 10;
  EXPECT_NE(validate(p).find("max_payload_bytes"), std::string::npos);
}

TEST(LightBridgeSession, OpeningRequestsTopicsByteExact) {
  LightBridgeSession s;
  SessionOutput out;
  EXPECT_EQ(s.state(), LinkState::kClosed);
  s.onOpened(0.0, out);
  EXPECT_EQ(out.tx, kRequestTopics);
  EXPECT_EQ(s.state(), LinkState::kNegotiating);
  // Repeated every negotiation_retry_s while the device stays silent.
  out = SessionOutput();
  s.tick(0.99, Stamp(), out);
  EXPECT_TRUE(out.tx.empty());
  s.tick(1.0, Stamp(), out);
  EXPECT_EQ(out.tx, kRequestTopics);
  EXPECT_EQ(s.counters().topic_requests, 2u);
}

TEST(LightBridgeSession, TimeRequestIsAnsweredWithRosTimeByteExact) {
  LightBridgeSession s;
  SessionOutput out;
  s.onOpened(0.0, out);
  out = SessionOutput();
  s.onBytes(kTimeRequest.data(), kTimeRequest.size(), 0.1, Stamp{1700000000u, 500000000u}, out);
  EXPECT_EQ(out.tx, kTimeReply);
  EXPECT_EQ(s.counters().time_replies, 1u);
}

TEST(LightBridgeSession, NegotiatesWithTheDeviceAndCommandsAtOnce) {
  Bench b;
  b.open();
  b.run(0.05);
  ASSERT_EQ(b.host.state(), LinkState::kSynced) << b.allText(SessionEvent::kError);
  EXPECT_EQ(b.host.cmdTopicId(), 100);
  EXPECT_EQ(b.host.stateTopicId(), 125);  // 100 + ros_lib's 25 subscriber slots
  EXPECT_EQ(b.count(SessionEvent::kLinkUp), 1);
  EXPECT_TRUE(b.device.connected());
  EXPECT_TRUE(b.device.timeSynced());
  EXPECT_EQ(b.device.lastTime().sec, 1700000000u);
  // No lamp_cmd from ROS yet: the first command is ON (fail-safe), byte-exact.
  EXPECT_TRUE(contains(b.host_tx, kBoolTrue100));
  EXPECT_GE(b.device_commands, 1);
  EXPECT_TRUE(b.lamp_on);

  b.host_tx.clear();
  b.command(false);
  EXPECT_EQ(b.host_tx, kBoolFalse100);  // sent at once, not at the next heartbeat
  b.run(0.2);
  EXPECT_FALSE(b.lamp_on);
  EXPECT_EQ(b.logic.reason(), icanc_fw::kCommandedOff);
  ASSERT_TRUE(b.host.hasLampReport());
  EXPECT_FALSE(b.host.lampReport());
  EXPECT_GT(b.count(SessionEvent::kLampState), 0);
}

TEST(LightBridgeSession, HeartbeatRepeatsTheCommandThenFailsSafeWhenLampCmdStops) {
  Bench b;
  b.open();
  b.run(0.05);
  b.command(false);
  const int before = b.device_commands;
  b.run(0.9);  // lamp_cmd given once, 0.9 s ago: still in force, repeated at 10 Hz
  EXPECT_GE(b.device_commands - before, 8);
  EXPECT_LE(b.device_commands - before, 10);
  EXPECT_FALSE(b.lamp_on);
  for (std::size_t i = 1; i < b.device_values.size(); ++i) EXPECT_FALSE(b.device_values[i]);
  // Past cmd_stale_timeout_s (1 s) without lamp_cmd: the heartbeat commands ON.
  b.run(0.3);
  EXPECT_TRUE(b.device_values.back());
  EXPECT_TRUE(b.lamp_on);
  EXPECT_GT(b.host.counters().stale_commands, 0u);
  // lamp_cmd resumes: OFF again at once.
  b.command(false);
  b.run(0.02);
  EXPECT_FALSE(b.lamp_on);
}

TEST(LightBridgeSession, SilentDeviceIsLostAfterTheLinkTimeoutAndRenegotiated) {
  Bench b;
  b.open();
  b.run(0.05);
  b.command(false);
  b.run(0.2);
  ASSERT_TRUE(b.host.synced());
  b.cable = false;  // unplugged: nothing either way
  const double cut = b.now;
  while (b.host.synced() && b.now < cut + 10.0) {
    b.command(false);
    b.step();
  }
  EXPECT_FALSE(b.host.synced());
  // link_timeout_s, to the last report before the cut
  EXPECT_NEAR(b.now - cut, b.host.params().link_timeout_s, 0.12);
  EXPECT_EQ(b.host.lampStatus(), LampStatus::kUnknownFailSafe);
  EXPECT_EQ(b.count(SessionEvent::kLinkLost), 1);
  EXPECT_EQ(b.host.counters().link_losses, 1u);
  // The device, cut off, fails safe within its command timeout.
  EXPECT_TRUE(b.lamp_on);
  b.cable = true;
  b.run(1.1);  // the next topic request (every negotiation_retry_s) reaches it
  EXPECT_EQ(b.host.lampStatus(), LampStatus::kOn) << "the device's report on the new link";
  b.command(false);
  b.run(0.05);
  EXPECT_TRUE(b.host.synced());
  EXPECT_EQ(b.host.counters().link_ups, 2u);
  EXPECT_FALSE(b.lamp_on);
}

TEST(LightBridgeSession, DeviceResetMidFrameIsSurvived) {
  Bench b;
  b.open();
  b.run(0.05);
  b.command(false);
  b.run(0.2);
  ASSERT_FALSE(b.lamp_on);
  // Half a lamp_state frame, then the board resets (ros_lib comes back unconfigured and silent).
  const Bytes state_frame = rosserial::encodeFrame(b.state_id, {0});
  b.inject.assign(state_frame.begin(), state_frame.begin() + 5);
  b.device.powerCycle();
  b.step();
  b.run(0.2);
  EXPECT_EQ(b.host.parserCounters().truncated, 1u);
  EXPECT_TRUE(b.lamp_on) << "a reset device is not connected: lamp ON";
  const double t0 = b.now;
  while (b.now < t0 + 10.0 && !(b.host.synced() && b.host.counters().link_ups == 2)) {
    b.command(false);
    b.step();
  }
  EXPECT_EQ(b.host.counters().link_losses, 1u);
  EXPECT_EQ(b.host.counters().link_ups, 2u);
  b.command(false);
  b.run(0.05);
  EXPECT_FALSE(b.lamp_on);
}

TEST(LightBridgeSession, FaultsOnTheWireAreCountedWithoutLosingTheLink) {
  Bench b;
  b.open();
  b.run(0.05);
  const auto faults = [&](int i) -> Bytes {
    Bytes f = rosserial::encodeFrame(b.state_id, {1});
    switch (i % 5) {
      case 0: return Bytes{0x00, 0xFF, 0x13, 0x37, 0xFE, 0xFF};  // garbage
      case 1: f[4] ^= 0x10; return f;                          // bad length checksum
      case 2: f.back() ^= 0x01; return f;                      // bad message checksum
      case 3: return Bytes{0xFF, 0xFE, 0x00, 0x40, 0xBF};      // oversized length
      default: return Bytes(f.begin(), f.begin() + 6);         // truncated (then a gap)
    }
  };
  for (int i = 0; i < 50; ++i) {
    b.command(false);
    b.inject = faults(i);
    b.step();
    b.run(0.15);
  }
  const auto& c = b.host.parserCounters();
  EXPECT_GT(c.garbage_bytes, 0u);
  EXPECT_GE(c.bad_length_checksum, 10u);
  EXPECT_GE(c.bad_message_checksum, 10u);
  EXPECT_GE(c.oversize_length, 10u);
  // A cut-off frame is either abandoned after frame_timeout_s (truncated) or, when the device's
  // next frame follows sooner, completed with its bytes and rejected by the checksum; both rescan.
  EXPECT_GE(c.truncated + c.bad_message_checksum, 20u);
  EXPECT_EQ(b.host.counters().link_losses, 0u);
  EXPECT_TRUE(b.host.synced());
  EXPECT_FALSE(b.lamp_on);
  EXPECT_FALSE(b.host.lampReport()) << "corrupted 'ON' reports must not be taken for real ones";
}

TEST(LightBridgeSession, CommandTypeMismatchIsRefused) {
  Bench b("std_msgs/Int32", kInt32Md5);
  b.open();
  b.run(0.05);
  EXPECT_EQ(b.host.state(), LinkState::kMismatch);
  const std::string errors = b.allText(SessionEvent::kError);
  EXPECT_NE(errors.find("std_msgs/Int32"), std::string::npos) << errors;
  EXPECT_NE(errors.find(kInt32Md5), std::string::npos) << errors;
  EXPECT_NE(errors.find(rosserial::kBoolMd5), std::string::npos) << errors;
  EXPECT_NE(errors.find("refusing"), std::string::npos) << errors;
  b.command(false);
  b.run(2.0);
  EXPECT_EQ(b.device_commands, 0) << "nothing may be sent to a subscriber of another type";
  EXPECT_EQ(b.host.counters().commands_sent, 0u);
  EXPECT_GE(b.host.counters().type_mismatches, 1u);
  EXPECT_TRUE(b.lamp_on);
}

TEST(LightBridgeSession, StatePublisherMismatchIsNotRepublished) {
  Bench b(rosserial::kBoolType, rosserial::kBoolMd5, "std_msgs/Int32", kInt32Md5);
  b.open();
  b.run(0.5);
  EXPECT_TRUE(b.host.synced());  // commands still flow
  EXPECT_EQ(b.host.stateTopicId(), 0);
  EXPECT_NE(b.allText(SessionEvent::kError).find("not republished"), std::string::npos);
  EXPECT_EQ(b.count(SessionEvent::kLampState), 0);
}

TEST(LightBridgeSession, MissingCommandSubscriberIsNamed) {
  Bench b(rosserial::kBoolType, rosserial::kBoolMd5, rosserial::kBoolType, rosserial::kBoolMd5, false);
  b.open();
  b.run(1.1);
  EXPECT_EQ(b.host.state(), LinkState::kNegotiating);
  const std::string errors = b.allText(SessionEvent::kError);
  EXPECT_NE(errors.find("no subscriber 'lamp_cmd'"), std::string::npos) << errors;
  EXPECT_NE(errors.find("'lamp_state'"), std::string::npos) << errors;
}

TEST(LightBridgeSession, DeviceLogsParametersAndUnknownTopics) {
  Bench b;
  b.open();
  b.run(0.05);
  Bytes tx;
  b.device.log(rosserial::LogMessage::kError, "lamp driver hot", tx);
  b.inject = tx;
  b.step();
  ASSERT_EQ(b.count(SessionEvent::kDeviceLog), 1);
  const auto log = *std::find_if(b.events.begin(), b.events.end(),
                                 [](const SessionEvent& e) { return e.kind == SessionEvent::kDeviceLog; });
  EXPECT_EQ(log.level, rosserial::LogMessage::kError);
  EXPECT_EQ(log.text, "lamp driver hot");

  // A parameter request gets an empty rosserial_msgs/RequestParamResponse (3 empty arrays).
  rosserial::Writer w(tx);
  tx.clear();
  w.str("~timeout");
  b.host_tx.clear();
  b.inject = rosserial::encodeFrame(rosserial::kIdParameterRequest, tx);
  b.step();
  EXPECT_TRUE(contains(b.host_tx, rosserial::encodeFrame(rosserial::kIdParameterRequest, Bytes(12, 0))));
  EXPECT_EQ(b.count(SessionEvent::kWarning), 1);

  // A frame on an id the device never announced: its topics are requested again (at most once
  // per negotiation_retry_s).
  b.run(1.0);
  b.host_tx.clear();
  b.inject = rosserial::encodeFrame(140, {1});
  b.step();
  EXPECT_EQ(b.host.counters().unknown_topics, 1u);
  EXPECT_TRUE(contains(b.host_tx, kRequestTopics));
  b.run(0.1);
  EXPECT_TRUE(b.host.synced());
  EXPECT_EQ(b.host.cmdTopicId(), 100);
}

TEST(LightBridgeSession, TxStopAndPortClosed) {
  Bench b;
  b.open();
  b.run(0.05);
  b.command(false);
  b.run(0.1);
  SessionOutput out;
  b.host.txStop(out);
  EXPECT_EQ(out.tx, (Bytes{0xFF, 0xFE, 0x00, 0x00, 0xFF, 0x0B, 0x00, 0xF4}));
  b.collect(out);
  b.step();
  EXPECT_EQ(b.device.txStops(), 1u);
  EXPECT_FALSE(b.device.connected());
  EXPECT_TRUE(b.lamp_on);
  b.host.onClosed(b.now, out);
  EXPECT_EQ(b.host.state(), LinkState::kClosed);
  EXPECT_EQ(out.events.size(), 1u);
  EXPECT_EQ(out.events[0].kind, SessionEvent::kLinkLost);
  out = SessionOutput();
  b.host.onCommand(false, b.now, out);
  b.host.tick(b.now + 5.0, Stamp(), out);
  EXPECT_TRUE(out.tx.empty()) << "a closed port gets no bytes";
}

}  // namespace
}  // namespace icanc

namespace icanc {
namespace {

TEST(LightBridgeSession, StockSubscribeOnlyDeviceIsKeptByItsTimeRequests) {
  // ros_lib with one subscriber and no publisher sends nothing but a time request every 2.5 s
  // (with a 1 s link timeout it was dropped and resynced every second).
  Bench b(rosserial::kBoolType, rosserial::kBoolMd5, rosserial::kBoolType, rosserial::kBoolMd5, true,
          false);
  EXPECT_GE(LightBridgeParams().link_timeout_s, 5.0) << "two ros_lib time-sync periods at least";
  b.open();
  b.run(0.05);
  ASSERT_TRUE(b.host.synced());
  EXPECT_EQ(b.host.lampStatus(), LampStatus::kNotReported);
  const std::uint64_t replies = b.host.counters().time_replies;
  for (int i = 0; i < 200; ++i) {  // 20 s
    b.command(false);
    b.run(0.1);
  }
  EXPECT_TRUE(b.host.synced());
  EXPECT_EQ(b.host.counters().link_losses, 0u);
  EXPECT_EQ(b.count(SessionEvent::kLinkLost), 0);
  EXPECT_GE(b.host.counters().time_replies - replies, 7u);  // the device's only frames
  EXPECT_FALSE(b.lamp_on);
  // Cut off, it is still noticed, after link_timeout_s.
  b.cable = false;
  const double cut = b.now;
  while (b.host.synced() && b.now < cut + 10.0) b.step();
  EXPECT_FALSE(b.host.synced());
  EXPECT_LE(b.now - cut, b.host.params().link_timeout_s + 0.05);
  EXPECT_EQ(b.host.lampStatus(), LampStatus::kUnknownFailSafe);
}

TEST(LightBridgeSession, LampStatusIsReportedOnlyWhileSynced) {
  Bench b;
  EXPECT_EQ(b.host.lampStatus(), LampStatus::kUnknownFailSafe);  // port closed
  b.open();
  EXPECT_EQ(b.host.lampStatus(), LampStatus::kUnknownFailSafe);  // negotiating
  b.run(0.05);
  b.command(false);
  b.run(0.3);
  EXPECT_EQ(b.host.lampStatus(), LampStatus::kOff);
  b.command(true);
  b.run(0.3);
  EXPECT_EQ(b.host.lampStatus(), LampStatus::kOn);
  SessionOutput out;
  b.host.onClosed(b.now, out);
  EXPECT_EQ(b.host.lampStatus(), LampStatus::kUnknownFailSafe);
  EXPECT_FALSE(b.host.hasLampReport()) << "a report of a closed link is forgotten";
}

// A device that stops answering is ON by its own command timeout long before link_timeout_s drops
// the link: the lamp status says unknown (fail-safe) within lamp_report_timeout_s of its last
// report, counted and warned about once, and follows the reports again when they come back.
TEST(LightBridgeSession, SilentDeviceIsUnknownWithinTheReportTimeout) {
  Bench b;
  b.open();
  b.run(0.05);
  b.command(false);
  b.run(0.3);
  ASSERT_EQ(b.host.lampStatus(), LampStatus::kOff);
  const double timeout = b.host.params().lamp_report_timeout_s;
  EXPECT_LE(timeout, 0.5) << "no later than the sketch's command timeout";
  b.cable = false;
  const double cut = b.now;
  const double last_report = b.host.lastLampReportTime();
  while (b.host.lampStatus() == LampStatus::kOff && b.now < cut + 10.0) {
    b.command(false);
    b.step();
  }
  EXPECT_EQ(b.host.lampStatus(), LampStatus::kUnknownFailSafe);
  EXPECT_TRUE(b.host.synced()) << "the link itself is only dropped after link_timeout_s";
  EXPECT_NEAR(b.now - last_report, timeout, 0.015) << "unknown " << b.now - cut << " s after the cut";
  EXPECT_EQ(b.host.counters().overdue_reports, 1u);
  int warnings = 0;
  for (const auto& e : b.events) warnings += e.kind == SessionEvent::kWarning && e.text.find("lamp_report_timeout_s") != std::string::npos;
  EXPECT_EQ(warnings, 1);
  b.run(1.0);
  EXPECT_TRUE(b.lamp_on) << "the device, cut off, failed safe ON";
  EXPECT_EQ(b.host.lampStatus(), LampStatus::kUnknownFailSafe);
  EXPECT_EQ(b.host.counters().overdue_reports, 1u);
  b.cable = true;  // back before link_timeout_s: its reports count again
  b.run(0.3);
  EXPECT_TRUE(b.host.synced());
  EXPECT_NE(b.host.lampStatus(), LampStatus::kUnknownFailSafe);
  LightBridgeParams bad;
  bad.lamp_report_timeout_s = 0.0;
  EXPECT_NE(validate(bad).find("lamp_report_timeout_s"), std::string::npos);
  bad.lamp_report_timeout_s = bad.link_timeout_s + 1.0;
  EXPECT_NE(validate(bad).find("lamp_report_timeout_s"), std::string::npos);
}

TEST(LightBridgeSession, CommandTypeChangingWhileSyncedDropsTheLink) {
  Bench b;
  b.open();
  b.run(0.05);
  b.command(false);
  b.run(0.3);
  ASSERT_TRUE(b.host.synced());
  // The device re-announces its command subscriber with another type (reflashed in place).
  rosserial::TopicInfo t;
  t.topic_id = b.host.cmdTopicId();
  t.topic_name = "lamp_cmd";
  t.message_type = "std_msgs/Int32";
  t.md5sum = kInt32Md5;
  t.buffer_size = 512;
  Bytes payload;
  rosserial::serialize(t, payload);
  rosserial::appendFrame(rosserial::kIdSubscriber, payload.data(), payload.size(), b.inject);
  const int sent = b.device_commands;
  b.step();  // the frame reaches the host (the emulated device itself still has a Bool)
  EXPECT_EQ(b.host.state(), LinkState::kMismatch);
  EXPECT_FALSE(b.host.synced());
  EXPECT_EQ(b.count(SessionEvent::kLinkLost), 1) << "link_up must go false on a mismatch";
  EXPECT_EQ(b.host.counters().link_losses, 1u);
  EXPECT_EQ(b.host.lampStatus(), LampStatus::kUnknownFailSafe);
  EXPECT_EQ(b.device_commands, sent) << "no command after the mismatch";
  bool kind = false;
  for (const auto& e : b.events) kind |= e.error == SessionError::kCommandTypeMismatch;
  EXPECT_TRUE(kind);
  // The next negotiation finds the Bool subscriber again.
  b.run(1.1);
  EXPECT_TRUE(b.host.synced());
}

// The segmented lamp's levels on an optional std_msgs/UInt8MultiArray subscriber.
struct LevelsBench : Bench {
  explicit LevelsBench(const std::string& type = rosserial::kUInt8ArrayType,
                       const std::string& md5 = rosserial::kUInt8ArrayMd5) {
    LightBridgeParams p;
    p.device_levels_topic = "lamp_levels";
    host = LightBridgeSession(p);
    device.subscribe("lamp_levels", type, md5, [this](const std::uint8_t* d, std::size_t n) {
      Bytes levels;
      if (rosserial::deserializeUInt8Array(d, n, levels)) received.push_back(levels);
    });
  }
  void levels(const Bytes& l) {
    SessionOutput out;
    host.onLevels(l, now, out);
    collect(out);
  }
  std::vector<Bytes> received;
};

TEST(LightBridgeSession, SegmentLevelsGoWithTheCommandAndFailSafeAt255) {
  LevelsBench b;
  b.open();
  b.run(0.05);
  ASSERT_EQ(b.host.state(), LinkState::kSynced) << b.allText(SessionEvent::kError);
  ASSERT_NE(b.host.levelsTopicId(), 0);
  ASSERT_FALSE(b.received.empty());
  EXPECT_EQ(b.received.back(), Bytes{255});  // none from ROS yet: every segment on
  const Bytes lit{0, 0, 0, 153, 153, 0, 0, 0};
  b.command(false);
  std::uint64_t sent = b.host.counters().levels_sent;
  b.levels(lit);
  EXPECT_EQ(b.host.counters().levels_sent, sent + 1) << "changed levels are sent at once";
  b.levels(lit);  // unchanged: they wait for the heartbeat
  EXPECT_EQ(b.host.counters().levels_sent, sent + 1);
  b.step();
  EXPECT_EQ(b.received.back(), lit);
  const std::size_t before = b.received.size();
  b.run(0.55);
  EXPECT_GE(b.received.size() - before, 4u);  // with every heartbeat
  EXPECT_EQ(b.received.back(), lit);
  b.command(false);  // lamp_cmd goes on, the levels stop: stale after 1 s
  b.run(0.5);
  b.command(false);
  b.run(0.2);
  EXPECT_EQ(b.received.back(), Bytes(8, 255));
  b.levels(lit);
  b.step();
  EXPECT_EQ(b.received.back(), lit);
  b.run(1.2);  // lamp_cmd stale as well: the binary command ON, every segment 255
  EXPECT_TRUE(b.device_values.back());
  EXPECT_EQ(b.received.back(), Bytes(8, 255));
  EXPECT_GT(b.host.counters().levels_sent, 10u);
}

TEST(LightBridgeSession, SegmentLevelsOfAnotherTypeAreRefusedTheCommandGoesOn) {
  LevelsBench b(rosserial::kBoolType, rosserial::kBoolMd5);
  b.open();
  b.run(0.05);
  EXPECT_EQ(b.host.state(), LinkState::kSynced);
  EXPECT_EQ(b.host.levelsTopicId(), 0);
  EXPECT_NE(b.allText(SessionEvent::kError).find("std_msgs/UInt8MultiArray"), std::string::npos);
  b.command(false);
  b.levels(Bytes{0, 255});
  b.run(0.2);
  EXPECT_FALSE(b.lamp_on);
  EXPECT_TRUE(b.received.empty());
  LightBridgeParams p;
  p.device_levels_topic = p.device_cmd_topic;
  EXPECT_NE(validate(p).find("device_levels_topic"), std::string::npos);
  // The payload: empty layout, then the bytes; a truncated one is refused.
  Bytes payload, back;
  rosserial::serializeUInt8Array(Bytes{1, 2, 3}, payload);
  EXPECT_EQ(payload, (Bytes{0, 0, 0, 0, 0, 0, 0, 0, 3, 0, 0, 0, 1, 2, 3}));
  ASSERT_TRUE(rosserial::deserializeUInt8Array(payload.data(), payload.size(), back));
  EXPECT_EQ(back, (Bytes{1, 2, 3}));
  EXPECT_FALSE(rosserial::deserializeUInt8Array(payload.data(), payload.size() - 1, back));
}

TEST(ErrorThrottle, EachKindHasItsOwnPeriod) {
  ErrorThrottle t(10.0);
  std::uint64_t held = 99;
  EXPECT_TRUE(t.allow(SessionError::kMalformedTopicInfo, 0.0, held));
  EXPECT_EQ(held, 0u);
  EXPECT_FALSE(t.allow(SessionError::kMalformedTopicInfo, 1.0, held));
  // Another kind right after is printed (one shared throttle once hid it).
  EXPECT_TRUE(t.allow(SessionError::kCommandTypeMismatch, 1.5, held));
  EXPECT_FALSE(t.allow(SessionError::kCommandTypeMismatch, 2.0, held));
  EXPECT_FALSE(t.allow(SessionError::kMalformedTopicInfo, 9.9, held));
  EXPECT_TRUE(t.allow(SessionError::kMalformedTopicInfo, 10.0, held));
  EXPECT_EQ(held, 2u) << "the ones held back are counted";
  EXPECT_TRUE(t.allow(SessionError::kCommandTypeMismatch, 11.5, held));
  EXPECT_EQ(held, 1u);
}

TEST(LightBridgeSession, ErrorEventsNameTheirKind) {
  Bench b("std_msgs/Int32", kInt32Md5);
  b.inject = rosserial::encodeFrame(rosserial::kIdPublisher, {0x01, 0x02});  // a 2-byte TopicInfo
  b.open();
  b.run(0.05);
  std::vector<SessionError> kinds;
  for (const auto& e : b.events)
    if (e.kind == SessionEvent::kError) kinds.push_back(e.error);
  EXPECT_NE(std::find(kinds.begin(), kinds.end(), SessionError::kMalformedTopicInfo), kinds.end());
  EXPECT_NE(std::find(kinds.begin(), kinds.end(), SessionError::kCommandTypeMismatch), kinds.end());
  EXPECT_EQ(std::find(kinds.begin(), kinds.end(), SessionError::kNone), kinds.end());
}

}  // namespace
}  // namespace icanc
