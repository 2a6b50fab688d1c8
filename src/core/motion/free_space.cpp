#include "icanc/core/motion/free_space.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif
// Eight lanes at a time where the CPU has AVX2, chosen at run time (the build targets x86-64).
#if defined(__GNUC__) && defined(__x86_64__)
#include <immintrin.h>
#define ICANC_FREE_SPACE_AVX2 1
#else
#define ICANC_FREE_SPACE_AVX2 0
#endif

namespace icanc {

namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr float kPi = static_cast<float>(M_PI);
constexpr float kDeg = kPi / 180.0f;
// The rows span this elevation band around the sensor: every spinning LiDAR's beams [deg].
constexpr float kElevationMinDeg = -40.0f;
constexpr float kElevationMaxDeg = 40.0f;

// atan2 to about 1e-5 rad with a polynomial (no library call per return).
inline float fastAtan2(float y, float x) {
  const float ax = std::abs(x), ay = std::abs(y);
  const float mx = std::max(ax, ay), mn = std::min(ax, ay);
  const float a = mn / (mx + 1e-30f);
  const float s = a * a;
  float r = ((-0.0464964749f * s + 0.15931422f) * s - 0.327622764f) * s * a + a;
  if (ay > ax) r = 0.5f * kPi - r;
  if (x < 0.0f) r = kPi - r;
  return y < 0.0f ? -r : r;
}

// The range image's rows and columns.
struct PixelGrid {
  float el_min, inv_el, inv_az;
  int rows, cols;
};

// The pixel of a direction from the sensor (-1 outside the rows) and its range.
inline std::int32_t pixelOne(const PixelGrid& g, float dx, float dy, float dz, float* range) {
  const float horizontal2 = dx * dx + dy * dy;
  const float horizontal = std::sqrt(horizontal2);
  *range = std::sqrt(horizontal2 + dz * dz);
  const int row = static_cast<int>((fastAtan2(dz, horizontal) - g.el_min) * g.inv_el);
  if (row < 0 || row >= g.rows) return -1;
  int col = static_cast<int>((fastAtan2(dy, dx) + kPi) * g.inv_az);
  if (col >= g.cols) col -= g.cols;
  return row * g.cols + col;
}

#if defined(__SSE2__)
// fastAtan2 on four lanes, operation for operation (IEEE single precision each: the same bits).
inline __m128 fastAtan2(__m128 y, __m128 x) {
  const __m128 sign = _mm_set1_ps(-0.0f);
  const __m128 ax = _mm_andnot_ps(sign, x), ay = _mm_andnot_ps(sign, y);
  const __m128 mx = _mm_max_ps(ay, ax);  // std::max(ax, ay): ax < ay ? ay : ax
  const __m128 mn = _mm_min_ps(ay, ax);  // std::min(ax, ay): ay < ax ? ay : ax
  const __m128 a = _mm_div_ps(mn, _mm_add_ps(mx, _mm_set1_ps(1e-30f)));
  const __m128 s = _mm_mul_ps(a, a);
  __m128 r = _mm_add_ps(_mm_mul_ps(_mm_set1_ps(-0.0464964749f), s), _mm_set1_ps(0.15931422f));
  r = _mm_sub_ps(_mm_mul_ps(r, s), _mm_set1_ps(0.327622764f));
  r = _mm_add_ps(_mm_mul_ps(_mm_mul_ps(r, s), a), a);
  __m128 m = _mm_cmpgt_ps(ay, ax);
  r = _mm_or_ps(_mm_and_ps(m, _mm_sub_ps(_mm_set1_ps(0.5f * kPi), r)), _mm_andnot_ps(m, r));
  m = _mm_cmplt_ps(x, _mm_setzero_ps());
  r = _mm_or_ps(_mm_and_ps(m, _mm_sub_ps(_mm_set1_ps(kPi), r)), _mm_andnot_ps(m, r));
  return _mm_xor_ps(r, _mm_and_ps(_mm_cmplt_ps(y, _mm_setzero_ps()), sign));
}

// pixelOne on four directions at a time, of the first n - n % 4; returns how many were done.
std::size_t pixelsSse2(const PixelGrid& g, const float* x, const float* y, const float* z,
                       float ox, float oy, float oz, std::size_t n, std::int32_t* pixel,
                       float* range) {
  const __m128 vox = _mm_set1_ps(ox), voy = _mm_set1_ps(oy), voz = _mm_set1_ps(oz);
  const __m128 el_min = _mm_set1_ps(g.el_min), inv_el = _mm_set1_ps(g.inv_el);
  const __m128 pi = _mm_set1_ps(kPi), inv_az = _mm_set1_ps(g.inv_az);
  const __m128i rows = _mm_set1_epi32(g.rows), cols = _mm_set1_epi32(g.cols);
  const __m128 cols_f = _mm_set1_ps(static_cast<float>(g.cols));
  std::size_t i = 0;
  for (; i + 4 <= n; i += 4) {
    const __m128 dx = _mm_sub_ps(_mm_loadu_ps(x + i), vox);
    const __m128 dy = _mm_sub_ps(_mm_loadu_ps(y + i), voy);
    const __m128 dz = _mm_sub_ps(_mm_loadu_ps(z + i), voz);
    const __m128 horizontal2 = _mm_add_ps(_mm_mul_ps(dx, dx), _mm_mul_ps(dy, dy));
    const __m128 horizontal = _mm_sqrt_ps(horizontal2);
    _mm_storeu_ps(range + i, _mm_sqrt_ps(_mm_add_ps(horizontal2, _mm_mul_ps(dz, dz))));
    const __m128i row =
        _mm_cvttps_epi32(_mm_mul_ps(_mm_sub_ps(fastAtan2(dz, horizontal), el_min), inv_el));
    __m128i col = _mm_cvttps_epi32(_mm_mul_ps(_mm_add_ps(fastAtan2(dy, dx), pi), inv_az));
    col = _mm_sub_epi32(col, _mm_andnot_si128(_mm_cmplt_epi32(col, cols), cols));
    const __m128i valid =
        _mm_andnot_si128(_mm_cmplt_epi32(row, _mm_setzero_si128()), _mm_cmplt_epi32(row, rows));
    // row * cols + col is below 2^24 for valid rows: exact in float.
    const __m128i at = _mm_cvttps_epi32(
        _mm_add_ps(_mm_mul_ps(_mm_cvtepi32_ps(row), cols_f), _mm_cvtepi32_ps(col)));
    const __m128i none = _mm_andnot_si128(valid, _mm_set1_epi32(-1));
    _mm_storeu_si128(reinterpret_cast<__m128i*>(pixel + i),
                     _mm_or_si128(_mm_and_si128(valid, at), none));
  }
  return i;
}
#endif

#if ICANC_FREE_SPACE_AVX2
// The same on eight lanes where the CPU has AVX2 (no FMA: each operation rounds as above).
__attribute__((target("avx2"))) inline __m256 fastAtan2Avx2(__m256 y, __m256 x) {
  const __m256 sign = _mm256_set1_ps(-0.0f);
  const __m256 ax = _mm256_andnot_ps(sign, x), ay = _mm256_andnot_ps(sign, y);
  const __m256 mx = _mm256_max_ps(ay, ax);
  const __m256 mn = _mm256_min_ps(ay, ax);
  const __m256 a = _mm256_div_ps(mn, _mm256_add_ps(mx, _mm256_set1_ps(1e-30f)));
  const __m256 s = _mm256_mul_ps(a, a);
  __m256 r = _mm256_add_ps(_mm256_mul_ps(_mm256_set1_ps(-0.0464964749f), s),
                           _mm256_set1_ps(0.15931422f));
  r = _mm256_sub_ps(_mm256_mul_ps(r, s), _mm256_set1_ps(0.327622764f));
  r = _mm256_add_ps(_mm256_mul_ps(_mm256_mul_ps(r, s), a), a);
  r = _mm256_blendv_ps(r, _mm256_sub_ps(_mm256_set1_ps(0.5f * kPi), r),
                       _mm256_cmp_ps(ay, ax, _CMP_GT_OQ));
  r = _mm256_blendv_ps(r, _mm256_sub_ps(_mm256_set1_ps(kPi), r),
                       _mm256_cmp_ps(x, _mm256_setzero_ps(), _CMP_LT_OQ));
  return _mm256_xor_ps(r, _mm256_and_ps(_mm256_cmp_ps(y, _mm256_setzero_ps(), _CMP_LT_OQ), sign));
}

__attribute__((target("avx2"))) std::size_t pixelsAvx2(const PixelGrid& g, const float* x,
                                                       const float* y, const float* z, float ox,
                                                       float oy, float oz, std::size_t n,
                                                       std::int32_t* pixel, float* range) {
  const __m256 vox = _mm256_set1_ps(ox), voy = _mm256_set1_ps(oy), voz = _mm256_set1_ps(oz);
  const __m256 el_min = _mm256_set1_ps(g.el_min), inv_el = _mm256_set1_ps(g.inv_el);
  const __m256 pi = _mm256_set1_ps(kPi), inv_az = _mm256_set1_ps(g.inv_az);
  const __m256i rows = _mm256_set1_epi32(g.rows), cols = _mm256_set1_epi32(g.cols);
  const __m256i cols_less = _mm256_set1_epi32(g.cols - 1), none = _mm256_set1_epi32(-1);
  std::size_t i = 0;
  for (; i + 8 <= n; i += 8) {
    const __m256 dx = _mm256_sub_ps(_mm256_loadu_ps(x + i), vox);
    const __m256 dy = _mm256_sub_ps(_mm256_loadu_ps(y + i), voy);
    const __m256 dz = _mm256_sub_ps(_mm256_loadu_ps(z + i), voz);
    const __m256 horizontal2 = _mm256_add_ps(_mm256_mul_ps(dx, dx), _mm256_mul_ps(dy, dy));
    const __m256 horizontal = _mm256_sqrt_ps(horizontal2);
    _mm256_storeu_ps(range + i,
                     _mm256_sqrt_ps(_mm256_add_ps(horizontal2, _mm256_mul_ps(dz, dz))));
    const __m256i row = _mm256_cvttps_epi32(
        _mm256_mul_ps(_mm256_sub_ps(fastAtan2Avx2(dz, horizontal), el_min), inv_el));
    __m256i col =
        _mm256_cvttps_epi32(_mm256_mul_ps(_mm256_add_ps(fastAtan2Avx2(dy, dx), pi), inv_az));
    col = _mm256_sub_epi32(col, _mm256_and_si256(_mm256_cmpgt_epi32(col, cols_less), cols));
    const __m256i valid = _mm256_andnot_si256(
        _mm256_or_si256(_mm256_cmpgt_epi32(_mm256_setzero_si256(), row),
                        _mm256_cmpgt_epi32(row, _mm256_sub_epi32(rows, _mm256_set1_epi32(1)))),
        none);
    const __m256i at = _mm256_add_epi32(_mm256_mullo_epi32(row, cols), col);
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(pixel + i),
                        _mm256_blendv_epi8(none, at, valid));
  }
  return i;
}
#endif

}  // namespace

