// Message <-> core conversions.
#pragma once

#include <vector>

#include <Eigen/Geometry>
#include <geometry_msgs/Twist.h>
#include <nav_msgs/Path.h>
#include <sensor_msgs/PointCloud2.h>
#include <std_msgs/Header.h>

#include "icanc/LampState.h"
#include "icanc/Obstacle.h"
#include "icanc/ObstacleArray.h"
#include "icanc/core/bridge/light_bridge_host.hpp"
#include "icanc/core/bridge/rosserial_protocol.hpp"
#include "icanc/core/perception/cloud_decode.hpp"
#include "icanc/core/danger/danger.hpp"
#include "icanc/core/motion/ego_motion.hpp"
#include "icanc/core/tracking/tracker.hpp"

namespace icanc {

// A view of the message's layout and bytes (no copy; valid while msg lives).
RawCloud toRawCloud(const sensor_msgs::PointCloud2& msg);

// A tracked object as an icanc/Obstacle: pose, boxes, the filter's velocity over ground, the
// velocity relative to the vehicle moving as `ego` says (relativeVelocity), speed and heading of
// the relative one. The danger fields are left zero for the DangerDetector.
void toObstacleMsg(const Track& track, const EgoStep& ego, Obstacle& out);

// The vehicle's twist as a message (linear velocity, yaw rate as angular z).
geometry_msgs::Twist toTwistMsg(const EgoStep& ego);

// What the danger rules need of an icanc/Obstacle, with the vehicle's twist of its array.
ObjectKinematics toKinematics(const Obstacle& obstacle, const geometry_msgs::Twist& ego_twist);

// The x-y of the axis-aligned bounds of the array's obstacles flagged dangerous (what lights the
// segments of the lamp), into `boxes` (cleared first: reused).
void dangerousBoxes(const ObstacleArray& array, std::vector<Eigen::AlignedBox2d>& boxes);

// lamp_status as the LightBridge decided it, stamped `stamp`.
LampState::ConstPtr toLampStateMsg(const LampStatusSnapshot& status, const ros::Time& stamp);

// A ROS time as a rosserial device receives it (std_msgs/Time).
inline rosserial::Stamp toStamp(const ros::Time& t) { return rosserial::Stamp{t.sec, t.nsec}; }

// A path of `poses` (in one fixed frame) as the vehicle at `here` (its pose in that frame) sees
// it: each pose relative to here, every one under `header` (the vehicle frame, the stamp). The
// simulated and KITTI bags' /planned_path.
nav_msgs::Path toRelativePath(const std_msgs::Header& header, const Eigen::Isometry3d& here,
                              const std::vector<Eigen::Isometry3d>& poses);

}  // namespace icanc
