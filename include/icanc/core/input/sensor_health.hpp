// Is the LiDAR seeing anything? A sensor under mud, snow or a cover returns NaN, (0, 0, 0), points
// on its own window or nothing in range: without this check such a frame is a valid, empty frame,
// i.e. a clear road, exactly when the lamp must come on. A frame is blind when its valid returns
// (finite, non-zero, range in [min_range_m, max_range_m] from the sensor) are fewer than
// min_frame_share of the expected points, or when the mean share over the last window_frames
// frames is below min_window_share (a sensor that degrades over seconds). It is healthy again
// once both are back above their thresholds. The shares are profile parameters: an organized
// cloud (NaN where nothing returned) can use its own width x height (expected_points 0); a driver
// that drops the non-returns needs the count of a healthy frame in expected_points.
#pragma once

#include <cstddef>
#include <cstdint>
#include <deque>
#include <string>

#include "icanc/core/perception/cloud_decode.hpp"

namespace icanc {

struct SensorHealthParams {
  int expected_points = 0;        // points of a healthy frame; 0: the cloud's width x height
  double min_range_m = 0.2;       // closer returns are the sensor's own window (dirt, a cover) [m]
  double max_range_m = 250.0;     // farther "returns" are not returns [m]
  double min_frame_share = 0.05;  // a frame with fewer valid returns (share of expected) is blind
  double min_window_share = 0.2;  // the mean share over window_frames below this: blind
  int window_frames = 10;         // frames in the window [frames]
};

// "" or why the parameters are invalid (naming the key).
std::string validate(const SensorHealthParams& params);

// Valid returns of a cloud planDecode accepted, in the sensor frame (finite, non-zero, range in
// [min_range_m, max_range_m]).
std::size_t countValidReturns(const RawCloud& in, const DecodePlan& plan,
                              const SensorHealthParams& params);

class SensorHealth {
 public:
  explicit SensorHealth(const SensorHealthParams& params = SensorHealthParams()) : params_(params) {}

  // One frame with `valid` valid returns out of `points` points in the message. Returns blind().
  bool update(std::size_t valid, std::size_t points);

  bool blind() const { return blind_; }
  double frameShare() const { return frame_share_; }    // of the last frame
  double windowShare() const { return window_share_; }  // mean over the window
  std::uint64_t blindFrames() const { return blind_frames_; }
  std::uint64_t blindEpisodes() const { return blind_episodes_; }  // healthy -> blind changes

  void setParams(const SensorHealthParams& params);
  const SensorHealthParams& params() const { return params_; }

 private:
  SensorHealthParams params_;
  std::deque<double> window_;
  double frame_share_ = 1.0, window_share_ = 1.0;
  bool blind_ = false;
  std::uint64_t blind_frames_ = 0, blind_episodes_ = 0;
};

template <class Reader>
void visitParams(Reader& r, SensorHealthParams& p) {
  r("sensor_health/expected_points", p.expected_points);
  r("sensor_health/min_range_m", p.min_range_m);
  r("sensor_health/max_range_m", p.max_range_m);
  r("sensor_health/min_frame_share", p.min_frame_share);
  r("sensor_health/min_window_share", p.min_window_share);
  r("sensor_health/window_frames", p.window_frames);
}

}  // namespace icanc
