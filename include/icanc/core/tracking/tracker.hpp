// Multi-object tracker: gating by centre displacement and BEV IoU, optimal assignment
// (solveAssignmentByComponents), one ImmConstantVelocity filter per track, birth / confirmation /
// deletion.
// The filter measures how the faces of the box that stay on the object moved (TrackAnchor), not
// how the centre of the visible points moved. Time is always the caller's (header stamps), never
// a clock.
#pragma once

#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "icanc/core/perception/box.hpp"
#include "icanc/core/tracking/hungarian.hpp"
#include "icanc/core/tracking/imm_cv.hpp"

namespace icanc {

// What the Kalman filter measures of a detection, per planar axis (x, y of the detections' frame).
// kCentre: the middle of the box. kNearestFace (Autoware's nearest corner or surface, on the
// axis-aligned box): the face nearest the sensor, where the sensor lies beyond the box on that
// axis; where it lies within the box's span (alongside, both ends in view), the face the track was
// followed by until then, or the middle. The face away from the
// sensor is hidden by the object itself, cut by the region of interest or too sparse to hold
// still, so the visible points' centre slides along a passing car as its visible part changes
// (0.4 m a frame in night_parked_cars: 4 m/s of false motion at 10 Hz). A face at the edge of the
// region of interest (TrackerView) is where the view ends, not the object: the other face is used.
// A footprint smaller than TrackerParams::face_min_extent_m keeps the middle (the object seen whole).
// The faces are taken along the track's own axes fixed to the ground (Track::face_axes_yaw: the
// object's sides once seen long enough), from the box's convex hull, not along the vehicle's.
enum class TrackAnchor : std::uint8_t { kCentre, kNearestFace, kInvalid };
const char* toString(TrackAnchor anchor);
TrackAnchor parseTrackAnchor(const std::string& name);  // "centre" | "nearest_face"; else kInvalid

// Where one frame's detections were seen from, in their frame (x, y): the sensor's origin and the
// region of interest outside which points were dropped. The default (origin at 0, no region)
// suits detections in the sensor's own frame.
struct TrackerView {
  Eigen::Vector2f origin = Eigen::Vector2f::Zero();
  Eigen::Vector2f region_min = Eigen::Vector2f::Constant(-std::numeric_limits<float>::infinity());
  Eigen::Vector2f region_max = Eigen::Vector2f::Constant(std::numeric_limits<float>::infinity());
  float region_tolerance_m = 0.0f;  // a face this close to the region's edge counts as cut there
};

struct TrackerParams {
  float gate_distance_m = 2.0f;        // max distance predicted centre -> detection centre (x/y)
  float iou_weight = 1.0f;             // cost = distance / gate + iou_weight * (1 - BEV IoU)
  int min_hits_to_confirm = 2;         // detections before a track is published
  // A detection with fewer points than this updates a track but starts none: a sparse box (a far
  // object's few returns) keeps its object's track, a sparse clump of clutter gets none (0: any).
  int min_birth_points = 0;
  int max_missed_frames = 2;           // a track survives this many consecutive misses
  // The filter is an IMM of two constant-velocity models (ImmConstantVelocity): manoeuvring
  // (accel_std) and steady (steady_accel_std), changing mode at mode_switch_rate_per_s. Equal
  // values make it the single constant-velocity filter.
  double accel_std = 3.0;              // process noise of the manoeuvring model [m/s^2]
  double steady_accel_std = 0.05;      // process noise of the steady model [m/s^2]
  double mode_switch_rate_per_s = 0.02;  // [1/s]: P(change per frame) = 1 - exp(-rate * dt)
  double measurement_std_m = 0.15;     // centre measurement noise [m]
  double initial_velocity_std = 5.0;   // velocity uncertainty of a new track [m/s]
  double max_dt_s = 1.0;               // a larger gap between frames resets the tracker
  // Huber-robust update: an innovation beyond this many standard deviations (per planar axis)
  // counts as one of exactly this many (its variance is raised); 0 = plain Kalman update.
  double robust_sigma = 3.0;
  TrackAnchor anchor = TrackAnchor::kNearestFace;  // what the filter measures (TrackAnchor)
  // kNearestFace: a box shorter than this along both x and y is an object seen whole, and its
  // middle is measured (two faces' noise averaged) [m]. 1.5: pedestrians, bins, chairs; a car
  // (1.8 m wide) keeps its near faces even where only its rear is seen.
  float face_min_extent_m = 1.5f;
  // kNearestFace: when a box's extent along a face axis changes by more than this from the
  // predicted box to the detection (something standing close joined it or came apart from it: a
  // pedestrian beside a wall, a parked car), the face that moved less is measured on that axis,
  // not the face toward the sensor nor the middle: the jump is the other object, not motion. An
  // object that moves moves both faces. 0: off [m].
  float face_jump_m = 0.0f;
  // kNearestFace: where the face toward the sensor ends, seen from the sensor, beside (within this
  // many degrees of bearing) a detection at least 0.5 m nearer at that bearing, the view ends
  // there, not the object (a wall behind a walker, a parked car behind the one before it): along
  // that axis the face that moved less against the prediction is measured (the far face is often
  // hidden by the object itself). The edge of a shadow moves with what casts it (a walker coming
  // toward a wall, the vehicle driving past a post); read as the object's motion it made a wall's
  // pieces fly sideways. A face seen along its length (a flank at grazing incidence) is never one.
  // 0: off [deg].
  float occlusion_gap_deg = 0.0f;
  // A track whose predicted centre lies inside a detection's box is where that detection is: it
  // takes only a detection whose box, grown by this plus three standard deviations of its
  // predicted position, holds its predicted centre, or whose centre lies in its predicted box
  // grown by as much; else it coasts. A box holding several tracks goes only to the one it fits
  // best. Two walkers seen as one box: the one whose track did not get that box no longer jumps
  // to the pedestrian standing 1.3 m away (the fixed gate allows 2 m a frame). 0: off [m].
  float merge_hold_m = 0.0f;
  // merge_hold_m > 0: a track that got no detection while its predicted centre lay inside one
  // (merged with what it walks beside) coasts up to this many such frames before a miss counts,
  // so it is there to take its own box back when the two come apart.
  int merge_hold_frames = 0;
  // > 0: a track whose predicted box lies wholly behind a nearer detection, seen from the sensor
  // (every bearing of it within that detection's, which is at least 0.5 m nearer there), is held
  // where it is, as a merged one (merge_hold_m): it takes only a detection near its prediction,
  // else coasts, up to this many such frames before a miss counts. What shows beside or through
  // the nearer object meanwhile (a sliver of the car behind a walker) is not its object: taken,
  // its edge, which moves with the nearer object's shadow, was read as the track's motion. 0: off.
  int hidden_hold_frames = 0;
};

std::string validate(const TrackerParams& params);

struct Track {
  std::uint32_t id = 0;
  // The last associated box moved by the filter's correction, then along the filter's prediction
  // while coasting: the detection as seen, placed where the filter puts its anchor faces.
  Box3D box;
  // The axes the anchor faces are measured along: their yaw in the vehicle frame [rad]. The
  // vehicle's axes at birth; the object's own sides (the oriented box's yaw) from a detection at
  // least 3 m long on; turned with every frame motion in between, so they stay fixed to the
  // ground: a parked car's faces along them do not move as the vehicle turns (along the vehicle's
  // axes its box changes shape, about 1 m/s of false motion on a yawed car at 0.2 rad/s).
  float face_axes_yaw = 0.0f;
  // Its position is a reference point rigidly attached to the object (the first detection's
  // centre, then moved as the anchor faces moved), not the box centre: use box for where the
  // object is, filter for its velocity.
  ImmConstantVelocity filter;
  int age = 0;                // frames since birth (1 on the birth frame)
  int hits = 0;               // frames with an associated detection
  int missed = 0;             // consecutive frames without one, but for the held ones:
  int held = 0;               // frames without one inside a detection another track took
                              // (merge_hold_frames); missed + held: how long it has coasted
  bool confirmed = false;     // hits >= min_hits_to_confirm (stays true once reached)
  // Whether it moves, from free space (updateMotionState).
  MotionState motion = MotionState::kUnknown;
  MotionEvidence evidence;    // the last associated detection's
  int moving_in_row = 0;      // consecutive detections that read moving ...
  int static_in_row = 0;      // ... and static

