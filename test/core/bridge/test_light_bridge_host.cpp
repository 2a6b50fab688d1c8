// Pins what the LightBridge nodelet decides above the protocol: its port parameters, the levels
// it sends, when it reopens and checks the port, what reaches the log (device lines at most 20 a
// second, errors per kind every 10 s, wire faults once a second), when link_up and lamp_status
// are republished, and the diagnostics it reports.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "icanc/core/bridge/light_bridge_host.hpp"
#include "icanc/core/bridge/rosserial_device.hpp"

namespace icanc {
namespace {

using Bytes = std::vector<std::uint8_t>;

SessionEvent event(SessionEvent::Kind kind, const std::string& text, SessionError error = SessionError::kNone,
                   std::uint8_t level = 0) {
  SessionEvent e;
  e.kind = kind;
  e.text = text;
  e.error = error;
  e.level = level;
  return e;
}

std::string joined(const HostActions& a) {
  std::string s;
  for (const LogLine& l : a.logs) s += l.text + "\n";
  return s;
}

// The host and an emulated device with a lamp_cmd subscriber and a lamp_state publisher.
struct Bench {
  Bench() : host(LightBridgeParams(), "/dev/ttyTEST", 57600, 1.0) {
    state_id = device.advertise("lamp_state", rosserial::kBoolType, rosserial::kBoolMd5);
    device.subscribe("lamp_cmd", rosserial::kBoolType, rosserial::kBoolMd5, [](const std::uint8_t*, std::size_t) {});
  }
  HostActions open() {
    HostActions a;
    SessionOutput out;
    host.onOpened(now, out, a);
    return exchange(out, a);
  }
  // The host's bytes to the device, the device's answer back, then the host's decisions.
  HostActions exchange(SessionOutput& out, HostActions a = HostActions()) {
    const auto ms = static_cast<std::uint32_t>(now * 1000.0 + 0.5);
    Bytes to_host;
    device.receive(out.tx.data(), out.tx.size(), ms, to_host);
    device.spinOnce(ms, to_host);
    if (report) device.publish(state_id, Bytes{1}, to_host);
    host.afterStep(out, now, a);
    SessionOutput in;
    host.session().onBytes(to_host.data(), to_host.size(), now, rosserial::Stamp{1, 0}, in);
    host.session().tick(now, rosserial::Stamp{1, 0}, in);
    host.afterStep(in, now, a);
    if (!in.tx.empty()) {
      Bytes ignored;
      device.receive(in.tx.data(), in.tx.size(), ms, ignored);
    }
    return a;
  }
  HostActions step(double dt) {
    now += dt;
    SessionOutput out;
    host.session().tick(now, rosserial::Stamp{1, 0}, out);
    return exchange(out);
  }

