// Message <-> core conversions.
#pragma once

#include <sensor_msgs/PointCloud2.h>

#include "icanc/Obstacle.h"
#include "icanc/core/cloud_decode.hpp"
#include "icanc/core/danger.hpp"
#include "icanc/core/tracker.hpp"

namespace icanc {

// A view of the message's layout and bytes (no copy; valid while msg lives).
RawCloud toRawCloud(const sensor_msgs::PointCloud2& msg);

// A tracked object as an icanc/Obstacle: pose, boxes, filtered velocity, speed and heading.
// The danger fields are left zero for the DangerDetector.
void toObstacleMsg(const Track& track, Obstacle& out);

// What the danger rules need of an icanc/Obstacle.
ObjectKinematics toKinematics(const Obstacle& obstacle);

}  // namespace icanc
