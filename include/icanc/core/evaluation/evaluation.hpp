// Scoring a replay against ground truth, as the paper's evaluation (Section V) and more:
// danger per object-frame (TP/FP/FN/TN, precision, recall, accuracy, F1), danger episodes
// (caught, missed, warning lead time), detection recall/precision, id switches, velocity RMSE,
// end-to-end latency percentiles and lamp duty cycle. ROS-free: the evaluator fills the frames.
#pragma once

#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>  // AlignedBox2d

#include "icanc/core/danger/danger.hpp"
#include "icanc/core/evaluation/lamp_causes.hpp"
#include "icanc/core/motion/motion_state.hpp"

namespace icanc {

struct TruthObject {
  std::uint32_t id = 0;
  std::string type;
  Eigen::Vector2d center = Eigen::Vector2d::Zero();  // x, y in the vehicle frame [m]
  Eigen::Vector2d size = Eigen::Vector2d::Zero();    // footprint length (along yaw), width [m]
  double yaw = 0.0;                                  // [rad]
  Eigen::Vector2d velocity = Eigen::Vector2d::Zero();
  bool has_velocity = true;
  std::uint32_t num_points = 0;   // LiDAR returns inside the true box
  bool dangerous = false;         // ground truth (enters the corridor within the horizon)
  double time_to_corridor = -1.0; // [s], -1 when not within the horizon
  bool horizon_cut = false;       // not dangerous, but the labels end within the horizon: its
                                  // danger is not scored (detection is)
};

struct DetectedObject {
  std::uint32_t id = 0;
  Eigen::Vector2d center = Eigen::Vector2d::Zero();
  Eigen::Vector2d velocity = Eigen::Vector2d::Zero();  // relative to the vehicle
  // Over ground (icanc/Obstacle velocity_over_ground; the relative one without ego motion).
  Eigen::Vector2d velocity_over_ground = Eigen::Vector2d::Zero();
  bool dangerous = false;
  std::uint32_t age = 0;  // frames since the track's birth (icanc/Obstacle age; 0 unknown)
  // What the danger model saw (the rows; the box bias): axis-aligned x, y bounds (when has_aabb)
  // and the filter's 1-sigma velocity uncertainty along x and y.
  bool has_aabb = false;
  Eigen::Vector2d aabb_min = Eigen::Vector2d::Zero();
  Eigen::Vector2d aabb_max = Eigen::Vector2d::Zero();
  Eigen::Vector2d velocity_std = Eigen::Vector2d::Zero();
  MotionState motion = MotionState::kUnknown;  // icanc/Obstacle motion_state
};

// How many object-frames read each motion state (icanc/Obstacle motion_state).
struct MotionCounts {
  std::uint64_t unknown = 0, still = 0, moving = 0;
  void add(MotionState state);
  std::uint64_t n() const { return unknown + still + moving; }
  double share(MotionState state) const;  // 0 without any
};

struct EvalFrame {
  double t = 0.0;                 // stamp [s]
  bool processed = false;         // the graph answered this frame
  bool lamp_on = false;           // lamp state after this frame
  double latency_ms = 0.0;        // cloud received -> light state published (wall)
  std::vector<TruthObject> truth;
  std::vector<DetectedObject> detections;
  // The vehicle's twist the graph used for this frame (ObstacleArray.ego_twist): the danger model on
  // perfect tracks predicts the vehicle along the same path.
  Eigen::Vector2d ego_velocity = Eigen::Vector2d::Zero();
  double ego_yaw_rate = 0.0;
  // The planner's path the graph's DangerDetector took, in the truth's frame (null: none): the
  // danger model on perfect tracks follows it too.
  std::shared_ptr<const EgoPath> ego_path;
  bool ego_motion = false;  // the twist was measured (or carried over a missing pose)
  // The pose was missing, jumped or lost at this frame (ObstacleArray.ego_motion_status
  // extrapolated / jump / lost): in a replay of a bag that carries the poses, a run whose result
  // depends on timing, not on the data.
  bool ego_motion_fault = false;
};

struct EvalParams {
  // A detection matches a true object when its BEV centre lies within this distance of the true
  // oriented footprint (0 inside it): a partly seen car's cluster centre sits off the true centre.
  double match_distance_m = 1.0;
  std::uint32_t min_points = 10;  // true objects with fewer returns are not expected to be seen
  double max_range_m = 40.0;      // true objects / detections farther away are not scored
  double fov_half_angle_deg = 180.0;  // scored sector around +x (KITTI labels: 45)
  // The detector's region of interest (obstacle_detector/prep/roi_min, roi_max: x, y in the
  // vehicle frame, where truth and detections are), for EvalReport::detection_roi. Unbounded by
  // default; the scored range and view above still apply.
  Eigen::AlignedBox2d roi{Eigen::Vector2d::Constant(-std::numeric_limits<double>::infinity()),
                          Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity())};
  std::uint32_t settled_age = 10;     // tracks this old count in velocity_rmse_settled
  double static_speed_mps = 0.5;      // true objects slower over ground than this stand still
  double moving_speed_mps = 1.0;      // ... and faster than this move (EvalReport::motion_*)
  double velocity_agree_mps = 2.0;    // EvalReport::detection_velocity_agrees' tolerance
  // The light controller of the run (light_controller/tau_s, recheck_below_s), for the duty cycle
  // a perfect danger detector would have had (EvalReport::truth_duty_cycle).
  double lamp_tau_s = 2.0;
  double lamp_recheck_below_s = 1.0;
  // The graph's danger detector (danger_detector/*), for EvalReport::perfect_tracks.
  DangerParams danger;
};

