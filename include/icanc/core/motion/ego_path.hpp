// The vehicle's planned path (a planner's nav_msgs/Path), as the predictive danger model follows
// it instead of the constant turn of the current twist: where the road bends the other way
// within the reaction time (an S-bend), the twist's arc leaves the road and sweeps the corridor
// over what stands beside it; the planner's path stays on the road. No ROS: the
// DangerDetector nodelet transforms the message into the vehicle frame at the obstacles' stamp.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "icanc/core/motion/ego_motion.hpp"

namespace icanc {

class EgoPath {
 public:
  enum class Refused { kNone, kTooShort, kNotFinite, kTooFar, kHeading };

  // points: the path in the vehicle frame (x ahead, y left) in driving order. What is kept is the
  // part ahead of the point of the path nearest the vehicle's origin (projected onto its segment),
  // moved so that point is the origin: the vehicle follows the path's shape from where it is.
  // Refused (and the path left empty): fewer than two distinct points, a non-finite one, the
  // nearest point farther than max_offset_m from the vehicle, or the path's direction there more
  // than max_heading_offset_rad from the vehicle's heading (a path it is not following).
  Refused set(const std::vector<Eigen::Vector2d>& points, double max_offset_m,
              double max_heading_offset_rad);

  bool empty() const { return points_.size() < 2; }
  double length() const { return empty() ? 0.0 : cumulative_.back(); }

  // The pose after travelling s metres along the path from the origin, its heading the direction
  // of the segment it is on; beyond the path's end, straight on along the last segment. s <= 0:
  // the origin with the first segment's heading.
  PlanarPose at(double s) const;

 private:
  std::vector<Eigen::Vector2d> points_;  // from the origin on
  std::vector<double> cumulative_;       // arc length at each point
};

const char* toString(EgoPath::Refused why);

}  // namespace icanc
