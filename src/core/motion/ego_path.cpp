#include "icanc/core/motion/ego_path.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace icanc {

EgoPath::Refused EgoPath::set(const std::vector<Eigen::Vector2d>& points, double max_offset_m,
                              double max_heading_offset_rad) {
  points_.clear();
  cumulative_.clear();
  for (const Eigen::Vector2d& p : points)
    if (!p.allFinite()) return Refused::kNotFinite;
  // The nearest point of the path to the vehicle's origin, on the segment it lies on.
  double best = std::numeric_limits<double>::infinity();
  std::size_t segment = 0;
  Eigen::Vector2d nearest = Eigen::Vector2d::Zero();
  bool any_segment = false;
  for (std::size_t i = 0; i + 1 < points.size(); ++i) {
    const Eigen::Vector2d d = points[i + 1] - points[i];
    const double len2 = d.squaredNorm();
    if (len2 <= 1e-12) continue;  // a repeated point
    any_segment = true;
    const double u = std::clamp(-points[i].dot(d) / len2, 0.0, 1.0);
    const Eigen::Vector2d q = points[i] + u * d;
    if (q.squaredNorm() < best) {
      best = q.squaredNorm();
      segment = i;
      nearest = q;
    }
  }
  if (!any_segment) return Refused::kTooShort;
  if (std::sqrt(best) > max_offset_m) return Refused::kTooFar;
  // From there on, moved to the origin; repeated points dropped.
  points_.push_back(Eigen::Vector2d::Zero());
  for (std::size_t i = segment + 1; i < points.size(); ++i) {
    const Eigen::Vector2d p = points[i] - nearest;
    if ((p - points_.back()).squaredNorm() > 1e-12) points_.push_back(p);
  }
  if (points_.size() < 2) {  // the vehicle is at the path's very end: its last direction on
    const Eigen::Vector2d d = points[segment + 1] - points[segment];
    points_.push_back(d.normalized());
  }
  const Eigen::Vector2d first = points_[1] - points_[0];
  if (std::abs(std::atan2(first.y(), first.x())) > max_heading_offset_rad) {
    points_.clear();
    return Refused::kHeading;
  }
  cumulative_.push_back(0.0);
  for (std::size_t i = 1; i < points_.size(); ++i)
    cumulative_.push_back(cumulative_.back() + (points_[i] - points_[i - 1]).norm());
  return Refused::kNone;
}

PlanarPose EgoPath::at(double s) const {
  PlanarPose pose;
  if (empty()) return pose;
  // The segment holding s (the last one beyond the end).
  const auto it = std::upper_bound(cumulative_.begin(), cumulative_.end(), s);
  std::size_t i = it == cumulative_.begin() ? 0 : static_cast<std::size_t>(it - cumulative_.begin()) - 1;
  i = std::min(i, points_.size() - 2);
  const Eigen::Vector2d d = points_[i + 1] - points_[i];
  const double len = cumulative_[i + 1] - cumulative_[i];
  pose.yaw = std::atan2(d.y(), d.x());
  pose.position = points_[i] + (std::max(0.0, s) - cumulative_[i]) / len * d;
  return pose;
}

const char* toString(EgoPath::Refused why) {
  switch (why) {
    case EgoPath::Refused::kNone: return "accepted";
    case EgoPath::Refused::kTooShort: return "fewer than two distinct points";
    case EgoPath::Refused::kNotFinite: return "a non-finite point";
    case EgoPath::Refused::kTooFar: return "the vehicle is not on it (nearest point too far)";
    case EgoPath::Refused::kHeading: return "it leads away from the vehicle's heading";
  }
  return "unknown";
}

}  // namespace icanc
