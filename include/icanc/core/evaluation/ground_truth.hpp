// Ground truth for "dangerous" (docs/design.md): an object is truly dangerous at time t when its
// true trajectory relative to the vehicle enters the vehicle's corridor within the next horizon
// seconds (the reaction time): |y| <= half_width + margin, 0 <= x <= vehicle_front +
// stopping_margin. Independent of the paper's rule, so the rule can be scored against it.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

namespace icanc {

struct CorridorParams {
  double half_width_m = 0.7;        // path half-width w of the vehicle profile
  double margin_m = 0.3;            // added to each side
  double vehicle_front_m = 0.5;     // bumper ahead of the vehicle origin
  double stopping_margin_m = 2.0;   // corridor length ahead of the bumper
  double horizon_s = 3.0;           // reaction time of the profile

  double halfWidth() const { return half_width_m + margin_m; }
  double length() const { return vehicle_front_m + stopping_margin_m; }
};

std::string validate(const CorridorParams& params);

// An object's true box relative to the vehicle at time t.
struct TruthPose {
  double t = 0.0;
  Eigen::Vector2d center = Eigen::Vector2d::Zero();  // x, y in the vehicle frame [m]
  Eigen::Vector2d size = Eigen::Vector2d::Zero();    // length (along yaw), width [m]
  double yaw = 0.0;                                  // [rad]
};

// True when the oriented footprint overlaps the corridor rectangle (separating-axis test).
bool inCorridor(const TruthPose& pose, const CorridorParams& corridor);

// Seconds from `t` until the object is first in the corridor, looking at the trajectory samples
// with time in [t, t + horizon] (sorted by time; linear between samples is not assumed: the
// caller samples finely enough), or -1 when it is not in the corridor within the horizon.
double timeToCorridor(const std::vector<TruthPose>& trajectory, double t,
                      const CorridorParams& corridor);

}  // namespace icanc