struct Confusion {
  std::uint64_t tp = 0, fp = 0, fn = 0, tn = 0;
  double precision() const;
  double recall() const;
  double accuracy() const;
  double f1() const;
};

struct EvalReport {
  std::size_t frames = 0, processed = 0;
  std::size_t ego_motion_faults = 0;  // processed frames with EvalFrame::ego_motion_fault
  // Per object-frame: eligible true objects (flagged when their matched detection, or a fragment
  // of them, is dangerous) and false alarms. A fragment is a detection left over by the one-to-one
  // matching within EvalParams::match_distance_m of a true object's footprint.
  Confusion danger;
  // Dangerous detections of no true object (in fp). A detection within the match distance of a
  // true object that is not scored (fewer than min_points returns, out of range or view) is not
  // scored either (as KITTI's DontCare), in danger and detection alike.
  std::uint64_t false_alarms_unmatched = 0;
  // Danger episodes per true id; caught: the object (its matched detection or a fragment) was
  // flagged dangerous with the lamp on during the episode (the lamp on for another reason is not).
  std::size_t episodes = 0, caught = 0;
  std::vector<double> lead_times_s;          // per caught episode: corridor entry - lamp on
  Confusion detection;              // tp = matched true objects, fn = missed, fp = unmatched dets
  // The same, of the true objects and unmatched detections whose centre lies in the detector's
  // region of interest (EvalParams::roi): what the detector is set to look at. A
  // profile's region of interest leaves out the road behind and beside the vehicle that the scored
  // range (max_range_m all around in the simulated scenarios) takes in.
  Confusion detection_roi;
  // Of detection.fn: true objects whose centre lies inside the box (its axis-aligned bounds) of a
  // detection matched to another true object: merged with what they stand or walk beside (two
  // walkers as one box, a walker against a wall, under a shelter's roof), not unseen. Of
  // danger.fn: dangerous ones whose merged box was flagged dangerous (the lamp came on for the box
  // that holds them; which of two walkers in one box the matching picks is a coin toss).
  std::uint64_t detection_merged = 0;
  std::uint64_t danger_fn_in_flagged_merge = 0;
  // The predictive model judges what stands still by the vehicle's swept path
  // (sweptPathTimeToReach), the ground truth by its wider corridor. True objects standing still
  // over ground (EvalParams::static_speed_mps, with ego motion) that are dangerous by the corridor
  // but beside the swept path (a parked car at the kerb, a wall beside the road) are counted here,
  // not in `danger`, and open no episode; _flagged: of them, flagged all the same. kPredictive runs
  // only (the paper's rule has no swept path).
  std::uint64_t danger_standing_apart = 0;
  std::uint64_t danger_standing_apart_flagged = 0;
  // Of detection.tp: true objects with a known velocity whose matched track's velocity (relative
  // to the vehicle, planar) lies within EvalParams::velocity_agree_mps of it. A box on the object
  // whose track moves with the vehicle instead (one scan line sliding along a parked car's side or
  // roof at the same range frame after frame) is found but does not agree.
  std::uint64_t detection_velocity_agrees = 0;
  double velocity_agree_mps = 0.0;  // the tolerance it was counted with
  double velocityAgreesShare() const;  // of the true objects (detection.tp + fn); 0 without any
  std::size_t id_switches = 0;
  double velocity_rmse = 0.0;       // planar, over matched pairs with known truth velocity
  std::size_t velocity_samples = 0;
  // Where the velocity error comes from: the same RMSE over settled tracks only (age >=
  // EvalParams::settled_age), and the RMS frame-to-frame change of the detected centre's offset
  // from the true centre while the same track follows the same object (box jitter, which the
  // filter reads as motion: 0.1 m per frame at 10 Hz is 1 m/s).
  double velocity_rmse_settled = 0.0;
  std::size_t velocity_samples_settled = 0;
  double offset_step_rms_m = 0.0;
  std::size_t offset_steps = 0;
  // How far the true footprint (its axis-aligned bounds) reaches beyond the matched detection's
  // box, median over matched detections with a box: the face toward the vehicle along x, and the
  // two faces along y. Labelled boxes are larger than what a LiDAR sees: this is what
  // danger_detector/predictive/footprint_margin_m makes up for (KITTI 0.19 / 0.25 m).
  double box_bias_near_m = 0.0;
  double box_bias_side_m = 0.0;
  std::size_t box_bias_samples = 0;
  // Tracking in the fixed frame: the speed over ground of the tracks matched to true
  // objects that stand still (their true relative velocity plus the frame's ego twist at them is
  // below EvalParams::static_speed_mps), median and 90th percentile over settled tracks. Zero
  // samples when the graph reports no ego motion (every object moves relative to the vehicle).
  // Motion states, with ego motion, from a track's second frame on (age >= 2): of the tracks
  // matched to true objects that stand still over ground (static_speed_mps) and to those that
  // move (moving_speed_mps), and of the detections of no true object in the scored view.
  MotionCounts motion_standing, motion_moving, motion_unlabelled;
  double static_speed_p50_mps = 0.0;
  double static_speed_p90_mps = 0.0;
  std::size_t static_speed_samples = 0;
  double latency_p50_ms = 0, latency_p90_ms = 0, latency_p99_ms = 0, latency_max_ms = 0;
  double duty_cycle = 0.0;          // fraction of processed frames with the lamp on
  // The same for a perfect danger detector: the light controller (EvalParams::lamp_*) given, each
  // processed frame, whether any true object is dangerous. What danger there is keeps the lamp on
  // at least this long; a lower duty_cycle means missed or late warnings.
  double truth_duty_cycle = 0.0;
  // The danger model (EvalParams::danger, with its hysteresis per true id when predictive) given
  // perfect perception: each scored true object's own box (its axis-aligned bounds, and its
  // oriented footprint as parts of at most 0.15 m, as icanc/Obstacle's footprint), relative
  // velocity (zero where the labels give none), no velocity uncertainty and no footprint margin
  // (the true box lacks nothing the LiDAR did not see), scored per object-frame as `danger`.
  // What it misses is the model's, or the truth's (a pedestrian who will stop, or start, is
  // labelled by where it will be): `danger` below this is perception's.
  Confusion perfect_tracks;
  // The lamp (EvalParams::lamp_*) driven by the danger model on perfect tracks: what the model
  // itself costs in lamp time once perception is perfect (truth_duty_cycle is the floor).
  double perfect_tracks_duty_cycle = 0.0;
  // What kept the lamp on: the flags of each processed frame sorted by cause (a true danger, the
  // model's own false alarm, perception's on a true object, a detection of no true object standing
  // or moving over ground, unscored), the light controller re-run on each cause alone and on all
  // but each one (lamp_causes.hpp).
  LampCauses lamp_causes;
};

