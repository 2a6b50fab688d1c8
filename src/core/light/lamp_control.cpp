#include "icanc/core/light/lamp_control.hpp"

#include <algorithm>

namespace icanc {

std::vector<float> faultLevels(const SegmentLampParams& lamp) {
  return std::vector<float>(std::max<std::size_t>(1, lamp.segments.size()), 1.0f);
}

double faultPublishRate(double publish_rate_hz) {
  return publish_rate_hz >= kMinPublishRateHz && publish_rate_hz <= kMaxRateHz ? publish_rate_hz : 10.0;
}

StatusReport faultReport(const std::string& why) {
  StatusReport stat;
  stat.summary(StatusLevel::kError, "cannot start, lamp on (fail-safe): invalid parameters: " + why);
  stat.add("lamp on", true);
  stat.add("reason", std::string(toString(LightReason::kFault)));
  stat.add("invalid parameters", why);
  return stat;
}

LampControl::LampControl(const LightControllerParams& params, const SegmentLampParams& lamp)
    : controller_(params), segmented_(params, lamp) {}

void LampControl::setParams(const LightControllerParams& params) {
  controller_.setParams(params);
  segmented_.setParams(params);
}

LampControl::InputResult LampControl::onInput(double now, std::uint32_t num_dangerous, bool sensor_blind,
                                              const std::vector<Eigen::AlignedBox2d>& dangerous_boxes) {
  InputResult result;
  ++inputs_;
  if (sensor_blind) ++blind_inputs_;
  result.triggered = controller_.onInput(now, num_dangerous > 0, sensor_blind);
  if (result.triggered) ++triggers_;
  // A count of dangerous objects above the flagged boxes is danger of unknown place.
  result.unlocated = num_dangerous > dangerous_boxes.size();
  if (result.unlocated) ++unlocated_inputs_;
  segmented_.onInput(now, dangerous_boxes, sensor_blind, result.unlocated);
  return result;
}

bool LampControl::onIllumination(double now, std::uint8_t state, bool& invalid) {
  invalid = state > static_cast<std::uint8_t>(Illumination::kBright);
  if (invalid) ++bad_illumination_;
  illumination_ = invalid ? Illumination::kUnknown : static_cast<Illumination>(state);
  const bool segments_changed = segmented_.onIllumination(now, illumination_);
  return controller_.onIllumination(now, illumination_) || segments_changed;
}

bool LampControl::tick(double now, bool& stale_event) {
  const bool segments_changed = segmented_.tick(now);
  const bool changed = controller_.tick(now);
  stale_event = changed && controller_.reason() == LightReason::kSensorStale;
  if (stale_event) ++stale_events_;
  return changed || segments_changed;
}

double LampControl::nextEvent() const {
  return std::min(controller_.nextEvent(), segmented_.nextEvent());
}

void LampControl::published(bool on) {
  if (on != last_on_) ++transitions_;
  last_on_ = on;
}

StatusReport LampControl::report() const {
  StatusReport stat;
  const LightReason reason = controller_.reason();
  if (reason == LightReason::kSensorStale)
    stat.summary(StatusLevel::kWarn, "lamp on: sensor stale (fail-safe)");
  else if (reason == LightReason::kSensorBlind)
    stat.summary(StatusLevel::kError, "lamp on: sensor blind (fail-safe)");
  else
    stat.summary(StatusLevel::kOk, std::string("lamp ") + (controller_.on() ? "on: " : "off: ") + toString(reason));
  const LightControllerParams& params = controller_.params();
  stat.add("lamp on", controller_.on());
  stat.add("reason", std::string(toString(reason)));
  stat.add("inputs", inputs_);
  stat.add("timer starts/resets", triggers_);
  stat.add("lamp transitions", transitions_);
  stat.add("sensor stale events", stale_events_);
  stat.add("sensor blind inputs", blind_inputs_);
  stat.add("watchdog enabled", params.watchdog_enabled);
  if (!params.watchdog_enabled)
    stat.mergeSummary(StatusLevel::kWarn, "watchdog disabled (watchdog_enabled: false)");
  if (params.illumination_enabled) {
    stat.add("illumination", std::string(toString(illumination_)));
    stat.add("invalid illumination messages", bad_illumination_);
  }
  stat.add("tau_s", params.tau_s);
  const std::vector<float> levels = segmented_.levels();
  stat.add("lamp segments", levels.size());
  stat.add("lamp segments lit", std::count_if(levels.begin(), levels.end(), [](float l) { return l > 0.0f; }));
  stat.add("dangerous objects outside every segment (all segments on)", segmented_.unlitObjects());
  stat.add("inputs with unlocated danger (all segments on)", unlocated_inputs_);
  return stat;
}

}  // namespace icanc
