#include "icanc/core/input/sensor_health.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <sstream>

namespace icanc {

namespace {

// A monotonic stand-in for atan2(y, x) over [0, 2 pi): the "diamond angle" in [0, 4), one unit
// per quadrant, a division instead of a transcendental call per point.
inline float diamondAngle(float x, float y) {
  if (y >= 0.0f) return x >= 0.0f ? y / (x + y) : 1.0f - x / (y - x);
  return x < 0.0f ? 2.0f - y / (-x - y) : 3.0f + x / (x - y);
}

// Sector of a direction by table over the diamond angle: 1024 bins per quadrant put a boundary
// at most a tenth of a degree off the sector's exact edge.
class SectorIndex {
 public:
  static constexpr int kBinsPerQuadrant = 1024;
  explicit SectorIndex(int sectors) {
    for (int b = 0; b < 4 * kBinsPerQuadrant; ++b) {
      // The bin's centre back to an angle: exact inverse of diamondAngle within the quadrant.
      const float d = (b + 0.5f) / kBinsPerQuadrant;
      const int q = static_cast<int>(d);
      const float f = d - q;  // tan of the angle within the quadrant is f / (1 - f)
      const double angle = q * M_PI / 2.0 + std::atan2(f, 1.0f - f);
      lut_[b] = static_cast<std::uint8_t>(
          std::min(sectors - 1, static_cast<int>(angle / (2.0 * M_PI) * sectors)));
    }
  }
  int operator()(float x, float y) const {
    if (x == 0.0f && y == 0.0f) return lut_[0];
    const int b = static_cast<int>(diamondAngle(x, y) * kBinsPerQuadrant);
    return lut_[std::min(b, 4 * kBinsPerQuadrant - 1)];
  }

