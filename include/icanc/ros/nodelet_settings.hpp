// What the LightController and the LightBridge nodelets read beyond one core parameter struct, read
// and validated in one call: loadSettings returns "" or the first problem, which the nodelet hands
// to checkParams (with the reader's wrong types and unknown keys) before it starts.
#pragma once

#include <string>

#include "icanc/core/bridge/rosserial_session.hpp"
#include "icanc/core/light/lamp_segments.hpp"
#include "icanc/core/light/light_controller.hpp"
#include "icanc/ros/markers.hpp"
#include "icanc/ros/param_reader.hpp"

namespace icanc {

// The LightController's private parameters: both lamps', its publication rate, its input's rate
// and its markers' lifetime (~marker_lifetime_s); ~trace_publications and the dynamic_reconfigure
// names are marked known (ZeroCopyPublisher and LiveParams read them).
struct LightControllerSettings {
  LightControllerParams params;
  SegmentLampParams lamp;
  double publish_rate_hz = 10.0;   // steady republication of the lamp [Hz]
  double expected_rate_hz = 10.0;  // the input's rate [Hz]
  MarkerStyle marker_style;
};
std::string loadSettings(ParamReader& reader, LightControllerSettings& settings);

// The LightBridge's private parameters: the port's (~port, ~baud, ~reconnect_period_s), the
// session's (LightBridgeParams) and its input's rate.
struct LightBridgeSettings {
  LightBridgeParams params;
  std::string port;                // required
  int baud = 57600;
  double reconnect_period_s = 1.0;
  double expected_rate_hz = 10.0;  // lamp_cmd's rate [Hz]
};
std::string loadSettings(ParamReader& reader, LightBridgeSettings& settings);

}  // namespace icanc
