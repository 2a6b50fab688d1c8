#include "icanc/core/motion/lidar_odometry.hpp"

#include <algorithm>
#include <chrono>
#include <limits>
#include <sstream>
#include <stdexcept>

#include <Eigen/Eigenvalues>
#include <boost/math/distributions/fisher_f.hpp>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace icanc {

double odometryNowMs() {
  return std::chrono::duration<double, std::milli>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

std::string validate(const LidarOdometryParams& p) {
  std::ostringstream why;
  const auto positive = [&](const char* key, double v) {
    if (why.tellp() == 0 && !(v > 0.0 && std::isfinite(v)))
      why << key << " must be > 0 (got " << v << ")";
  };
  positive("voxel_m", p.voxel_m);
  positive("max_range_m", p.max_range_m);
  positive("convergence_eps", p.convergence_eps);
  positive("initial_threshold_m", p.initial_threshold_m);
  positive("map_voxel_factor", p.map_voxel_factor);
  positive("registration_voxel_factor", p.registration_voxel_factor);
  positive("max_correction_m", p.max_correction_m);
  positive("max_dt_s", p.max_dt_s);
  if (!why.str().empty()) return why.str();
  if (!(p.min_range_m >= 0.0 && p.min_range_m < p.max_range_m))
    return "min_range_m must be in [0, max_range_m)";
  if (p.max_range_m / p.voxel_m > 1e5) return "max_range_m / voxel_m must be <= 1e5";
  if (p.max_points_per_voxel < 1 || p.max_points_per_voxel > kMaxPointsPerVoxel)
    return "max_points_per_voxel must be in [1, " + std::to_string(kMaxPointsPerVoxel) + "]";
  if (p.input_stride < 1 || p.input_stride > 16) return "input_stride must be in [1, 16]";
  if (p.max_iterations < 1) return "max_iterations must be >= 1";
  if (!(p.min_motion_m >= 0.0)) return "min_motion_m must be >= 0";
  if (p.max_registration_points < 10) return "max_registration_points must be >= 10";
  if (p.min_points < 6) return "min_points must be >= 6 (six unknowns)";
  if (p.min_points > p.max_registration_points)
    return "min_points must be <= max_registration_points";
  if (!(p.ground_share >= 0.0 && p.ground_share <= 1.0)) return "ground_share must be in [0, 1]";
  if (!std::isfinite(p.ground_max_z_m)) return "ground_max_z_m must be finite";
  if (!(p.min_correspondence_ratio >= 0.0 && p.min_correspondence_ratio <= 1.0))
    return "min_correspondence_ratio must be in [0, 1]";
  if (!(p.min_horizontal_observability >= 0.0 && p.min_horizontal_observability <= 0.5))
    return "min_horizontal_observability must be in [0, 0.5] (0: not checked)";
  return "";
}

const char* toString(LidarOdometryStats::Result result) {
  switch (result) {
    case LidarOdometryStats::Result::kFirstFrame:
      return "first frame";
    case LidarOdometryStats::Result::kRegistered:
      return "registered";
    case LidarOdometryStats::Result::kDegenerate:
      return "degenerate (motion prior)";
    case LidarOdometryStats::Result::kExtrapolated:
      return "too few points (motion prior)";
    case LidarOdometryStats::Result::kReset:
      return "reset (time went backwards)";
    case LidarOdometryStats::Result::kHeld:
      return "registered, along-track from the measured twist";
    case LidarOdometryStats::Result::kAtRest:
      return "at rest (the scan fits no motion)";
  }
  return "?";
}

// --- VoxelIndex ----------------------------------------------------------------------------------

VoxelIndex::VoxelIndex() : slots_(4096, Slot{0, 0, 0}), shift_(64 - 12) {}

void VoxelIndex::clear() {
  size_ = 0;
  if (++generation_ == 0) {  // wrapped: old generations could look current
    for (Slot& s : slots_) s.generation = 0;
    generation_ = 1;
  }
}

void VoxelIndex::grow() {
  std::vector<Slot> old(slots_.size() * 2, Slot{0, 0, 0});
  old.swap(slots_);
  --shift_;
  const std::size_t mask = slots_.size() - 1;
  for (const Slot& s : old) {
    if (s.generation != generation_) continue;
    std::size_t i = slotOf(s.key);
    while (slots_[i].generation == generation_) i = (i + 1) & mask;
    slots_[i] = s;
  }
}

std::int32_t& VoxelIndex::findOrInsert(std::uint64_t key, std::int32_t value_if_new,
                                       bool& inserted) {
  if (size_ * 2 >= slots_.size()) grow();  // load <= 1/2: short probes
  const std::size_t mask = slots_.size() - 1;
  for (std::size_t i = slotOf(key);; i = (i + 1) & mask) {
    Slot& s = slots_[i];
    if (s.generation != generation_) {
      s = Slot{key, value_if_new, generation_};
      ++size_;
      inserted = true;
      return s.value;
    }
    if (s.key == key) {
      inserted = false;
      return s.value;
    }
  }
}

std::int32_t VoxelIndex::find(std::uint64_t key) const {
  const std::size_t mask = slots_.size() - 1;
  for (std::size_t i = slotOf(key);; i = (i + 1) & mask) {
    const Slot& s = slots_[i];
    if (s.generation != generation_) return -1;
    if (s.key == key) return s.value;
  }
}

void ColumnVoxelSet::reset(int half) {
  half_ = std::max(0, half);
  side_ = static_cast<std::uint32_t>(2 * half_);
  columns_.assign(static_cast<std::size_t>(side_) * side_, 0);
  touched_.assign(columns_.size() + 1, 0);  // insert writes one past the columns set so far
  touched_count_ = 0;
  overflow_.clear();
}

void ColumnVoxelSet::clear() {
  for (std::uint32_t t = 0; t < touched_count_; ++t) columns_[touched_[t]] = 0;
  touched_count_ = 0;
  overflow_.clear();
}

// --- LidarOdometry -------------------------------------------------------------------------------

LidarOdometry::LidarOdometry(const LidarOdometryParams& params) : params_(params) {
  const std::string why = validate(params);
  if (!why.empty()) throw std::invalid_argument("LidarOdometryParams: " + why);
  min_range2_ = static_cast<float>(params.min_range_m * params.min_range_m);
  max_range2_ = static_cast<float>(params.max_range_m * params.max_range_m);
  inv_frame_voxel_ = static_cast<float>(1.0 / (params.voxel_m * params.map_voxel_factor));
  inv_map_voxel_ = static_cast<float>(1.0 / params.voxel_m);
  // Every frame point lies within max_range_m of the origin: a grid spans that (one voxel more
  // for rounding) when its masks take at most 4 MB; a finer voxel keeps the hash alone.
  const auto gridHalf = [&](double inv_voxel) {
    const double half = std::ceil(params.max_range_m * inv_voxel) + 1.0;
    return 4.0 * half * half * sizeof(std::uint64_t) <= 4e6 ? static_cast<int>(half) : 0;
  };
  frame_voxels_.reset(gridHalf(inv_frame_voxel_));
  registration_voxels_.reset(
      gridHalf(1.0 / (params.voxel_m * params.registration_voxel_factor)));
}

void LidarOdometry::reset() {
  initialized_ = false;
  pose_.setIdentity();
  last_delta_.setIdentity();
  last_delta_dt_ = 0.0;
  has_last_seed_ = false;
  at_rest_ = false;
  linear_velocity_.setZero();
  angular_velocity_.setZero();
  deviation_sse_ = 0.0;
  deviation_samples_ = 0;
  map_index_.clear();
  map_keys_.clear();
  map_counts_.clear();
  map_points_data_.clear();
  map_points_ = 0;
  last_prune_origin_.setZero();
}

Eigen::Isometry3d LidarOdometry::registerFrame(double stamp_s,
                                               const std::vector<Eigen::Vector3f>& points) {
  return registerFrom(stamp_s, [&](auto&& sink) {
    for (const Eigen::Vector3f& p : points) sink(p.x(), p.y(), p.z());
  });
}

void LidarOdometry::beginFrame(Thinning thinning) {
  input_points_ = 0;
  stride_ = thinning == Thinning::kBySource ? 1 : params_.input_stride;
  // Points phase, phase + stride, ... are read (sourcePhase: a different set every frame).
  stride_count_ = stride_ - 1 - static_cast<int>(thinning == Thinning::kBySource ? 0 : sourcePhase());
  frame_voxels_.clear();
  frame_count_ = 0;
}

namespace {

// A measured wheel speed below this is wheels that stand (an encoder's resolution) [m/s].
constexpr double kWheelsStandMps = 0.01;

// `n` of `from` (n <= size), evenly over the scan order so that every direction keeps points,
// appended to `to`.
void appendThinned(const std::vector<Eigen::Vector3f>& from, std::size_t n,
                   std::vector<Eigen::Vector3f>& to) {
  for (std::size_t i = 0; i < n; ++i) to.push_back(from[i * from.size() / n]);
}
}  // namespace

void LidarOdometry::selectRegistrationPoints() {
  registration_voxels_.clear();
  const float inv = static_cast<float>(1.0 / (params_.voxel_m * params_.registration_voxel_factor));
  const float ground_z = static_cast<float>(params_.ground_max_z_m);
  // Without a branch on the point, as in addPoint: written to both, counted in one.
  candidates_.resize(frame_.size() + 1);
  ground_.resize(frame_.size() + 1);
  std::size_t n_candidates = 0, n_low = 0;
  for (const Eigen::Vector3f& p : frame_) {
    const bool first = registration_voxels_.insert(voxelOf(p.x(), p.y(), p.z(), inv));
    const bool low = p.z() < ground_z;
    candidates_[n_candidates] = p;
    ground_[n_low] = p;
    n_candidates += first & !low;
    n_low += first & low;
  }
  candidates_.resize(n_candidates);
  ground_.resize(n_low);
  const std::size_t cap = static_cast<std::size_t>(params_.max_registration_points);
  const std::size_t ground_cap = static_cast<std::size_t>(params_.ground_share * cap);
  // The ground fills its share, and what the rest of the scene leaves free.
  const std::size_t n_ground =
      std::min(ground_.size(), std::max(ground_cap, cap - std::min(cap, candidates_.size())));
  const std::size_t n_rest = std::min(candidates_.size(), cap - n_ground);
  registration_.clear();
  appendThinned(candidates_, n_rest, registration_);
  appendThinned(ground_, n_ground, registration_);
}

void LidarOdometry::countSeed(bool seeded) {
  stats_.speed_seeded = seeded;
  counters_.speed_seeded += seeded ? 1 : 0;
}

void LidarOdometry::seedTwist(const MeasuredTwist& twist) {
  has_seed_ = std::isfinite(twist.forward_mps);
  seed_ = twist;
}

Eigen::Isometry3d LidarOdometry::predict(double dt, bool with_seed) const {
  if (dt <= 0.0) return pose_;
  Eigen::Isometry3d delta = Eigen::Isometry3d::Identity();
  if (last_delta_dt_ > 0.0) {  // constant velocity: the last motion scaled to this dt
    const double s = dt / last_delta_dt_;
    const Eigen::AngleAxisd rotation(last_delta_.rotation());
    delta.linear() = Eigen::AngleAxisd(rotation.angle() * s, rotation.axis()).toRotationMatrix();
    delta.translation() = last_delta_.translation() * s;
  }
  if (with_seed && has_seed_) {
    const auto mean = [&](double now, double before) {
      return has_last_seed_ && std::isfinite(before) ? 0.5 * (now + before) : now;
    };
    if (std::isfinite(seed_.yaw_rate_rad_s))  // the measured turn, about the vehicle's z
      delta.linear() = Eigen::AngleAxisd(mean(seed_.yaw_rate_rad_s, last_seed_.yaw_rate_rad_s) * dt,
                                         Eigen::Vector3d::UnitZ()).toRotationMatrix();
    // The measured speed along the chord of the turn.
    const Eigen::AngleAxisd turn(delta.rotation());
    delta.translation() = Eigen::AngleAxisd(0.5 * turn.angle(), turn.axis()) *
                          Eigen::Vector3d(mean(seed_.forward_mps, last_seed_.forward_mps) * dt, 0.0, 0.0);
  }
  return pose_ * delta;
}

double LidarOdometry::adaptiveThreshold() const {
  return deviation_samples_ == 0 ? params_.initial_threshold_m
                                 : std::sqrt(deviation_sse_ / deviation_samples_);
}

std::uint64_t LidarOdometry::blockCorner(const Eigen::Vector3f& s, std::int32_t base[3]) const {
  for (int k = 0; k < 3; ++k) {
    const float v = s[k] * inv_map_voxel_;
    const std::int32_t f = floorToInt(v);
    base[k] = f - (v - static_cast<float>(f) < 0.5f ? 1 : 0);
  }
  return packKey(base[0], base[1], base[2]);
}

void LidarOdometry::findBlock(const std::int32_t base[3], std::int32_t voxels[8]) const {
  for (int c = 0; c < 8; ++c)
    voxels[c] = map_index_.find(packKey(base[0] + (c & 1), base[1] + ((c >> 1) & 1), base[2] + ((c >> 2) & 1)));
}

int nearestPacked(const float* xs, int count, std::size_t stride, const Eigen::Vector3f& s,
                  float& best) {
  // Eigen's squaredNorm of a 3-vector sums as x^2 + (y^2 + z^2); so does this, so that the match
  // is the same point, bit for bit.
#if defined(__SSE2__)
  const __m128 sx = _mm_set1_ps(s.x()), sy = _mm_set1_ps(s.y()), sz = _mm_set1_ps(s.z());
  __m128 lane_best = _mm_set1_ps(best);
  __m128i lane_index = _mm_set1_epi32(-1), index = _mm_setr_epi32(0, 1, 2, 3);
  const __m128i four = _mm_set1_epi32(4);
  for (int j = 0; j < count; j += 4) {
    const __m128 dx = _mm_sub_ps(_mm_loadu_ps(xs + j), sx);
    const __m128 dy = _mm_sub_ps(_mm_loadu_ps(xs + j + stride), sy);
    const __m128 dz = _mm_sub_ps(_mm_loadu_ps(xs + j + 2 * stride), sz);
    const __m128 d2 = _mm_add_ps(_mm_mul_ps(dx, dx), _mm_add_ps(_mm_mul_ps(dy, dy), _mm_mul_ps(dz, dz)));
    const __m128i nearer = _mm_castps_si128(_mm_cmplt_ps(d2, lane_best));  // strictly: the first
    lane_best = _mm_min_ps(d2, lane_best);
    lane_index = _mm_or_si128(_mm_and_si128(nearer, index), _mm_andnot_si128(nearer, lane_index));
    index = _mm_add_epi32(index, four);
  }
  alignas(16) float lanes[4];
  alignas(16) std::int32_t indices[4];
  _mm_store_ps(lanes, lane_best);
  _mm_store_si128(reinterpret_cast<__m128i*>(indices), lane_index);
  int k = -1;
  for (int l = 0; l < 4; ++l) {  // the least distance; of equal ones, the first point
    if (indices[l] < 0) continue;
    if (k < 0 || lanes[l] < best || (lanes[l] == best && indices[l] < k)) {
      best = lanes[l];
      k = indices[l];
    }
  }
  return k;
#else
  int k = -1;
  for (int j = 0; j < count; ++j) {
    const float dx = xs[j] - s.x(), dy = xs[j + stride] - s.y(),
                dz = xs[j + 2 * stride] - s.z();
    const float d2 = dx * dx + (dy * dy + dz * dz);
    if (d2 < best) {
      best = d2;
      k = j;
    }
  }
  return k;
#endif
}

bool LidarOdometry::registerScan(const Eigen::Isometry3d& guess, double sigma,
                                 Eigen::Isometry3d& result, const Eigen::Vector3d* held) {
  slid_ = false;
  weakly_observed_ = false;
  rest_fit_ = RestFit();
  rest_fit_.prior = guess;
  // Held: the step is solved in the five directions orthogonal to (held, 0): the other horizontal
  // one, up, and the three rotations.
  Eigen::Matrix<double, 6, 5> basis = Eigen::Matrix<double, 6, 5>::Zero();
  if (held) {
    basis.block<3, 1>(0, 0) = Eigen::Vector3d(-held->y(), held->x(), 0.0).normalized();
    basis(2, 1) = 1.0;
    basis.block<3, 3>(3, 2).setIdentity();
  }
  const float max_d2 = static_cast<float>(9.0 * sigma * sigma);  // 3 sigma
  const double kernel = sigma / 3.0;
  const double kernel2 = kernel * kernel;
  const int per_voxel = params_.max_points_per_voxel;
  const bool point_to_plane = params_.point_to_plane;
  const std::size_t n = registration_.size();
  neighbourhoods_.resize(n);
  block_stride_ = 8 * static_cast<std::size_t>(per_voxel);
  block_points_.resize(n * 3 * block_stride_);
  for (Neighbourhood& nb : neighbourhoods_) nb.block = ~0ull;

  Eigen::Matrix3d rotation = guess.rotation();
  Eigen::Vector3d translation = guess.translation();
  Eigen::Matrix<double, 6, 6> hessian = Eigen::Matrix<double, 6, 6>::Zero();
  double weight_sum = 0.0;
  std::size_t matched = 0;
  int iteration = 0;
  while (iteration < params_.max_iterations) {
    ++iteration;
    const Eigen::Matrix3f r = rotation.cast<float>();
    const Eigen::Vector3f t = translation.cast<float>();
    // Normal equations of J = [I, -[a]x] (a = R p, the point about the sensor origin, so that
    // the rotation is about the vehicle, not about a far-away odom origin), accumulated as the
    // few sums they are made of.
    double sw = 0.0, swa2 = 0.0;
    Eigen::Vector3d swa = Eigen::Vector3d::Zero(), swr = Eigen::Vector3d::Zero(),
                    swaxr = Eigen::Vector3d::Zero();
    Eigen::Matrix3d swaa = Eigen::Matrix3d::Zero();
    matched = 0;
    // Point-to-plane matches, summed as J^T w J (lower triangle) and J^T w r.
    Eigen::Matrix<double, 6, 6> plane_hessian = Eigen::Matrix<double, 6, 6>::Zero();
    Eigen::Matrix<double, 6, 1> plane_gradient = Eigen::Matrix<double, 6, 1>::Zero();
    double plane_weight = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
      const Eigen::Vector3f a = r * registration_[i];
      const Eigen::Vector3f s = a + t;
      std::int32_t base[3];
      const std::uint64_t block = blockCorner(s, base);
      Neighbourhood& nb = neighbourhoods_[i];
      if (block != nb.block) {
        nb.block = block;
        findBlock(base, nb.voxels);
        // Its points side by side (x, then y, then z), padded to whole packets with points at
        // infinity: the search over them then has no branch per voxel.
        nb.xs = &block_points_[i * 3 * block_stride_];
        nb.count = 0;
        for (const std::int32_t slot : nb.voxels) {
          if (slot < 0) continue;
          const Eigen::Vector3f* q = &map_points_data_[static_cast<std::size_t>(slot) * per_voxel];
          for (int j = 0, m = map_counts_[slot]; j < m; ++j, ++nb.count) {
            nb.xs[nb.count] = q[j].x();
            nb.xs[nb.count + block_stride_] = q[j].y();
            nb.xs[nb.count + 2 * block_stride_] = q[j].z();
          }
        }
        for (int j = nb.count; j % 4 != 0; ++j)
          nb.xs[j] = nb.xs[j + block_stride_] = nb.xs[j + 2 * block_stride_] =
              std::numeric_limits<float>::infinity();
        nb.planar = point_to_plane && fitPlane(nb.voxels, nb.normal);
      }
      float best = max_d2;
      const int k = nearestPacked(nb.xs, nb.count, block_stride_, s, best);
      if (k < 0) continue;
      const Eigen::Vector3f nearest(nb.xs[k], nb.xs[k + block_stride_], nb.xs[k + 2 * block_stride_]);
      ++matched;
      const Eigen::Vector3d ad = a.cast<double>();
      const Eigen::Vector3d res = (s - nearest).cast<double>();
      if (nb.planar) {  // r = n.(s - q), J = [n, a x n]
        const Eigen::Vector3d nd = nb.normal.cast<double>();
        const double r = nd.dot(res);
        const double w = kernel2 / ((kernel + r * r) * (kernel + r * r));
        Eigen::Matrix<double, 6, 1> j;
        j << nd, ad.cross(nd);
        plane_hessian.selfadjointView<Eigen::Lower>().rankUpdate(j, w);
        plane_gradient += (w * r) * j;
        plane_weight += w;
        continue;
      }
      const double w = kernel2 / ((kernel + best) * (kernel + best));  // Geman-McClure
      sw += w;
      swa += w * ad;
      swa2 += w * ad.squaredNorm();
      swaa += w * ad * ad.transpose();
      swr += w * res;
      swaxr += w * ad.cross(res);
    }
    if (matched < 6) break;
    Eigen::Matrix3d skew;
    skew << 0, -swa.z(), swa.y(), swa.z(), 0, -swa.x(), -swa.y(), swa.x(), 0;
    hessian.topLeftCorner<3, 3>() = sw * Eigen::Matrix3d::Identity();
    hessian.topRightCorner<3, 3>() = -skew;
    hessian.bottomLeftCorner<3, 3>() = skew;
    hessian.bottomRightCorner<3, 3>() = swa2 * Eigen::Matrix3d::Identity() - swaa;
    weight_sum = sw;
    Eigen::Matrix<double, 6, 1> gradient;
    gradient << swr, swaxr;
    if (plane_weight > 0.0) {
      const Eigen::Matrix<double, 6, 6> full = plane_hessian.selfadjointView<Eigen::Lower>();
      hessian += full;
      gradient += plane_gradient;
      weight_sum += plane_weight;
    }
    const Eigen::Matrix<double, 6, 1> dx =
        held ? Eigen::Matrix<double, 6, 1>(
                   basis * (basis.transpose() * hessian * basis).ldlt().solve(-basis.transpose() * gradient))
             : Eigen::Matrix<double, 6, 1>(hessian.ldlt().solve(-gradient));
    if (!dx.allFinite()) break;
    translation += dx.head<3>();
    const double angle = dx.tail<3>().norm();
    if (angle > 0.0)
      rotation = Eigen::AngleAxisd(angle, dx.tail<3>() / angle).toRotationMatrix() * rotation;
    if (dx.norm() < params_.convergence_eps) break;
  }
  stats_.iterations = iteration;
  stats_.correspondences = matched;
  result.setIdentity();
  result.linear() = Eigen::Quaterniond(rotation).normalized().toRotationMatrix();
  result.translation() = translation;
  if (matched >= 6)
    stats_.horizontal_observability =
        horizontalObservability(result, max_d2, &weakest_, &across_observability_, &rest_fit_);
  // Degenerate: too few matches, a rotation the points cannot observe (all on one line: the
  // smallest eigenvalue of the information, per unit weight, near zero), a horizontal direction
  // no matched surface faces (horizontal_observability), or a correction of the prior no real
  // vehicle makes in one frame.
  if (matched < 6 || static_cast<double>(matched) < params_.min_correspondence_ratio * n)
    return false;
  if (held) {  // the five directions solved
    const Eigen::Matrix<double, 5, 5> reduced = basis.transpose() * hessian * basis;
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 5, 5>> eig(reduced, Eigen::EigenvaluesOnly);
    if (!(eig.eigenvalues()(0) > 1e-3 * weight_sum)) return false;
  } else {
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 6, 6>> eig(hessian,
                                                                         Eigen::EigenvaluesOnly);
    if (!(eig.eigenvalues()(0) > 1e-3 * weight_sum)) return false;
    // A horizontal direction the matched surfaces do not constrain: ICP slid along it.
    if (stats_.horizontal_observability < params_.min_horizontal_observability) {
      slid_ = across_observability_ >= params_.min_horizontal_observability;
      weakly_observed_ = result.matrix().allFinite() &&
                         (result.translation() - guess.translation()).norm() <= params_.max_correction_m;
      return false;
    }
  }
  if ((result.translation() - guess.translation()).norm() > params_.max_correction_m) return false;
  return result.matrix().allFinite();
}

