// Pins the LightBridge's port under its host on a pseudo-terminal: opened when due, each step's
// bytes written, the device's bytes to the session, a lost port closed and reopened at once, open
// failures retried every reconnect period, and the device told to stop at the end.
#include <gtest/gtest.h>

#include <poll.h>
#include <unistd.h>

#include <string>
#include <vector>

#include "icanc/core/bridge/light_bridge_link.hpp"
#include "pty.hpp"

namespace icanc {
namespace {

bool logged(const HostActions& a, const std::string& text) {
  for (const LogLine& l : a.logs)
    if (l.text.find(text) != std::string::npos) return true;
  return false;
}

// A link on a pseudo-terminal, opened at t = 100 s.
class OpenLink : public ::testing::Test {
 protected:
  void SetUp() override {
    link.openIfDue(100.0, out, actions);
    ASSERT_TRUE(link.isOpen());
  }
  // The frames the link wrote so far (waits up to 1 s for the first byte).
  std::vector<rosserial::Frame> frames() {
    std::vector<rosserial::Frame> got;
    pollfd p{pty.master, POLLIN, 0};
    std::uint8_t buf[256];
    while (::poll(&p, 1, got.empty() ? 1000 : 50) > 0) {
      const ssize_t n = ::read(pty.master, buf, sizeof buf);
      if (n <= 0) break;
      parser.feed(buf, static_cast<std::size_t>(n), 0.0, got);
    }
    return got;
  }
  std::string report(double now, const std::string& key) { return link.host().report(now).value(key); }

  test_pty::Pty pty;
  LightBridgeLink link{LightBridgeParams(), pty.path, 57600, 1.0};
  SessionOutput out;
  HostActions actions;
  rosserial::FrameParser parser;
  std::uint8_t buf[64];
  std::string error;
};

TEST_F(OpenLink, WritesTheStepsBytesAndStopsTheDevice) {
  EXPECT_TRUE(logged(actions, "opened " + pty.path));
  link.finish(out, 100.0, actions);
  std::vector<rosserial::Frame> got = frames();
  ASSERT_FALSE(got.empty());
  EXPECT_EQ(got[0].topic, rosserial::kIdPublisher);  // "request topics"
  EXPECT_TRUE(got[0].payload.empty());
  EXPECT_EQ(report(100.0, "port opens"), "1");

  link.stop();
  EXPECT_FALSE(link.isOpen());
  got = frames();
  ASSERT_EQ(got.size(), 1u);
  EXPECT_EQ(got[0].topic, rosserial::kIdTxStop);
}

TEST_F(OpenLink, TheDevicesBytesReachTheSession) {
  const std::uint8_t noise[] = {0x01, 0x02, 0x03};
  ASSERT_EQ(::write(pty.master, noise, sizeof noise), static_cast<ssize_t>(sizeof noise));
  long n = 0;
  for (int i = 0; i < 50 && n == 0; ++i) n = link.read(buf, sizeof buf, 0.02, error);
  ASSERT_EQ(n, 3) << error;
  link.afterRead(n, error, buf, 100.1, rosserial::Stamp{1, 0}, out, actions);
  EXPECT_TRUE(link.isOpen());
  EXPECT_EQ(link.host().session().parserCounters().bytes, 3u);
}

TEST_F(OpenLink, ALostPortIsClosedAndReopenedAtOnce) {
  pty.close();  // unplugged
  const long n = link.read(buf, sizeof buf, 1.0, error);
  ASSERT_EQ(n, -1);
  HostActions lost;
  link.afterRead(n, error, buf, 100.2, rosserial::Stamp{1, 0}, out, lost);
  EXPECT_FALSE(link.isOpen());
  EXPECT_TRUE(logged(lost, "headlight port " + pty.path + " lost"));
  EXPECT_EQ(report(100.2, "port losses"), "1");

  HostActions reopen;  // due at once, not a reconnect period later
  link.openIfDue(100.2, out, reopen);
  EXPECT_FALSE(link.isOpen());  // the pseudo-terminal is gone
  EXPECT_EQ(report(100.2, "open failures"), "1");
  EXPECT_TRUE(logged(reopen, "cannot open the headlight port"));
}

TEST(LightBridgeLink, OpenFailuresAreRetriedEveryReconnectPeriod) {
  LightBridgeLink link(LightBridgeParams(), "/nonexistent/ttyACM9", 57600, 1.0);
  SessionOutput out;
  HostActions actions;
  link.openIfDue(100.0, out, actions);
  EXPECT_FALSE(link.isOpen());
  link.openIfDue(100.5, out, actions);  // not due yet
  EXPECT_EQ(link.host().report(100.5).value("open failures"), "1");
  link.openIfDue(101.0, out, actions);
  EXPECT_EQ(link.host().report(101.0).value("open failures"), "2");
  link.finish(out, 101.0, actions);  // nothing to write to a closed port
  EXPECT_FALSE(link.commandWritten(out));
  link.stop();  // closed already: nothing to tell
  EXPECT_FALSE(link.isOpen());
}

}  // namespace
}  // namespace icanc
