// Reads a vehicle profile (config/*.yaml) without ROS, for the command-line tools.
#pragma once

#include <string>

#include "icanc/core/danger.hpp"
#include "icanc/core/light_controller.hpp"
#include "icanc/core/obstacle_detector.hpp"

namespace icanc {

struct Profile {
  ObstacleDetectorParams detector;
  DangerParams danger;
  LightControllerParams light;
};

// Loads the obstacle_detector, danger_detector and light_controller sections of a profile and
// validates them; throws std::runtime_error naming the file and the key or problem.
Profile loadProfile(const std::string& path);

}  // namespace icanc