bool LidarOdometry::fitPlane(const std::int32_t voxels[8], Eigen::Vector3f& normal) const {
  const int per_voxel = params_.max_points_per_voxel;
  // Moments about one of the points: odom coordinates (tens of metres) would cancel in float.
  Eigen::Vector3f sum = Eigen::Vector3f::Zero(), origin = Eigen::Vector3f::Zero();
  Eigen::Matrix3f outer = Eigen::Matrix3f::Zero();
  int count = 0;
  for (int c = 0; c < 8; ++c) {
    const std::int32_t slot = voxels[c];
    if (slot < 0) continue;
    const Eigen::Vector3f* q = &map_points_data_[static_cast<std::size_t>(slot) * per_voxel];
    for (int j = 0, m = map_counts_[slot]; j < m; ++j) {
      if (count == 0) origin = q[j];
      const Eigen::Vector3f d = q[j] - origin;
      sum += d;
      outer += d * d.transpose();
      ++count;
    }
  }
  if (count < 5) return false;
  const Eigen::Vector3f mean = sum / static_cast<float>(count);
  const Eigen::Matrix3f cov = outer / static_cast<float>(count) - mean * mean.transpose();
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3f> eig;
  eig.computeDirect(cov);
  const Eigen::Vector3f& l = eig.eigenvalues();  // ascending
  // A line, a blob or a corner (or points all at one place: no plane): point-to-point.
  if (!(l(1) > 1e-6f && l(0) <= 0.1f * l(1))) return false;
  normal = eig.eigenvectors().col(0);
  return true;
}

