#include "icanc/core/light/light_controller.hpp"

#include <algorithm>
#include <limits>
#include <sstream>

namespace icanc {

namespace {
// Stamps are seconds as doubles (1.3 - 1.0 > 0.3): every threshold on them is compared with this
// slack, and nextEvent() names the instants tick() sees past it.
constexpr double kStampSlackS = 1e-9;
}  // namespace

std::string validate(const LightControllerParams& params) {
  std::ostringstream why;
  if (!(params.tau_s > 0.0 && params.tau_s <= 60.0))
    why << "light.tau_s must be in (0, 60] s (got " << params.tau_s << ")";
  else if (!(params.recheck_below_s >= 0.0 && params.recheck_below_s <= params.tau_s))
    why << "light.recheck_below_s must be in [0, tau_s = " << params.tau_s << "] (got "
        << params.recheck_below_s << ")";
  else if (!(params.stale_timeout_s > 0.0 && params.stale_timeout_s <= kMaxStaleTimeoutS))
    why << "light.stale_timeout_s must be in (0, " << kMaxStaleTimeoutS << "] s; to run without "
        << "the watchdog set watchdog_enabled: false (got " << params.stale_timeout_s << ")";
  else if (!(params.illumination_stale_timeout_s > 0.0))
    why << "light.illumination/stale_timeout_s must be > 0 (got "
        << params.illumination_stale_timeout_s << ")";
  return why.str();
}

std::string validatePublishRate(double publish_rate_hz) {
  std::ostringstream why;
  if (!(publish_rate_hz >= kMinPublishRateHz && publish_rate_hz <= kMaxRateHz))
    why << "light.publish_rate_hz must be in [" << kMinPublishRateHz << ", " << kMaxRateHz
        << "] Hz (got " << publish_rate_hz << ")";
  return why.str();
}

const char* toString(LightReason reason) {
  switch (reason) {
    case LightReason::kOff: return "off";
    case LightReason::kDanger: return "danger";
    case LightReason::kSensorStale: return "sensor stale";
    case LightReason::kDaylight: return "daylight";
    case LightReason::kSensorBlind: return "sensor blind";
    case LightReason::kFault: return "fault";
  }
  return "unknown";
}

LightController::LightController(const LightControllerParams& params) : params_(params) {}

void LightController::reset() {
  timer_running_ = false;
  has_input_ = false;
  stale_ = true;
  blind_ = false;
  illumination_ = Illumination::kUnknown;
  daylight_ = false;
}

void LightController::updateDaylight(double now) {
  daylight_ = params_.illumination_enabled && illumination_ == Illumination::kBright &&
              now - illumination_s_ <= params_.illumination_stale_timeout_s + kStampSlackS;
  if (daylight_) timer_running_ = false;  // no danger lamp in daylight
}

bool LightController::tick(double now) {
  const bool was_on = on();
  const LightReason was_reason = reason();
  if (has_now_ && now < last_now_s_) reset();  // bag loop: start over, fail-safe on
  has_now_ = true;
  last_now_s_ = now;

  if (timer_running_ && now >= timer_end_s_ - kStampSlackS) timer_running_ = false;
  stale_ = !has_input_ || (params_.watchdog_enabled &&
                           now - last_input_s_ > params_.stale_timeout_s + kStampSlackS);
  updateDaylight(now);
  return was_on != on() || was_reason != reason();
}

double LightController::nextEvent() const {
  // With tick()'s slack: the timer ends kStampSlackS early, the watchdog and the daylight fire
  // past their thresholds by more than it, so tick() at the returned time sees the change.
  constexpr double kPast = 1e-6;
  double next = std::numeric_limits<double>::infinity();
  if (timer_running_) next = timer_end_s_ - kStampSlackS;
  if (params_.watchdog_enabled && has_input_ && !stale_)
    next = std::min(next, last_input_s_ + params_.stale_timeout_s + kPast);
  if (daylight_) next = std::min(next, illumination_s_ + params_.illumination_stale_timeout_s + kPast);
  return next;
}

bool LightController::onIllumination(double now, Illumination state) {
  const bool was_on = on();
  const LightReason was_reason = reason();
  tick(now);
  illumination_ = state;
  illumination_s_ = now;
  updateDaylight(now);
  return was_on != on() || was_reason != reason();
}

bool LightController::onInput(double now, bool any_danger, bool sensor_blind) {
  tick(now);
  has_input_ = true;
  last_input_s_ = now;
  stale_ = false;
  blind_ = sensor_blind;
  if (!any_danger || daylight_) return false;
  // Danger while the timer has more than recheck_below_s left is ignored.
  if (timer_running_ && timer_end_s_ - now > params_.recheck_below_s + kStampSlackS) return false;
  timer_running_ = true;
  timer_end_s_ = now + params_.tau_s;
  last_trigger_s_ = now;
  return true;
}

bool LightController::restartTimer(double now) {
  if (!timer_running_ || daylight_) return false;
  timer_end_s_ = std::max(timer_end_s_, now + params_.tau_s);
  last_trigger_s_ = now;
  return true;
}

LightReason LightController::reason() const {
  if (stale_) return LightReason::kSensorStale;
  if (blind_) return LightReason::kSensorBlind;
  if (daylight_) return LightReason::kDaylight;
  if (timer_running_) return LightReason::kDanger;
  return LightReason::kOff;
}

double LightController::timeLeft(double now) const {
  return timer_running_ ? std::max(0.0, timer_end_s_ - now) : 0.0;
}

}  // namespace icanc
