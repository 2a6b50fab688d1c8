// Ray intersection maths of the LiDAR simulator (internal to icanc_sim).
// Rays are o + s * d with s >= 0 in the object's own frame, centred on the object with z up.
// Each function returns the ray parameter s of the first surface hit (the distance when |d| = 1),
// or +infinity when the ray misses. A ray starting inside the solid hits its inner wall.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Core>

namespace icanc {
namespace sim {
namespace raycast {

constexpr double kNoHit = std::numeric_limits<double>::infinity();
constexpr double kParallel = 1e-12;

// Axis-aligned box [-half, half] (slab method).
inline double box(const Eigen::Vector3d& o, const Eigen::Vector3d& d, const Eigen::Vector3d& half) {
  double near = -std::numeric_limits<double>::infinity();
  double far = std::numeric_limits<double>::infinity();
  for (int i = 0; i < 3; ++i) {
    if (std::abs(d[i]) < kParallel) {
      if (std::abs(o[i]) > half[i]) return kNoHit;  // parallel to and outside this slab
      continue;
    }
    const double inv = 1.0 / d[i];
    double s1 = (-half[i] - o[i]) * inv;
    double s2 = (half[i] - o[i]) * inv;
    if (s1 > s2) std::swap(s1, s2);
    near = std::max(near, s1);
    far = std::min(far, s2);
    if (near > far) return kNoHit;
  }
  if (far < 0.0) return kNoHit;     // box behind the ray
  return near >= 0.0 ? near : far;  // from inside: the exit wall
}

// Cylinder with axis z, radius `radius`, z in [-half_height, half_height]: side and both caps.
inline double cylinder(const Eigen::Vector3d& o, const Eigen::Vector3d& d, double radius,
                       double half_height) {
  double best = kNoHit;
  const double r_sq = radius * radius;
  // Side: |(o + s d)_xy|^2 = r^2.
  const double a = d.x() * d.x() + d.y() * d.y();
  if (a > kParallel) {
    const double b = o.x() * d.x() + o.y() * d.y();  // half of the linear coefficient
    const double c = o.x() * o.x() + o.y() * o.y() - r_sq;
    const double disc = b * b - a * c;
    if (disc >= 0.0) {
      const double root = std::sqrt(disc);
      const double s_in = (-b - root) / a;
      const double s_out = (-b + root) / a;
      for (double s : {s_in, s_out}) {
        if (s < 0.0 || s >= best) continue;
        if (std::abs(o.z() + s * d.z()) <= half_height) best = s;
      }
    }
  }
  // Caps: z = +-half_height inside the radius.
  if (std::abs(d.z()) > kParallel) {
    for (double z : {-half_height, half_height}) {
      const double s = (z - o.z()) / d.z();
      if (s < 0.0 || s >= best) continue;
      const double x = o.x() + s * d.x(), y = o.y() + s * d.y();
      if (x * x + y * y <= r_sq) best = s;
    }
  }
  return best;
}

}  // namespace raycast
}  // namespace sim
}  // namespace icanc