double LidarOdometry::horizontalObservability(const Eigen::Isometry3d& pose, float max_d2,
                                              Eigen::Vector3d* weakest, double* across,
                                              RestFit* rest) const {
  const Eigen::Matrix3f r = pose.rotation().cast<float>();
  const Eigen::Vector3f t = pose.translation().cast<float>();
  // The two alternatives of the at-rest test: the last pose (no motion) and the prior.
  const Eigen::Matrix3f r_still = pose_.rotation().cast<float>();
  const Eigen::Vector3f t_still = pose_.translation().cast<float>();
  const Eigen::Matrix3f r_prior = rest ? rest->prior.rotation().cast<float>() : r;
  const Eigen::Vector3f t_prior = rest ? rest->prior.translation().cast<float>() : t;
  const int per_voxel = params_.max_points_per_voxel;
  Eigen::Matrix3d info = Eigen::Matrix3d::Zero();
  std::size_t used = 0;
  Eigen::Vector3f block_points[8 * kMaxPointsPerVoxel];
  for (std::size_t i = 0; i < registration_.size(); ++i) {
    const Eigen::Vector3f s = r * registration_[i] + t;
    // The voxels registerScan searches around s: its match and the neighbours the plane is fitted
    // to. The last iteration's, unless its step moved s into another block.
    std::int32_t base[3], found[8];
    const std::int32_t* voxels = neighbourhoods_[i].voxels;
    if (blockCorner(s, base) != neighbourhoods_[i].block) {
      findBlock(base, found);
      voxels = found;
    }
    int count = 0;
    float best = max_d2;
    for (int c = 0; c < 8; ++c) {
      const std::int32_t slot = voxels[c];
      if (slot < 0) continue;
      const Eigen::Vector3f* q = &map_points_data_[static_cast<std::size_t>(slot) * per_voxel];
      for (int j = 0, m = map_counts_[slot]; j < m; ++j) {
        best = std::min(best, (q[j] - s).squaredNorm());
        block_points[count++] = q[j];
      }
    }
    if (best >= max_d2 || count < 5) continue;  // unmatched, or too few points for a plane
    Eigen::Vector3f mean = Eigen::Vector3f::Zero();
    for (int j = 0; j < count; ++j) mean += block_points[j];
    mean /= static_cast<float>(count);
    // The six sums as scalars: Eigen's `cov += d * d.transpose()` goes through a temporary on the
    // stack whose packed reload stalls on the scalar stores (two thirds of this function's time).
    float xx = 0.0f, xy = 0.0f, xz = 0.0f, yy = 0.0f, yz = 0.0f, zz = 0.0f;
    for (int j = 0; j < count; ++j) {
      const Eigen::Vector3f d = block_points[j] - mean;
      xx += d.x() * d.x();
      xy += d.x() * d.y();
      xz += d.x() * d.z();
      yy += d.y() * d.y();
      yz += d.y() * d.z();
      zz += d.z() * d.z();
    }
    Eigen::Matrix3f cov;
    cov << xx, xy, xz, xy, yy, yz, xz, yz, zz;
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3f> eig;
    eig.computeDirect(cov);
    const Eigen::Vector3d n = eig.eigenvectors().col(0).cast<double>();  // smallest spread: normal
    info += n * n.transpose();
    ++used;
    // At rest: on a plane (as fitPlane judges it), the distances along its normal of the point
    // placed at the result, at the last pose and at the prior. The same planes for all three, so
    // the sums differ only by the motion they assume.
    const Eigen::Vector3f& l = eig.eigenvalues();
    if (rest && l(1) > 1e-6f && l(0) <= 0.1f * l(1)) {
      const Eigen::Vector3f nf = eig.eigenvectors().col(0);
      const double d_result = nf.dot(s - mean);
      const double d_still = nf.dot(r_still * registration_[i] + t_still - mean);
      const double d_prior = nf.dot(r_prior * registration_[i] + t_prior - mean);
      rest->sse_result += d_result * d_result;
      rest->sse_still += d_still * d_still;
      rest->sse_prior += d_prior * d_prior;
      ++rest->count;
    }
  }
  if (across) *across = 0.0;
  if (used == 0) return 0.0;
  const Eigen::Matrix2d horizontal = info.topLeftCorner<2, 2>() / static_cast<double>(used);
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(horizontal);
  if (weakest) *weakest = Eigen::Vector3d(eig.eigenvectors()(0, 0), eig.eigenvectors()(1, 0), 0.0);
  if (across) *across = eig.eigenvalues()(1);
  return eig.eigenvalues()(0);
}

