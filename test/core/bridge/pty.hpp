// A pseudo-terminal in raw mode for the bridge's gtests: the port under test opens `path`, the
// test plays the device on `master`.
#pragma once

#include <pty.h>
#include <termios.h>
#include <unistd.h>

#include <string>

#include <gtest/gtest.h>

namespace icanc {
namespace test_pty {

struct Pty {
  Pty() {
    termios raw;
    cfmakeraw(&raw);
    char name[128];
    EXPECT_EQ(openpty(&master, &slave, name, &raw, nullptr), 0);
    path = name;
  }
  ~Pty() { close(); }
  Pty(const Pty&) = delete;
  Pty& operator=(const Pty&) = delete;
  // Both ends closed: the device is gone (unplugged).
  void close() {
    if (master >= 0) ::close(master);
    if (slave >= 0) ::close(slave);
    master = slave = -1;
  }
  int master = -1, slave = -1;
  std::string path;
};

}  // namespace test_pty
}  // namespace icanc
