// Small planar (x, y) geometry shared by the stages: the heading of a rotation, and whether an
// oriented rectangle overlaps an axis-aligned one (the danger model's predicted parts against its
// corridor, the ground truth's labelled footprints against the same corridor).
#pragma once

#include <cmath>

#include <Eigen/Core>

namespace icanc {

// The heading (rotation about +z) of a rotation matrix [rad], in (-pi, pi].
inline double yawOf(const Eigen::Matrix3d& rotation) {
  return std::atan2(rotation(1, 0), rotation(0, 0));
}

// True when the rectangle with this centre, half-size (along its own axes) and yaw overlaps the
// axis-aligned rectangle with box_center and box_half (separating axes: the box's two, the
// rectangle's two; touching counts as overlapping).
inline bool orientedRectOverlapsBox(const Eigen::Vector2d& center, const Eigen::Vector2d& half,
                                    double yaw, const Eigen::Vector2d& box_center,
                                    const Eigen::Vector2d& box_half) {
  const double c = std::cos(yaw), s = std::sin(yaw);
  const Eigen::Vector2d ax(c, s), ay(-s, c);
  const Eigen::Vector2d d = center - box_center;
  // The box's axes (x, y): the rectangle's extent along each.
  const double ext_x = half.x() * std::abs(ax.x()) + half.y() * std::abs(ay.x());
  const double ext_y = half.x() * std::abs(ax.y()) + half.y() * std::abs(ay.y());
  if (std::abs(d.x()) > box_half.x() + ext_x) return false;
  if (std::abs(d.y()) > box_half.y() + ext_y) return false;
  // The rectangle's axes: the box's extent along each.
  for (int k = 0; k < 2; ++k) {
    const Eigen::Vector2d& axis = k == 0 ? ax : ay;
    const double ext = box_half.x() * std::abs(axis.x()) + box_half.y() * std::abs(axis.y());
    if (std::abs(d.dot(axis)) > half[k] + ext) return false;
  }
  return true;
}

}  // namespace icanc
