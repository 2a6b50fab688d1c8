// Pins the termios serial port on a pseudo-terminal: raw bytes both ways, timeouts that return
// 0, and a vanished peer (closed master, removed path) reported as an error, not a stall.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cstdio>
#include <cstring>
#include <string>

#include "icanc/core/bridge/serial_port.hpp"
#include "pty.hpp"

namespace icanc {
namespace {

using test_pty::Pty;

TEST(SerialPort, BaudRates) {
  EXPECT_TRUE(SerialPort::baudSupported(57600));
  EXPECT_TRUE(SerialPort::baudSupported(115200));
  EXPECT_FALSE(SerialPort::baudSupported(12345));
  SerialPort p;
  std::string error;
  EXPECT_FALSE(p.open("/dev/null", 12345, error));
  EXPECT_NE(error.find("baud"), std::string::npos);
}

TEST(SerialPort, MissingPathAndNonTtyAreErrors) {
  SerialPort p;
  std::string error;
  EXPECT_FALSE(p.open("/nonexistent/ttyUSB9", 57600, error));
  EXPECT_NE(error.find("/nonexistent/ttyUSB9"), std::string::npos) << error;
  EXPECT_FALSE(p.open("/dev/null", 57600, error));
  EXPECT_FALSE(p.isOpen());
}

TEST(SerialPort, RawBytesBothWaysAndTimeouts) {
  Pty pty;
  SerialPort p;
  std::string error;
  ASSERT_TRUE(p.open(pty.path, 115200, error)) << error;
  EXPECT_TRUE(p.stillPresent());
  std::uint8_t buf[64];
  EXPECT_EQ(p.read(buf, sizeof buf, 0.02, error), 0);  // nothing: timeout, not an error

  const std::uint8_t out[] = {0xFF, 0xFE, 0x00, 0x0A, 0x0D, 0x03, 0x11, 0x13};  // CR, LF, ^C, XON/XOFF
  ASSERT_TRUE(p.write(out, sizeof out, true, error)) << error;
  std::uint8_t got[16];
  ASSERT_EQ(::read(pty.master, got, sizeof got), static_cast<ssize_t>(sizeof out));
  EXPECT_EQ(std::memcmp(got, out, sizeof out), 0) << "bytes altered: the port is not raw";

  ASSERT_EQ(::write(pty.master, out, sizeof out), static_cast<ssize_t>(sizeof out));
  long n = 0, total = 0;
  while ((n = p.read(buf + total, sizeof buf - total, 0.2, error)) > 0 && total < 8) total += n;
  ASSERT_EQ(total, 8);
  EXPECT_EQ(std::memcmp(buf, out, sizeof out), 0);
}

TEST(SerialPort, ClosedPeerIsReportedAsGone) {
  Pty pty;
  SerialPort p;
  std::string error;
  ASSERT_TRUE(p.open(pty.path, 57600, error)) << error;
  pty.close();
  std::uint8_t buf[16];
  error.clear();
  EXPECT_EQ(p.read(buf, sizeof buf, 1.0, error), -1);
  EXPECT_FALSE(error.empty());
}

TEST(SerialPort, RemovedSymlinkIsNotPresent) {
  Pty pty;
  const std::string link = "/tmp/icanc_test_serial_" + std::to_string(::getpid());
  ::unlink(link.c_str());
  ASSERT_EQ(::symlink(pty.path.c_str(), link.c_str()), 0);
  SerialPort p;
  std::string error;
  ASSERT_TRUE(p.open(link, 57600, error)) << error;
  EXPECT_TRUE(p.stillPresent());
  ::unlink(link.c_str());
  EXPECT_FALSE(p.stillPresent());
}

}  // namespace
}  // namespace icanc
