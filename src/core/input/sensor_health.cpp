#include "icanc/core/input/sensor_health.hpp"

#include <algorithm>
#include <sstream>

namespace icanc {

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
  return why.str();
}

std::size_t countValidReturns(const RawCloud& in, const DecodePlan& plan,
                              const SensorHealthParams& params) {
  const float min2 = static_cast<float>(params.min_range_m * params.min_range_m);
  const float max2 = static_cast<float>(params.max_range_m * params.max_range_m);
  std::size_t valid = 0;
  // forEachXYZ already drops non-finite and (0, 0, 0) points; the identity keeps the sensor frame.
  forEachXYZ(in, plan, Eigen::Affine3f::Identity(), [&](float x, float y, float z) {
    const float r2 = x * x + y * y + z * z;
    valid += r2 >= min2 && r2 <= max2;
  });
  return valid;
}

bool SensorHealth::update(std::size_t valid, std::size_t points) {
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
  if (blind_) ++blind_frames_;
  if (blind_ && !was_blind) ++blind_episodes_;
  return blind_;
}

void SensorHealth::setParams(const SensorHealthParams& params) {
  params_ = params;
  window_.clear();
}

}  // namespace icanc