  int coasted() const { return missed + held; }  // consecutive frames without a detection
  // Its velocity over ground: zero while free space says it stands still (the jitter of a
  // fragment's faces is not motion), the filter's otherwise. The filter itself runs on in either
  // state, so a track that turns moving has its velocity at once and its box never lags.
  Eigen::Vector3d velocity() const;
  // 1-sigma uncertainty of the planar velocity [m/s] (sqrt of the x/y velocity variance sum);
  // kStaticVelocityStd per axis while static.
  double velocityStd() const;           // planar: sqrt(var vx + var vy)
  Eigen::Vector2d velocityStdXY() const;  // per axis: sqrt(var vx), sqrt(var vy)
};

// A static track's reported velocity uncertainty per axis [m/s] (Track::velocity).
constexpr double kStaticVelocityStd = 0.05;

// A track's motion state after a detection read `evidence`: unknown takes the first reading;
// a static track turns moving after two moving readings in a row (one is a glimpse of what moves
// beside it), a moving one static after three static ones. A track whose filter has long measured
// a clear motion is not turned static by its sides (a car driving beside the vehicle: its flank
// lies where its flank was). Returns true when the state changed.
bool updateMotionState(Track& track, const MotionEvidence& evidence);

// A detection as seen from the sensor (TrackerParams::occlusion_gap_deg).
struct BearingSpan {
  float bearing = 0.0f;        // of the outline's first point [rad]
  float lo = 0.0f, hi = 0.0f;  // the outline's bearings relative to that [rad]
  float near_range = 0.0f;     // the range of the outline's nearest point [m]
  bool valid = false;          // false: the sensor within its outline, or no outline
};
BearingSpan bearingSpan(const Box3D& box, const Eigen::Vector2f& origin);

class MultiObjectTracker {
 public:
  enum class UpdateResult {
    kOk,
    kResetTimeBackwards,  // stamp older than the previous frame: tracks dropped (bag loop)
    kResetGap,            // gap larger than max_dt_s: tracks dropped
  };

