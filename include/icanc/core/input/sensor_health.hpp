// Is the LiDAR seeing anything? A sensor under mud, snow or a cover returns NaN, (0, 0, 0), points
// on its own window or nothing in range: without this check such a frame is a valid, empty frame,
// i.e. a clear road, exactly when the lamp must come on. A frame is blind when its valid returns
// (finite, non-zero, range in [min_range_m, max_range_m] from the sensor) are fewer than
// min_frame_share of the expected points, or when the mean share over the last window_frames
// frames is below min_window_share (a sensor that degrades over seconds). It is healthy again
// once both are back above their thresholds. The shares are profile parameters: an organized
// cloud (NaN where nothing returned) can use its own width x height (expected_points 0); a driver
// that drops the non-returns needs the count of a healthy frame in expected_points.
//
// A half-covered sensor still delivers most of a frame, and a driver that drops the covered
// returns delivers a smaller cloud whose every point is valid. So each azimuth sector (`sectors`
// of equal width around the sensor's z axis) is also judged against the most valid returns it has
// delivered since the start: a sector that returns nothing at all in a frame (NaN, dropped) is
// blind at once (min_frame_share); one whose valid returns stay low over the window (a cover
// nearer than min_range_m, which returns, or a slow loss) is blind once the window's mean is below
// min_window_share. Something passing close by the sensor returns too, and for a few frames only:
// it does not make the sector blind. A sector that has never delivered a quarter of the best
// sector's returns is outside the field of view and is not judged. A sensor covered from power-on
// gives its covered sectors no reference: the frame share (expected_points) is the check then.
#pragma once

#include <cstddef>
#include <cstdint>
#include <deque>
#include <string>
#include <vector>

#include "icanc/core/perception/cloud_decode.hpp"

namespace icanc {

struct SensorHealthParams {
  int expected_points = 0;        // points of a healthy frame; 0: the cloud's width x height
  double min_range_m = 0.5;       // nearer returns are the window or a cover on it [m]
  double max_range_m = 250.0;     // farther "returns" are not returns [m]
  double min_frame_share = 0.05;  // a frame with fewer valid returns (share of expected) is blind
  double min_window_share = 0.2;  // the mean share over window_frames below this: blind
  int window_frames = 10;         // frames in the window [frames]
  int sectors = 12;               // azimuth sectors judged apart; 1: the whole frame only
};

// "" or why the parameters are invalid (naming the key).
std::string validate(const SensorHealthParams& params);

// Returns per azimuth sector (sector k spans [k, k + 1) * 360 / sectors degrees,
// counter-clockwise from +x in the sensor frame).
struct SectorReturns {
  std::vector<std::uint32_t> valid;     // range in [min_range_m, max_range_m]
  std::vector<std::uint32_t> returned;  // finite, non-zero and within max_range_m, nearer ones too
};

namespace health_detail {
constexpr int kBinsPerQuadrant = 1024;
// The table of azimuth sectors over the "diamond angle" bins, built once per thread and count.
const std::uint8_t* sectorTable(int sectors);
// Sector of the direction (x, y) by that table over the diamond angle in [0, 4) (one unit per
// quadrant): a division instead of a transcendental call per point.
inline int sectorOf(const std::uint8_t* table, float x, float y) {
  if (x == 0.0f && y == 0.0f) return table[0];
  const float d = y >= 0.0f ? (x >= 0.0f ? y / (x + y) : 1.0f - x / (y - x))
                            : (x < 0.0f ? 2.0f - y / (-x - y) : 3.0f + x / (x - y));
  const int b = static_cast<int>(d * kBinsPerQuadrant);
  return table[b < 4 * kBinsPerQuadrant - 1 ? b : 4 * kBinsPerQuadrant - 1];
}
}  // namespace health_detail

// Counts a frame's returns point by point, in the sensor frame, so that a pass over the cloud made
// for something else (the fast detector's decode) counts them too: no second pass for the check.
class ReturnCounter {
 public:
  // Starts a frame (counts zeroed) with the ranges and sectors of `params`.
  void begin(const SensorHealthParams& params);
  // One finite, non-zero point of the frame, in the sensor frame.
  void add(float x, float y, float z) {
    const float r2 = x * x + y * y + z * z;
    const std::uint32_t in = r2 <= max2_;
    const std::uint32_t valid = in & (r2 >= min2_);
    const int k = sector_ == nullptr ? 0 : health_detail::sectorOf(sector_, x, y);
    counts_.returned[k] += in;
    counts_.valid[k] += valid;
    valid_total_ += valid;
  }
  // Valid returns (range in [min_range_m, max_range_m]) since begin().
  std::size_t valid() const { return valid_total_; }
  // The counts per sector (empty with params.sectors <= 1).
  const SectorReturns& sectors() const;