const char* toString(MotionState state) {
  switch (state) {
    case MotionState::kUnknown: return "unknown";
    case MotionState::kStatic: return "static";
    case MotionState::kMoving: return "moving";
  }
  return "invalid";
}

MotionState MotionEvidence::state() const {
  // A few free points on a still thing are the sampling's (a thin pole between two past rays);
  // a moving walker's leading edge is a sixth of its points or more.
  if (free >= 3 && free * 100 >= 15 * tested) return MotionState::kMoving;
  if (tested >= 3 && seen * 2 >= tested && free * 20 <= tested) return MotionState::kStatic;
  return MotionState::kUnknown;
}

std::string validate(const FreeSpaceParams& params) {
  std::ostringstream why;
  if (!(params.azimuth_step_deg >= 0.05f && params.azimuth_step_deg <= 5.0f))
    why << "free_space.azimuth_step_deg must be in [0.05, 5] (got " << params.azimuth_step_deg << ")";
  else if (!(params.elevation_step_deg >= 0.05f && params.elevation_step_deg <= 10.0f))
    why << "free_space.elevation_step_deg must be in [0.05, 10] (got " << params.elevation_step_deg
        << ")";
  else if (!(params.tolerance_m >= 0.02f && params.tolerance_m <= 5.0f))
    why << "free_space.tolerance_m must be in [0.02, 5] m (got " << params.tolerance_m << ")";
  return why.str();
}

