// The nearest-rank percentile every report of the project prints (latency, timing, spreads):
// the sorted values' element at round(p * (n - 1)); 0 for no values. p in [0, 1].
#pragma once

#include <algorithm>
#include <cstddef>
#include <vector>

namespace icanc {

// The same of values already sorted (several percentiles of one set: sort it once).
inline double percentileOfSorted(const std::vector<double>& sorted, double p) {
  if (sorted.empty()) return 0.0;
  return sorted[std::min(sorted.size() - 1, static_cast<std::size_t>(p * (sorted.size() - 1) + 0.5))];
}

inline double percentile(std::vector<double> v, double p) {
  std::sort(v.begin(), v.end());
  return percentileOfSorted(v, p);
}

}  // namespace icanc