// One object-frame of the danger score and what decided it: an eligible true object (with the
// detection matched to it, or the dangerous fragment that flagged it), or a dangerous detection of
// no true object (a false alarm). Counting the TP/FP/FN/TN rows gives EvalReport::danger.
// kDontCare rows are dangerous detections on a true object that is not scored (too few returns,
// out of range or view): not counted, listed because they light the lamp (duty_cycle).
// kStandingApart rows are true objects dangerous by the corridor that stand beside the swept path
// (EvalReport::danger_standing_apart): not counted in `danger`.
enum class Outcome : std::uint8_t {
  kTruePositive, kFalsePositive, kFalseNegative, kTrueNegative, kDontCare, kStandingApart
};
const char* toString(Outcome outcome);  // "TP", "FP", "FN", "TN", "DC", "SA"

struct ScoredRow {
  double t = 0.0;
  Outcome outcome = Outcome::kTrueNegative;
  bool has_truth = false;   // false: a false alarm of no true object
                            // (a kDontCare row has the unscored object)
  TruthObject truth;
  bool has_detection = false;  // the matched detection, else the flagging fragment, else none
  bool fragment = false;       // the detection is a fragment of the true object, not its match
  DetectedObject detection;
  // With a truth: whether the danger model flagged the true object on its perfect track this frame
  // (EvalReport::perfect_tracks), so a row tells perception's share from the model's.
  bool perfect_flagged = false;
  // Unmatched, its centre inside the box of the detection matched to another true object: that
  // detection's id (EvalReport::detection_merged), else 0.
  std::uint32_t merged_into = 0;
};

