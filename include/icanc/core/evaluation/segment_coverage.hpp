// The segmented lamp on a scored replay (issue 23 targets): the frames' dangerous detections drive,
// offline and side by side, the paper's binary controller and the segmented one (watchdog off:
// frames are given). Coverage: of the truly dangerous object-frames the binary lamp lights, the
// share whose true footprint (its axis-aligned bounds, seen from the lamp) meets a lit segment.
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
  std::size_t binary_tp_object_frames = 0;  // truly dangerous, binary lamp on
  std::size_t covered_object_frames = 0;    // ... and inside a lit segment
  double coverage = 0.0;                    // covered / binary TP (1 when there are none)
  double binary_wh = 0.0;                   // all segments' watts x binary on-time
  double segmented_wh = 0.0;                // sum of lit segments' watts x level x time
  double energy_ratio = 0.0;                // segmented / binary (0 when the binary lamp is off)
};

// Frames not processed are skipped. Only true objects with at least min_points returns count.
SegmentCoverage segmentCoverage(const std::vector<EvalFrame>& frames, const LightControllerParams& light,
                                const SegmentLampParams& lamp, std::uint32_t min_points);

// N equal segments over [-span/2, span/2] deg, watts_total / N each on high beam and
// low_watts_total / N on low beam (0: high beam only).
SegmentLampParams evenLamp(std::size_t segments, double span_deg, double watts_total,
                           double low_watts_total = 0.0);

}  // namespace icanc
