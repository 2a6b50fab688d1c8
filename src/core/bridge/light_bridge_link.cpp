#include "icanc/core/bridge/light_bridge_link.hpp"

namespace icanc {

LightBridgeLink::LightBridgeLink(const LightBridgeParams& params, const std::string& port, int baud,
                                 double reconnect_period_s)
    : host_(params, port, baud, reconnect_period_s), port_name_(port), baud_(baud) {}

void LightBridgeLink::openIfDue(double now, SessionOutput& out, HostActions& actions) {
  if (port_.isOpen() || !host_.openDue(now)) return;
  std::string error;
  if (port_.open(port_name_, baud_, error))
    host_.onOpened(now, out, actions);
  else
    host_.onOpenFailed(error, now, actions);
}

long LightBridgeLink::read(std::uint8_t* buffer, std::size_t capacity, double timeout_s, std::string& error) {
  return port_.read(buffer, capacity, timeout_s, error);
}

void LightBridgeLink::afterRead(long n, const std::string& error, const std::uint8_t* data, double now,
                                const rosserial::Stamp& ros_now, SessionOutput& out, HostActions& actions) {
  if (n < 0 || !write_error_.empty()) {
    lost(n < 0 ? error : write_error_, now, out, actions);
  } else if (host_.presenceCheckDue(now) && !port_.stillPresent()) {
    lost("the path no longer names the opened device", now, out, actions);
  }
  if (!port_.isOpen()) return;
  if (n > 0) host_.session().onBytes(data, static_cast<std::size_t>(n), now, ros_now, out);
  host_.session().tick(now, ros_now, out);
}

void LightBridgeLink::finish(SessionOutput& out, double now, HostActions& actions) {
  if (!out.tx.empty() && port_.isOpen() && write_error_.empty()) {
    std::string error;
    if (port_.write(out.tx.data(), out.tx.size(), true, error))
      host_.onWritten(out.tx.size());
    else
      write_error_ = error;  // the reading thread closes the port (it may be polling it now)
  }
  host_.afterStep(out, now, actions);
}

void LightBridgeLink::stop() {
  if (port_.isOpen()) {
    SessionOutput out;
    host_.session().txStop(out);
    std::string error;
    port_.write(out.tx.data(), out.tx.size(), true, error);
  }
  port_.close();
}

void LightBridgeLink::lost(const std::string& why, double now, SessionOutput& out, HostActions& actions) {
  write_error_.clear();
  port_.close();
  host_.onLost(why, now, out, actions);
}

}  // namespace icanc
