// LiDAR odometry for vehicles without wheel odometry: each cloud is registered against
// a small local map of the previous clouds, as KISS-ICP does it (Vizzo et al., RA-L 2023):
//
//  1. the cloud (already in the vehicle frame) is range-filtered and voxel-downsampled twice, one
//     point (the first) per voxel: at map_voxel_factor * voxel_m (what goes into the map) and at
//     registration_voxel_factor * voxel_m (what is registered, at most max_registration_points);
//  2. the initial guess is the previous pose moved by the constant-velocity prior (the last
//     frame-to-frame motion scaled to this frame's dt);
//  3. point-to-point ICP against the map, solved by Gauss-Newton with a Geman-McClure kernel:
//     correspondences within 3 sigma, kernel scale sigma / 3, where sigma is the adaptive
//     threshold: the RMS of the past deviations of the estimate from the prior (those above
//     min_motion_m), initial_threshold_m until there is one;
//  4. the map (voxel_m voxels, at most max_points_per_voxel points each, in `odom`) gets the
//     frame's points at the estimated pose; voxels farther than max_range_m are dropped.
//
// Nearest neighbours are searched in the 2 x 2 x 2 voxels around a point (the ones within
// voxel_m / 2 of it on every axis): exact within voxel_m / 2, which is why the map voxel, not a
// kd-tree, bounds the correction per frame. Every buffer is reused; time is an argument.
#pragma once

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "icanc/core/common/always_inline.hpp"
#include "icanc/core/motion/measured_twist.hpp"

