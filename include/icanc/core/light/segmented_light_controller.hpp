// The paper's light controller per lamp segment: one icanc::LightController per
// segment, each fed every input, with danger when a dangerous object's box (seen from the lamp,
// widened by segment_margin_deg) meets its azimuth range. The paper's lamp is the one-segment case:
// its segment covers every direction, so it sees exactly the inputs of a single LightController.
//
// Fail-safe: every segment hears every input, tick and illumination report, so a stale or blind
// sensor lights all segments, and the daylight gate holds them all, exactly as the single lamp.
//
// Never darker than the binary lamp (the paper's one LightController fed the same inputs, which
// `lamp_cmd` follows): whenever the binary lamp is ON for danger, at least one segment is lit.
// - A dangerous object that meets no segment (beside or behind the lamp's field) lights every
//   segment at high beam, as the binary lamp lights its whole beam: no segment covers it, so none
//   is nearer to it in a sense that matters for the camera, and a partial answer would be darker
//   than the lamp the paper switches.
// - When an input (re)starts the binary lamp's timer, every segment that input hits restarts its
//   timer too, even where its own timer has more than recheck_below_s left and would ignore it,
//   so no segment's light ends before the binary lamp's.
// Level of a lit segment: the highest level (requiredLevel: high beam 1, the low beam's
// low_watts / watts for a near object, or dimmed by distance) any object that lit it needed since
// its timer was (re)started. Fail-safe light is always 1.
#pragma once

#include <cstddef>
#include <vector>

#include <Eigen/Geometry>

#include "icanc/core/light/lamp_segments.hpp"
#include "icanc/core/light/light_controller.hpp"

namespace icanc {

class SegmentedLightController {
 public:
  // The lamp parameters must validate (icanc::validate); invalid ones are the caller's fault path.
  SegmentedLightController(const LightControllerParams& params, const SegmentLampParams& lamp);

  // An input at `now`: the boxes (base_link, x-y) of its dangerous objects. unlocated_danger:
  // danger whose boxes are not known (lights every segment, high beam).
  void onInput(double now, const std::vector<Eigen::AlignedBox2d>& dangerous, bool sensor_blind,
               bool unlocated_danger = false);
  bool tick(double now);  // true when a level or the reason changed
  double nextEvent() const;  // the earliest of the segments' (LightController::nextEvent)
  bool onIllumination(double now, Illumination state);

  std::vector<float> levels() const;  // 0..1 per segment, in profile order
  bool anyOn() const;
  // Shared fail-safe / daylight reasons first; else kDanger when a segment is lit, else kOff.
  LightReason reason() const;

  // Dangerous boxes of the inputs so far that met no segment (every segment lit for them).
  std::size_t unlitObjects() const { return unlit_objects_; }
  // The binary lamp of the same inputs (the paper's machine, what `lamp_cmd` says).
  const LightController& binaryLamp() const { return binary_; }
  const std::vector<LampSegment>& segments() const { return segments_; }
  const SegmentLampParams& lamp() const { return lamp_; }
  void setParams(const LightControllerParams& params);

 private:
  SegmentLampParams lamp_;
  std::vector<LampSegment> segments_;
  std::vector<LightController> timers_;
  LightController binary_;     // the paper's lamp over the same inputs
  std::vector<double> level_;  // per segment: the highest level its objects needed since (re)start
  std::size_t unlit_objects_ = 0;
};

}  // namespace icanc