void LidarOdometry::updateMap(const Eigen::Isometry3d& pose) {
  const Eigen::Matrix3f r = pose.rotation().cast<float>();
  const Eigen::Vector3f t = pose.translation().cast<float>();
  const int per_voxel = params_.max_points_per_voxel;
  std::uint64_t last_key = ~0ull;
  std::int32_t last_slot = -1;
  for (const Eigen::Vector3f& p : frame_) {
    const Eigen::Vector3f q = r * p + t;
    const std::uint64_t key = voxelOf(q.x(), q.y(), q.z(), inv_map_voxel_).key;
    std::int32_t slot = last_slot;
    if (key != last_key) {  // scan order: consecutive points often share a map voxel
      bool inserted;
      slot = map_index_.findOrInsert(key, static_cast<std::int32_t>(map_keys_.size()), inserted);
      if (inserted) {
        map_keys_.push_back(key);
        map_counts_.push_back(0);
        map_points_data_.resize(map_points_data_.size() + per_voxel);
      }
      last_key = key;
      last_slot = slot;
    }
    std::uint8_t& count = map_counts_[slot];
    if (count < per_voxel) {
      map_points_data_[static_cast<std::size_t>(slot) * per_voxel + count++] = q;
      ++map_points_;
    }
  }
}

void LidarOdometry::pruneMap(const Eigen::Vector3d& origin) {
  // Compacting the map and rebuilding its index costs about as much as one frame's insertion:
  // done when the vehicle has moved 5 % of max_range_m, not every frame. Until then voxels at
  // most that much beyond max_range_m stay, which no registration point reaches anyway.
  if ((origin - last_prune_origin_).norm() < 0.05 * params_.max_range_m) return;
  last_prune_origin_ = origin;
  const int per_voxel = params_.max_points_per_voxel;
  const Eigen::Vector3f o = origin.cast<float>();
  const float limit2 = max_range2_;
  std::size_t kept = 0;
  map_points_ = 0;
  map_index_.clear();
  for (std::size_t s = 0; s < map_keys_.size(); ++s) {
    const Eigen::Vector3f* q = &map_points_data_[s * per_voxel];
    if ((q[0] - o).squaredNorm() > limit2) continue;
    if (kept != s) {
      map_keys_[kept] = map_keys_[s];
      map_counts_[kept] = map_counts_[s];
      std::copy(q, q + per_voxel, &map_points_data_[kept * per_voxel]);
    }
    bool inserted;
    map_index_.findOrInsert(map_keys_[kept], static_cast<std::int32_t>(kept), inserted);
    map_points_ += map_counts_[kept];
    ++kept;
  }
  map_keys_.resize(kept);
  map_counts_.resize(kept);
  map_points_data_.resize(kept * per_voxel);
}