FreeSpaceMotion::FreeSpaceMotion(const FreeSpaceParams& params) { setParams(params); }

void FreeSpaceMotion::setParams(const FreeSpaceParams& params) {
  const bool same = params.azimuth_step_deg == params_.azimuth_step_deg &&
                    params.elevation_step_deg == params_.elevation_step_deg && cols_ > 0;
  params_ = params;
  if (!same) layout();
}

void FreeSpaceMotion::layout() {
  cols_ = static_cast<int>(std::ceil(360.0f / params_.azimuth_step_deg));
  rows_ = static_cast<int>(std::ceil((kElevationMaxDeg - kElevationMinDeg) / params_.elevation_step_deg));
  inv_az_ = cols_ / (2.0f * kPi);
  inv_el_ = 1.0f / (params_.elevation_step_deg * kDeg);
  el_min_ = kElevationMinDeg * kDeg;
  pixel_rad_ = params_.azimuth_step_deg * kDeg;
  // Each row's elevations, grown by more than fastAtan2's error and the rounding (row 0 also holds
  // what truncates to it from below): its sines and its cosines' bounds.
  row_bands_.resize(rows_);
  const double step = params_.elevation_step_deg * M_PI / 180.0;
  const double bottom = kElevationMinDeg * M_PI / 180.0;
  constexpr double kBandMargin = 5e-4;  // [rad]
  for (int r = 0; r < rows_; ++r) {
    const double lo = bottom + (r == 0 ? -1 : r) * step - kBandMargin;
    const double hi = bottom + (r + 1) * step + kBandMargin;
    RowBand& band = row_bands_[r];
    band.sin_lo = std::sin(lo);
    band.sin_hi = std::sin(hi);
    band.cos_min = std::min(std::cos(lo), std::cos(hi));
    band.cos_max = lo <= 0.0 && hi >= 0.0 ? 1.0 : std::max(std::cos(lo), std::cos(hi));
  }
  // One more pixel past the rows: where returns outside them go (never read).
  point_of_.assign(static_cast<std::size_t>(cols_) * rows_ + 1, -1);
  past_.clear();
  spare_.clear();
  current_ = Image();
  current_.range.assign(point_of_.size(), kInf);
}

