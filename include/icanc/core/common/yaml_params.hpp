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
  SegmentLampParams lamp;  // light_controller section: the segmented lamp (issue 23)
  // The ground_truth section, with half_width_m and horizon_s from the danger section.
  CorridorParams corridor;
  IlluminationParams illumination;  // illumination_monitor section (camera)
  LidarOdometryParams lidar_odometry;  // lidar_odometry section (issue 19)
};

// Loads the obstacle_detector, danger_detector, light_controller, ground_truth, illumination_monitor
// and lidar_odometry sections of a profile and validates them; throws std::runtime_error naming
// the file and the key or problem.
Profile loadProfile(const std::string& path);

}  // namespace icanc