std::vector<Eigen::Vector3f> LidarOdometry::mapCloud() const {
  std::vector<Eigen::Vector3f> out;
  out.reserve(map_points_);
  const int per_voxel = params_.max_points_per_voxel;
  for (std::size_t s = 0; s < map_keys_.size(); ++s)
    for (int j = 0; j < map_counts_[s]; ++j) out.push_back(map_points_data_[s * per_voxel + j]);
  return out;
}

LidarOdometry::RestTest LidarOdometry::testRest() {
  // Nested least squares: "no motion" is the six-parameter motion fixed at zero. Its extra sum of
  // squares over the best fit, per parameter, against the best fit's residual variance is
  // F(6, n - 6) distributed when the vehicle stands; the scatter of the residuals (sensor noise,
  // the map's planes) sets the scale, so no tolerance is tuned. The prior is judged the same way.
  constexpr int kDof = 6;
  RestTest test;
  const RestFit& f = rest_fit_;
  if (f.count < static_cast<std::size_t>(params_.min_points)) return test;
  const double best = std::min({f.sse_result, f.sse_still, f.sse_prior});
  const double variance =
      std::max(best / static_cast<double>(f.count - kDof), std::numeric_limits<double>::min());
  // The 99.9 % point of F(6, n - 6), once per n (an inverse incomplete beta function).
  if (rest_critical_.size() <= f.count)
    rest_critical_.resize(f.count + 1, std::numeric_limits<double>::quiet_NaN());
  double& critical = rest_critical_[f.count];
  if (std::isnan(critical))
    critical = boost::math::quantile(
        boost::math::fisher_f_distribution<double>(kDof, static_cast<double>(f.count - kDof)), 0.999);
  const auto statistic = [&](double sse) { return (sse - best) / (kDof * variance); };
  stats_.rest_residuals = f.count;
  stats_.rest_f = statistic(f.sse_still);
  test.still_fits = stats_.rest_f <= critical;
  test.prior_ruled_out = statistic(f.sse_prior) > critical;
  return test;
}