void FreeSpaceMotion::grow() {
  const std::size_t size = std::max<std::size_t>(4096, 2 * xs_.size());
  xs_.resize(size);
  ys_.resize(size);
  zs_.resize(size);
}

void FreeSpaceMotion::reset() {
  while (!past_.empty()) {
    spare_.push_back(std::move(past_.front()));
    past_.pop_front();
  }
}

FreeSpaceMotion::Image& FreeSpaceMotion::takeImage() {
  // current_ was handed to past_ by endFrame (or never filled): a clean buffer for this frame.
  if (current_.range.size() != point_of_.size()) {
    if (!spare_.empty() && spare_.back().range.size() == point_of_.size()) {
      current_ = std::move(spare_.back());
      spare_.pop_back();
    } else {
      current_ = Image();
      current_.range.assign(point_of_.size(), kInf);
    }
  }
  if (current_.written_lo <= current_.written_hi) {
    std::fill(current_.range.begin() + current_.written_lo,
              current_.range.begin() + current_.written_hi + 1, kInf);
  }
  current_.range.back() = kInf;  // the spare pixel
  current_.written_lo = std::numeric_limits<std::int32_t>::max();
  current_.written_hi = -1;
  return current_;
}

void FreeSpaceMotion::beginFrame(double stamp_s, const Eigen::Isometry3d& motion,
                                 const Eigen::Vector3f& sensor) {
  if (!past_.empty() && stamp_s < past_.back().stamp_s) reset();  // a replay restarted
  const Eigen::Isometry3f back = motion.inverse().cast<float>();  // now -> previous frame
  for (Image& image : past_) image.to_image = image.to_image * back;
  while (!past_.empty() && stamp_s - past_.front().stamp_s > kMaxAgeS + 1e-3) {
    spare_.push_back(std::move(past_.front()));
    past_.pop_front();
  }
  stamp_s_ = stamp_s;
  takeImage();
  current_.sensor = sensor;
  current_.stamp_s = stamp_s;
  current_.to_image.setIdentity();
  count_ = 0;
  built_ = false;
}

void FreeSpaceMotion::pixelsOf(const float* x, const float* y, const float* z,
                               const Eigen::Vector3f& origin, std::size_t n, std::int32_t* pixel,
                               float* range) const {
  const PixelGrid grid{el_min_, inv_el_, inv_az_, rows_, cols_};
  const float ox = origin.x(), oy = origin.y(), oz = origin.z();
  std::size_t i = 0;
#if ICANC_FREE_SPACE_AVX2
  static const bool avx2 = __builtin_cpu_supports("avx2");
  if (avx2) i = pixelsAvx2(grid, x, y, z, ox, oy, oz, n, pixel, range);
#endif
#if defined(__SSE2__)
  i += pixelsSse2(grid, x + i, y + i, z + i, ox, oy, oz, n - i, pixel + i, range + i);
  if (i < n) {  // the last one to three, padded (the same operations as the others)
    alignas(16) float px[4] = {ox, ox, ox, ox}, py[4] = {oy, oy, oy, oy}, pz[4] = {oz, oz, oz, oz};
    alignas(16) float d[4];
    alignas(16) std::int32_t p[4];
    const std::size_t left = n - i;
    for (std::size_t k = 0; k < left; ++k) {
      px[k] = x[i + k];
      py[k] = y[i + k];
      pz[k] = z[i + k];
    }
    pixelsSse2(grid, px, py, pz, ox, oy, oz, 4, p, d);
    for (std::size_t k = 0; k < left; ++k) {
      range[i + k] = d[k];
      pixel[i + k] = p[k];
    }
    i = n;
  }
#endif
  for (; i < n; ++i) pixel[i] = pixelOne(grid, x[i] - ox, y[i] - oy, z[i] - oz, range + i);
}

