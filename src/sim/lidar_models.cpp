// LiDAR sensor presets and the column (azimuth) geometry of a LidarModel.
#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "icanc/sim/lidar_sim.hpp"

namespace icanc {
namespace sim {
namespace {

bool isFullCircle(const LidarModel& m) {
  return double(m.h_fov_max_deg) - double(m.h_fov_min_deg) >= 360.0 - 1e-3;
}

// n angles evenly from `from` to `to`, both included.
std::vector<float> evenly(double from, double to, int n) {
  std::vector<float> v(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) {
    v[static_cast<std::size_t>(i)] =
        static_cast<float>(n == 1 ? from : from + (to - from) * double(i) / double(n - 1));
  }
  return v;
}

}  // namespace

std::size_t LidarModel::columns() const {
  const double res = horizontal_resolution_deg;
  const double span = double(h_fov_max_deg) - double(h_fov_min_deg);
  if (!(res > 0.0) || !(span >= 0.0)) return 0;
  if (isFullCircle(*this)) return std::max<std::size_t>(1, std::llround(360.0 / res));
  return static_cast<std::size_t>(std::floor(span / res + 1e-4)) + 1;
}

double LidarModel::azimuthStepDeg() const {
  const std::size_t n = columns();
  if (n == 0) return 0.0;
  if (isFullCircle(*this)) return 360.0 / double(n);
  const double res = horizontal_resolution_deg;
  const double span = double(h_fov_max_deg) - double(h_fov_min_deg);
  // When the resolution divides the field of view, land exactly on both ends.
  if (n > 1 && std::abs(double(n - 1) * res - span) <= 1e-4 * res) return span / double(n - 1);
  return res;
}

double LidarModel::azimuthDeg(std::size_t column) const {
  return double(h_fov_min_deg) + double(column) * azimuthStepDeg();
}

LidarModel LidarModel::vlp16() {
  LidarModel m;
  m.name = "vlp16";
  m.vertical_angles_deg = evenly(15.0, -15.0, 16);  // every 2 deg, top beam first
  m.horizontal_resolution_deg = 0.2f;
  m.rate_hz = 10.0f;
  m.min_range_m = 0.5f;
  m.max_range_m = 100.0f;
  return m;
}

LidarModel LidarModel::hdl64e() {
  LidarModel m;
  m.name = "hdl64e";
  m.vertical_angles_deg = evenly(2.0, -8.33, 32);          // upper block
  const std::vector<float> lower = evenly(-8.83, -24.9, 32);  // lower block
  m.vertical_angles_deg.insert(m.vertical_angles_deg.end(), lower.begin(), lower.end());
  m.horizontal_resolution_deg = 0.17f;
  m.rate_hz = 10.0f;
  m.min_range_m = 0.5f;
  m.max_range_m = 120.0f;
  return m;
}

LidarModel LidarModel::hdl32e() {
  // Velodyne HDL-32E: 32 lasers, +10.67 to -30.67 deg every 1.33 deg; about 0.16 deg at 10 Hz.
  LidarModel m;
  m.name = "hdl32e";
  m.vertical_angles_deg = evenly(10.67, -30.67, 32);
  m.horizontal_resolution_deg = 0.16f;
  m.rate_hz = 10.0f;
  m.min_range_m = 1.0f;
  m.max_range_m = 100.0f;
  return m;
}

LidarModel LidarModel::carla128() {
  // The paper's CARLA sensor: 128 channels, 640,000 points/s. CARLA's default fov (upper 10 deg,
  // lower -30 deg); at 10 Hz that is 640000 / 10 / 128 = 500 columns over 360 deg (0.72 deg).
  LidarModel m;
  m.name = "carla128";
  const int channels = 128;
  const double points_per_second = 640000.0;
  m.rate_hz = 10.0f;
  m.vertical_angles_deg = evenly(10.0, -30.0, channels);
  const double cols = points_per_second / m.rate_hz / channels;
  m.horizontal_resolution_deg = static_cast<float>(360.0 / cols);
  m.min_range_m = 0.5f;
  m.max_range_m = 100.0f;
  return m;
}

LidarModel LidarModel::robosenseM1() {
  // Forward-looking solid-state sensor (RoboSense M1 on the Zebra): 120 x 25 deg, 200 m.
  LidarModel m;
  m.name = "robosense_m1";
  m.vertical_angles_deg = evenly(12.5, -12.5, 126);
  m.horizontal_resolution_deg = 0.2f;
  m.h_fov_min_deg = -60.0f;
  m.h_fov_max_deg = 60.0f;
  m.rate_hz = 10.0f;
  m.min_range_m = 0.5f;
  m.max_range_m = 200.0f;
  return m;
}

LidarModel LidarModel::byName(const std::string& name) {
  if (name == "vlp16") return vlp16();
  if (name == "hdl64e") return hdl64e();
  if (name == "hdl32e") return hdl32e();
  if (name == "carla128") return carla128();
  if (name == "robosense_m1") return robosenseM1();
  throw std::invalid_argument("unknown lidar model '" + name +
                              "' (expected vlp16, hdl32e, hdl64e, carla128 or robosense_m1)");
}

}  // namespace sim
}  // namespace icanc
