#include "icanc/core/danger/danger.hpp"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <sstream>

#include "icanc/core/common/planar_geometry.hpp"
#include "icanc/core/motion/ego_motion.hpp"

namespace icanc {

const char* toString(Section section) {
  switch (section) {
    case Section::kLeft: return "left";
    case Section::kFront: return "front";
    case Section::kRight: return "right";
  }
  return "unknown";
}

const char* toString(DangerModel model) {
  switch (model) {
    case DangerModel::kPaper: return "paper";
    case DangerModel::kPredictive: return "predictive";
    case DangerModel::kInvalid: break;
  }
  return "invalid";
}

DangerModel parseDangerModel(const std::string& name) {
  if (name == "paper") return DangerModel::kPaper;
  if (name == "predictive") return DangerModel::kPredictive;
  return DangerModel::kInvalid;
}

std::string validate(const DangerParams& params) {
  std::ostringstream why;
  if (!(params.half_width_m > 0.0 && params.half_width_m <= 10.0))
    why << "danger.half_width_m must be in (0, 10] m (got " << params.half_width_m << ")";
  else if (!(params.reaction_time_s > 0.0 && params.reaction_time_s <= 30.0))
    why << "danger.reaction_time_s must be in (0, 30] s (got " << params.reaction_time_s << ")";
  else if (!(params.heading_window_deg > 0.0 && params.heading_window_deg <= 180.0))
    why << "danger.heading_window_deg must be in (0, 180] (got " << params.heading_window_deg << ")";
  else if (params.model != DangerModel::kPaper && params.model != DangerModel::kPredictive)
    why << "danger.model must be \"paper\" or \"predictive\"";
  else if (!(params.margin_m >= 0.0))
    why << "danger.margin_m must be >= 0 (got " << params.margin_m << ")";
  else if (!(params.vehicle_front_m >= 0.0))
    why << "danger.vehicle_front_m must be >= 0 (got " << params.vehicle_front_m << ")";
  else if (!(params.stopping_margin_m > 0.0))
    why << "danger.stopping_margin_m must be > 0 (got " << params.stopping_margin_m << ")";
  else if (!(params.velocity_std_k >= 0.0))
    why << "danger.velocity_std_k must be >= 0 (got " << params.velocity_std_k << ")";
  else if (!(params.uncertainty_cap_m >= 0.0))
    why << "danger.uncertainty_cap_m must be >= 0 (got " << params.uncertainty_cap_m << ")";
  else if (!(params.static_prior_k >= 0.0 && params.static_prior_k <= 10.0))
    why << "danger.static_prior_k must be in [0, 10] (got " << params.static_prior_k << ")";
  else if (!(params.static_clearance_m >= 0.0 && params.static_clearance_m <= 5.0))
    why << "danger.static_clearance_m must be in [0, 5] m (got " << params.static_clearance_m << ")";
  else if (!(params.footprint_margin_m >= 0.0))
    why << "danger.footprint_margin_m must be >= 0 (got " << params.footprint_margin_m << ")";
  else if (!(params.time_step_s > 0.0 && params.time_step_s <= params.reaction_time_s))
    why << "danger.time_step_s must be in (0, reaction_time_s] (got " << params.time_step_s << ")";
  else if (params.on_frames < 1)
    why << "danger.on_frames must be >= 1 (got " << params.on_frames << ")";
  else if (params.off_frames < 1)
    why << "danger.off_frames must be >= 1 (got " << params.off_frames << ")";
  else if (!(params.immediate_ttc_s >= 0.0))
    why << "danger.immediate_ttc_s must be >= 0 (got " << params.immediate_ttc_s << ")";
  else if (!(params.forget_after_s > 0.0))
    why << "danger.forget_after_s must be > 0 (got " << params.forget_after_s << ")";
  return why.str();
}

Section getSection(double closest_y, double half_width_m) {
  if (closest_y >= half_width_m) return Section::kLeft;
  if (closest_y <= -half_width_m) return Section::kRight;
  return Section::kFront;
}

double getSpeedOfObject(const Eigen::Vector3d& velocity) { return velocity.head<2>().norm(); }

double headingDeg(const Eigen::Vector3d& velocity) {
  if (velocity.x() == 0.0 && velocity.y() == 0.0) return 0.0;
  double deg = std::atan2(velocity.y(), velocity.x()) * 180.0 / M_PI;
  if (deg < 0.0) deg += 360.0;
  return deg >= 360.0 ? 0.0 : deg;
}

double headingRad(const Eigen::Vector3d& velocity) {
  if (velocity.x() == 0.0 && velocity.y() == 0.0) return 0.0;
  const double rad = std::atan2(velocity.y(), velocity.x());
  return float(rad) <= -float(M_PI) ? M_PI : rad;
}

bool isMovingTowardMe(double heading_deg, Section section, double window_deg) {
  double centre = 0.0;  // the heading straight across or into the path
  switch (section) {
    case Section::kRight: centre = 90.0; break;
    case Section::kLeft: centre = 270.0; break;
    case Section::kFront: centre = 180.0; break;
  }
  const double half = 0.5 * window_deg;
  return heading_deg >= centre - half && heading_deg <= centre + half;
}

Eigen::Vector3d closestPoint(const Eigen::Vector3d& aabb_min, const Eigen::Vector3d& aabb_max) {
  return Eigen::Vector3d::Zero().cwiseMax(aabb_min).cwiseMin(aabb_max);
}

double closestPointDistance(const Eigen::Vector3d& aabb_min, const Eigen::Vector3d& aabb_max) {
  return closestPoint(aabb_min, aabb_max).norm();
}

double staticPriorShrink(double v, double t) {
  if (!(t > 0.0)) return v;
  return std::abs(v) > t ? v * (1.0 - (t / v) * (t / v)) : 0.0;
}

namespace {

// The vehicle s metres along the planner's path; beyond its end (a path shorter than the reaction
// time's reach, a recording's last seconds) on from its end at the twist's turn rate, as the
// vehicle would go without a path.
PlanarPose alongPath(const EgoPath& path, const Eigen::Vector2d& ego_v, double ego_w, double s) {
  if (s <= path.length()) return path.at(s);
  const PlanarPose end = path.at(path.length());
  const PlanarPose beyond =
      predictEgoPose(ego_v, ego_w, (s - path.length()) / ego_v.norm());
  PlanarPose pose;
  pose.position = end.position + Eigen::Rotation2Dd(end.yaw) * beyond.position;
  pose.yaw = end.yaw + beyond.yaw;
  return pose;
}

}  // namespace

double predictedTimeToCorridor(const ObjectKinematics& object, const DangerParams& params) {
  const double half_width = params.half_width_m + params.margin_m;
  const double length = params.vehicle_front_m + params.stopping_margin_m;
  const auto sigmaOf = [](double s) { return std::isfinite(s) ? std::max(0.0, s) : 0.0; };
  const double sigma_x = sigmaOf(object.velocity_std.x()), sigma_y = sigmaOf(object.velocity_std.y());
  // The object's velocity over ground: its relative velocity plus the velocity of the
  // vehicle-fixed point where it is (relativeVelocity's inverse, planar).
  const Eigen::Vector2d ego_v = object.ego_velocity;
  const double ego_w = object.ego_yaw_rate;
  Eigen::Vector2d ground_v = object.velocity.head<2>() + ego_v +
                             ego_w * Eigen::Vector2d(-object.center.y(), object.center.x());
  if (object.motion == MotionState::kStatic) ground_v.setZero();
  // The static-world prior, per axis with its own sigma.
  ground_v.x() = staticPriorShrink(ground_v.x(), params.static_prior_k * sigma_x);
  ground_v.y() = staticPriorShrink(ground_v.y(), params.static_prior_k * sigma_y);
  // Along the planner's path while moving forward (at the speed over ground), else the twist.
  const EgoPath* const path = object.ego_path && !object.ego_path->empty() && alongPlannedPath(ego_v)
                                  ? object.ego_path.get()
                                  : nullptr;
  const double speed = ego_v.norm();
  const bool turning = path != nullptr || ego_w != 0.0;
  const int steps = static_cast<int>(std::ceil(params.reaction_time_s / params.time_step_s - 1e-9));
  for (int i = 0; i <= steps; ++i) {
    const double t = std::min(i * params.time_step_s, params.reaction_time_s);
    const double grow_x = params.footprint_margin_m +
                          std::min(params.velocity_std_k * sigma_x * t, params.uncertainty_cap_m);
    const double grow_y = params.footprint_margin_m +
                          std::min(params.velocity_std_k * sigma_y * t, params.uncertainty_cap_m);
    // Where the vehicle will be, and the object's displacement seen from there.
    const PlanarPose ego = path ? (t > 0.0 ? alongPath(*path, ego_v, ego_w, speed * t)
                                           : PlanarPose())
                                : predictEgoPose(ego_v, ego_w, t);
    const Eigen::Rotation2Dd to_future(-ego.yaw);
    const Eigen::Vector2d shift = ground_v * t - ego.position;
    // The corridor grown by the uncertainty against the moved parts: the axis-aligned box first,
    // then (only then) its parts. A part moved and seen from the future vehicle frame: a
    // rectangle turned by the vehicle's heading change (only shifted while it goes straight).
    const Eigen::Vector2d lo(-grow_x, -half_width - grow_y);
    const Eigen::Vector2d hi(length + grow_x, half_width + grow_y);
    const auto overlaps = [&](const Eigen::Vector2d& min, const Eigen::Vector2d& max) {
      if (!turning) {
        return ((max + shift).array() >= lo.array()).all() &&
               ((min + shift).array() <= hi.array()).all();
      }
      return orientedRectOverlapsBox(to_future * (0.5 * (min + max) + shift), 0.5 * (max - min),
                                     -ego.yaw, 0.5 * (lo + hi), 0.5 * (hi - lo));
    };
    if (!overlaps(object.aabb_min.head<2>(), object.aabb_max.head<2>())) continue;
    if (object.footprint.empty()) return t;
    for (const Eigen::AlignedBox2d& part : object.footprint)
      if (overlaps(part.min(), part.max())) return t;
  }
  return -1.0;
}

double sweptPathTimeToReach(const ObjectKinematics& object, const DangerParams& params) {
  DangerParams swept = params;
  swept.margin_m = params.static_clearance_m;
  swept.stopping_margin_m = params.static_clearance_m;
  swept.footprint_margin_m = 0.0;
  swept.velocity_std_k = 0.0;
  ObjectKinematics still = object;
  still.motion = MotionState::kStatic;
  return predictedTimeToCorridor(still, swept);
}

DangerAssessment assessDanger(const ObjectKinematics& object, const DangerParams& params) {
  DangerAssessment a;
  a.speed_mps = getSpeedOfObject(object.velocity);
  a.section = getSection(closestPoint(object.aabb_min, object.aabb_max).y(), params.half_width_m);
  a.distance_m = closestPointDistance(object.aabb_min, object.aabb_max);
  a.heading_deg = headingDeg(object.velocity);
  a.threshold_m = a.speed_mps * params.reaction_time_s;
  a.moving_toward = isMovingTowardMe(a.heading_deg, a.section, params.heading_window_deg);
  if (params.model == DangerModel::kPredictive && object.motion == MotionState::kStatic) {
    a.time_to_corridor_s = a.mean_time_to_corridor_s = sweptPathTimeToReach(object, params);
    a.dangerous = a.time_to_corridor_s >= 0.0;
  } else if (params.model == DangerModel::kPredictive) {
    a.time_to_corridor_s = predictedTimeToCorridor(object, params);
    // The mean footprint lies inside the grown one: it can only reach the corridor later, if at all.
    if (a.time_to_corridor_s >= 0.0) {
      DangerParams mean = params;
      mean.velocity_std_k = 0.0;
      a.mean_time_to_corridor_s = predictedTimeToCorridor(object, mean);
    }
    a.dangerous = a.time_to_corridor_s >= 0.0;
  } else {
    // The sections split the frontal field of view: what lies wholly behind the vehicle origin is
    // in none of them (a car behind, receding at the vehicle's speed, heads at 180 degrees).
    a.dangerous = object.aabb_max.x() >= 0.0 && a.distance_m <= a.threshold_m && a.moving_toward;
  }
  return a;
}

bool DangerHysteresis::update(std::uint32_t id, const DangerAssessment& raw, double now_s) {
  if (now_s < last_now_s_) tracks_.clear();  // time went backwards: a new replay
  last_now_s_ = now_s;
  if (now_s - last_prune_s_ >= params_.forget_after_s) {
    for (auto it = tracks_.begin(); it != tracks_.end();)
      it = now_s - it->second.last_seen_s > params_.forget_after_s ? tracks_.erase(it) : std::next(it);
    last_prune_s_ = now_s;
  }
  Track& track = tracks_[id];
  track.last_seen_s = now_s;
  if (raw.dangerous) {
    ++track.positives;
    track.negatives = 0;
    // At once only when the mean prediction is about to enter: danger that only the velocity's
    // uncertainty brings near waits for on_frames (a young track's, whose sigma is still large).
    const bool urgent =
        raw.mean_time_to_corridor_s >= 0.0 && raw.mean_time_to_corridor_s <= params_.immediate_ttc_s;
    if (urgent || track.positives >= params_.on_frames) track.on = true;
  } else {
    ++track.negatives;
    track.positives = 0;
    if (track.negatives >= params_.off_frames) track.on = false;
  }
  return track.on;
}

}  // namespace icanc