namespace icanc {

struct LidarOdometryParams {
  double voxel_m = 1.0;                    // local map voxel [m]
  int input_stride = 1;                    // every n-th input point is read (scan order: 2
                                           // thins azimuth steps, not rings; saves pass 1 time)
  double max_range_m = 60.0;               // points beyond, and map voxels beyond, are dropped [m]
  double min_range_m = 3.0;                // points nearer (the vehicle itself) are dropped [m]
  int max_points_per_voxel = 4;            // map points per voxel (1 .. kMaxPointsPerVoxel)
  int max_iterations = 10;                 // Gauss-Newton iterations per frame
  double convergence_eps = 1e-3;           // stop when the step's norm (m, rad) is below this
  double initial_threshold_m = 2.0;        // adaptive threshold before any deviation is known [m]
  double min_motion_m = 0.1;               // deviations below this do not feed the threshold [m]
  double map_voxel_factor = 0.5;           // map input: one point per voxel_m * this
  double registration_voxel_factor = 1.5;  // registered: one point per voxel_m * this ...
  int max_registration_points = 400;       // ... at most this many (evenly thinned)
  // Flat road gives point-to-point ICP nothing horizontal, and its rings (fixed ranges on a flat
  // road) travel with the vehicle: left to dominate the registered points, it holds the estimate
  // at "not moving". Points below ground_max_z_m (base frame) make at most ground_share of the
  // registered points (they still fix height, roll and pitch); all go into the map.
  double ground_max_z_m = 0.3;            // [m] in the base frame (REP-105: on the road); -1e9: no split
  double ground_share = 0.05;             // [0, 1]
  int min_points = 50;                    // fewer registration points: pose extrapolated
  double min_correspondence_ratio = 0.2;  // fewer matched points than this share: degenerate
  double max_correction_m = 3.0;          // larger correction of the prior per frame: degenerate
  // Fewer matched points constraining the weakest horizontal direction than this share
  // (LidarOdometryStats::horizontal_observability): degenerate. A road with walls along it only
  // lets ICP slide and report "not moving"; a street with façades along it stays above it.
  double min_horizontal_observability = 0.12;
  double max_dt_s = 1.0;                  // longer gap between clouds: motion prior dropped [s]
  // Point-to-plane residuals where the map around a match is a plane (its points' smallest spread
  // under a tenth of the next): the distance along the plane's normal, so a point may slide along
  // a wall or the road. Sensors that sample a wall in fixed columns or rings (a sparse azimuth:
  // CARLA's 128-channel unit at 0.72 deg) otherwise pull point-to-point ICP onto the previous
  // scan's columns, toward "not moving". Elsewhere (poles, corners, sparse map): point-to-point.
  bool point_to_plane = false;
};

constexpr int kMaxPointsPerVoxel = 32;

// "" when valid, else the first problem naming its key.
std::string validate(const LidarOdometryParams& params);

// The parameter keys (config/*.yaml section lidar_odometry), for the YAML and ROS readers.
template <class Reader>
void visitParams(Reader& r, LidarOdometryParams& p) {
  r("voxel_m", p.voxel_m);
  r("input_stride", p.input_stride);
  r("max_range_m", p.max_range_m);
  r("min_range_m", p.min_range_m);
  r("max_points_per_voxel", p.max_points_per_voxel);
  r("max_iterations", p.max_iterations);
  r("convergence_eps", p.convergence_eps);
  r("initial_threshold_m", p.initial_threshold_m);
  r("min_motion_m", p.min_motion_m);
  r("map_voxel_factor", p.map_voxel_factor);
  r("registration_voxel_factor", p.registration_voxel_factor);
  r("max_registration_points", p.max_registration_points);
  r("ground_max_z_m", p.ground_max_z_m);
  r("ground_share", p.ground_share);
  r("min_points", p.min_points);
  r("min_correspondence_ratio", p.min_correspondence_ratio);
  r("max_correction_m", p.max_correction_m);
  r("min_horizontal_observability", p.min_horizontal_observability);
  r("max_dt_s", p.max_dt_s);
  r("point_to_plane", p.point_to_plane);
}

struct LidarOdometryStats {
  enum class Result {
    kFirstFrame,    // map started, pose unchanged
    kRegistered,    // ICP result
    kDegenerate,    // registration rejected: pose from the motion prior
    kHeld,          // a horizontal direction unobserved, a measured speed but no yaw rate:
                    // registered with the translation along it held at the speed's (seedTwist)
    kExtrapolated,  // too few points (empty / tiny cloud): pose from the motion prior
    kReset,         // stamp went backwards: everything restarted at this frame
    kAtRest,        // the scan fits the map without motion since the last frame as well as at
                    // the registration's result (and, for a degenerate registration, the motion
                    // prior does not fit): pose held, twist zero
  };
  Result result = Result::kFirstFrame;
  std::size_t input_points = 0;         // points offered (incl. NaN / out of range)
  std::size_t frame_points = 0;         // after range filter + map-resolution downsampling
  std::size_t registration_points = 0;  // registered
  std::size_t correspondences = 0;      // matched in the last iteration
  std::size_t map_points = 0;
  int iterations = 0;
  // Of the matched points at the result, the share that constrains the registration's weakest
  // horizontal direction: the smallest eigenvalue of the x-y block of mean(n n^T), n the map's
  // surface normal at each match (plane fit of its neighbourhood). A flat road or walls along one
  // direction leave it near 0 (ICP slides); a street with structure across it does not.
  double horizontal_observability = 0.0;
  double threshold_m = 0.0;  // adaptive sigma used this frame
  // The at-rest test (kAtRest): of the registration points matched to a planar neighbourhood at
  // the result, how many, and how much worse "no motion since the last frame" fits them than the
  // best of it, the result and the prior, as an F statistic (6 and residuals - 6 degrees of
  // freedom; 0 when not tested).
  std::size_t rest_residuals = 0;
  double rest_f = 0.0;
  bool speed_seeded = false;  // a pose from the vehicle's measured twist (seedTwist)
  double downsample_ms = 0.0, register_ms = 0.0, map_ms = 0.0;
  double totalMs() const { return downsample_ms + register_ms + map_ms; }
};

const char* toString(LidarOdometryStats::Result result);

struct LidarOdometryCounters {
  std::uint64_t frames = 0, registered = 0, degenerate = 0, extrapolated = 0, resets = 0;
  std::uint64_t held = 0;  // of the degenerate, registered along the rest (Result::kHeld)
  std::uint64_t at_rest = 0;  // pose held: the scan fits no motion (Result::kAtRest)
  std::uint64_t gaps = 0;  // dt above max_dt_s: prior dropped
  std::uint64_t speed_seeded = 0;  // poses from the vehicle's measured twist (seedTwist)
  std::uint64_t nonfinite_points = 0;
};

// Open-addressing hash from a packed voxel key to an int32, cleared in O(1) by a generation
// counter. Used for the downsampling sets and the map index.
class VoxelIndex {
 public:
  VoxelIndex();
  void clear();
  // The value slot of `key`, inserted with `value_if_new` when absent (`inserted` set).
  std::int32_t& findOrInsert(std::uint64_t key, std::int32_t value_if_new, bool& inserted);
  std::int32_t find(std::uint64_t key) const;  // -1 when absent
  std::size_t size() const { return size_; }

