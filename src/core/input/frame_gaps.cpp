#include "icanc/core/input/frame_gaps.hpp"

#include <cmath>

namespace icanc {

std::uint64_t missedFrames(double previous_s, double stamp_s, double expected_rate_hz) {
  if (!(expected_rate_hz > 0.0) || !(stamp_s > previous_s)) return 0;
  const double periods = (stamp_s - previous_s) * expected_rate_hz;
  if (!(periods > 1.5) || !std::isfinite(periods)) return 0;
  return static_cast<std::uint64_t>(std::llround(periods)) - 1;
}

}  // namespace icanc