 private:
  std::array<std::uint8_t, 4 * kBinsPerQuadrant> lut_{};
};

constexpr int kMaxSectors = 72;

// The table for `sectors`, built once per thread and sector count (not once per frame).
const SectorIndex& sectorIndex(int sectors) {
  thread_local int built_for = 0;
  thread_local std::unique_ptr<SectorIndex> index;
  if (built_for != sectors) {
    index.reset(new SectorIndex(sectors));
    built_for = sectors;
  }
  return *index;
}

}  // namespace

int azimuthSector(float x, float y, int sectors) { return sectorIndex(sectors)(x, y); }

std::string validate(const SensorHealthParams& params) {
  std::ostringstream why;
  if (params.expected_points < 0)
    why << "sensor_health/expected_points must be >= 0, 0 = the cloud's size (got "
        << params.expected_points << ")";
  else if (!(params.min_range_m >= 0.0))
    why << "sensor_health/min_range_m must be >= 0 (got " << params.min_range_m << ")";
  else if (!(params.max_range_m > params.min_range_m && params.max_range_m <= 1e4))
    why << "sensor_health/max_range_m must be in (min_range_m, 10000] (got " << params.max_range_m
        << ")";
  // 0 would switch the blind-sensor check off (an all-NaN cloud: lamp off, diagnostics OK).
  else if (!(params.min_frame_share > 0.0 && params.min_frame_share < 1.0))
    why << "sensor_health/min_frame_share must be in (0, 1): 0 would never call the sensor blind (got "
        << params.min_frame_share << ")";
  else if (!(params.min_window_share > 0.0 && params.min_window_share < 1.0))
    why << "sensor_health/min_window_share must be in (0, 1): 0 would never call the sensor blind (got "
        << params.min_window_share
        << ")";
  else if (params.window_frames < 1 || params.window_frames > 1000)
    why << "sensor_health/window_frames must be in [1, 1000] (got " << params.window_frames << ")";
  else if (params.sectors < 1 || params.sectors > kMaxSectors)
    why << "sensor_health/sectors must be in [1, " << kMaxSectors
        << "], 1 = the whole frame only (got " << params.sectors << ")";
  return why.str();
}

std::size_t countValidReturns(const RawCloud& in, const DecodePlan& plan,
                              const SensorHealthParams& params, SectorReturns* sectors) {
  const float min2 = static_cast<float>(params.min_range_m * params.min_range_m);
  const float max2 = static_cast<float>(params.max_range_m * params.max_range_m);
  std::size_t valid = 0;
  // forEachXYZ already drops non-finite and (0, 0, 0) points; the identity keeps the sensor frame.
  if (sectors == nullptr || params.sectors <= 1) {
    if (sectors != nullptr) sectors->valid.clear(), sectors->returned.clear();
    forEachXYZ(in, plan, Eigen::Affine3f::Identity(), [&](float x, float y, float z) {
      const float r2 = x * x + y * y + z * z;
      valid += r2 >= min2 && r2 <= max2;
    });
    return valid;
  }
  const SectorIndex& sector = sectorIndex(params.sectors);
  sectors->valid.assign(params.sectors, 0);
  sectors->returned.assign(params.sectors, 0);
  std::uint32_t* valid_in = sectors->valid.data();
  std::uint32_t* returned_in = sectors->returned.data();
  forEachXYZ(in, plan, Eigen::Affine3f::Identity(), [&](float x, float y, float z) {
    const float r2 = x * x + y * y + z * z;
    if (r2 > max2) return;
    const int k = sector(x, y);
    ++returned_in[k];
    if (r2 < min2) return;
    ++valid;
    ++valid_in[k];
  });
  return valid;
}

bool SensorHealth::update(std::size_t valid, std::size_t points, const SectorReturns& sectors) {
  const std::size_t expected =
      params_.expected_points > 0 ? static_cast<std::size_t>(params_.expected_points) : points;
  frame_share_ = expected > 0 ? std::min(1.0, static_cast<double>(valid) / expected) : 0.0;
  window_.push_back(frame_share_);
  while (window_.size() > static_cast<std::size_t>(params_.window_frames)) window_.pop_front();
  // Summed afresh (at most 1000 values): no drift from adding and subtracting doubles.
  double sum = 0.0;
  for (double share : window_) sum += share;
  window_share_ = sum / window_.size();
  const bool was_blind = blind_;
  blind_ = frame_share_ < params_.min_frame_share || window_share_ < params_.min_window_share;
  updateSectors(sectors);
  if (blind_sector_ >= 0) {
    blind_ = true;
    ++blind_sector_frames_;
  }
  if (blind_) ++blind_frames_;
  if (blind_ && !was_blind) ++blind_episodes_;
  return blind_;
}

void SensorHealth::updateSectors(const SectorReturns& sectors) {
  blind_sector_ = -1;
  blind_sector_share_ = 1.0;
  const std::size_t n = sectors.valid.size();
  if (params_.sectors <= 1 || n != static_cast<std::size_t>(params_.sectors) ||
      sectors.returned.size() != n)
    return;
  if (reference_.size() != n) {
    reference_.assign(n, 0);
    sector_window_.assign(n, {});
  }
  for (std::size_t s = 0; s < n; ++s) reference_[s] = std::max(reference_[s], sectors.valid[s]);
  const std::uint32_t best = *std::max_element(reference_.begin(), reference_.end());
  for (std::size_t s = 0; s < n; ++s) {
    std::deque<double>& window = sector_window_[s];
    // Outside the field of view (never a quarter of the best sector): not judged.
    if (best == 0 || 4u * reference_[s] < best) {
      window.clear();
      continue;
    }
    const double share = static_cast<double>(sectors.valid[s]) / reference_[s];
    window.push_back(share);
    while (window.size() > static_cast<std::size_t>(params_.window_frames)) window.pop_front();
    double sum = 0.0;
    for (double v : window) sum += v;
    // Nothing returned at all: blind now. Returns nearer than min_range_m: blind only when they
    // last (the window), since a passer-by close to the sensor returns there for a few frames.
    const double returned_share = static_cast<double>(sectors.returned[s]) / reference_[s];
    const bool blind =
        returned_share < params_.min_frame_share || sum / window.size() < params_.min_window_share;
    if (blind && (blind_sector_ < 0 || share < blind_sector_share_)) {
      blind_sector_ = static_cast<int>(s);
      blind_sector_share_ = share;
    }
  }
}

void SensorHealth::setParams(const SensorHealthParams& params) {
  params_ = params;
  window_.clear();
  reference_.clear();
  sector_window_.clear();
}

}  // namespace icanc
