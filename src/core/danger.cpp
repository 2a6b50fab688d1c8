#include "icanc/core/danger.hpp"

#include <cmath>
#include <sstream>

namespace icanc {

const char* toString(Section section) {
  switch (section) {
    case Section::kLeft: return "left";
    case Section::kFront: return "front";
    case Section::kRight: return "right";
  }
  return "unknown";
}

std::string validate(const DangerParams& params) {
  std::ostringstream why;
  if (!(params.half_width_m > 0.0))
    why << "danger.half_width_m must be > 0 (got " << params.half_width_m << ")";
  else if (!(params.reaction_time_s > 0.0))
    why << "danger.reaction_time_s must be > 0 (got " << params.reaction_time_s << ")";
  return why.str();
}

Section getSection(double center_y, double half_width_m) {
  if (center_y >= half_width_m) return Section::kLeft;
  if (center_y <= -half_width_m) return Section::kRight;
  return Section::kFront;
}

double getSpeedOfObject(const Eigen::Vector3d& velocity) { return velocity.head<2>().norm(); }

double headingDeg(const Eigen::Vector3d& velocity) {
  if (velocity.x() == 0.0 && velocity.y() == 0.0) return 0.0;
  double deg = std::atan2(velocity.y(), velocity.x()) * 180.0 / M_PI;
  if (deg < 0.0) deg += 360.0;
  return deg >= 360.0 ? 0.0 : deg;
}

bool isMovingTowardMe(double heading_deg, Section section) {
  switch (section) {
    case Section::kRight: return heading_deg >= 15.0 && heading_deg <= 165.0;
    case Section::kLeft: return heading_deg >= 195.0 && heading_deg <= 345.0;
    case Section::kFront: return heading_deg >= 105.0 && heading_deg <= 255.0;
  }
  return false;
}

double closestPointDistance(const Eigen::Vector3d& aabb_min, const Eigen::Vector3d& aabb_max) {
  const Eigen::Vector3d closest = Eigen::Vector3d::Zero().cwiseMax(aabb_min).cwiseMin(aabb_max);
  return closest.norm();
}

DangerAssessment assessDanger(const ObjectKinematics& object, const DangerParams& params) {
  DangerAssessment a;
  a.speed_mps = getSpeedOfObject(object.velocity);
  a.section = getSection(object.center.y(), params.half_width_m);
  a.distance_m = closestPointDistance(object.aabb_min, object.aabb_max);
  a.heading_deg = headingDeg(object.velocity);
  a.threshold_m = a.speed_mps * params.reaction_time_s;
  a.moving_toward = isMovingTowardMe(a.heading_deg, a.section);
  a.dangerous = a.distance_m <= a.threshold_m && a.moving_toward;
  return a;
}

}  // namespace icanc
