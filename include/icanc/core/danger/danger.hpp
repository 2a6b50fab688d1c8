// The paper's danger rules (Section III "Danger Detector Node", Listing 1 "Danger Detecting with
// VPI"): getSection, isMovingTowardMe, getSpeedOfObject, the closest-point distance and the rule
// `distance <= speed * reaction_time && isMovingTowardMe`. Everything is in the vehicle frame
// (REP-103: x forward, y left, z up) with the vehicle origin at (0, 0, 0).
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <unordered_map>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>  // AlignedBox

#include "icanc/core/motion/ego_path.hpp"
#include "icanc/core/motion/motion_state.hpp"

namespace icanc {

// Paper Fig. "Current Danger Detector design": Section 1 left, 2 front (the path), 3 right.
enum class Section : std::uint8_t { kLeft = 1, kFront = 2, kRight = 3 };
const char* toString(Section section);

// Which rule assessDanger applies. kPaper: Listing 1 (the reference, default). kPredictive: the
// predicted relative motion of the box over the reaction time against the vehicle's corridor.
// kInvalid: an unknown name was read; validate() rejects it.
enum class DangerModel : std::uint8_t { kPaper, kPredictive, kInvalid };
const char* toString(DangerModel model);
// "paper" / "predictive" -> the model; anything else -> kInvalid.
DangerModel parseDangerModel(const std::string& name);

// The width of isMovingTowardMe's heading windows in the current design [deg].
constexpr double kPaperHeadingWindowDeg = 150.0;

struct DangerParams {
  double half_width_m = 0.7;     // w: path half-width (paper: 0.7 Zebra, 1.2 CARLA Model 3)
  double reaction_time_s = 3.0;  // t: reaction time allowed (paper: 3 Zebra, 2 CARLA)
  double heading_window_deg = kPaperHeadingWindowDeg;  // isMovingTowardMe's windows (0, 180]
  DangerModel model = DangerModel::kPaper;

