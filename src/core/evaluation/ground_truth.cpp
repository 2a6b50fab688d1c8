#include "icanc/core/evaluation/ground_truth.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

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
  const double c = std::cos(pose.yaw), s = std::sin(pose.yaw);
  const Eigen::Vector2d ax(c, s), ay(-s, c);
  const double hl = 0.5 * pose.size.x(), hw = 0.5 * pose.size.y();
  const Eigen::Vector2d rect_center(0.5 * corridor.length(), 0.0);
  const Eigen::Vector2d rect_half(0.5 * corridor.length(), corridor.halfWidth());
  const Eigen::Vector2d d = pose.center - rect_center;
  // Axes of the corridor (x, y): the footprint's extent along each.
  const double ext_x = hl * std::abs(ax.x()) + hw * std::abs(ay.x());
  const double ext_y = hl * std::abs(ax.y()) + hw * std::abs(ay.y());
  if (std::abs(d.x()) > rect_half.x() + ext_x) return false;
  if (std::abs(d.y()) > rect_half.y() + ext_y) return false;
  // Axes of the footprint: the corridor's extent along each.
  for (int k = 0; k < 2; ++k) {
    const Eigen::Vector2d& axis = k == 0 ? ax : ay;
    const double half = k == 0 ? hl : hw;
    const double ext = rect_half.x() * std::abs(axis.x()) + rect_half.y() * std::abs(axis.y());
    if (std::abs(d.dot(axis)) > half + ext) return false;
  }
  return true;
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
