// The LightController nodelet's logic, without ROS: the paper's binary lamp (LightController) and
// the segmented lamp (SegmentedLightController) fed the same inputs, illumination and ticks; which
// input is danger of unknown place, which illumination state is invalid, the counters and the
// diagnostics report; and the fault path's lamp when the parameters are invalid. Time is ROS time
// [s], an argument.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "icanc/core/common/status_report.hpp"
#include "icanc/core/light/segmented_light_controller.hpp"

namespace icanc {

// The fault path (invalid parameters): every segment of the lamp ON, at publish_rate_hz when
// that is a valid rate, else 10 Hz, and an ERROR naming the problem.
std::vector<float> faultLevels(const SegmentLampParams& lamp);
double faultPublishRate(double publish_rate_hz);
StatusReport faultReport(const std::string& why);

class LampControl {
 public:
  // The parameters must validate (icanc::validate); invalid ones take the fault path.
  LampControl(const LightControllerParams& params, const SegmentLampParams& lamp);

  void setParams(const LightControllerParams& params);  // a live tuning, from the next call on

  struct InputResult {
    bool triggered = false;  // the binary lamp's timer was started or reset
    bool unlocated = false;  // num_dangerous above the boxes: every segment lights
  };
  // One DangerDetector output at `now`: its count of dangerous objects, whether the sensor was
  // blind, and the x-y boxes of the obstacles flagged dangerous.
  InputResult onInput(double now, std::uint32_t num_dangerous, bool sensor_blind,
                      const std::vector<Eigen::AlignedBox2d>& dangerous_boxes);
  // An illumination state as icanc/IlluminationState numbers it; a number beyond them is
  // counted and taken as unknown (`invalid`). True when a lamp changed.
  bool onIllumination(double now, std::uint8_t state, bool& invalid);
  // Advances both lamps. True when one changed; `stale_event` when the binary lamp just turned
  // on for want of input (counted).
  bool tick(double now, bool& stale_event);
  // When tick() next changes a lamp without new input (infinity: not before the next input).
  double nextEvent() const;
  // The lamp was published ON or OFF (counts transitions).
  void published(bool on);

  const LightController& binary() const { return controller_; }
  const SegmentedLightController& segmented() const { return segmented_; }
  StatusReport report() const;

 private:
  LightController controller_;
  SegmentedLightController segmented_;
  Illumination illumination_ = Illumination::kUnknown;
  bool last_on_ = true;
  std::uint64_t inputs_ = 0, triggers_ = 0, transitions_ = 0, stale_events_ = 0, blind_inputs_ = 0;
  std::uint64_t unlocated_inputs_ = 0, bad_illumination_ = 0;
};

}  // namespace icanc
