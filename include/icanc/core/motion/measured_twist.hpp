// The vehicle's own measurement of its motion (wheel speed on a CAN bus, the yaw rate of its
// stability control's gyro), kept over the last seconds and looked up at a cloud's stamp (issue
// 19: the LiDAR odometry's pose where the scene fixes no motion). No ROS: the LidarOdometry
// nodelet feeds it from geometry_msgs/TwistStamped.
#pragma once

#include <cstddef>
#include <limits>

#include "icanc/core/common/stamped_history.hpp"

namespace icanc {

struct MeasuredTwist {
  double forward_mps = 0.0;  // along the vehicle's x [m/s]; negative reversing
  double yaw_rate_rad_s = std::numeric_limits<double>::quiet_NaN();  // about its z; NaN: not measured
};

inline MeasuredTwist measuredTwist(double forward_mps,
                                   double yaw_rate_rad_s = std::numeric_limits<double>::quiet_NaN()) {
  MeasuredTwist m;
  m.forward_mps = forward_mps;
  m.yaw_rate_rad_s = yaw_rate_rad_s;
  return m;
}

class TwistHistory {
 public:
  // Samples older than horizon_s behind the newest are dropped; a speed beyond max_speed_mps or a
  // yaw rate beyond max_yaw_rate_rad_s either way is not a measurement.
  explicit TwistHistory(double horizon_s = 2.0, double max_speed_mps = 100.0,
                        double max_yaw_rate_rad_s = 5.0);

  enum class Added { kAdded, kInvalid, kRestarted };
  // kInvalid: a non-finite stamp or speed, a yaw rate neither finite nor NaN (infinite), or
  // beyond the limits; not kept. kRestarted: the stamp went backwards (bag loop, restarted
  // driver): what came before is forgotten, this is kept.
  Added add(double stamp_s, const MeasuredTwist& twist);

  // The twist at stamp_s: linear between the samples on either side when both are within
  // max_age_s of it, else the nearest sample within max_age_s. false: none that near.
  bool at(double stamp_s, double max_age_s, MeasuredTwist& twist) const;

  std::size_t size() const { return samples_.size(); }

 private:
  double max_speed_mps_, max_yaw_rate_rad_s_;
  StampedHistory<MeasuredTwist> samples_;
};

}  // namespace icanc
