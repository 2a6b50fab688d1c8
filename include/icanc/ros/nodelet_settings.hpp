// What the LightController nodelet reads beyond one core parameter struct, read and validated in
// one call: loadSettings returns "" or the first problem, which the nodelet hands
// to checkParams (with the reader's wrong types and unknown keys) before it starts.
#pragma once

#include <string>

#include "icanc/core/light/lamp_segments.hpp"
#include "icanc/core/light/light_controller.hpp"
#include "icanc/ros/markers.hpp"
#include "icanc/ros/param_reader.hpp"

namespace icanc {

// The LightController's private parameters: both lamps', its clocks, its input's rate and its
// markers' lifetime (~marker_lifetime_s); ~trace_publications and the dynamic_reconfigure names
// are marked known (ZeroCopyPublisher and LiveParams read them).
struct LightControllerSettings {
  LightControllerParams params;
  SegmentLampParams lamp;
  double publish_rate_hz = 10.0;   // steady republication of the lamp [Hz]
  double tick_rate_hz = 50.0;      // the state machine's timer [Hz]
  double expected_rate_hz = 10.0;  // the input's rate [Hz]
  MarkerStyle marker_style;
};
std::string loadSettings(ParamReader& reader, LightControllerSettings& settings);

}  // namespace icanc
