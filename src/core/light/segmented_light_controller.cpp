#include "icanc/core/light/segmented_light_controller.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace icanc {

SegmentedLightController::SegmentedLightController(const LightControllerParams& params,
                                                   const SegmentLampParams& lamp)
    : lamp_(lamp), segments_(effectiveSegments(lamp)), timers_(segments_.size(), LightController(params)),
      binary_(params), level_(segments_.size(), 1.0) {}

void SegmentedLightController::setParams(const LightControllerParams& params) {
  for (LightController& t : timers_) t.setParams(params);
  binary_.setParams(params);
}

void SegmentedLightController::onInput(double now, const std::vector<Eigen::AlignedBox2d>& dangerous,
                                       bool sensor_blind, bool unlocated_danger) {
  const Eigen::Vector2d lamp = lamp_.lamp_position_m.head<2>().cast<double>();
  std::vector<bool> hit(segments_.size(), unlocated_danger);
  std::vector<double> needs(segments_.size(), unlocated_danger ? 1.0 : 0.0);
  for (const Eigen::AlignedBox2d& box : dangerous) {
    const AzimuthRange range = azimuthRange(box, lamp);
    const double distance = box.isEmpty() ? std::nan("") : box.exteriorDistance(lamp);
    bool lit = false;
    for (std::size_t i = 0; i < segments_.size(); ++i) {
      if (!covers(segments_[i], range, lamp_.segment_margin_deg)) continue;
      lit = true;
      hit[i] = true;
      needs[i] = std::max(needs[i], requiredLevel(lamp_, segments_[i], distance));
    }
    if (lit) continue;
    ++unlit_objects_;  // outside every segment: the whole lamp, as the binary lamp
    std::fill(hit.begin(), hit.end(), true);
    std::fill(needs.begin(), needs.end(), 1.0);
  }
  const bool binary_restarted = binary_.onInput(now, !dangerous.empty() || unlocated_danger, sensor_blind);
  for (std::size_t i = 0; i < segments_.size(); ++i) {
    if (timers_[i].onInput(now, hit[i], sensor_blind)) {
      level_[i] = needs[i];  // (re)started: the level these objects need
    } else if (hit[i] && timers_[i].on()) {
      // Ignored by the segment's timer: a farther object still raises the level, and the binary
      // lamp's restart carries the segment's light as far as the binary lamp's.
      if (binary_restarted) timers_[i].restartTimer(now);
      level_[i] = std::max(level_[i], needs[i]);
    }
  }
}

bool SegmentedLightController::tick(double now) {
  bool changed = false;
  for (LightController& t : timers_) changed = t.tick(now) || changed;
  binary_.tick(now);
  return changed;
}

double SegmentedLightController::nextEvent() const {
  double next = std::numeric_limits<double>::infinity();
  for (const LightController& t : timers_) next = std::min(next, t.nextEvent());
  return next;
}

bool SegmentedLightController::onIllumination(double now, Illumination state) {
  bool changed = false;
  for (LightController& t : timers_) changed = t.onIllumination(now, state) || changed;
  binary_.onIllumination(now, state);
  return changed;
}

std::vector<float> SegmentedLightController::levels() const {
  std::vector<float> out(segments_.size(), 0.0f);
  for (std::size_t i = 0; i < segments_.size(); ++i) {
    if (!timers_[i].on()) continue;
    const bool fail_safe = timers_[i].reason() != LightReason::kDanger;
    out[i] = fail_safe ? 1.0f : static_cast<float>(level_[i]);
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
