// Reads a vehicle profile (config/*.yaml) without ROS, for the command-line tools.
#pragma once

#include <string>

#include "icanc/core/danger/danger.hpp"
#include "icanc/core/evaluation/ground_truth.hpp"
#include "icanc/core/camera/illumination.hpp"
#include "icanc/core/motion/lidar_odometry.hpp"
#include "icanc/core/light/lamp_segments.hpp"
#include "icanc/core/light/light_controller.hpp"
#include "icanc/core/perception/obstacle_detector.hpp"

namespace icanc {

struct Profile {
  ObstacleDetectorParams detector;
  DangerParams danger;
  LightControllerParams light;
  SegmentLampParams lamp;  // light_controller section: the segmented lamp
  // The ground_truth section; what it leaves out is the danger section's corridor (half_width_m,
  // reaction_time_s, predictive margin_m, vehicle_front_m, stopping_margin_m).
  CorridorParams corridor;
  IlluminationParams illumination;  // illumination_monitor section (camera)
  LidarOdometryParams lidar_odometry;  // lidar_odometry section
};

// Loads the obstacle_detector, danger_detector, light_controller, ground_truth, illumination_monitor
// and lidar_odometry sections of a profile and validates them; throws std::runtime_error naming
// the file and the key or problem.
Profile loadProfile(const std::string& path);

}  // namespace icanc
