#include "icanc/core/evaluation/ground_truth.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "icanc/core/common/planar_geometry.hpp"

namespace icanc {

std::string validate(const CorridorParams& p) {
  std::ostringstream why;
  if (!(p.half_width_m > 0.0)) why << "corridor.half_width_m must be > 0 (got " << p.half_width_m << ")";
  else if (!(p.margin_m >= 0.0)) why << "corridor.margin_m must be >= 0 (got " << p.margin_m << ")";
  else if (!(p.vehicle_front_m >= 0.0))
    why << "corridor.vehicle_front_m must be >= 0 (got " << p.vehicle_front_m << ")";
  else if (!(p.stopping_margin_m >= 0.0))
    why << "corridor.stopping_margin_m must be >= 0 (got " << p.stopping_margin_m << ")";
  else if (!(p.horizon_s > 0.0)) why << "corridor.horizon_s must be > 0 (got " << p.horizon_s << ")";
  return why.str();
}

bool inCorridor(const TruthPose& pose, const CorridorParams& corridor) {
  // Corridor: axis-aligned rectangle [0, L] x [-W, W]; footprint: oriented rectangle.
  return orientedRectOverlapsBox(pose.center, 0.5 * pose.size, pose.yaw,
                                 Eigen::Vector2d(0.5 * corridor.length(), 0.0),
                                 Eigen::Vector2d(0.5 * corridor.length(), corridor.halfWidth()));
}

double timeToCorridor(const std::vector<TruthPose>& trajectory, double t,
                      const CorridorParams& corridor) {
  const double eps = 1e-9;
  for (const TruthPose& p : trajectory) {
    if (p.t < t - eps) continue;
    if (p.t > t + corridor.horizon_s + eps) break;
    if (inCorridor(p, corridor)) return std::max(0.0, p.t - t);
  }
  return -1.0;
}

}  // namespace icanc