  // kPredictive only. The corridor has the ground truth's meaning (CorridorParams):
  // |y| <= half_width_m + margin_m, 0 <= x <= vehicle_front_m + stopping_margin_m.
  double margin_m = 0.3;
  double vehicle_front_m = 0.5;
  double stopping_margin_m = 1.0;
  // Velocity uncertainty: the predicted footprint grows by min(k * sigma_axis * t, cap) along x and
  // along y (each axis by its own sigma), so a track whose velocity is still uncertain errs toward
  // danger when it is near the path, and a well-measured axis does not widen the other.
  double velocity_std_k = 1.0;
  double uncertainty_cap_m = 0.5;
  // The LiDAR sees less of an object than it is (its far side, the edges between beams, a voxel
  // grid's centroids inside the surface): the footprint grows by this much on every side [m].
  double footprint_margin_m = 0.0;
  // The world mostly stands still: the object's velocity over ground (relative velocity + the
  // vehicle's at the object) is shrunk toward zero per axis before it is extrapolated
  // (staticPriorShrink with static_prior_k * sigma), so a young track of a parked car or a
  // fragment, whose velocity is still mostly noise, does not fly across the corridor on it, while
  // an object that clearly moves (a car ahead at the vehicle's speed) keeps nearly all of its
  // speed; a settled track (sigma 0.04 m/s) keeps its velocity. Meaningful with ego motion
  // (velocities over ground); 0 = off.
  double static_prior_k = 0.0;
  // A static obstacle (ObjectKinematics::motion) is dangerous only where the vehicle's own swept
  // footprint reaches it within the reaction time: the vehicle (half_width_m beside its axis,
  // vehicle_front_m ahead) along its predicted path, grown by this clearance on every side [m].
  // A parked car beside the lane or a wall beside the road is not in the way; a car protruding
  // into the lane or a thing lying in it is.
  double static_clearance_m = 0.2;
  double time_step_s = 0.05;     // prediction sampling step over [0, reaction_time]
  // Hysteresis (DangerHysteresis, per track): on after on_frames consecutive dangerous frames, or
  // at once when the mean prediction's time-to-corridor (DangerAssessment::mean_time_to_corridor_s)
  // is at most immediate_ttc_s; off after off_frames consecutive safe ones.
  int on_frames = 2;
  int off_frames = 2;
  double immediate_ttc_s = 1.0;
  double forget_after_s = 1.0;   // a track id not seen for this long is forgotten
};

std::string validate(const DangerParams& params);

// getSection: front when -w < y < w, left when y >= w, right when y <= -w, where y is that of the
// box's point closest to the vehicle origin (closestPoint), as the paper's reference code
// (danielma4/ICanC_v2 danger_publisher_node.cpp: getSection(getClosestPoint(box))): a car whose
// centre is beside the path but whose near edge is inside it is in the front section.
Section getSection(double closest_y, double half_width_m);

// getSpeedOfObject: planar speed |(vx, vy)| of the velocity relative to the vehicle [m/s].
double getSpeedOfObject(const Eigen::Vector3d& velocity);

// Heading of the relative velocity in degrees [0, 360): 0 = moving along +x (away), 90 = +y
// (left), 180 = toward the vehicle, 270 = -y. This is the paper's angle between u = +x and the
// displacement v, theta = acos(u.v / (|u||v|)) in [0, 180], continued to [0, 360) by the side
// (sign of u x v) the displacement points to. Zero velocity gives 0.
double headingDeg(const Eigen::Vector3d& velocity);

// The same direction in radians (REP-103, icanc/Obstacle heading): atan2(vy, vx) in (-pi, pi],
// 0 = +x (away), pi/2 = +y (left), -pi/2 = -y (right), pi = toward the vehicle (-pi is returned as
// pi, also where a float32 would round the angle to -pi). Zero velocity gives 0.
double headingRad(const Eigen::Vector3d& velocity);

// isMovingTowardMe with the current design's 150 degree windows, edges included:
// right section [15, 165], left section [195, 345], front section [105, 255]. Other widths
// (DangerParams::heading_window_deg, (0, 180]) keep the centres 90, 270 and 180.
bool isMovingTowardMe(double heading_deg, Section section, double window_deg = kPaperHeadingWindowDeg);

// The point of an axis-aligned box closest to the vehicle origin: the origin clamped into the box
// per axis (x, y and z, as the paper's reference code getClosestPoint).
Eigen::Vector3d closestPoint(const Eigen::Vector3d& aabb_min, const Eigen::Vector3d& aabb_max);

// Distance from the vehicle origin to the closest point of an axis-aligned box (its norm).
double closestPointDistance(const Eigen::Vector3d& aabb_min, const Eigen::Vector3d& aabb_max);

// The predictive model follows the planner's path (ObjectKinematics::ego_path) only while the
// vehicle moves forward; standing or reversing, its twist.
inline bool alongPlannedPath(const Eigen::Vector2d& ego_velocity) { return ego_velocity.x() > 0.0; }

// What the rules need of one tracked object.
struct ObjectKinematics {
  Eigen::Vector3d center = Eigen::Vector3d::Zero();
  Eigen::Vector3d aabb_min = Eigen::Vector3d::Zero();
  Eigen::Vector3d aabb_max = Eigen::Vector3d::Zero();
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();  // relative to the vehicle [m/s]
  // 1-sigma velocity uncertainty of the filter along x and y [m/s].
  Eigen::Vector2d velocity_std = Eigen::Vector2d::Zero();
  // kPredictive: where the object is inside its axis-aligned box, seen from above (x, y): tight
  // parts of the footprint (icanc/Obstacle footprint). Empty: the axis-aligned box.
  std::vector<Eigen::AlignedBox2d> footprint;
  // kPredictive: the vehicle's own twist (body velocity x, y [m/s] and yaw rate [rad/s]); the
  // vehicle is predicted along it (constant turn rate and velocity) and the object with its velocity
  // over ground (velocity + the vehicle's velocity where the object is). Zero: the vehicle stands
  // still and the object moves at its relative velocity (the ego_motion source none).
  Eigen::Vector2d ego_velocity = Eigen::Vector2d::Zero();
  double ego_yaw_rate = 0.0;
  // kPredictive: the planner's path in the vehicle frame (EgoPath::set). Set and not empty while
  // the vehicle moves forward: the vehicle is predicted along it at its current speed instead of
  // along the constant turn; beyond the path's end, on at the twist's turn rate. Null: the twist.
  std::shared_ptr<const EgoPath> ego_path;
  // kPredictive: whether it moves, from free space (icanc/Obstacle motion_state). kStatic: judged
  // by the vehicle's swept path (sweptPathTimeToReach); kMoving and kUnknown by its prediction.
  MotionState motion = MotionState::kUnknown;
};

struct DangerAssessment {
  Section section = Section::kFront;
  double distance_m = 0.0;
  double speed_mps = 0.0;
  double heading_deg = 0.0;
  double threshold_m = 0.0;  // speed * reaction_time
  bool moving_toward = false;
  bool dangerous = false;
  // kPredictive: seconds until the predicted (inflated) footprint first overlaps the corridor,
  // 0 when it already does, -1 when not within the reaction time. kPaper: always -1.
  double time_to_corridor_s = -1.0;
  // kPredictive: the same for the mean prediction, without the velocity-uncertainty growth
  // (velocity_std_k 0; the footprint margin kept): when only the uncertainty reaches the corridor,
  // -1 or later than time_to_corridor_s. The hysteresis's immediate case reads this one.
  double mean_time_to_corridor_s = -1.0;
};

// Dispatches on params.model. kPaper (Listing 1): dangerous when distance <= speed *
// reaction_time and isMovingTowardMe, for what is ahead of the vehicle origin (the sections split
// the frontal field of view: a box wholly behind it is in none). kPredictive: a static object
// when the vehicle's swept path reaches it (sweptPathTimeToReach >= 0), any other when
// predictedTimeToCorridor >= 0 (section, distance, speed, heading and moving_toward are filled as
// for the paper's rule, for display). The section is that of the closest point of
// [aabb_min, aabb_max] (getSection).
DangerAssessment assessDanger(const ObjectKinematics& object, const DangerParams& params);

// kPredictive's core: the footprint (its parts, else [aabb_min, aabb_max]; x, y) moving at its
// velocity over ground, seen from where the vehicle will be along its own twist (the corridor
// turns with the vehicle), grown on every side by
// footprint_margin_m and per axis by min(k * velocity_std(axis) * t, cap), sampled every
// time_step_s over [0, reaction_time]: the first time a part of it overlaps the corridor, or -1.
// A part seen from a turned vehicle is a rotated rectangle, tested exactly against the corridor
// (separating axes), not by its axis-aligned bounds. With no ego twist this is the footprint
// moving at the relative velocity against the corridor ahead.
double predictedTimeToCorridor(const ObjectKinematics& object, const DangerParams& params);

// kPredictive's rule for a static object: the first time within the reaction time that the
// vehicle's own footprint (|y| <= half_width_m, x up to vehicle_front_m), grown by
// static_clearance_m on every side and moved along its predicted path (twist or planner's path),
// overlaps the object's footprint standing still; -1 when it does not. No velocity uncertainty
// and no footprint margin: the object does not move, and the clearance is the margin.
double sweptPathTimeToReach(const ObjectKinematics& object, const DangerParams& params);

// The static-world prior on one velocity component v with threshold t = k * sigma >= 0: the
// non-negative garrote (Breiman 1995), v * (1 - t^2 / v^2) beyond t, 0 within it. Continuous, as
// the soft threshold (|v| - t) it replaced, but it takes t^2 / |v| from a clearly moving object
// instead of t: a car 10 m ahead driving at the vehicle's speed with a young track's sigma of
// 0.76 m/s keeps 9.6 of its 9.8 m/s rather than 8.3 (which brought it 3 m closer over 2 s).
double staticPriorShrink(double v, double t);

// Per-track hysteresis of the danger label (params: on_frames, off_frames, immediate_ttc_s,
// forget_after_s). Call update() for each obstacle of a frame with the frame's time; ids not
// seen for forget_after_s are dropped, and time going backwards (a replay restarting) clears all.
class DangerHysteresis {
 public:
  explicit DangerHysteresis(const DangerParams& params) : params_(params) {}
  bool update(std::uint32_t id, const DangerAssessment& raw, double now_s);
  // Takes effect on the next update(); the per-track states are kept.
  void setParams(const DangerParams& params) { params_ = params; }
  std::size_t size() const { return tracks_.size(); }

 private:
  struct Track {
    bool on = false;
    int positives = 0;
    int negatives = 0;
    double last_seen_s = 0.0;
  };
  DangerParams params_;
  std::unordered_map<std::uint32_t, Track> tracks_;
  double last_now_s_ = -1e300;
  double last_prune_s_ = -1e300;
};

}  // namespace icanc
