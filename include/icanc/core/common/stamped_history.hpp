// A stream of stamped samples kept over the last seconds and looked up around a stamp: the
// vehicle's measured twist (TwistHistory) and the odometry the ObstacleDetector takes its pose from
// (EgoPoseSource). Stamps in seconds, as the caller's clock has them (a replay's included): a stamp
// older than the newest means the stream restarted (bag loop, restarted driver), and what came
// before is forgotten. What a sample means, and how two are blended, is the caller's.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <deque>
#include <iterator>

namespace icanc {

template <typename T>
class StampedHistory {
 public:
  struct Sample {
    double stamp_s;
    T value;
  };

  // Samples more than horizon_s older than the newest are dropped.
  explicit StampedHistory(double horizon_s) : horizon_s_(horizon_s) {}

  enum class Added { kAdded, kRestarted };
  // stamp_s must be finite (the caller validates its input). kRestarted: stamp_s is older than the
  // newest sample; all before it is dropped and this one kept. Equal stamps are kept, in the order
  // they came.
  Added add(double stamp_s, const T& value) {
    Added added = Added::kAdded;
    if (!samples_.empty() && stamp_s < samples_.back().stamp_s) {
      samples_.clear();
      added = Added::kRestarted;
    }
    samples_.push_back(Sample{stamp_s, value});
    while (samples_.front().stamp_s < stamp_s - horizon_s_) samples_.pop_front();
    return added;
  }

  // The samples around a stamp: the last at or before it (of equal stamps, the one that came last)
  // and the first after it. Either is null when there is none (before the first sample, after the
  // last, no samples, a NaN stamp). The pointers are valid until the next add().
  struct Bracket {
    const Sample* at_or_before = nullptr;
    const Sample* after = nullptr;
  };
  Bracket bracket(double stamp_s) const {
    Bracket b;
    if (std::isnan(stamp_s)) return b;
    const auto after = std::upper_bound(samples_.begin(), samples_.end(), stamp_s,
                                        [](double t, const Sample& s) { return t < s.stamp_s; });
    if (after != samples_.begin()) b.at_or_before = &*std::prev(after);
    if (after != samples_.end()) b.after = &*after;
    return b;
  }

  bool empty() const { return samples_.empty(); }
  std::size_t size() const { return samples_.size(); }
  // The oldest and the newest sample; not for an empty history.
  const Sample& front() const { return samples_.front(); }
  const Sample& back() const { return samples_.back(); }

 private:
  double horizon_s_;
  std::deque<Sample> samples_;  // stamps non-decreasing
};

}  // namespace icanc