 private:
  struct Slot {
    std::uint64_t key;
    std::int32_t value;
    std::uint32_t generation;
  };
  void grow();
  std::size_t slotOf(std::uint64_t key) const {
    return static_cast<std::size_t>((key * 0x9E3779B97F4A7C15ull) >> shift_);
  }
  std::vector<Slot> slots_;
  std::uint32_t generation_ = 1;
  std::size_t size_ = 0;
  int shift_ = 64;
};

// The voxels one frame holds, around the sensor, for "the first point of each voxel": a dense
// grid of columns (x and y within `half` voxels of the origin) of 64-bit masks over the voxels
// z = -32 .. 31, the rest in a VoxelIndex. A scan visits neighbouring voxels one after another;
// a hash scatters them over its table, and its lookups (one per voxel change along the scan)
// would each miss the cache. Cleared through the columns it touched.
// A voxel's indices along x, y, z and their packed key (LidarOdometry::voxelOf).
struct VoxelCoord {
  std::int32_t i, j, k;
  std::uint64_t key;
};

class ColumnVoxelSet {
 public:
  // half: columns on each side of the origin along x and y; 0: every voxel in the hash.
  void reset(int half);
  void clear();
  // Adds the voxel when `keep`; true when it was kept and not in the set. Inside the grid without
  // a branch on the point: a scan's voxel changes are too irregular to predict, and the
  // mispredictions were most of the odometry's reading time.
  bool insert(const VoxelCoord& v, bool keep = true) {
    const std::uint32_t ci = static_cast<std::uint32_t>(v.i + half_);  // a negative one wraps
    const std::uint32_t cj = static_cast<std::uint32_t>(v.j + half_);  // past side_
    const std::uint32_t ck = static_cast<std::uint32_t>(v.k + 32);
    if (ci < side_ && cj < side_ && ck < 64u) {
      const std::uint32_t c = cj * side_ + ci;
      const std::uint64_t bit = static_cast<std::uint64_t>(keep) << ck;
      const std::uint64_t old = columns_[c];
      columns_[c] = old | bit;
      touched_[touched_count_] = c;  // kept when the column was empty
      touched_count_ += static_cast<std::uint32_t>((old == 0) & (bit != 0));
      return ((old & bit) == 0) & keep;
    }
    if (!keep) return false;
    bool inserted;
    overflow_.findOrInsert(v.key, 0, inserted);
    return inserted;
  }

 private:
  std::int32_t half_ = 0;
  std::uint32_t side_ = 0;
  std::vector<std::uint64_t> columns_;
  std::vector<std::uint32_t> touched_;  // one per column and one more: the first touched_count_ are set
  std::uint32_t touched_count_ = 0;
  VoxelIndex overflow_;
};

// Of the points x = xs[j], y = xs[stride + j], z = xs[2 * stride + j] (j < count, the arrays
// padded with +inf to a whole multiple of 4), the first nearest to s strictly nearer than
// sqrt(best): its index, `best` set to its squared distance, the same bits as Eigen's
// (q - s).squaredNorm(); -1 when none is. Four at a time where SSE2 is.
int nearestPacked(const float* xs, int count, std::size_t stride, const Eigen::Vector3f& s,
                  float& best);

class LidarOdometry {
 public:
  // Throws std::invalid_argument when `params` is invalid.
  explicit LidarOdometry(const LidarOdometryParams& params = {});