// Distance from a point to the oriented footprint of a true object (0 when inside).
double distanceToFootprint(const TruthObject& truth, const Eigen::Vector2d& point);

// The axis-aligned bounds (x, y) of a true object's oriented footprint.
Eigen::AlignedBox2d footprintBounds(const TruthObject& truth);

// What a perfect tracker would hand the danger model for a true object in `frame`: its box and
// oriented footprint, its labelled relative velocity, the frame's ego twist and path, and its
// motion state from its speed over ground (static below static_speed_mps, else moving; unknown
// without ego motion or a labelled velocity).
ObjectKinematics perfectTrack(const TruthObject& o, const EvalFrame& frame, double static_speed_mps);

// True when `o` is dangerous by the ground truth's corridor, stands still over ground (its perfect
// track static) and the vehicle's swept path does not reach it (EvalReport::danger_standing_apart).
bool standsApart(const TruthObject& o, const EvalFrame& frame, const EvalParams& params);

// `rows`, when given, receives one ScoredRow per object-frame counted in EvalReport::danger, one
// kDontCare row per dangerous detection on an unscored true object and one kStandingApart row per
// true object counted apart.
EvalReport evaluate(const std::vector<EvalFrame>& frames, const EvalParams& params,
                    std::vector<ScoredRow>* rows = nullptr);

// A fixed-width table like the paper's, and the same figures as JSON.
std::string toTable(const EvalReport& report, const std::string& title);
std::string toJson(const EvalReport& report, const std::string& name);
// The rows as CSV with a header line (one object-frame per line; empty fields where no truth or
// no detection).
std::string toCsv(const std::vector<ScoredRow>& rows);

}  // namespace icanc
