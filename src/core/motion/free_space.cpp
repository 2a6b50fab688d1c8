#include "icanc/core/motion/free_space.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

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
  point_of_.assign(static_cast<std::size_t>(cols_) * rows_, -1);
  past_.clear();
  spare_.clear();
  current_ = Image();
  current_.range.assign(point_of_.size(), kInf);
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
  for (std::int32_t pixel : current_.hit) current_.range[pixel] = kInf;
  current_.hit.clear();
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
  xs_.clear();
  ys_.clear();
  zs_.clear();
  built_ = false;
}

inline std::int32_t FreeSpaceMotion::pixelOf(float dx, float dy, float dz, float* range) const {
  const float horizontal2 = dx * dx + dy * dy;
  const float horizontal = std::sqrt(horizontal2);
  *range = std::sqrt(horizontal2 + dz * dz);
  const int row = static_cast<int>((fastAtan2(dz, horizontal) - el_min_) * inv_el_);
  if (row < 0 || row >= rows_) return -1;
  int col = static_cast<int>((fastAtan2(dy, dx) + kPi) * inv_az_);
  if (col >= cols_) col -= cols_;
  return row * cols_ + col;
}

void FreeSpaceMotion::buildCurrent() {
  if (built_) return;
  built_ = true;
  const Eigen::Vector3f o = current_.sensor;
  const std::size_t n = xs_.size();
  for (std::size_t i = 0; i < n; ++i) {
    float range;
    const std::int32_t pixel = pixelOf(xs_[i] - o.x(), ys_[i] - o.y(), zs_[i] - o.z(), &range);
    if (pixel < 0 || !(range > 0.0f)) continue;
    float& nearest = current_.range[pixel];
    if (range < nearest) {
      if (nearest == kInf) current_.hit.push_back(pixel);
      nearest = range;
      point_of_[pixel] = static_cast<std::int32_t>(i);
    }
  }
}

FreeSpaceMotion::PointResult FreeSpaceMotion::test(const Image& past, const Eigen::Vector3f& p) const {
  const Eigen::Vector3f q = past.to_image * p - past.sensor;
  float d;
  const std::int32_t pixel = pixelOf(q.x(), q.y(), q.z(), &d);
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
  const auto inside = [&](float x, float y, float z) {
    if (z < box.min.z() - kEdge || z > box.max.z() + kEdge) return false;
    if (x < box.min.x() - kEdge || x > box.max.x() + kEdge || y < box.min.y() - kEdge ||
        y > box.max.y() + kEdge)
      return false;
    if (box.footprint.empty()) return true;
    for (const FootprintCell& part : box.footprint) {
      if (x >= part.min.x() - kEdge && x <= part.max.x() + kEdge && y >= part.min.y() - kEdge &&
          y <= part.max.y() + kEdge)
        return true;
    }
    return false;
  };
  candidates_.clear();
  for (int r = r0; r <= r1; ++r) {
    const std::int32_t* line = point_of_.data() + static_cast<std::size_t>(r) * cols_;
    const float* ranges = current_.range.data() + static_cast<std::size_t>(r) * cols_;
    for (int c = c0; c <= c1; ++c) {
      const int cc = c < 0 ? c + cols_ : (c >= cols_ ? c - cols_ : c);
      if (ranges[cc] == kInf) continue;
      const std::int32_t i = line[cc];
      if (inside(xs_[i], ys_[i], zs_[i])) candidates_.push_back(i);
    }
  }
  MotionEvidence& evidence = box.motion;
  const std::size_t n = candidates_.size();
  if (n == 0) return;
  const std::size_t stride = (n + kMaxTestedPerBox - 1) / kMaxTestedPerBox;
  int tested = 0, free = 0, seen = 0;
  for (std::size_t k = 0; k < n; k += stride) {
    const std::int32_t i = candidates_[k];
    const Eigen::Vector3f p(xs_[i], ys_[i], zs_[i]);
    PointResult result = PointResult::kNone;
    for (const Image* past : tested_) {
      const PointResult one = test(*past, p);
      if (one == PointResult::kFree) {
        result = one;
        break;
      }
      if (one == PointResult::kSeen) result = one;
    }
    ++tested;
    if (result == PointResult::kFree) {
      ++free;
      if (collect_free_) free_points_.push_back(Point(p.x(), p.y(), p.z()));
    } else if (result == PointResult::kSeen) {
      ++seen;
    }
  }
  evidence.tested = static_cast<std::uint16_t>(tested);
  evidence.free = static_cast<std::uint16_t>(free);
  evidence.seen = static_cast<std::uint16_t>(seen);
}

void FreeSpaceMotion::endFrame() {
  buildCurrent();
  for (std::int32_t pixel : current_.hit) point_of_[pixel] = -1;
  past_.push_back(std::move(current_));
  current_ = Image();  // takeImage() brings a recycled buffer next frame
}

}  // namespace icanc