  double now = 100.0;
  bool report = true;
  LightBridgeHost host;
  rosserial::RosserialDevice device;
  std::uint16_t state_id = 0;
};

TEST(LightBridgeHost, PortParametersAreValidated) {
  EXPECT_EQ(validatePort("/dev/ttyACM0", 57600, 1.0), "");
  EXPECT_EQ(validatePort("", 57600, 1.0), "port must be set (e.g. /dev/ttyACM0)");
  EXPECT_EQ(validatePort("/dev/ttyACM0", 12345, 1.0),
            "baud 12345 is not supported (9600 ... 921600; 57600 default)");
  EXPECT_EQ(validatePort("/dev/ttyACM0", 115200, 0.0), "reconnect_period_s must be > 0");
  LightBridgeParams p;
  EXPECT_EQ(linkTimeoutWarning(p), "");
  p.link_timeout_s = 2.0;
  EXPECT_NE(linkTimeoutWarning(p).find("link_timeout_s 2.00 s is shorter than two time requests"), std::string::npos);
}

TEST(LightBridgeHost, LevelsAreClampedAndNotANumberIsOn) {
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  EXPECT_EQ(deviceLevels({0.0f, 0.5f, 1.0f, -0.2f, 1.7f, nan, inf}), (Bytes{0, 128, 255, 0, 255, 255, 255}));
}

TEST(LightBridgeHost, ReopensEveryPeriodAndAtOnceAfterALoss) {
  LightBridgeHost host(LightBridgeParams(), "/dev/ttyTEST", 57600, 1.0);
  EXPECT_TRUE(host.openDue(10.0));
  EXPECT_FALSE(host.openDue(10.5));
  EXPECT_TRUE(host.openDue(11.0));
  EXPECT_FALSE(host.presenceCheckDue(11.5));
  EXPECT_TRUE(host.presenceCheckDue(12.0));
  EXPECT_FALSE(host.presenceCheckDue(12.5));
  SessionOutput out;
  HostActions a;
  host.onLost("unplugged", 12.5, out, a);
  ASSERT_EQ(a.logs.size(), 1u);
  EXPECT_EQ(a.logs[0].severity, LogSeverity::kError);
  EXPECT_EQ(a.logs[0].text, "headlight port /dev/ttyTEST lost: unplugged; reopening every 1.0 s (the device fails safe ON)");
  EXPECT_TRUE(host.openDue(12.5));
  const StatusReport r = host.report(12.5);
  EXPECT_EQ(r.level, StatusLevel::kError);
  EXPECT_EQ(r.message, "port /dev/ttyTEST not open: unplugged (device lamp fails safe ON)");
  EXPECT_EQ(r.value("port losses"), "1");
  EXPECT_EQ(r.value("link state"), "port closed");
}

TEST(LightBridgeHost, OpenFailuresAreCountedAndLoggedEveryTenSeconds) {
  LightBridgeHost host(LightBridgeParams(), "/dev/ttyTEST", 57600, 1.0);
  HostActions a;
  for (int i = 0; i < 12; ++i) host.onOpenFailed("No such file or directory", 10.0 + i, a);
  ASSERT_EQ(a.logs.size(), 2u);  // at 10 s and 20 s
  EXPECT_EQ(a.logs[0].severity, LogSeverity::kWarn);
  EXPECT_EQ(a.logs[0].text, "cannot open the headlight port: No such file or directory (retrying every 1.0 s; "
                            "the device keeps its lamp ON meanwhile)");
  EXPECT_EQ(host.report(22.0).value("open failures"), "12");
  EXPECT_EQ(host.report(22.0).value("last error"), "No such file or directory");
}

TEST(LightBridgeHost, SyncPublishesLinkUpAndTheLampStatusThenReportsOk) {
  Bench b;
  const LampStatusSnapshot start = b.host.statusPublished(b.now);
  EXPECT_EQ(start.status, LampStatus::kUnknownFailSafe);
  EXPECT_FALSE(start.link_up);
  EXPECT_TRUE(start.commanded_on);
  EXPECT_EQ(b.host.report(b.now).value("port opens"), "0");
  HostActions a = b.open();
  EXPECT_EQ(a.logs.at(0).text, "opened /dev/ttyTEST at 57600 baud: requesting the device's topics");
  for (int i = 0; i < 5 && !b.host.session().synced(); ++i) {
    HostActions more = b.step(0.01);
    a.logs.insert(a.logs.end(), more.logs.begin(), more.logs.end());
    a.lamp_states.insert(a.lamp_states.end(), more.lamp_states.begin(), more.lamp_states.end());
    a.publish_link |= more.publish_link;
    a.link_up |= more.link_up;
  }
  ASSERT_TRUE(b.host.session().synced()) << joined(a);
  EXPECT_TRUE(a.publish_link);
  EXPECT_TRUE(a.link_up);
  EXPECT_NE(joined(a).find("headlight device synced on /dev/ttyTEST: "), std::string::npos) << joined(a);
  // Reports republish lamp_state and lamp_status each time.
  HostActions r = b.step(0.01);
  ASSERT_FALSE(r.lamp_states.empty());
  EXPECT_TRUE(r.lamp_states.back());
  EXPECT_TRUE(r.publish_status);
  EXPECT_EQ(r.status.status, LampStatus::kOn);
  EXPECT_TRUE(r.status.link_up);
  EXPECT_FALSE(r.publish_link) << "link_up only on a change";
  // No lamp_cmd yet: the lamp is commanded ON, fail-safe.
  StatusReport rep = b.host.report(b.now);
  EXPECT_EQ(rep.level, StatusLevel::kWarn);
  EXPECT_EQ(rep.message, "synced; no lamp_cmd: commanding the lamp ON (fail-safe)");
  SessionOutput out;
  b.host.onCommand(false, b.now, out);
  EXPECT_TRUE(out.command_sent);
  b.host.onWritten(out.tx.size());
  b.host.onCommandLatency(2.0);
  HostActions c = b.exchange(out);
  EXPECT_TRUE(c.publish_status) << "the command in force changed";
  EXPECT_FALSE(c.status.commanded_on);
  rep = b.host.report(b.now);
  EXPECT_EQ(rep.level, StatusLevel::kOk);
  EXPECT_EQ(rep.message, "synced: lamp commanded OFF");
  EXPECT_EQ(rep.value("lamp_cmd received"), "1");
  EXPECT_EQ(rep.value("command latency samples"), "1");
  EXPECT_EQ(rep.value("command latency p50 [ms]"), "2");
  EXPECT_EQ(rep.value("tx bytes"), std::to_string(out.tx.size()));
  EXPECT_EQ(rep.value("lamp_command (segment levels) received"), "") << "no levels topic configured";
}

TEST(LightBridgeHost, UnknownStatusIsRepublishedOnceASecond) {
  LightBridgeHost host(LightBridgeParams(), "/dev/ttyTEST", 57600, 1.0);
  host.statusPublished(10.0);
  HostActions a;
  host.afterStep(SessionOutput(), 10.5, a);
  EXPECT_FALSE(a.publish_status);
  EXPECT_FALSE(a.publish_link);
  host.afterStep(SessionOutput(), 11.0, a);
  EXPECT_TRUE(a.publish_status);
  EXPECT_EQ(a.status.status, LampStatus::kUnknownFailSafe);
  HostActions b;
  host.afterStep(SessionOutput(), 11.5, b);
  EXPECT_FALSE(b.publish_status);
}

TEST(LightBridgeHost, DeviceLinesAreLimitedToTwentyASecond) {
  LightBridgeHost host(LightBridgeParams(), "/dev/ttyTEST", 57600, 1.0);
  SessionOutput out;
  for (int i = 0; i < 25; ++i)
    out.events.push_back(event(SessionEvent::kDeviceLog, "line", SessionError::kNone, rosserial::LogMessage::kWarn));
  HostActions a;
  host.afterStep(out, 10.0, a);
  ASSERT_EQ(a.logs.size(), 20u);
  EXPECT_EQ(a.logs[0].severity, LogSeverity::kWarn);
  EXPECT_EQ(a.logs[0].text, "[device] line");
  SessionOutput next;
  next.events.push_back(event(SessionEvent::kDeviceLog, "fatal", SessionError::kNone, rosserial::LogMessage::kFatal));
  HostActions b;
  host.afterStep(next, 11.0, b);
  ASSERT_EQ(b.logs.size(), 2u);
  EXPECT_EQ(b.logs[0].text, "[device] 5 log lines dropped (over 20/s)");
  EXPECT_EQ(b.logs[1].severity, LogSeverity::kFatal);
}

TEST(LightBridgeHost, ErrorsAreThrottledPerKindAndInfoEveryMinute) {
  LightBridgeHost host(LightBridgeParams(), "/dev/ttyTEST", 57600, 1.0);
  const auto at = [&](double now, const SessionEvent& e) {
    SessionOutput out;
    out.events.push_back(e);
    HostActions a;
    host.afterStep(out, now, a);
    return a.logs;
  };
  const SessionEvent mismatch = event(SessionEvent::kError, "wrong type", SessionError::kCommandTypeMismatch);
  const SessionEvent malformed = event(SessionEvent::kError, "malformed", SessionError::kMalformedTopicInfo);
  EXPECT_EQ(at(10.0, mismatch).at(0).text, "headlight device: wrong type");
  EXPECT_TRUE(at(11.0, mismatch).empty());
  EXPECT_EQ(at(12.0, malformed).size(), 1u) << "another kind is not held back";
  EXPECT_TRUE(at(13.0, mismatch).empty());
  EXPECT_EQ(at(20.0, mismatch).at(0).text, "headlight device: wrong type (and 2 more of this kind in the last 10 s)");
  const SessionEvent info = event(SessionEvent::kInfo, "note");
  EXPECT_EQ(at(10.0, info).at(0).text, "headlight device: note");
  EXPECT_TRUE(at(69.0, info).empty());
  EXPECT_EQ(at(70.0, info).size(), 1u);
  EXPECT_EQ(at(70.0, event(SessionEvent::kWarning, "w")).at(0).severity, LogSeverity::kWarn);
  EXPECT_EQ(at(70.0, event(SessionEvent::kLinkLost, "silent")).at(0).text, "headlight link lost: silent");
}

TEST(LightBridgeHost, WireFaultsAreLoggedOnceASecond) {
  Bench b;
  b.open();
  for (int i = 0; i < 5 && !b.host.session().synced(); ++i) b.step(0.01);
  ASSERT_TRUE(b.host.session().synced());
  const auto garbage = [&](double now) {
    const Bytes noise = {0x00, 0x13, 0x37};
    SessionOutput out;
    b.host.session().onBytes(noise.data(), noise.size(), now, rosserial::Stamp{1, 0}, out);
    HostActions a;
    b.host.afterStep(out, now, a);
    std::string s;
    for (const LogLine& l : a.logs)
      if (l.text.find("rosserial link /dev/ttyTEST: ") == 0) s += l.text;
    return s;
  };
  EXPECT_NE(garbage(b.now).find("(the parser resynchronised; totals in /diagnostics)"), std::string::npos);
  EXPECT_EQ(garbage(b.now + 0.5), "");
  EXPECT_NE(garbage(b.now + 1.0), "");
  EXPECT_EQ(b.host.report(b.now).value("faults: garbage bytes"), "9");
}

TEST(LightBridgeHost, SegmentLevelsAreCountedWhenTheLampHasThem) {
  LightBridgeParams p;
  p.device_levels_topic = "lamp_levels";
  LightBridgeHost host(p, "/dev/ttyTEST", 57600, 1.0);
  SessionOutput out;
  host.onLevels({0.5f, 1.0f}, 10.0, out);
  EXPECT_EQ(host.report(10.0).value("lamp_command (segment levels) received"), "1");
  EXPECT_EQ(host.report(10.0).value("device levels topic id"), "0");
}

TEST(StatusReport, WritesValuesAsDiagnosticUpdaterDoes) {
  StatusReport r;
  r.add("flag", true);
  r.add("count", std::uint64_t{3});
  r.add("ratio", 0.25);
  r.add("text", "abc");
  EXPECT_EQ(r.value("flag"), "True");
  EXPECT_EQ(r.value("count"), "3");
  EXPECT_EQ(r.value("ratio"), "0.25");
  EXPECT_EQ(r.value("text"), "abc");
  r.summary(StatusLevel::kOk, "fine");
  r.mergeSummary(StatusLevel::kWarn, "watchdog disabled");
  EXPECT_EQ(r.level, StatusLevel::kWarn);
  EXPECT_EQ(r.message, "watchdog disabled");
  r.mergeSummary(StatusLevel::kError, "blind");
  EXPECT_EQ(r.level, StatusLevel::kError);
  EXPECT_EQ(r.message, "watchdog disabled; blind");
}

}  // namespace
}  // namespace icanc
