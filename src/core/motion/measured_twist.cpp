#include "icanc/core/motion/measured_twist.hpp"

#include <algorithm>
#include <cmath>
#include <iterator>

namespace icanc {

TwistHistory::TwistHistory(double horizon_s, double max_speed_mps, double max_yaw_rate_rad_s)
    : horizon_s_(horizon_s), max_speed_mps_(max_speed_mps), max_yaw_rate_rad_s_(max_yaw_rate_rad_s) {}

TwistHistory::Added TwistHistory::add(double stamp_s, const MeasuredTwist& twist) {
  const double w = twist.yaw_rate_rad_s;
  if (!std::isfinite(stamp_s) || !std::isfinite(twist.forward_mps) ||
      std::abs(twist.forward_mps) > max_speed_mps_ || std::isinf(w) || std::abs(w) > max_yaw_rate_rad_s_)
    return Added::kInvalid;
  Added added = Added::kAdded;
  if (!samples_.empty() && stamp_s < samples_.back().first) {
    samples_.clear();
    added = Added::kRestarted;
  }
  samples_.emplace_back(stamp_s, twist);
  while (samples_.front().first < stamp_s - horizon_s_) samples_.pop_front();
  return added;
}

bool TwistHistory::at(double stamp_s, double max_age_s, MeasuredTwist& twist) const {
  if (samples_.empty() || !std::isfinite(stamp_s)) return false;
  // The first sample after stamp_s, and the one before it.
  const auto after = std::upper_bound(
      samples_.begin(), samples_.end(), stamp_s,
      [](double t, const std::pair<double, MeasuredTwist>& s) { return t < s.first; });
  const bool has_after = after != samples_.end() && after->first - stamp_s <= max_age_s;
  const bool has_before = after != samples_.begin() && stamp_s - std::prev(after)->first <= max_age_s;
  if (has_before && has_after) {
    const auto& a = *std::prev(after);
    const auto& b = *after;
    const double k = b.first > a.first ? (stamp_s - a.first) / (b.first - a.first) : 0.0;
    twist.forward_mps = a.second.forward_mps + k * (b.second.forward_mps - a.second.forward_mps);
    // NaN on either side (a source without a gyro): not measured.
    twist.yaw_rate_rad_s = a.second.yaw_rate_rad_s + k * (b.second.yaw_rate_rad_s - a.second.yaw_rate_rad_s);
    return true;
  }
  if (has_before) twist = std::prev(after)->second;
  else if (has_after) twist = after->second;
  return has_before || has_after;
}

}  // namespace icanc
