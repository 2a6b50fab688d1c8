// icanc_sim_odometry: the LiDAR odometry on simulated scenarios (every scenario evaluated
// with `ego_motion/source: lidar` as well as `tf`). Each scenario is rendered as icanc_sim_bag
// renders it (same seed, sensor, mount and noise), read as the LidarOdometry nodelet reads the
// organized cloud (every input_stride-th point of each row, from its phase), moved into base_link
// by the sensor's mount and registered with the scenario profile's lidar_odometry section; the
// estimate is compared with the scripted vehicle pose at every frame.
//
//   icanc_sim_odometry SCENARIO.yaml [SCENARIO.yaml ...] [--twist | --speed] [--trace]
//                      [--base-height H]
// Prints per scenario the worst position and yaw error, the worst forward-speed error after the
// first second, the frames registered, and what the registration had to work with: the returns
// in range above the road (structure) against those on it, median per frame, and the horizontal
// observability of the frames registered or found degenerate (median, min).
// --twist: each frame also gets the vehicle's measured twist, as the nodelet gets it from
// icanc_sim_bag's /vehicle/twist (sim::canTwist, the same draws; lidar_odometry/twist_yaw_rate of
// the profile says whether its yaw rate is taken). --speed: the same without the yaw rate (a
// speed-only source).
// --trace: one line per frame.
// --base-height H: base_link H metres above the road instead of on it (the mount and
// ground_max_z_m moved with it): the voxel grids, laid from base_link, then meet the road
// elsewhere; how much the result depends on that.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "icanc/core/common/percentile.hpp"
#include "icanc/core/common/yaml_params.hpp"
#include "icanc/core/motion/lidar_odometry.hpp"
#include "icanc/core/perception/cloud_decode.hpp"
#include "icanc/sim/lidar_sim.hpp"
#include "icanc/sim/scenario.hpp"
#include "tool_help.hpp"