void FreeSpaceMotion::buildCurrent() {
  if (built_) return;
  built_ = true;
  const std::size_t n = count_;
  constexpr std::size_t kBlock = 256;
  std::int32_t pixels[kBlock];
  float ranges[kBlock];
  float* image = current_.range.data();
  std::int32_t* point_of = point_of_.data();
  // Every return is written somewhere, without branches (whether a return is the nearest of its
  // pixel follows no pattern): one outside the rows or at no range into the spare last pixel.
  // The pixels written lie between the least and the greatest pixel of the rows.
  const std::int32_t spare = rows_ * cols_;
  std::uint32_t lo = static_cast<std::uint32_t>(current_.written_lo);  // -1 (none) is the largest
  std::int32_t hi = current_.written_hi;
  for (std::size_t start = 0; start < n; start += kBlock) {
    const std::size_t m = std::min(kBlock, n - start);
    pixelsOf(xs_.data() + start, ys_.data() + start, zs_.data() + start, current_.sensor, m,
             pixels, ranges);
    for (std::size_t k = 0; k < m; ++k) {
      const float range = ranges[k];
      lo = std::min(lo, static_cast<std::uint32_t>(pixels[k]));
      hi = std::max(hi, pixels[k]);
      const std::int32_t pixel = (pixels[k] < 0 || !(range > 0.0f)) ? spare : pixels[k];
      const float nearest = image[pixel];
      image[pixel] = std::min(nearest, range);  // range < nearest ? range : nearest
      const std::int32_t i = static_cast<std::int32_t>(start + k);
      const std::int32_t take = -static_cast<std::int32_t>(range < nearest);  // all ones: this one
      point_of[pixel] = (i & take) | (point_of[pixel] & ~take);
    }
  }
  current_.written_lo = static_cast<std::int32_t>(std::min<std::uint32_t>(lo, spare));
  current_.written_hi = hi;
}

FreeSpaceMotion::PointResult FreeSpaceMotion::test(const Image& past, std::int32_t pixel,
                                                   float d) const {
  if (pixel < 0) return PointResult::kNone;
  const float tol = params_.tolerance_m + 2.0f * d * pixel_rad_;
  const int row = pixel / cols_, col = pixel % cols_;
  float nearest = kInf;
  bool seen = false, any = false;
  for (int r = std::max(0, row - 1); r <= std::min(rows_ - 1, row + 1); ++r) {
    const float* line = past.range.data() + static_cast<std::size_t>(r) * cols_;
    for (int dc = -2; dc <= 2; ++dc) {
      int c = col + dc;
      if (c < 0) c += cols_;
      else if (c >= cols_) c -= cols_;
      const float D = line[c];
      if (D == kInf) continue;
      any = true;
      nearest = std::min(nearest, D);
      seen = seen || std::abs(D - d) <= tol;
    }
  }
  if (!any) return PointResult::kNone;
  if (d + tol < nearest) return PointResult::kFree;
  return seen ? PointResult::kSeen : PointResult::kNone;
}

void FreeSpaceMotion::evaluate(std::vector<Box3D>& boxes) {
  buildCurrent();
  if (collect_free_) free_points_.clear();
  // The images tested: the youngest at least kMinAgeS old and the oldest kept.
  tested_.clear();
  for (auto it = past_.rbegin(); it != past_.rend(); ++it) {
    if (stamp_s_ - it->stamp_s >= kMinAgeS - 1e-3) {
      tested_.push_back(&*it);
      break;
    }
  }
  if (!past_.empty() && !tested_.empty() && &past_.front() != tested_.front())
    tested_.push_back(&past_.front());
  for (Box3D& box : boxes) {
    box.motion = MotionEvidence();
    if (!tested_.empty()) evaluateBox(box);
  }
}

