#include "icanc/ros/nodelet_settings.hpp"

#include "icanc/LightControllerConfig.h"
#include "icanc/ros/live_params.hpp"
#include "icanc/ros/nodelet_support.hpp"

namespace icanc {

std::string loadSettings(ParamReader& reader, LightControllerSettings& s) {
  readParams(reader, s.params);
  readParams(reader, s.lamp);
  reader.read("publish_rate_hz", s.publish_rate_hz);
  reader.read("tick_rate_hz", s.tick_rate_hz);
  bool trace = false;
  reader.read("trace_publications", trace);  // read by ZeroCopyPublisher
  const std::string rate_problem = readExpectedRate(reader, s.expected_rate_hz);
  std::string why = validate(s.params);
  if (why.empty()) why = validate(s.lamp);
  if (why.empty()) why = rate_problem;
  if (why.empty()) why = validateRates(s.publish_rate_hz, s.tick_rate_hz);
  reader.read("marker_lifetime_s", s.marker_style.lifetime_s);
  acceptReconfigureKeys<LightControllerConfig>(reader);
  return why;
}

}  // namespace icanc
