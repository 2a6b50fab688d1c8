// Scenario files (YAML): the scene, its scripted motion, the sensor and its mount, the ego motion
// and the noise, deterministic from a seed. See config/scenarios/*.yaml.
#pragma once

#include <cstdint>
#include <string>

#include <Eigen/Geometry>

#include "icanc/sim/lidar_sim.hpp"

namespace icanc {
namespace sim {

struct Scenario {
  std::string name;
  std::string description;
  std::string lidar = "vlp16";               // LidarModel::byName
  std::string vehicle_frame = "base_link";
  std::string sensor_frame = "lidar";
  Eigen::Isometry3f sensor_mount = Eigen::Isometry3f::Identity();  // sensor in vehicle frame
  Eigen::Vector3f ego_velocity = Eigen::Vector3f::Zero();  // vehicle velocity in the world [m/s]
  double duration_s = 10.0;
  double rate_hz = 10.0;
  std::uint64_t seed = 1;
  NoiseParams noise;
  Scene scene;

  // Vehicle frame -> world at time t (the vehicle starts at the world origin, facing +x).
  Eigen::Isometry3f vehiclePose(double t) const;
  Eigen::Isometry3f sensorPose(double t) const { return vehiclePose(t) * sensor_mount; }
  std::size_t frames() const;
};

// Loads a scenario; throws std::runtime_error naming the file and the offending key.
Scenario loadScenario(const std::string& path);

}  // namespace sim
}  // namespace icanc