void FreeSpaceMotion::evaluateBox(Box3D& box) {
  const Eigen::Vector3f o = current_.sensor;
  // The box's azimuths, relative to its centre's, from its outline (hull, else its corners).
  const float az_c = std::atan2(box.center.y() - o.y(), box.center.x() - o.x());
  float lo = 0.0f, hi = 0.0f, r_min = kInf, r_max = 0.0f;
  bool around = box.min.x() <= o.x() && o.x() <= box.max.x() && box.min.y() <= o.y() &&
                o.y() <= box.max.y();
  const auto extend = [&](float x, float y) {
    const float dx = x - o.x(), dy = y - o.y();
    const float rel = std::remainder(std::atan2(dy, dx) - az_c, 2.0f * kPi);
    lo = std::min(lo, rel);
    hi = std::max(hi, rel);
    r_max = std::max(r_max, std::hypot(dx, dy));
  };
  extend(box.min.x(), box.min.y());
  extend(box.min.x(), box.max.y());
  extend(box.max.x(), box.min.y());
  extend(box.max.x(), box.max.y());
  {
    const float cx = std::clamp(o.x(), box.min.x(), box.max.x());
    const float cy = std::clamp(o.y(), box.min.y(), box.max.y());
    r_min = std::hypot(cx - o.x(), cy - o.y());
  }
  int c0, c1;
  if (around || hi - lo > kPi) {
    c0 = 0;
    c1 = cols_ - 1;
    around = true;
  } else {
    c0 = static_cast<int>(std::floor((az_c + lo + kPi) * inv_az_)) - 1;
    c1 = static_cast<int>(std::floor((az_c + hi + kPi) * inv_az_)) + 1;
  }
  const float z_lo = box.min.z() - o.z(), z_hi = box.max.z() - o.z();
  const float el_lo = std::min(std::atan2(z_lo, std::max(r_min, 1e-3f)), std::atan2(z_lo, r_max));
  const float el_hi = std::max(std::atan2(z_hi, std::max(r_min, 1e-3f)), std::atan2(z_hi, r_max));
  const int r0 = std::max(0, static_cast<int>((el_lo - el_min_) * inv_el_) - 1);
  const int r1 = std::min(rows_ - 1, static_cast<int>((el_hi - el_min_) * inv_el_) + 1);

  constexpr float kEdge = 0.05f;  // a return on the box's edge [m]
  const bool by_grid = box.footprint.size() > 4;
  if (by_grid) buildFootprintGrid(box, kEdge);
  const float x_lo = box.min.x() - kEdge, x_hi = box.max.x() + kEdge;
  const float y_lo = box.min.y() - kEdge, y_hi = box.max.y() + kEdge;
  const float z_lo_edge = box.min.z() - kEdge, z_hi_edge = box.max.z() + kEdge;
  const auto inPart = [&](const FootprintCell& part, float x, float y) {
    return x >= part.min.x() - kEdge && x <= part.max.x() + kEdge && y >= part.min.y() - kEdge &&
           y <= part.max.y() + kEdge;
  };
  const auto inside = [&](float x, float y, float z) {
    if (z < z_lo_edge || z > z_hi_edge) return false;
    if (x < x_lo || x > x_hi || y < y_lo || y > y_hi) return false;
    if (box.footprint.empty()) return true;
    if (by_grid) {
      // x, y lie within the grid's bounds (the box's, grown by the edge).
      const int ix = std::min(grid_.nx - 1, static_cast<int>((x - grid_.x0) * grid_.inv_x));
      const int iy = std::min(grid_.ny - 1, static_cast<int>((y - grid_.y0) * grid_.inv_y));
      const int cell = iy * grid_.nx + ix;
      for (std::int32_t k = grid_.start[cell]; k < grid_.start[cell + 1]; ++k) {
        if (inPart(box.footprint[grid_.parts[k]], x, y)) return true;
      }
      return false;
    }
    for (const FootprintCell& part : box.footprint) {
      if (inPart(part, x, y)) return true;
    }
    return false;
  };
  // A return inside the box (grown by the edge) lies between these ranges from the sensor; the
  // margins cover the float rounding of both sides. The pixels' ranges are read in order, the
  // points only of pixels in between.
  float range_lo = 0.0f, range_hi = kInf;
  {
    double near2 = 0.0, far2 = 0.0;
    const float lo3[3] = {x_lo, y_lo, z_lo_edge}, hi3[3] = {x_hi, y_hi, z_hi_edge};
    for (int a = 0; a < 3; ++a) {
      const double l = static_cast<double>(lo3[a]) - o[a], h = static_cast<double>(hi3[a]) - o[a];
      const double gap = l > 0.0 ? l : (h < 0.0 ? -h : 0.0);
      near2 += gap * gap;
      far2 += std::max(l * l, h * h);
    }
    range_lo = static_cast<float>(std::sqrt(near2) * (1.0 - 1e-4) - 1e-3);
    const double far = std::sqrt(far2) * (1.0 + 1e-4) + 1e-3;
    if (far < 1e30) range_hi = static_cast<float>(far);
  }
  // Per row, tighter: a return of the row at range R from the sensor lies R sin(e) above it and
  // R cos(e) from it horizontally, for an elevation e of the row's band. Bounds grown by 1 mm.
  double horizontal_lo, horizontal_hi, above_lo, above_hi;
  {
    const double x0 = static_cast<double>(x_lo) - o.x(), x1 = static_cast<double>(x_hi) - o.x();
    const double y0 = static_cast<double>(y_lo) - o.y(), y1 = static_cast<double>(y_hi) - o.y();
    const double gx = x0 > 0.0 ? x0 : (x1 < 0.0 ? -x1 : 0.0);
    const double gy = y0 > 0.0 ? y0 : (y1 < 0.0 ? -y1 : 0.0);
    horizontal_lo = std::max(0.0, std::sqrt(gx * gx + gy * gy) - 1e-3);
    horizontal_hi = std::sqrt(std::max(x0 * x0, x1 * x1) + std::max(y0 * y0, y1 * y1)) + 1e-3;
    above_lo = static_cast<double>(z_lo_edge) - o.z() - 1e-3;
    above_hi = static_cast<double>(z_hi_edge) - o.z() + 1e-3;
  }
  // The ranges of row r's returns that may lie inside; false: none.
  const auto rowRanges = [&](int r, float* lo_out, float* hi_out) {
    const RowBand& band = row_bands_[r];
    double lo = horizontal_lo / band.cos_max, hi = horizontal_hi / band.cos_min;
    // R sin_lo <= above_hi
    if (band.sin_lo > 0.0) hi = std::min(hi, above_hi / band.sin_lo);
    else if (above_hi < 0.0) {
      if (band.sin_lo < 0.0) lo = std::max(lo, above_hi / band.sin_lo);
      else return false;
    }
    // R sin_hi >= above_lo
    if (band.sin_hi < 0.0) hi = std::min(hi, above_lo / band.sin_hi);
    else if (above_lo > 0.0) {
      if (band.sin_hi > 0.0) lo = std::max(lo, above_lo / band.sin_hi);
      else return false;
    }
    const float l = std::max(range_lo, static_cast<float>(lo * (1.0 - 1e-4) - 1e-3));
    const float h = hi < 1e30 ? std::min(range_hi, static_cast<float>(hi * (1.0 + 1e-4) + 1e-3))
                              : range_hi;
    *lo_out = l;
    *hi_out = h;
    return l <= h;
  };
  // The window's columns c0..c1 in order, as at most two runs of image columns (it wraps once).
  int runs[2][2];
  int run_count = 0;
  if (c0 < 0) {
    runs[run_count][0] = c0 + cols_;
    runs[run_count++][1] = cols_ - 1;
    runs[run_count][0] = 0;
    runs[run_count++][1] = std::min(c1, cols_ - 1);
  } else if (c1 >= cols_) {
    runs[run_count][0] = c0;
    runs[run_count++][1] = cols_ - 1;
    runs[run_count][0] = 0;
    runs[run_count++][1] = c1 - cols_;
  } else {
    runs[run_count][0] = c0;
    runs[run_count++][1] = c1;
  }
  candidates_.clear();
  for (int r = r0; r <= r1; ++r) {
    float row_lo, row_hi;
    if (!rowRanges(r, &row_lo, &row_hi)) continue;
    const std::int32_t* line = point_of_.data() + static_cast<std::size_t>(r) * cols_;
    const float* ranges = current_.range.data() + static_cast<std::size_t>(r) * cols_;
    const auto take = [&](int c) {
      const std::int32_t i = line[c];
      if (inside(xs_[i], ys_[i], zs_[i])) candidates_.push_back(i);
    };
    for (int k = 0; k < run_count; ++k) {
      int c = runs[k][0];
      const int end = runs[k][1] + 1;
#if defined(__SSE2__)
      const __m128 lo = _mm_set1_ps(row_lo), hi = _mm_set1_ps(row_hi), inf = _mm_set1_ps(kInf);
      for (; c + 4 <= end; c += 4) {
        const __m128 v = _mm_loadu_ps(ranges + c);
        unsigned mask = static_cast<unsigned>(_mm_movemask_ps(_mm_and_ps(
            _mm_and_ps(_mm_cmpge_ps(v, lo), _mm_cmple_ps(v, hi)), _mm_cmpneq_ps(v, inf))));
        while (mask) {
          take(c + __builtin_ctz(mask));
          mask &= mask - 1;
        }
      }
#endif
      for (; c < end; ++c) {
        const float range = ranges[c];
        if (range == kInf || range < row_lo || range > row_hi) continue;
        take(c);
      }
    }
  }
  MotionEvidence& evidence = box.motion;
  const std::size_t n = candidates_.size();
  if (n == 0) return;
  const std::size_t stride = (n + kMaxTestedPerBox - 1) / kMaxTestedPerBox;
  // The tested points seen from each tested image: where, and their pixels and ranges there.
  const std::size_t count = (n + stride - 1) / stride, images = tested_.size();
  qx_.resize(count * images);
  qy_.resize(count * images);
  qz_.resize(count * images);
  qd_.resize(count * images);
  qpixel_.resize(count * images);
  for (std::size_t j = 0; j < images; ++j) {
    const Image& past = *tested_[j];
    for (std::size_t t = 0; t < count; ++t) {
      const std::int32_t i = candidates_[t * stride];
      const Eigen::Vector3f p(xs_[i], ys_[i], zs_[i]);
      const Eigen::Vector3f q = past.to_image * p - past.sensor;
      qx_[j * count + t] = q.x();
      qy_[j * count + t] = q.y();
      qz_[j * count + t] = q.z();
    }
  }
  pixelsOf(qx_.data(), qy_.data(), qz_.data(), Eigen::Vector3f::Zero(), count * images,
           qpixel_.data(), qd_.data());
  // The past images are read at scattered pixels: ask for their rows' lines before the tests.
  for (std::size_t j = 0; j < images; ++j) {
    const float* image = tested_[j]->range.data();
    const std::int32_t last = rows_ * cols_ - 1;
    for (std::size_t t = 0; t < count; ++t) {
      const std::int32_t pixel = qpixel_[j * count + t];
      if (pixel < 0) continue;
      const std::int32_t row = pixel / cols_;
      for (std::int32_t r = std::max(0, row - 1); r <= std::min(rows_ - 1, row + 1); ++r) {
        const std::int32_t at = pixel + (r - row) * cols_;
        __builtin_prefetch(image + std::max(at - 2, 0));
        __builtin_prefetch(image + std::min(at + 2, last));
      }
    }
  }
  int tested = 0, free = 0, seen = 0;
  for (std::size_t t = 0; t < count; ++t) {
    PointResult result = PointResult::kNone;
    for (std::size_t j = 0; j < images; ++j) {
      const PointResult one = test(*tested_[j], qpixel_[j * count + t], qd_[j * count + t]);
      if (one == PointResult::kFree) {
        result = one;
        break;
      }
      if (one == PointResult::kSeen) result = one;
    }
    ++tested;
    if (result == PointResult::kFree) {
      ++free;
      const std::int32_t i = candidates_[t * stride];
      if (collect_free_) free_points_.push_back(Point(xs_[i], ys_[i], zs_[i]));
    } else if (result == PointResult::kSeen) {
      ++seen;
    }
  }
  evidence.tested = static_cast<std::uint16_t>(tested);
  evidence.free = static_cast<std::uint16_t>(free);
  evidence.seen = static_cast<std::uint16_t>(seen);
}

