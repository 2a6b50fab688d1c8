#include "icanc/core/motion/measured_twist.hpp"

#include <cmath>

namespace icanc {

TwistHistory::TwistHistory(double horizon_s, double max_speed_mps, double max_yaw_rate_rad_s)
    : max_speed_mps_(max_speed_mps), max_yaw_rate_rad_s_(max_yaw_rate_rad_s), samples_(horizon_s) {}

TwistHistory::Added TwistHistory::add(double stamp_s, const MeasuredTwist& twist) {
  const double w = twist.yaw_rate_rad_s;
  if (!std::isfinite(stamp_s) || !std::isfinite(twist.forward_mps) ||
      std::abs(twist.forward_mps) > max_speed_mps_ || std::isinf(w) || std::abs(w) > max_yaw_rate_rad_s_)
    return Added::kInvalid;
  return samples_.add(stamp_s, twist) == StampedHistory<MeasuredTwist>::Added::kRestarted
             ? Added::kRestarted
             : Added::kAdded;
}

bool TwistHistory::at(double stamp_s, double max_age_s, MeasuredTwist& twist) const {
  if (!std::isfinite(stamp_s)) return false;
  const auto around = samples_.bracket(stamp_s);
  // The samples on either side, each only when within max_age_s of the stamp.
  const auto* a = around.at_or_before && stamp_s - around.at_or_before->stamp_s <= max_age_s
                      ? around.at_or_before
                      : nullptr;
  const auto* b = around.after && around.after->stamp_s - stamp_s <= max_age_s ? around.after : nullptr;
  if (a && b) {
    const double k = b->stamp_s > a->stamp_s ? (stamp_s - a->stamp_s) / (b->stamp_s - a->stamp_s) : 0.0;
    twist.forward_mps = a->value.forward_mps + k * (b->value.forward_mps - a->value.forward_mps);
    // NaN on either side (a source without a gyro): not measured.
    twist.yaw_rate_rad_s = a->value.yaw_rate_rad_s + k * (b->value.yaw_rate_rad_s - a->value.yaw_rate_rad_s);
    return true;
  }
  if (a) twist = a->value;
  else if (b) twist = b->value;
  return a || b;
}

}  // namespace icanc
