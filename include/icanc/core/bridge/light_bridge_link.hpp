// The LightBridge nodelet's serial link, without ROS: the port (icanc/serial_port.hpp) under the
// decisions of its host (icanc/light_bridge_host.hpp). It opens the port when an attempt is due,
// writes each step's bytes (a failed write is kept: the reading thread then closes the port),
// hands what it reads and each tick to the session, closes the port when it is lost (an I/O error,
// a failed write, a path that no longer names the device) and, at the end, tells the device to
// drop its configuration. Time is the nodelet's steady clock [s], an argument.
// Not thread-safe: the caller makes every call under one lock, except read(), which the thread that
// calls openIfDue and afterRead makes without it (only those two open and close the port).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

#include "icanc/core/bridge/light_bridge_host.hpp"
#include "icanc/core/bridge/serial_port.hpp"

namespace icanc {

class LightBridgeLink {
 public:
  LightBridgeLink(const LightBridgeParams& params, const std::string& port, int baud,
                  double reconnect_period_s);

  LightBridgeHost& host() { return host_; }
  const LightBridgeHost& host() const { return host_; }
  bool isOpen() const { return port_.isOpen(); }

  // The port closed: an attempt to open it when one is due.
  void openIfDue(double now, SessionOutput& out, HostActions& actions);
  // Waits up to timeout_s for the device's bytes: their count, 0 for none, -1 when the port
  // failed (`error` says why).
  long read(std::uint8_t* buffer, std::size_t capacity, double timeout_s, std::string& error);
  // What read() returned (`n`, `error`, the bytes in `data`): the port closed when it failed, a
  // write failed or its path no longer names the device; while it is open, the bytes and a tick
  // to the session (`ros_now`: the time the device is told).
  void afterRead(long n, const std::string& error, const std::uint8_t* data, double now,
                 const rosserial::Stamp& ros_now, SessionOutput& out, HostActions& actions);
  // Writes the step's bytes (while the port is open and no write failed), then hands the step to
  // the host (afterStep: what to log and publish).
  void finish(SessionOutput& out, double now, HostActions& actions);
  // Whether the step's lamp command went out: sent, on an open port, no write failed.
  bool commandWritten(const SessionOutput& out) const {
    return out.command_sent && port_.isOpen() && write_error_.empty();
  }
  // The device told to drop its configuration (its lamp fails safe ON), the port closed.
  void stop();

 private:
  void lost(const std::string& why, double now, SessionOutput& out, HostActions& actions);

  LightBridgeHost host_;
  SerialPort port_;
  std::string port_name_;
  int baud_;
  std::string write_error_;  // set by a failed write; the reading thread then closes the port
};

}  // namespace icanc
