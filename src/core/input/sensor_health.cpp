#include "icanc/core/input/sensor_health.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <sstream>

namespace icanc {

namespace {

constexpr int kMaxSectors = 72;

}  // namespace

// Each of the 4 * kBinsPerQuadrant diamond-angle bins to its sector: 1024 bins per quadrant put a
// boundary at most a tenth of a degree off the sector's exact edge.
const std::uint8_t* health_detail::sectorTable(int sectors) {
  thread_local int built_for = 0;
  thread_local std::array<std::uint8_t, 4 * kBinsPerQuadrant> table{};
  if (built_for != sectors) {
    for (int b = 0; b < 4 * kBinsPerQuadrant; ++b) {
      // The bin's centre back to an angle: exact inverse of the diamond angle within the quadrant.
      const float d = (b + 0.5f) / kBinsPerQuadrant;
      const int q = static_cast<int>(d);
      const float f = d - q;  // tan of the angle within the quadrant is f / (1 - f)
      const double angle = q * M_PI / 2.0 + std::atan2(f, 1.0f - f);
      table[b] = static_cast<std::uint8_t>(
          std::min(sectors - 1, static_cast<int>(angle / (2.0 * M_PI) * sectors)));
    }
    built_for = sectors;
  }
  return table.data();
}

int azimuthSector(float x, float y, int sectors) {
  return health_detail::sectorOf(health_detail::sectorTable(sectors), x, y);
}

void ReturnCounter::begin(const SensorHealthParams& params) {
  min2_ = static_cast<float>(params.min_range_m * params.min_range_m);
  max2_ = static_cast<float>(params.max_range_m * params.max_range_m);
  valid_total_ = 0;
  sector_ = params.sectors > 1 ? health_detail::sectorTable(params.sectors) : nullptr;
  const std::size_t n = static_cast<std::size_t>(std::max(1, params.sectors));
  counts_.valid.assign(n, 0);
  counts_.returned.assign(n, 0);
}

const SectorReturns& ReturnCounter::sectors() const {
  static const SectorReturns kNone;
  return sector_ != nullptr ? counts_ : kNone;
}

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
  ReturnCounter counter;
  counter.begin(params);
  // forEachXYZ already drops non-finite and (0, 0, 0) points; the identity keeps the sensor frame.
  forEachXYZ(in, plan, Eigen::Affine3f::Identity(),
             [&](float x, float y, float z) { counter.add(x, y, z); });
  if (sectors != nullptr) *sectors = counter.sectors();
  return counter.valid();
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
