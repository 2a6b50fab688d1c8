// Scenario files (YAML): the scene, its scripted motion, the sensor and its mount, the ego motion
// and the noise, deterministic from a seed. See config/scenarios/*.yaml.
#pragma once

#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "icanc/core/motion/measured_twist.hpp"
#include "icanc/sim/lidar_sim.hpp"
#include "icanc/sim/path.hpp"

namespace icanc {
namespace sim {

// The vehicle's motion at one time: velocity in its own frame and yaw rate.
struct EgoTwist {
  Eigen::Vector3f linear = Eigen::Vector3f::Zero();  // [m/s] in the vehicle frame
  float yaw_rate = 0.0f;                             // [rad/s]
};

struct Scenario {
  std::string name;
  std::string description;
  std::string lidar = "vlp16";               // LidarModel::byName
  std::string vehicle_frame = "base_link";
  std::string sensor_frame = "lidar";
  Eigen::Isometry3f sensor_mount = Eigen::Isometry3f::Identity();  // sensor in vehicle frame
  Eigen::Vector3f ego_velocity = Eigen::Vector3f::Zero();  // vehicle velocity in the world [m/s]
  // When not empty, the vehicle follows these segments from the origin (facing +x) instead of
  // ego_velocity (poseAlong: exact arcs, continuous at the joins; the last segment's motion
  // continues past its end, where the truth looks a reaction time past the last frame).
  std::vector<PathSegment> ego_segments;
  double duration_s = 10.0;
  double rate_hz = 10.0;
  std::uint64_t seed = 1;
  // Vehicle profile whose corridor defines the ground truth: config/<profile>.yaml (see
  // profilePath), or a path ending in .yaml relative to the scenario file's directory.
  std::string profile = "zebra";
  NoiseParams noise;
  Scene scene;

  // Vehicle frame -> world at time t (the vehicle starts at the world origin, facing +x).
  Eigen::Isometry3f vehiclePose(double t) const;
  // The vehicle's velocity in its own frame and its yaw rate at time t (at a join: the later
  // segment's).
  EgoTwist vehicleTwist(double t) const;
  // The vehicle's velocity in the world at time t.
  Eigen::Vector3f vehicleVelocity(double t) const;
  Eigen::Isometry3f sensorPose(double t) const { return vehiclePose(t) * sensor_mount; }
  std::size_t frames() const;
};

// The vehicle's motion at t as its CAN bus reports it (icanc_sim_bag's /vehicle/twist, kCanTwistHz):
// the wheel speed 1 % over (a tyre's rolling radius is never the nominal one) with 0.05 m/s noise
// while the wheels turn and exactly zero while they stand,
// the stability control's yaw rate with a 0.003 rad/s bias and 0.01 rad/s noise. Two draws of rng.
constexpr double kCanTwistHz = 50.0;
MeasuredTwist canTwist(const Scenario& s, double t, std::mt19937_64& rng);

// Loads a scenario; throws std::runtime_error naming the file and the offending key.
Scenario loadScenario(const std::string& path);

// The profile file of a scenario loaded from scenario_path: a bare name resolves to
// <scenario dir>/../<name>.yaml (config/scenarios/x.yaml -> config/<name>.yaml); a name ending in
// .yaml is a path, relative to the scenario file's directory unless absolute.
std::string profilePath(const std::string& scenario_path, const std::string& profile);

}  // namespace sim
}  // namespace icanc