  // One cloud, in the vehicle frame (base_link), taken at stamp_s. Returns odom_T_base.
  Eigen::Isometry3d registerFrame(double stamp_s, const std::vector<Eigen::Vector3f>& points);
  // Who keeps every input_stride-th point: the odometry, counting what the source gives it, or
  // the source itself (forEachXYZ over everyNthPoint(plan, input_stride)), so that the points
  // skipped are never decoded (LidarOdometryStats::input_points then counts those read).
  enum class Thinning { kByOdometry, kBySource };
  // Same, reading points through `source(sink)`, sink(x, y, z) per point (forEachXYZ's shape),
  // so a decoder feeds the downsampling directly.
  template <class Source>
  Eigen::Isometry3d registerFrom(double stamp_s, Source&& source,
                                 Thinning thinning = Thinning::kByOdometry);

  // The vehicle's motion as the vehicle measures it (wheel speed, CAN; a yaw-rate gyro), for the
  // next frame only. A flat road or a road between walls leaves ICP nothing to fix the motion
  // with (horizontal_observability): the frame is degenerate and its pose is the motion prior,
  // which says "as before": "not moving" for a vehicle already at speed in the first frame,
  // "straight on" into a bend. With a seed, that pose turns at the measured yaw rate (when
  // measured; else the prior's turn) and moves at the measured speed along the chord of the turn
  // (a car does not slide sideways), each the mean of this seed and the previous frame's when it
  // had one. Registered frames are as without it. Without a yaw rate (NaN), a frame that slid
  // along one horizontal direction only (walls along the road) is registered in the other five
  // with the translation along it held at the measured speed's (Result::kHeld): the turn from the
  // walls. A speed of zero in this seed and the previous frame's is the vehicle at rest
  // (Result::kAtRest) whatever the registration says. A non-finite speed: no seed.
  void seedTwist(const MeasuredTwist& twist);

  const Eigen::Isometry3d& pose() const { return pose_; }
  Eigen::Vector3d linearVelocity() const { return linear_velocity_; }    // base frame [m/s]
  Eigen::Vector3d angularVelocity() const { return angular_velocity_; }  // base frame [rad/s]
  const LidarOdometryStats& lastStats() const { return stats_; }
  const LidarOdometryCounters& counters() const { return counters_; }
  const LidarOdometryParams& params() const { return params_; }
  // Which of every input_stride points the next frame reads: points phase, phase + n, ... of the
  // scan order (each row, at the source: everyNthPoint(plan, input_stride, sourcePhase())). It
  // turns with every frame: a driver's organized cloud has its columns at the same azimuths every
  // frame, and the same columns kept frame after frame lock ICP onto them, as a sparse scan's
  // columns do (night_town_street's turn: 8.4 m off with the phase fixed, 0.08 m turning).
  std::size_t sourcePhase() const {
    return params_.input_stride > 1 ? counters_.frames % static_cast<std::uint64_t>(params_.input_stride)
                                    : 0;
  }
  std::size_t mapPoints() const { return map_points_; }
  // Current map points (odom frame), for tests and visualisation.
  std::vector<Eigen::Vector3f> mapCloud() const;

  // Forgets the map, pose (identity), velocity and threshold history; counters stay.
  void reset();

 private:
  void beginFrame(Thinning thinning);
  // Pass 1, per point: range filter and the first point of each map-resolution voxel.
  ICANC_ALWAYS_INLINE void addPoint(float x, float y, float z) {
    ++input_points_;
    if (++stride_count_ < stride_) return;
    stride_count_ = 0;
    counters_.nonfinite_points += !std::isfinite(x + y + z);
    const float r2 = x * x + y * y + z * z;  // NaN or inf: out of range
    const bool keep = (r2 >= min_range2_) & (r2 <= max_range2_);
    // Without a branch on the point (ColumnVoxelSet::insert): a point out of range is written
    // past the end and not counted; its voxel is taken at the origin (finite, and not set).
    const VoxelCoord voxel =
        voxelOf(keep ? x : 0.0f, keep ? y : 0.0f, keep ? z : 0.0f, inv_frame_voxel_);
    if (frame_count_ == frame_.size()) frame_.resize(2 * frame_.size() + 4096);
    frame_[frame_count_] = Eigen::Vector3f(x, y, z);
    frame_count_ += frame_voxels_.insert(voxel, keep);
  }
  Eigen::Isometry3d finishFrame(double stamp_s, double downsample_start_ms);

