// The nearest-rank percentile every report of the project prints (latency, timing, spreads):
// the sorted values' element at round(p * (n - 1)); 0 for no values. p in [0, 1].
#pragma once

#include <algorithm>
#include <cstddef>
#include <vector>

namespace icanc {

inline double percentile(std::vector<double> v, double p) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<std::size_t>(p * (v.size() - 1) + 0.5))];
}

}  // namespace icanc
