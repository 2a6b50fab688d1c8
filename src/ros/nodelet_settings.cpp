#include "icanc/ros/nodelet_settings.hpp"

#include "icanc/LightControllerConfig.h"
#include "icanc/core/bridge/light_bridge_host.hpp"
#include "icanc/ros/live_params.hpp"
#include "icanc/ros/nodelet_support.hpp"

namespace icanc {

std::string loadSettings(ParamReader& reader, LightControllerSettings& s) {
  readParams(reader, s.params);
  readParams(reader, s.lamp);
  reader.read("publish_rate_hz", s.publish_rate_hz);
  bool trace = false;
  reader.read("trace_publications", trace);  // read by ZeroCopyPublisher
  const std::string rate_problem = readExpectedRate(reader, s.expected_rate_hz);
  std::string why = validate(s.params);
  if (why.empty()) why = validate(s.lamp);
  if (why.empty()) why = rate_problem;
  if (why.empty()) why = validatePublishRate(s.publish_rate_hz);
  reader.read("marker_lifetime_s", s.marker_style.lifetime_s);
  acceptReconfigureKeys<LightControllerConfig>(reader);
  return why;
}

std::string loadSettings(ParamReader& reader, LightBridgeSettings& s) {
  reader.read("port", s.port);
  reader.read("baud", s.baud);
  reader.read("reconnect_period_s", s.reconnect_period_s);
  visitParams(reader, s.params);
  const std::string rate_problem = readExpectedRate(reader, s.expected_rate_hz);
  std::string why = validate(s.params);
  if (why.empty()) why = rate_problem;
  if (why.empty()) why = validatePort(s.port, s.baud, s.reconnect_period_s);
  return why;
}

}  // namespace icanc
