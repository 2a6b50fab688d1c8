// The headlight state machine of the paper (Fig. "State diagram for the Light Controller"), with
// a fail-safe input watchdog. Time is always an argument (seconds, e.g. header stamps or sim
// time), never read from a clock.
//
//   OFF --danger--> ON, timer = tau
//   ON: timer > recheck_below (1 s): danger ignored; timer <= 1 s: danger resets timer to tau
//   ON --timer reaches 0--> OFF
//
// Fail-safe: while no input has arrived for stale_timeout (or none has arrived yet) the lamp is ON
// with reason kSensorStale; it returns to the timer's state when input resumes. Time going
// backwards (a bag loop) resets the machine to "no input yet", i.e. ON until input resumes.
// The watchdog is switched off only by watchdog_enabled = false (the offline evaluation, where
// frames are given rather than awaited), never by a timeout value: stale_timeout_s must be in
// (0, kMaxStaleTimeoutS]. An input that reports a blind sensor (icanc/sensor_health.hpp) is no
// clear road either: the lamp is ON with reason kSensorBlind until an input says the returns are
// back.
//
// Illumination gate (optional, off by default = the paper): while the camera's illumination
// monitor reports a bright scene, danger does not switch the lamp on (lamp OFF, reason
// kDaylight; a running timer is cancelled). An unknown or stale illumination (no report for
// illumination_stale_timeout_s) leaves the paper's machine in charge. The watchdog still wins:
// stale sensor input is lamp ON, whatever the daylight.
#pragma once

#include <cstdint>
#include <string>

#include "icanc/core/camera/illumination.hpp"

namespace icanc {

struct LightControllerParams {
  double tau_s = 3.0;            // timer length [s] (paper: 3; reference launch files: 2)
  double recheck_below_s = 1.0;  // danger resets the timer only when at most this is left [s]
  double stale_timeout_s = 0.3;  // watchdog: lamp on without input for this long [s]
  bool watchdog_enabled = true;  // false: no watchdog at all (offline evaluation; WARN in diagnostics)
  bool illumination_enabled = false;          // gate danger by the camera's illumination state
  double illumination_stale_timeout_s = 1.0;  // illumination report older than this: unknown
};

constexpr double kMaxStaleTimeoutS = 5.0;  // a longer watchdog is no watchdog at 10 Hz

std::string validate(const LightControllerParams& params);

// The nodelet has no periodic tick: it wakes at nextEvent() (timer expiry, watchdog, stale
// illumination) and when the steady publication is due. publish_rate_hz has a floor: the
// LightBridge commands the lamp ON when lamp_cmd is silent for its cmd_stale_timeout_s (1 s),
// so a slower steady rate would only make the bridge light the lamp between publications.
constexpr double kMinPublishRateHz = 2.0;
constexpr double kMaxRateHz = 1000.0;
// "" when the rate is usable, else why, naming the key.
std::string validatePublishRate(double publish_rate_hz);

// kFault: the controller could not start (invalid parameters); the nodelet publishes lamp ON.
enum class LightReason : std::uint8_t {
  kOff = 0, kDanger = 1, kSensorStale = 2, kDaylight = 3, kSensorBlind = 4, kFault = 5
};
const char* toString(LightReason reason);

class LightController {
 public:
  explicit LightController(const LightControllerParams& params = LightControllerParams());

  // Output of the danger detector arrived at `now`: valid input, with or without danger, and
  // whether the sensor was blind for it. Returns true when the timer was started or reset by it.
  bool onInput(double now, bool any_danger, bool sensor_blind = false);

  // Advances the clock without input: timer expiry and watchdog. Returns true when on() or
  // reason() changed.
  bool tick(double now);
  // The first time at which tick() changes on() or reason() unless an input or illumination
  // report comes first (the danger timer's end, the watchdog's, a bright report going stale);
  // infinity when none is pending.
  double nextEvent() const;

  // Restarts a running danger timer to tau at `now` whatever is left of it (recheck_below_s does
  // not apply); false when no timer runs (or in daylight). The segmented lamp uses it to keep a
  // segment's danger light as long as the binary lamp's (icanc/segmented_light_controller.hpp).
  bool restartTimer(double now);

  // The illumination monitor reported `state` at `now` (ignored unless illumination_enabled).
  // Returns true when on() or reason() changed.
  bool onIllumination(double now, Illumination state);

  bool on() const { return stale_ || blind_ || (timer_running_ && !daylight_); }
  LightReason reason() const;
  double timeLeft(double now) const;
  // Time of the last input that started or reset the timer (valid after the first trigger).
  double lastTriggerTime() const { return last_trigger_s_; }

  void setParams(const LightControllerParams& params) { params_ = params; }
  const LightControllerParams& params() const { return params_; }

 private:
  void reset();
  void updateDaylight(double now);

  LightControllerParams params_;
  bool timer_running_ = false;
  double timer_end_s_ = 0.0;
  double last_trigger_s_ = 0.0;
  bool has_input_ = false;
  double last_input_s_ = 0.0;
  bool has_now_ = false;
  double last_now_s_ = 0.0;
  bool stale_ = true;
  bool blind_ = false;
  Illumination illumination_ = Illumination::kUnknown;
  double illumination_s_ = 0.0;
  bool daylight_ = false;
};

}  // namespace icanc
