#include "icanc/core/evaluation/segment_coverage.hpp"

#include <cmath>
#include <set>
#include <utility>

#include "icanc/core/light/segmented_light_controller.hpp"

namespace icanc {

SegmentLampParams evenLamp(std::size_t segments, double span_deg, double watts_total, double low_watts_total) {
  SegmentLampParams p;
  for (std::size_t i = 0; i < segments; ++i) {
    LampSegment s;
    s.azimuth_min_deg = -0.5 * span_deg + span_deg * double(i) / double(segments);
    s.azimuth_max_deg = -0.5 * span_deg + span_deg * double(i + 1) / double(segments);
    s.watts = watts_total / double(segments);
    s.low_watts = low_watts_total / double(segments);
    p.segments.push_back(s);
  }
  return p;
}

SegmentCoverage segmentCoverage(const std::vector<EvalFrame>& frames, const LightControllerParams& light,
                                const SegmentLampParams& lamp, std::uint32_t min_points,
                                const std::vector<ScoredRow>* rows) {
  std::set<std::pair<double, std::uint32_t>> flagged;  // (t, true id) the detector flagged
  if (rows)
    for (const ScoredRow& r : *rows)
      if (r.outcome == Outcome::kTruePositive && r.has_truth) flagged.emplace(r.t, r.truth.id);
  LightControllerParams offline = light;
  offline.watchdog_enabled = false;  // frames are given, not awaited
  LightController binary(offline);
  SegmentedLightController segmented(offline, lamp);
  const std::vector<LampSegment>& segments = segmented.segments();
  const Eigen::Vector2d at = lamp.lamp_position_m.head<2>().cast<double>();
  double all_w = 0.0;
  for (const LampSegment& s : segments) all_w += s.watts;

  SegmentCoverage out;
  out.segments = segments.size();
  const EvalFrame* previous = nullptr;
  bool binary_on = false;
  std::vector<float> levels;
  std::vector<Eigen::AlignedBox2d> boxes;
  for (const EvalFrame& f : frames) {
    if (!f.processed) continue;
    if (previous) {  // the previous frame's state held until this one
      const double dt = f.t - previous->t;
      out.binary_wh += binary_on ? all_w * dt / 3600.0 : 0.0;
      for (std::size_t i = 0; i < levels.size(); ++i) out.segmented_wh += levels[i] * segments[i].watts * dt / 3600.0;
    }
    boxes.clear();
    bool unlocated = false;
    for (const DetectedObject& d : f.detections) {
      if (!d.dangerous) continue;
      if (d.has_aabb) boxes.emplace_back(d.aabb_min, d.aabb_max);
      else unlocated = true;
    }
    binary.onInput(f.t, !boxes.empty() || unlocated);
    segmented.onInput(f.t, boxes, false, unlocated);
    binary_on = binary.on();
    levels = segmented.levels();
    previous = &f;
    if (!binary_on) continue;
    for (const TruthObject& o : f.truth) {
      if (!o.dangerous || o.num_points < min_points) continue;
      const AzimuthRange range = azimuthRange(footprintBounds(o), at);
      bool in_beam = false, lit = false;
      for (std::size_t i = 0; i < segments.size(); ++i) {
        if (!covers(segments[i], range, 0.0)) continue;
        in_beam = true;
        lit = lit || levels[i] > 0.0f;
      }
      out.outside_beam_object_frames += !in_beam;
      out.binary_tp_object_frames += in_beam;
      out.covered_object_frames += lit;
      if (in_beam && flagged.count({f.t, o.id})) {
        ++out.flagged_object_frames;
        out.flagged_covered_object_frames += lit;
      }
    }
  }
  out.coverage = out.binary_tp_object_frames
      ? double(out.covered_object_frames) / double(out.binary_tp_object_frames) : 1.0;
  out.flagged_coverage = out.flagged_object_frames
      ? double(out.flagged_covered_object_frames) / double(out.flagged_object_frames) : 1.0;
  out.energy_ratio = out.binary_wh > 0.0 ? out.segmented_wh / out.binary_wh : 0.0;
  return out;
}

}  // namespace icanc
