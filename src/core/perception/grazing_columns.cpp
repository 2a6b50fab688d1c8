#include "icanc/core/perception/grazing_columns.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <utility>

namespace icanc {
namespace {

constexpr double kDeg = 3.14159265358979323846 / 180.0;

// The box's outline seen from above: its hull, else its axis-aligned corners (written into
// `corners`; the hull is not copied).
const std::vector<Eigen::Vector2f>& outline(const Box3D& box,
                                            std::vector<Eigen::Vector2f>& corners) {
  if (!box.hull.empty()) return box.hull;
  corners = {{box.min.x(), box.min.y()},
             {box.max.x(), box.min.y()},
             {box.max.x(), box.max.y()},
             {box.min.x(), box.max.y()}};
  return corners;
}

// Roots of a t^2 + b t + c in [0, 1], appended to `out`.
void rootsInUnit(double a, double b, double c, std::vector<double>& out) {
  if (std::abs(a) < 1e-12) {
    if (std::abs(b) > 1e-12) out.push_back(-c / b);
    return;
  }
  const double disc = b * b - 4.0 * a * c;
  if (disc < 0.0) return;
  const double sq = std::sqrt(disc);
  out.push_back((-b - sq) / (2.0 * a));
  out.push_back((-b + sq) / (2.0 * a));
}

// Whether a point of the segment a-b lies within `reach` of c and within the double cone of
// half-angle asin(s) about the unit direction u through c. Both conditions are quadratic in the
// segment's parameter t, so where they overlap in [0, 1] they do so at 0, 1 or a root of one.
bool segmentInCone(const Eigen::Vector2d& c, const Eigen::Vector2d& u, double s, double reach,
                   const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                   std::vector<double>& candidates) {
  const Eigen::Vector2d p = a - c, q = b - a;
  const auto cross = [&u](const Eigen::Vector2d& v) { return u.x() * v.y() - u.y() * v.x(); };
  const double k0 = cross(p), k1 = cross(q);
  const double pp = p.squaredNorm(), pq = p.dot(q), qq = q.squaredNorm(), s2 = s * s;
  // f(t) = s^2 |d|^2 - (u x d)^2 >= 0 (in the cone), g(t) = reach^2 - |d|^2 >= 0 (in reach).
  const auto f = [&](double t) {
    const double k = k0 + t * k1;
    return s2 * (pp + 2.0 * t * pq + t * t * qq) - k * k;
  };
  const auto g = [&](double t) { return reach * reach - (pp + 2.0 * t * pq + t * t * qq); };
  candidates.assign({0.0, 1.0});
  rootsInUnit(s2 * qq - k1 * k1, 2.0 * (s2 * pq - k0 * k1), s2 * pp - k0 * k0, candidates);
  rootsInUnit(-qq, -2.0 * pq, reach * reach - pp, candidates);
  constexpr double kEps = 1e-9;
  for (double t : candidates) {
    if (!(t >= 0.0 && t <= 1.0)) continue;
    if (f(t) >= -kEps && g(t) >= -kEps) return true;
  }
  return false;
}

// Whether any footprint part (else the hull) of `box` lies within reach of c in the cone.
bool continuesAlong(const Box3D& box, const Eigen::Vector2d& c, const Eigen::Vector2d& u, double s,
                    double reach, std::vector<double>& scratch,
                    std::vector<Eigen::Vector2f>& corners) {
  if (box.min.x() > c.x() + reach || box.max.x() < c.x() - reach || box.min.y() > c.y() + reach ||
      box.max.y() < c.y() - reach)
    return false;
  if (!box.footprint.empty()) {
    for (const FootprintCell& cell : box.footprint) {
      const Eigen::Vector2d lo = cell.min.cast<double>(), hi = cell.max.cast<double>();
      if (c.x() >= lo.x() && c.x() <= hi.x() && c.y() >= lo.y() && c.y() <= hi.y()) return true;
      const Eigen::Vector2d corners[4] = {lo, {hi.x(), lo.y()}, hi, {lo.x(), hi.y()}};
      for (int k = 0; k < 4; ++k)
        if (segmentInCone(c, u, s, reach, corners[k], corners[(k + 1) % 4], scratch)) return true;
    }
    return false;
  }
  const std::vector<Eigen::Vector2f>& hull = outline(box, corners);
  for (std::size_t k = 0; k < hull.size(); ++k) {
    const Eigen::Vector2d a = hull[k].cast<double>(), b = hull[(k + 1) % hull.size()].cast<double>();
    if (segmentInCone(c, u, s, reach, a, b, scratch)) return true;
  }
  return false;
}

}  // namespace

std::string validate(const GrazingColumnParams& p, const std::string& prefix) {
  std::ostringstream why;
  if (!(p.reach_m >= 0.0f && p.reach_m <= 10.0f)) {
    why << prefix << "grazing_reach_m must be in [0, 10] (got " << p.reach_m << ")";
  } else if (!(p.angle_deg >= 0.0f && p.angle_deg < 90.0f)) {
    why << prefix << "grazing_angle_deg must be in [0, 90) (got " << p.angle_deg << ")";
  } else if (!(p.max_step_m >= 0.0f) || !std::isfinite(p.max_step_m)) {
    why << prefix << "grazing_max_step_m must be >= 0 (got " << p.max_step_m << ")";
  } else if (!(p.thin_m > 0.0f) || !std::isfinite(p.thin_m) || !(p.max_length_m > 0.0f) ||
             !std::isfinite(p.max_length_m)) {
    why << prefix << "grazing column's thin_m and max_length_m must be > 0";
  }
  return why.str();
}

std::size_t dropGrazingColumnBoxes(std::vector<Box3D>& boxes, const Eigen::Vector2f& origin,
                                   const GrazingColumnParams& params) {
  if (params.reach_m <= 0.0f || boxes.size() < 2) return 0;
  const double s = std::sin(params.angle_deg * kDeg);
  std::vector<char> dropped(boxes.size(), 0);
  std::vector<double> scratch;
  std::vector<Eigen::Vector2f> corners, other_corners;
  std::size_t count = 0;
  for (std::size_t i = 0; i < boxes.size(); ++i) {
    const Box3D& column = boxes[i];
    const std::vector<Eigen::Vector2f>& hull = outline(column, corners);
    Eigen::Vector2d c = Eigen::Vector2d::Zero();
    for (const Eigen::Vector2f& v : hull) c += v.cast<double>();
    c /= static_cast<double>(hull.size());
    const Eigen::Vector2d sight = c - origin.cast<double>();
    const double r = sight.norm();
    if (r < params.max_length_m) continue;  // at the sensor: no line of sight to speak of
    const Eigen::Vector2d u = sight / r;
    double across_lo = 1e300, across_hi = -1e300, along_lo = 1e300, along_hi = -1e300;
    for (const Eigen::Vector2f& v : hull) {
      const Eigen::Vector2d d = v.cast<double>() - c;
      const double across = u.x() * d.y() - u.y() * d.x(), along = u.dot(d);
      across_lo = std::min(across_lo, across);
      across_hi = std::max(across_hi, across);
      along_lo = std::min(along_lo, along);
      along_hi = std::max(along_hi, along);
    }
    if (across_hi - across_lo > params.thin_m || along_hi - along_lo > params.max_length_m) continue;
    for (std::size_t j = 0; j < boxes.size(); ++j) {
      if (j == i || std::abs(boxes[j].max.z() - column.max.z()) > params.max_step_m) continue;
      if (continuesAlong(boxes[j], c, u, s, params.reach_m, scratch, other_corners)) {
        dropped[i] = 1;
        ++count;
        break;
      }
    }
  }
  std::size_t kept = 0;
  for (std::size_t i = 0; i < boxes.size(); ++i)
    if (!dropped[i]) {
      if (kept != i) boxes[kept] = std::move(boxes[i]);
      ++kept;
    }
  boxes.resize(kept);
  return count;
}

}  // namespace icanc
