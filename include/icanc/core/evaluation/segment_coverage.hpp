// The segmented lamp on a scored replay: the frames' dangerous detections drive,
// offline and side by side, the paper's binary controller and the segmented one (watchdog off:
// frames are given). Coverage: of the truly dangerous object-frames the binary lamp lights, the
// share whose true footprint (its axis-aligned bounds, seen from the lamp) meets a lit segment.
// The binary lamp is the same headlight with every segment on: it lights what its beam (the union
// of the segments) reaches, so a truly dangerous object outside every segment (beside or behind a
// forward lamp) is lit by neither and counted apart (outside_beam_object_frames).
// Energy: lit segments' watts x time against the binary lamp's (all segments) x its on-time, each
// frame's state holding until the next frame.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "icanc/core/evaluation/evaluation.hpp"
#include "icanc/core/light/lamp_segments.hpp"
#include "icanc/core/light/light_controller.hpp"

namespace icanc {

struct SegmentCoverage {
  std::size_t segments = 0;
  std::size_t binary_tp_object_frames = 0;  // truly dangerous, binary lamp on, inside its beam
  std::size_t covered_object_frames = 0;    // ... and inside a lit segment
  double coverage = 0.0;                    // covered / binary TP (1 when there are none)
  // Truly dangerous while the binary lamp is on, but outside the lamp's beam (no segment meets it).
  std::size_t outside_beam_object_frames = 0;
  // With the scored rows: of the binary TP object-frames, those whose object the danger detector
  // flagged (outcome TP), and of them the covered ones. The rest the binary lamp lit only by chance,
  // for another object's danger (a missed danger, counted as FN by the evaluator).
  std::size_t flagged_object_frames = 0;
  std::size_t flagged_covered_object_frames = 0;
  double flagged_coverage = 0.0;  // flagged covered / flagged (1 when there are none)
  double binary_wh = 0.0;                   // all segments' watts x binary on-time
  double segmented_wh = 0.0;                // sum of lit segments' watts x level x time
  double energy_ratio = 0.0;                // segmented / binary (0 when the binary lamp is off)
};

// Frames not processed are skipped. Only true objects with at least min_points returns count.
// `rows`: evaluate()'s scored rows of the same frames (for the flagged_* counts), or null.
SegmentCoverage segmentCoverage(const std::vector<EvalFrame>& frames, const LightControllerParams& light,
                                const SegmentLampParams& lamp, std::uint32_t min_points,
                                const std::vector<ScoredRow>* rows = nullptr);

// N equal segments over [-span/2, span/2] deg, watts_total / N each on high beam and
// low_watts_total / N on low beam (0: high beam only).
SegmentLampParams evenLamp(std::size_t segments, double span_deg, double watts_total,
                           double low_watts_total = 0.0);

}  // namespace icanc