  explicit MultiObjectTracker(const TrackerParams& params = TrackerParams());

  // One frame: predict every track to `stamp_s`, associate, update, age, birth, delete.
  // The first frame after construction or reset() only starts tracks. `view` says where the
  // detections were seen from (which faces are the near ones). `motion` maps the previous frame's
  // vehicle frame into this one (EgoStep::motion: p_now = motion * p_prev): the tracks are
  // re-expressed in it first, so their velocities are over ground. Identity: the vehicle is taken
  // to stand still and the velocities are relative to it (the paper).
  UpdateResult update(double stamp_s, const std::vector<Box3D>& detections,
                      const TrackerView& view = TrackerView(),
                      const Eigen::Isometry3d& motion = Eigen::Isometry3d::Identity());

  // Drops all tracks; the next update() only starts tracks. Ids keep counting (never reused).
  void reset();
  void setParams(const TrackerParams& params) { params_ = params; }
  const TrackerParams& params() const { return params_; }

  // All live tracks (tentative ones too; check Track::confirmed).
  const std::vector<Track>& tracks() const { return tracks_; }

 private:
  // merge_hold_m: forbids (in cost_) what a track inside a detection may not take.
  void holdTracksInsideDetections(const std::vector<Box3D>& detections);
  // hidden_hold_frames: marks the tracks wholly behind a nearer detection (track_hidden_) and
  // forbids them (in cost_) every detection but one where they are predicted.
  void holdHiddenTracks(const std::vector<Box3D>& detections, const TrackerView& view);
  // How far from its prediction a held track may take a detection [m].
  double holdMargin(const Track& track) const;

  TrackerParams params_;
  std::vector<Track> tracks_;
  std::vector<BearingSpan> spans_;  // this frame's detections, for occlusion_gap_deg
  std::uint32_t next_id_ = 1;
  double last_stamp_s_ = 0.0;
  bool has_stamp_ = false;

  // Per-frame scratch, kept to avoid allocating in steady state (grows only).
  Eigen::MatrixXd cost_;  // tracks x detections, used through its top-left corner
  ComponentWorkspace assignment_workspace_;  // solved per connected component of gated pairs
  std::vector<int> track_to_detection_;
  std::vector<char> detection_used_;
  std::vector<char> track_held_;  // its predicted centre inside a detection (merge_hold_m)
  std::vector<char> track_hidden_;  // wholly behind a nearer detection (hidden_hold_frames)
  std::vector<int> best_inside_;  // per detection: the track inside it it fits best, or -1
};

}  // namespace icanc
