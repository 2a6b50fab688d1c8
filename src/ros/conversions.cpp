#include "icanc/ros/conversions.hpp"

#include <cmath>

#include <boost/make_shared.hpp>
#include <tf2_eigen/tf2_eigen.h>

namespace icanc {

RawCloud toRawCloud(const sensor_msgs::PointCloud2& msg) {
  RawCloud raw;
  raw.width = msg.width;
  raw.height = msg.height;
  raw.point_step = msg.point_step;
  raw.row_step = msg.row_step;
  raw.is_bigendian = msg.is_bigendian;
  raw.fields.reserve(msg.fields.size());
  for (const auto& f : msg.fields) raw.fields.push_back({f.name, f.offset, f.datatype, f.count});
  raw.data = msg.data.data();
  raw.data_size = msg.data.size();
  return raw;
}

void toObstacleMsg(const Track& track, const EgoStep& ego, Obstacle& out) {
  const Eigen::Vector3f& p = track.box.center;
  const Eigen::Vector3d ground = track.velocity();
  const Eigen::Vector3d v =
      relativeVelocity(ground, p.cast<double>(), ego.linear_velocity, ego.yaw_rate_rad_s);
  out.id = track.id;
  out.pose.position.x = p.x();
  out.pose.position.y = p.y();
  out.pose.position.z = p.z();
  out.pose.orientation.x = 0.0;
  out.pose.orientation.y = 0.0;
  out.pose.orientation.z = std::sin(0.5 * track.box.yaw);
  out.pose.orientation.w = std::cos(0.5 * track.box.yaw);
  out.dimensions.x = track.box.size.x();
  out.dimensions.y = track.box.size.y();
  out.dimensions.z = track.box.size.z();
  out.aabb_min.x = track.box.min.x();
  out.aabb_min.y = track.box.min.y();
  out.aabb_min.z = track.box.min.z();
  out.aabb_max.x = track.box.max.x();
  out.aabb_max.y = track.box.max.y();
  out.aabb_max.z = track.box.max.z();
  out.footprint.resize(track.box.footprint.size());
  for (std::size_t i = 0; i < track.box.footprint.size(); ++i) {
    const FootprintCell& cell = track.box.footprint[i];
    out.footprint[i].x_min = cell.min.x();
    out.footprint[i].x_max = cell.max.x();
    out.footprint[i].y_min = cell.min.y();
    out.footprint[i].y_max = cell.max.y();
  }
  out.velocity.x = v.x();
  out.velocity.y = v.y();
  out.velocity.z = v.z();
  out.velocity_over_ground.x = ground.x();
  out.velocity_over_ground.y = ground.y();
  out.velocity_over_ground.z = ground.z();
  out.speed = getSpeedOfObject(v);
  out.heading = headingRad(v);
  out.velocity_std = track.velocityStd();
  const Eigen::Vector2d std_xy = track.velocityStdXY();
  out.velocity_std_axes.x = std_xy.x();
  out.velocity_std_axes.y = std_xy.y();
  out.age = track.age;
  out.hits = track.hits;
  out.motion_state = static_cast<std::uint8_t>(track.motion);
  out.motion_points_tested = track.evidence.tested;
  out.motion_points_free = track.evidence.free;
  out.motion_points_seen = track.evidence.seen;
  out.missed = track.coasted();
  out.num_points = track.box.num_points;
}

geometry_msgs::Twist toTwistMsg(const EgoStep& ego) {
  geometry_msgs::Twist twist;
  twist.linear.x = ego.linear_velocity.x();
  twist.linear.y = ego.linear_velocity.y();
  twist.linear.z = ego.linear_velocity.z();
  twist.angular.z = ego.yaw_rate_rad_s;
  return twist;
}

LampState::ConstPtr toLampStateMsg(const LampStatusSnapshot& status, const ros::Time& stamp) {
  auto msg = boost::make_shared<LampState>();
  msg->header.stamp = stamp;
  msg->state = static_cast<std::uint8_t>(status.status);
  msg->link_up = status.link_up;
  msg->commanded_on = status.commanded_on;
  return msg;
}

void dangerousBoxes(const ObstacleArray& array, std::vector<Eigen::AlignedBox2d>& boxes) {
  boxes.clear();
  for (const Obstacle& o : array.obstacles)
    if (o.dangerous)
      boxes.emplace_back(Eigen::Vector2d(o.aabb_min.x, o.aabb_min.y), Eigen::Vector2d(o.aabb_max.x, o.aabb_max.y));
}

ObjectKinematics toKinematics(const Obstacle& o, const geometry_msgs::Twist& ego_twist) {
  ObjectKinematics k;
  k.center = Eigen::Vector3d(o.pose.position.x, o.pose.position.y, o.pose.position.z);
  k.aabb_min = Eigen::Vector3d(o.aabb_min.x, o.aabb_min.y, o.aabb_min.z);
  k.aabb_max = Eigen::Vector3d(o.aabb_max.x, o.aabb_max.y, o.aabb_max.z);
  k.velocity = Eigen::Vector3d(o.velocity.x, o.velocity.y, o.velocity.z);
  k.velocity_std = Eigen::Vector2d(o.velocity_std_axes.x, o.velocity_std_axes.y);
  k.ego_velocity = Eigen::Vector2d(ego_twist.linear.x, ego_twist.linear.y);
  k.ego_yaw_rate = ego_twist.angular.z;
  k.motion = o.motion_state == Obstacle::MOTION_STATIC   ? MotionState::kStatic
             : o.motion_state == Obstacle::MOTION_MOVING ? MotionState::kMoving
                                                         : MotionState::kUnknown;
  k.footprint.reserve(o.footprint.size());
  for (const auto& cell : o.footprint)
    k.footprint.emplace_back(Eigen::Vector2d(cell.x_min, cell.y_min),
                             Eigen::Vector2d(cell.x_max, cell.y_max));
  return k;
}

nav_msgs::Path toRelativePath(const std_msgs::Header& header, const Eigen::Isometry3d& here,
                              const std::vector<Eigen::Isometry3d>& poses) {
  nav_msgs::Path path;
  path.header = header;
  const Eigen::Isometry3d here_inv = here.inverse();
  path.poses.reserve(poses.size());
  for (const Eigen::Isometry3d& pose : poses) {
    geometry_msgs::PoseStamped stamped;
    stamped.header = header;
    stamped.pose = tf2::toMsg(here_inv * pose);
    path.poses.push_back(stamped);
  }
  return path;
}

}  // namespace icanc