  // floor as a truncation and a correction: std::floor is a libm call per coordinate on plain
  // x86-64 (no SSE4.1 round instruction), three per point in the hottest loop.
  static std::int32_t floorToInt(float v) {
    const std::int32_t i = static_cast<std::int32_t>(v);
    return i - (v < static_cast<float>(i) ? 1 : 0);
  }
  static VoxelCoord voxelOf(float x, float y, float z, float inv_voxel) {
    VoxelCoord v{floorToInt(x * inv_voxel), floorToInt(y * inv_voxel), floorToInt(z * inv_voxel), 0};
    v.key = packKey(v.i, v.j, v.k);
    return v;
  }
  static std::uint64_t packKey(std::int32_t i, std::int32_t j, std::int32_t k) {
    const std::uint64_t m = (1u << 21) - 1;
    return ((static_cast<std::uint64_t>(i) & m) << 42) |
           ((static_cast<std::uint64_t>(j) & m) << 21) | (static_cast<std::uint64_t>(k) & m);
  }

  // The constant-velocity prior; with_seed: moved by the measured twist (seedTwist) instead.
  Eigen::Isometry3d predict(double dt, bool with_seed) const;
  void countSeed(bool seeded);
  void selectRegistrationPoints();
  // The 2 x 2 x 2 map voxels nearest to s, searched for its match: on each axis its voxel and the
  // neighbour on the side of the voxel's half it lies in. blockCorner: the block's lowest corner
  // (voxel indices), returned as its key; findBlock: each voxel's map slot (-1: empty).
  std::uint64_t blockCorner(const Eigen::Vector3f& s, std::int32_t base[3]) const;
  void findBlock(const std::int32_t base[3], std::int32_t voxels[8]) const;
  // ICP from `guess`; false when the result is degenerate (slid_: only because a horizontal
  // direction was unobserved, weakest_ that direction in odom, while the one across it was:
  // walls along a road, not an open road, whose rings lock the yaw as well). With `held` (a horizontal unit
  // vector in odom), the translation along it stays the guess's: the other five degrees of
  // freedom are solved, and the horizontal observability is not asked for.
  bool registerScan(const Eigen::Isometry3d& guess, double sigma, Eigen::Isometry3d& result,
                    const Eigen::Vector3d* held = nullptr);
  // LidarOdometryStats::horizontal_observability of the registration points at `pose`, matches
  // within sqrt(max_d2).
  // weakest: set to the unit horizontal direction (odom) the matched surfaces constrain least;
  // across: the same share for the direction across it (the largest eigenvalue).
  // rest: also sums the point-to-plane residuals of the planar matches at `pose`, at the last
  // pose (no motion) and at the prior, each against the plane found at `pose`.
  struct RestFit {
    Eigen::Isometry3d prior = Eigen::Isometry3d::Identity();
    std::size_t count = 0;
    double sse_result = 0.0, sse_still = 0.0, sse_prior = 0.0;
  };
  double horizontalObservability(const Eigen::Isometry3d& pose, float max_d2,
                                 Eigen::Vector3d* weakest = nullptr, double* across = nullptr,
                                 RestFit* rest = nullptr) const;
  // Of rest_fit_ (the last registerScan): does "no motion since the last frame" fit the scan as
  // well as the best of it, the result and the prior, within what the residuals' own scatter
  // allows (an F test at 1 %), and is the prior ruled out by the same test? Sets stats_.rest_*.
  struct RestTest {
    bool still_fits = false, prior_ruled_out = false;
  };
  RestTest testRest();
  void updateMap(const Eigen::Isometry3d& pose);
  void pruneMap(const Eigen::Vector3d& origin);
  double adaptiveThreshold() const;