void FreeSpaceMotion::buildFootprintGrid(const Box3D& box, float edge) {
  // Grid cells about one footprint cell (grown by the edge) wide: each holds the few footprint
  // cells that reach into it, registered with a margin for the float rounding of the lookup.
  FootprintGrid& g = grid_;
  g.x0 = box.min.x() - edge;
  g.y0 = box.min.y() - edge;
  const float wx = std::max(box.max.x() + edge - g.x0, 1e-3f);
  const float wy = std::max(box.max.y() + edge - g.y0, 1e-3f);
  float cell = 0.1f;
  for (const FootprintCell& part : box.footprint)
    cell = std::max({cell, part.max.x() - part.min.x() + 2.0f * edge,
                     part.max.y() - part.min.y() + 2.0f * edge});
  constexpr int kMaxCells = 64;  // per axis
  g.nx = std::clamp(static_cast<int>(std::ceil(wx / cell)), 1, kMaxCells);
  g.ny = std::clamp(static_cast<int>(std::ceil(wy / cell)), 1, kMaxCells);
  g.inv_x = g.nx / wx;
  g.inv_y = g.ny / wy;
  const auto range = [](float lo, float hi, float origin, float inv, int n, int* a, int* b) {
    constexpr float kMargin = 1e-2f;  // of a grid cell
    *a = std::clamp(static_cast<int>(std::floor((lo - origin) * inv - kMargin)), 0, n - 1);
    *b = std::clamp(static_cast<int>(std::floor((hi - origin) * inv + kMargin)), 0, n - 1);
  };
  g.start.assign(static_cast<std::size_t>(g.nx) * g.ny + 1, 0);
  for (int pass = 0; pass < 2; ++pass) {  // count, then place from each cell's end
    if (pass == 1) {
      for (std::size_t k = 1; k < g.start.size(); ++k) g.start[k] += g.start[k - 1];
      g.parts.resize(g.start.back());
    }
    for (std::size_t p = 0; p < box.footprint.size(); ++p) {
      const FootprintCell& part = box.footprint[p];
      int ax, bx, ay, by;
      range(part.min.x() - edge, part.max.x() + edge, g.x0, g.inv_x, g.nx, &ax, &bx);
      range(part.min.y() - edge, part.max.y() + edge, g.y0, g.inv_y, g.ny, &ay, &by);
      for (int iy = ay; iy <= by; ++iy) {
        for (int ix = ax; ix <= bx; ++ix) {
          const int c = iy * g.nx + ix;
          if (pass == 0) ++g.start[c];
          else g.parts[--g.start[c]] = static_cast<std::int32_t>(p);  // ends at its cell's first
        }
      }
    }
  }
}

void FreeSpaceMotion::endFrame() {
  buildCurrent();
  past_.push_back(std::move(current_));
  current_ = Image();  // takeImage() brings a recycled buffer next frame
}

}  // namespace icanc
