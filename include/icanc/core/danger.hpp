// The paper's danger rules (Section III "Danger Detector Node", Listing 1 "Danger Detecting with
// VPI"): getSection, isMovingTowardMe, getSpeedOfObject, the closest-point distance and the rule
// `distance <= speed * reaction_time && isMovingTowardMe`. Everything is in the vehicle frame
// (REP-103: x forward, y left, z up) with the vehicle origin at (0, 0, 0).
#pragma once

#include <cstdint>
#include <string>

#include <Eigen/Core>

namespace icanc {

// Paper Fig. "Current Danger Detector design": Section 1 left, 2 front (the path), 3 right.
enum class Section : std::uint8_t { kLeft = 1, kFront = 2, kRight = 3 };
const char* toString(Section section);

struct DangerParams {
  double half_width_m = 0.7;     // w: path half-width (paper: 0.7 Zebra, 1.2 CARLA Model 3)
  double reaction_time_s = 3.0;  // t: reaction time allowed (paper: 3 Zebra, 2 CARLA)
};

std::string validate(const DangerParams& params);

// getSection: front when -w < y < w, left when y >= w, right when y <= -w (y of the box centre).
Section getSection(double center_y, double half_width_m);

// getSpeedOfObject: planar speed |(vx, vy)| of the velocity relative to the vehicle [m/s].
double getSpeedOfObject(const Eigen::Vector3d& velocity);

// Heading of the relative velocity in degrees [0, 360): 0 = moving along +x (away), 90 = +y
// (left), 180 = toward the vehicle, 270 = -y. This is the paper's angle between u = +x and the
// displacement v, theta = acos(u.v / (|u||v|)) in [0, 180], continued to [0, 360) by the side
// (sign of u x v) the displacement points to. Zero velocity gives 0.
double headingDeg(const Eigen::Vector3d& velocity);

// isMovingTowardMe with the current design's 150 degree windows, edges included:
// right section [15, 165], left section [195, 345], front section [105, 255].
bool isMovingTowardMe(double heading_deg, Section section);

// Distance from the vehicle origin to the closest point of an axis-aligned box: the origin
// clamped into the box per axis (x, y and z, as the paper's reference code), then its norm.
double closestPointDistance(const Eigen::Vector3d& aabb_min, const Eigen::Vector3d& aabb_max);

// What the rules need of one tracked object.
struct ObjectKinematics {
  Eigen::Vector3d center = Eigen::Vector3d::Zero();
  Eigen::Vector3d aabb_min = Eigen::Vector3d::Zero();
  Eigen::Vector3d aabb_max = Eigen::Vector3d::Zero();
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();  // relative to the vehicle [m/s]
};

struct DangerAssessment {
  Section section = Section::kFront;
  double distance_m = 0.0;
  double speed_mps = 0.0;
  double heading_deg = 0.0;
  double threshold_m = 0.0;  // speed * reaction_time
  bool moving_toward = false;
  bool dangerous = false;
};

// Listing 1: dangerous when distance <= speed * reaction_time and isMovingTowardMe.
DangerAssessment assessDanger(const ObjectKinematics& object, const DangerParams& params);

}  // namespace icanc