namespace {

const char* const kUsage =
    "usage: icanc_sim_odometry SCENARIO.yaml [SCENARIO.yaml ...] [--twist | --speed] [--trace]\n"
    "                          [--base-height H]\n";

double yawOf(const Eigen::Isometry3d& pose) { return std::atan2(pose(1, 0), pose(0, 0)); }

void follow(const std::string& path, bool twist, bool speed_only, bool trace, double base_height) {
  const icanc::sim::Scenario s = icanc::sim::loadScenario(path);
  const icanc::Profile profile = icanc::loadProfile(icanc::sim::profilePath(path, s.profile));
  icanc::LidarOdometryParams params = profile.lidar_odometry;
  params.ground_max_z_m -= base_height;
  icanc::LidarOdometry odometry(params);
  const icanc::sim::LidarModel model = icanc::sim::LidarModel::byName(s.lidar);
  std::mt19937_64 rng(s.seed), can_rng(s.seed + 1);  // as icanc_sim_bag draws them
  // The nodelet's own key (not in LidarOdometryParams): does the twist topic carry a yaw rate.
  const YAML::Node yaw_node = YAML::LoadFile(icanc::sim::profilePath(path, s.profile))["lidar_odometry"]["twist_yaw_rate"];
  const bool yaw_rate = !speed_only && yaw_node && yaw_node.as<bool>();
  const Eigen::Isometry3d start_inv = s.vehiclePose(0.0).cast<double>().inverse();
  Eigen::Affine3f mount(s.sensor_mount.matrix());  // sensor frame -> base_link
  mount.pretranslate(Eigen::Vector3f(0.0f, 0.0f, static_cast<float>(-base_height)));
  double worst_position = 0.0, worst_yaw = 0.0, worst_speed = 0.0;
  std::size_t registered = 0, held = 0, at_rest = 0;
  double worst_standing = 0.0;  // speed while the scripted vehicle stands
  std::vector<double> structure, road, observability;
  for (std::size_t f = 0; f < s.frames(); ++f) {
    const double t = double(f) / s.rate_hz;
    icanc::Cloud cloud;
    icanc::sim::renderScan(s.scene, t, s.sensorPose(t), model, s.noise, rng, cloud);
    std::size_t above = 0, below = 0;
    for (const auto& p : cloud.points) {
      if (!std::isfinite(p.x)) continue;
      const Eigen::Vector3f q = mount * Eigen::Vector3f(p.x, p.y, p.z);
      const double r = q.head<2>().norm();
      if (r >= params.min_range_m && r <= params.max_range_m) ++(q.z() < params.ground_max_z_m ? below : above);
    }
    structure.push_back(double(above));
    road.push_back(double(below));
    // Read as the LidarOdometry nodelet reads a driver's organized cloud: only every
    // input_stride-th point of each row decoded, from the odometry's phase.
    const icanc::RawCloud raw = icanc::rawView(cloud);
    icanc::DecodePlan plan;
    if (icanc::planDecode(raw, cloud.size(), plan) != icanc::DecodeError::kNone)
      throw std::runtime_error("rendered scan not decodable");
    const icanc::DecodePlan thinned =
        icanc::everyNthPoint(plan, static_cast<std::size_t>(params.input_stride), odometry.sourcePhase());
    for (int j = 0; j < static_cast<int>(icanc::sim::kCanTwistHz / s.rate_hz + 0.5); ++j) {
      icanc::MeasuredTwist m = icanc::sim::canTwist(s, t + j / icanc::sim::kCanTwistHz, can_rng);
      if (!yaw_rate) m.yaw_rate_rad_s = std::numeric_limits<double>::quiet_NaN();
      if (j == 0 && twist) odometry.seedTwist(m);  // the sample at the cloud's stamp
    }
    const Eigen::Isometry3d estimate = odometry.registerFrom(
        t, [&](auto&& sink) { icanc::forEachXYZ(raw, thinned, mount, sink); },
        icanc::LidarOdometry::Thinning::kBySource);
    const Eigen::Isometry3d truth = start_inv * s.vehiclePose(t).cast<double>();
    const double position = (estimate.translation() - truth.translation()).norm();
    const double yaw = std::fabs(std::remainder(yawOf(estimate) - yawOf(truth), 2.0 * M_PI));
    worst_position = std::max(worst_position, position);
    worst_yaw = std::max(worst_yaw, yaw);
    if (t >= 1.0)
      worst_speed = std::max(worst_speed, std::fabs(odometry.linearVelocity().x() - s.vehicleTwist(t).linear.x()));
    const auto& stats = odometry.lastStats();
    using Result = icanc::LidarOdometryStats::Result;
    registered += stats.result == Result::kRegistered;
    held += stats.result == Result::kHeld;
    at_rest += stats.result == Result::kAtRest;
    if (f > 0 && s.vehicleTwist(t).linear.norm() == 0.0 && s.vehicleTwist(t).yaw_rate == 0.0)
      worst_standing = std::max(worst_standing, odometry.linearVelocity().norm());
    if (stats.result == Result::kRegistered || stats.result == Result::kDegenerate ||
        stats.result == Result::kHeld || stats.result == Result::kAtRest)  // registration attempted
      observability.push_back(stats.horizontal_observability);
    if (trace)
      std::printf("  t %5.1f  estimate (%7.2f %6.2f %6.3f)  truth (%7.2f %6.2f %6.3f)  speed %5.2f / %5.2f  "
                  "points above / on the road %zu / %zu  observability %.3f  rest F %.2f  %s\n",
                  t, estimate.translation().x(), estimate.translation().y(), yawOf(estimate),
                  truth.translation().x(), truth.translation().y(), yawOf(truth),
                  odometry.linearVelocity().x(), s.vehicleTwist(t).linear.x(), above, below,
                  stats.horizontal_observability, stats.rest_f, icanc::toString(stats.result));
  }
  std::printf("%s: %zu frames, %zu registered, %zu along-track held, %zu at rest; worst position error %.2f m, yaw %.3f rad, forward speed "
              "%.2f m/s (after 1 s), speed while standing %.3f m/s; returns in range above / on the road, median per frame: %.0f / %.0f; "
              "horizontal observability median %.3f, min %.3f\n",
              s.name.c_str(), s.frames(), registered, held, at_rest, worst_position, worst_yaw, worst_speed,
              worst_standing,
              icanc::percentile(structure, 0.5), icanc::percentile(road, 0.5),
              icanc::percentile(observability, 0.5), icanc::percentile(observability, 0.0));
}

}  // namespace

int main(int argc, char** argv) {
  if (icanc::tools::wantsHelp(argc, argv)) return icanc::tools::printUsage(kUsage, true);
  std::vector<std::string> scenarios;
  bool trace = false, twist = false, speed_only = false;
  double base_height = 0.0;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--trace") trace = true;
    else if (a == "--twist") twist = true;
    else if (a == "--speed") twist = speed_only = true;
    else if (a == "--base-height" && i + 1 < argc) base_height = std::atof(argv[++i]);
    else if (a.rfind("--", 0) == 0) return icanc::tools::printUsage(kUsage, false);
    else scenarios.push_back(a);
  }
  if (scenarios.empty()) return icanc::tools::printUsage(kUsage, false);
  try {
    for (const std::string& s : scenarios) follow(s, twist, speed_only, trace, base_height);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "icanc_sim_odometry: %s\n", e.what());
    return 1;
  }
  return 0;
}
