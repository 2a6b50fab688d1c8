// Energy of a segmented (matrix) lamp, beside the binary lamp of energy.hpp: each
// segment draws its watts x its level (0..1, icanc/LampCommand levels) while lit.
//
// Paper cases: worst = every segment always on (the binary lamp's worst case); average and best =
// the binary lamp's on-time with `lit_per_object` segments lit instead of all of them, i.e. each
// dangerous object lights that many segments (one at a time, as the paper's "one object a second"
// and its 47 objects > tau apart). A catalogue lamp is split evenly into `segments` segments.
#pragma once

#include <cstddef>
#include <vector>

#include "icanc/core/evaluation/energy.hpp"

namespace icanc {

// One row per catalogue lamp and case, the lamp split evenly into `segments` (watts = the whole
// lamp), `lit_per_object` of them on in the average and best cases. Throws std::invalid_argument
// for segments == 0 or lit_per_object == 0.
std::vector<EnergyRow> segmentedEnergyTable(const LampCatalogue& catalogue,
                                            const std::vector<DriveCase>& cases, Beam beam,
                                            std::size_t segments, std::size_t lit_per_object);

// The lamp's levels from t_s on (until the next sample).
struct LevelSample {
  double t_s = 0.0;
  std::vector<float> levels;
};

struct SegmentEnergy {
  double wh = 0.0;         // sum over segments of watts x level x time
  double wh_all_on = 0.0;  // every segment at level 1 over the span (the always-on lamp)
  double span_s = 0.0;     // first sample to end_s
  double any_on_s = 0.0;   // time with at least one segment lit
};

// Integrates the piecewise-constant levels (each sample until the next, the last until end_s).
// A sample whose level count is not the lamp's (a fault command) counts as every segment on.
// Throws std::invalid_argument as integrateOnTime, or for an empty segment_watts.
SegmentEnergy integrateSegmentEnergy(const std::vector<LevelSample>& samples, double end_s,
                                     const std::vector<double>& segment_watts);

}  // namespace icanc