  LidarOdometryParams params_;
  float min_range2_ = 0.0f, max_range2_ = 0.0f;
  float inv_frame_voxel_ = 1.0f, inv_map_voxel_ = 1.0f;

  // This frame.
  std::size_t input_points_ = 0;
  std::size_t frame_count_ = 0;  // frame_'s points while reading (its size is the buffer's)
  int stride_ = 1, stride_count_ = 0;
  ColumnVoxelSet frame_voxels_;         // this frame's map-resolution voxels
  ColumnVoxelSet registration_voxels_;  // ... and registration-resolution ones
  std::vector<Eigen::Vector3f> frame_;         // map-resolution points, base frame
  std::vector<Eigen::Vector3f> registration_;  // registration points, base frame
  std::vector<Eigen::Vector3f> candidates_;    // registration candidates above it
  std::vector<Eigen::Vector3f> ground_;        // registration candidates below ground_max_z_m
  // Per registration point: the 2 x 2 x 2 voxel block last searched and its voxel ids, reused
  // across iterations while the point stays in the same block.
  struct Neighbourhood {
    std::uint64_t block = ~0ull;
    std::int32_t voxels[8];
    // Its map points in voxel order, in block_points_: x at xs[0 .. count), y at
    // xs[block_stride_ ..], z at xs[2 * block_stride_ ..]; padded to a multiple of 4 with infinity.
    float* xs = nullptr;
    int count = 0;
    Eigen::Vector3f normal;  // of the block's map points when they are planar (point_to_plane)
    bool planar = false;
  };
  // The plane of the block's map points: false when fewer than 5 or not planar.
  bool fitPlane(const std::int32_t voxels[8], Eigen::Vector3f& normal) const;
  std::vector<Neighbourhood> neighbourhoods_;
  std::size_t block_stride_ = 0;      // 8 * max_points_per_voxel (whole packets of 4)
  std::vector<float> block_points_;  // 3 * block_stride_ per registration point
  bool slid_ = false;
  bool weakly_observed_ = false;  // degenerate only for the horizontal observability
  RestFit rest_fit_;
  bool at_rest_ = false;  // the last frame was at rest
  std::vector<double> rest_critical_;  // testRest's critical F per number of residuals (NaN: not yet)
  Eigen::Vector3d weakest_ = Eigen::Vector3d::UnitX();
  double across_observability_ = 0.0;

  // Map: voxel key -> slot; slot s holds counts_[s] points at points_[s * per_voxel].
  VoxelIndex map_index_;
  std::vector<std::uint64_t> map_keys_;
  std::vector<std::uint8_t> map_counts_;
  std::vector<Eigen::Vector3f> map_points_data_;
  std::size_t map_points_ = 0;
  Eigen::Vector3d last_prune_origin_ = Eigen::Vector3d::Zero();

  // State.
  bool initialized_ = false;
  double last_stamp_s_ = 0.0;
  Eigen::Isometry3d pose_ = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d last_delta_ = Eigen::Isometry3d::Identity();  // previous frame's motion ...
  double last_delta_dt_ = 0.0;                                    // ... over this dt (0: none)
  bool has_seed_ = false;       // seedTwist for the next frame
  MeasuredTwist seed_;
  bool has_last_seed_ = false;  // the previous frame's: the seeded pose moves at the mean of the
  MeasuredTwist last_seed_;     // two (the distance of a vehicle speeding up or braking)
  Eigen::Vector3d linear_velocity_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d angular_velocity_ = Eigen::Vector3d::Zero();
  double deviation_sse_ = 0.0;
  std::size_t deviation_samples_ = 0;

  LidarOdometryStats stats_;
  LidarOdometryCounters counters_;
};

double odometryNowMs();

template <class Source>
Eigen::Isometry3d LidarOdometry::registerFrom(double stamp_s, Source&& source, Thinning thinning) {
  const double t0 = odometryNowMs();
  beginFrame(thinning);
  source([&](float x, float y, float z) ICANC_ALWAYS_INLINE { addPoint(x, y, z); });
  return finishFrame(stamp_s, t0);
}

}  // namespace icanc
