#include "icanc/core/light/segmented_light_controller.hpp"

#include <algorithm>

namespace icanc {

SegmentedLightController::SegmentedLightController(const LightControllerParams& params,
                                                   const SegmentLampParams& lamp)
    : lamp_(lamp), segments_(effectiveSegments(lamp)), timers_(segments_.size(), LightController(params)),
      high_(segments_.size(), true) {}

void SegmentedLightController::setParams(const LightControllerParams& params) {
  for (LightController& t : timers_) t.setParams(params);
}

void SegmentedLightController::onInput(double now, const std::vector<Eigen::AlignedBox2d>& dangerous,
                                       bool sensor_blind, bool unlocated_danger) {
  const Eigen::Vector2d lamp = lamp_.lamp_position_m.head<2>().cast<double>();
  std::vector<bool> hit(segments_.size(), unlocated_danger);
  std::vector<bool> needs_high(segments_.size(), unlocated_danger);
  for (const Eigen::AlignedBox2d& box : dangerous) {
    const AzimuthRange range = azimuthRange(box, lamp);
    const bool far = !(box.exteriorDistance(lamp) < lamp_.low_beam_below_m);  // NaN box: high
    bool lit = false;
    for (std::size_t i = 0; i < segments_.size(); ++i) {
      if (!covers(segments_[i], range, lamp_.segment_margin_deg)) continue;
      lit = true;
      hit[i] = true;
      needs_high[i] = needs_high[i] || far || !(segments_[i].low_watts > 0.0);
    }
    unlit_objects_ += !lit;
  }
  for (std::size_t i = 0; i < segments_.size(); ++i) {
    if (timers_[i].onInput(now, hit[i], sensor_blind))
      high_[i] = needs_high[i];  // (re)started: the beam these objects need
    else if (hit[i] && timers_[i].on())
      high_[i] = high_[i] || needs_high[i];  // ignored by the timer: a far object still raises it
  }
}

bool SegmentedLightController::tick(double now) {
  bool changed = false;
  for (LightController& t : timers_) changed = t.tick(now) || changed;
  return changed;
}

bool SegmentedLightController::onIllumination(double now, Illumination state) {
  bool changed = false;
  for (LightController& t : timers_) changed = t.onIllumination(now, state) || changed;
  return changed;
}

std::vector<float> SegmentedLightController::levels() const {
  std::vector<float> out(segments_.size(), 0.0f);
  for (std::size_t i = 0; i < segments_.size(); ++i) {
    if (!timers_[i].on()) continue;
    const bool fail_safe = timers_[i].reason() != LightReason::kDanger;
    out[i] = fail_safe || high_[i] ? 1.0f : static_cast<float>(segments_[i].low_watts / segments_[i].watts);
  }
  return out;
}

bool SegmentedLightController::anyOn() const {
  return std::any_of(timers_.begin(), timers_.end(), [](const LightController& t) { return t.on(); });
}

LightReason SegmentedLightController::reason() const {
  // Stale, blind and daylight are shared: every timer hears the same inputs and reports.
  const LightReason shared = timers_.front().reason();
  if (shared != LightReason::kDanger && shared != LightReason::kOff) return shared;
  return anyOn() ? LightReason::kDanger : LightReason::kOff;
}

}  // namespace icanc