Eigen::Isometry3d LidarOdometry::finishFrame(double stamp_s, double downsample_start_ms) {
  frame_.resize(frame_count_);
  ++counters_.frames;
  stats_ = LidarOdometryStats();
  stats_.input_points = input_points_;
  stats_.frame_points = frame_.size();
  stats_.result = LidarOdometryStats::Result::kFirstFrame;
  // A seed holds for this frame only, whatever happens to it; the next frame's prior averages it
  // with its own.
  struct SeedUse {
    LidarOdometry& o;
    ~SeedUse() {
      o.has_last_seed_ = o.has_seed_;
      o.last_seed_ = o.seed_;
      o.has_seed_ = false;
    }
  } seed_use{*this};
  if (initialized_ && stamp_s < last_stamp_s_) {  // bag loop, restarted driver: start over
    reset();
    ++counters_.resets;
    stats_.result = LidarOdometryStats::Result::kReset;
  }
  const double dt = initialized_ ? stamp_s - last_stamp_s_ : 0.0;
  if (dt > params_.max_dt_s) {  // the last motion says nothing about this one
    ++counters_.gaps;
    last_delta_dt_ = 0.0;
    has_last_seed_ = false;
  }
  selectRegistrationPoints();
  stats_.registration_points = registration_.size();
  const double t1 = odometryNowMs();
  stats_.downsample_ms = t1 - downsample_start_ms;
  stats_.threshold_m = adaptiveThreshold();
  const bool enough = registration_.size() >= static_cast<std::size_t>(params_.min_points);

  if (!initialized_) {
    if (enough) {
      updateMap(pose_);
      initialized_ = true;
      last_stamp_s_ = stamp_s;
      last_prune_origin_ = pose_.translation();
    } else {
      ++counters_.extrapolated;
      stats_.result = LidarOdometryStats::Result::kExtrapolated;
    }
    stats_.map_points = map_points_;
    stats_.map_ms = odometryNowMs() - t1;
    return pose_;
  }

  // ICP starts from the constant-velocity prior, and its adaptive threshold measures how far
  // registrations stray from it. Where the scene fixes no motion, the pose is the prior, moved
  // by the measured speed when there is one (a seeded ICP start tightens the threshold: the turn
  // of RecoversAStraightThenTurningPath then falls outside it).
  const Eigen::Isometry3d prediction = predict(dt, false);
  const bool seeded = has_seed_ && dt > 0.0;
  const Eigen::Isometry3d fallback = seeded ? predict(dt, true) : prediction;
  Eigen::Isometry3d estimate = prediction;
  if (!enough || map_points_ == 0) {
    ++counters_.extrapolated;
    stats_.result = LidarOdometryStats::Result::kExtrapolated;
    countSeed(seeded);
    pose_ = fallback;  // velocity and prior unchanged: the next frame continues the motion
    last_stamp_s_ = stamp_s;
    stats_.map_points = map_points_;
    return pose_;
  }
  const bool registered = registerScan(prediction, stats_.threshold_m, estimate);
  // The vehicle at rest: the pose holds, where the scan fits no motion and rules the prior out
  // (or the vehicle stood already: the prior is no motion then). Where the prior fits as well
  // (a slow drive, walls that fit any motion along them) the data do not say it stopped, and the
  // registration or the prior stays. Not where a degenerate frame has a measured twist: the twist
  // says how it moved.
  const RestTest rest = registered || !seeded ? testRest() : RestTest();
  // Wheels that stood at both ends of the frame's interval: at rest, whatever the registration
  // makes of a scene that fixes no motion well (an encoder counts no ticks while they stand).
  const bool wheels_stand = seeded && has_last_seed_ &&
                            std::abs(seed_.forward_mps) < kWheelsStandMps &&
                            std::abs(last_seed_.forward_mps) < kWheelsStandMps;
  const bool at_rest = wheels_stand || (rest.still_fits && (at_rest_ || rest.prior_ruled_out));
  // A frame degenerate only for its weak horizontal direction whose prior carries a motion that
  // the scan rules out (the vehicle braked, or the prior came from a poor registration) takes the
  // registration's fit instead of carrying the prior on. A prior of no motion stays: the rest
  // test judged it, and what rules it out in a weakly observed scene may be a moving object.
  const Eigen::Isometry3d prior_motion = pose_.inverse() * prediction;
  const bool prior_moves = prior_motion.translation().norm() > 1e-6 ||
                           Eigen::AngleAxisd(prior_motion.rotation()).angle() > 1e-6;  // rounding
  const bool fit_over_prior = !registered && !at_rest && !seeded && weakly_observed_ &&
                              prior_moves && rest.prior_ruled_out;
  at_rest_ = at_rest;
  if (at_rest) {
    ++counters_.at_rest;
    stats_.result = LidarOdometryStats::Result::kAtRest;
    estimate = pose_;
  } else if (registered || fit_over_prior) {
    ++counters_.registered;
    stats_.result = LidarOdometryStats::Result::kRegistered;
    const Eigen::Isometry3d deviation = prediction.inverse() * estimate;
    const double theta = Eigen::AngleAxisd(deviation.rotation()).angle();
    const double error =
        deviation.translation().norm() + 2.0 * params_.max_range_m * std::sin(0.5 * theta);
    if (error > params_.min_motion_m) {
      deviation_sse_ += error * error;
      ++deviation_samples_;
    }
  } else {
    ++counters_.degenerate;
    stats_.result = LidarOdometryStats::Result::kDegenerate;
    countSeed(seeded);
    // Slid along one direction only, and no gyro: the other five from the scene (the turn from
    // the walls), that one from the measured speed. With a gyro its yaw rate is kept: ICP's yaw on
    // such a scene is the noisier (the suite's false alarms 155 -> 176 with it, docs/lidar_odometry.md).
    const Eigen::Vector3d along = weakest_;
    if (seeded && slid_ && !std::isfinite(seed_.yaw_rate_rad_s) &&
        registerScan(fallback, stats_.threshold_m, estimate, &along)) {
      ++counters_.held;
      stats_.result = LidarOdometryStats::Result::kHeld;
    } else {
      estimate = fallback;
    }
  }
  const double t2 = odometryNowMs();
  stats_.register_ms = t2 - t1;

  if (dt > 0.0 && at_rest) {  // exactly no motion (pose_^-1 pose_ is identity only to rounding)
    linear_velocity_.setZero();
    angular_velocity_.setZero();
    last_delta_.setIdentity();
    last_delta_dt_ = dt;
  } else if (dt > 0.0) {
    const Eigen::Isometry3d delta = pose_.inverse() * estimate;
    const Eigen::AngleAxisd turn(delta.rotation());
    linear_velocity_ = delta.translation() / dt;
    angular_velocity_ = turn.axis() * (turn.angle() / dt);
    last_delta_ = delta;
    last_delta_dt_ = dt;
  }
  pose_ = estimate;
  last_stamp_s_ = stamp_s;
  // At rest the scan sees what the map holds from where it stands; placed again at a held pose
  // (off by the last registrations' error) it would only blur the map the next frames match.
  if (!at_rest) updateMap(pose_);
  pruneMap(pose_.translation());
  stats_.map_points = map_points_;
  stats_.map_ms = odometryNowMs() - t2;
  return pose_;
}

}  // namespace icanc