 private:
  float min2_ = 0.0f, max2_ = 0.0f;
  const std::uint8_t* sector_ = nullptr;  // health_detail::sectorTable; null: one sector
  SectorReturns counts_{{0}, {0}};        // one entry per sector (one with a single sector)
  std::size_t valid_total_ = 0;
};

// Valid returns of a cloud planDecode accepted, in the sensor frame (finite, non-zero, range in
// [min_range_m, max_range_m]). With `sectors` (and params.sectors > 1), also the counts per sector.
std::size_t countValidReturns(const RawCloud& in, const DecodePlan& plan,
                              const SensorHealthParams& params,
                              SectorReturns* sectors = nullptr);

// The sector of the direction (x, y) among `sectors` equal ones, as countValidReturns counts it.
int azimuthSector(float x, float y, int sectors);

class SensorHealth {
 public:
  explicit SensorHealth(const SensorHealthParams& params = SensorHealthParams()) : params_(params) {}

  // One frame with `valid` valid returns out of `points` points in the message, and (with
  // params.sectors > 1) its returns per sector. Returns blind().
  bool update(std::size_t valid, std::size_t points, const SectorReturns& sectors = {});

  bool blind() const { return blind_; }
  // The sector that made the last frame blind, -1 when none did (healthy, or blind as a whole).
  int blindSector() const { return blind_sector_; }
  // That sector's valid returns in the last frame, as a share of its reference.
  double blindSectorShare() const { return blind_sector_share_; }
  std::uint64_t blindSectorFrames() const { return blind_sector_frames_; }
  double frameShare() const { return frame_share_; }    // of the last frame
  double windowShare() const { return window_share_; }  // mean over the window
  std::uint64_t blindFrames() const { return blind_frames_; }
  std::uint64_t blindEpisodes() const { return blind_episodes_; }  // healthy -> blind changes

  void setParams(const SensorHealthParams& params);
  const SensorHealthParams& params() const { return params_; }

 private:
  SensorHealthParams params_;
  // Judges the sectors; the first blind one (or -1) and its share.
  void updateSectors(const SectorReturns& sectors);

  std::deque<double> window_;
  double frame_share_ = 1.0, window_share_ = 1.0;
  bool blind_ = false;
  std::uint64_t blind_frames_ = 0, blind_episodes_ = 0;
  // Per sector: the most valid returns it has delivered, and its valid shares over the window.
  std::vector<std::uint32_t> reference_;
  std::vector<std::deque<double>> sector_window_;
  int blind_sector_ = -1;
  double blind_sector_share_ = 1.0;
  std::uint64_t blind_sector_frames_ = 0;
};

template <class Reader>
void visitParams(Reader& r, SensorHealthParams& p) {
  r("sensor_health/expected_points", p.expected_points);
  r("sensor_health/min_range_m", p.min_range_m);
  r("sensor_health/max_range_m", p.max_range_m);
  r("sensor_health/min_frame_share", p.min_frame_share);
  r("sensor_health/min_window_share", p.min_window_share);
  r("sensor_health/window_frames", p.window_frames);
  r("sensor_health/sectors", p.sectors);
}

}  // namespace icanc
