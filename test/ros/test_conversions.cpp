// toObstacleMsg / toKinematics (src/ros/conversions.cpp): what the DangerDetector is given of a
// track is what the tracker holds, the footprint's parts included; dangerousBoxes: what lights the
// lamp's segments.
#include <cmath>

#include <gtest/gtest.h>

#include "icanc/ros/conversions.hpp"

namespace icanc {
namespace {

TEST(Conversions, ATrackRoundTripsIntoTheDangerModelsKinematics) {
  MultiObjectTracker tracker;
  Box3D b;
  b.center = Eigen::Vector3f(6.0f, -1.0f, 0.8f);
  b.size = Eigen::Vector3f(2.0f, 1.0f, 1.6f);
  b.yaw = 0.3f;
  b.min = Eigen::Vector3f(5.0f, -1.5f, 0.0f);
  b.max = Eigen::Vector3f(7.0f, -0.5f, 1.6f);
  b.num_points = 40;
  b.footprint = {{Eigen::Vector2f(5.0f, -1.5f), Eigen::Vector2f(5.9f, -1.4f)},
                 {Eigen::Vector2f(6.0f, -1.5f), Eigen::Vector2f(7.0f, -0.5f)}};
  tracker.update(0.0, {b});
  b.center.x() -= 0.1f;
  b.min.x() -= 0.1f;
  b.max.x() -= 0.1f;
  for (FootprintCell& c : b.footprint) {
    c.min.x() -= 0.1f;
    c.max.x() -= 0.1f;
  }
  tracker.update(0.1, {b});
  ASSERT_EQ(tracker.tracks().size(), 1u);
  const Track& track = tracker.tracks()[0];

  Obstacle msg;
  toObstacleMsg(track, EgoStep(), msg);
  EXPECT_EQ(msg.id, track.id);
  EXPECT_NEAR(2.0 * std::atan2(msg.pose.orientation.z, msg.pose.orientation.w), 0.3, 1e-6);
  EXPECT_EQ(msg.num_points, 40u);
  EXPECT_EQ(msg.age, 2u);
  ASSERT_EQ(msg.footprint.size(), 2u);
  EXPECT_FLOAT_EQ(msg.footprint[1].x_max, track.box.footprint[1].max.x());
  EXPECT_FLOAT_EQ(msg.footprint[0].y_min, track.box.footprint[0].min.y());

  const ObjectKinematics k = toKinematics(msg, geometry_msgs::Twist());
  EXPECT_TRUE(k.aabb_min.isApprox(track.box.min.cast<double>(), 1e-6));
  EXPECT_TRUE(k.aabb_max.isApprox(track.box.max.cast<double>(), 1e-6));
  EXPECT_TRUE(k.velocity.isApprox(track.velocity(), 1e-6));
  EXPECT_TRUE(k.velocity_std.isApprox(track.velocityStdXY(), 1e-6));
  ASSERT_EQ(k.footprint.size(), 2u);
  for (std::size_t i = 0; i < 2; ++i) {
    EXPECT_TRUE(k.footprint[i].min().isApprox(track.box.footprint[i].min.cast<double>(), 1e-6));
    EXPECT_TRUE(k.footprint[i].max().isApprox(track.box.footprint[i].max.cast<double>(), 1e-6));
  }
  EXPECT_LT(k.velocity.x(), -0.3);  // it is closing in: 0.1 m per 0.1 s
  EXPECT_NEAR(msg.heading, M_PI, 1e-6);  // straight toward the vehicle: pi [rad], never -pi
  // No ego motion: over ground is relative.
  EXPECT_DOUBLE_EQ(msg.velocity_over_ground.x, msg.velocity.x);
}

// With the vehicle's motion, the message carries the velocity over ground (the filter's)
// and the relative one the paper's rule uses, and the array's twist reaches the danger model.
TEST(Conversions, VelocityOverGroundAndRelativeToATurningVehicle) {
  MultiObjectTracker tracker;
  Box3D b;
  b.center = Eigen::Vector3f(10.0f, 0.0f, 0.8f);
  b.size = Eigen::Vector3f(0.5f, 0.5f, 1.6f);
  b.min = b.center - 0.5f * b.size;
  b.max = b.center + 0.5f * b.size;
  tracker.update(0.0, {b});
  ASSERT_EQ(tracker.tracks().size(), 1u);
  EgoStep ego;
  ego.status = EgoStep::Status::kMeasured;
  ego.linear_velocity = Eigen::Vector3d(5.0, 0.0, 0.0);
  ego.yaw_rate_rad_s = 0.5;
  Obstacle msg;
  toObstacleMsg(tracker.tracks()[0], ego, msg);  // a standing object: zero over ground
  EXPECT_DOUBLE_EQ(msg.velocity_over_ground.x, 0.0);
  EXPECT_NEAR(msg.velocity.x, -5.0, 1e-6);  // the vehicle-fixed point (10, 0) moves at (5, 5)
  EXPECT_NEAR(msg.velocity.y, -5.0, 1e-6);
  EXPECT_NEAR(msg.speed, std::sqrt(50.0), 1e-5);
  EXPECT_NEAR(msg.heading, -0.75 * M_PI, 1e-6);  // toward and to the right: REP-103 radians
  const geometry_msgs::Twist twist = toTwistMsg(ego);
  EXPECT_DOUBLE_EQ(twist.angular.z, 0.5);
  const ObjectKinematics k = toKinematics(msg, twist);
  EXPECT_DOUBLE_EQ(k.ego_velocity.x(), 5.0);
  EXPECT_DOUBLE_EQ(k.ego_yaw_rate, 0.5);
}

// The planned path as the vehicle sees it: a vehicle at (10, 5) heading +y (90 deg) sees the
// point 2 m further along +y 2 m straight ahead, and one 3 m to its right (+x in the fixed frame)
// at y = -3, turned by -90 deg.
TEST(Conversions, APathSeenFromTheVehiclesPose) {
  const auto pose = [](double x, double y, double yaw) {
    Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
    p.translate(Eigen::Vector3d(x, y, 0.0));
    p.rotate(Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()));
    return p;
  };
  std_msgs::Header header;
  header.frame_id = "base_link";
  header.stamp = ros::Time(7.0);
  const nav_msgs::Path path = toRelativePath(
      header, pose(10, 5, M_PI / 2), {pose(10, 5, M_PI / 2), pose(10, 7, M_PI / 2), pose(13, 5, 0.0)});
  ASSERT_EQ(path.poses.size(), 3u);
  EXPECT_EQ(path.header.frame_id, "base_link");
  EXPECT_EQ(path.poses[2].header.stamp, ros::Time(7.0));
  EXPECT_NEAR(path.poses[0].pose.position.x, 0.0, 1e-9);
  EXPECT_NEAR(path.poses[1].pose.position.x, 2.0, 1e-9);
  EXPECT_NEAR(path.poses[1].pose.position.y, 0.0, 1e-9);
  EXPECT_NEAR(path.poses[2].pose.position.x, 0.0, 1e-9);
  EXPECT_NEAR(path.poses[2].pose.position.y, -3.0, 1e-9);
  // -90 deg about z: w = cos(-45 deg), z = sin(-45 deg).
  EXPECT_NEAR(path.poses[2].pose.orientation.z, -std::sqrt(0.5), 1e-9);
  EXPECT_NEAR(path.poses[2].pose.orientation.w, std::sqrt(0.5), 1e-9);
  EXPECT_TRUE(toRelativePath(header, pose(0, 0, 0), {}).poses.empty());
}

TEST(Conversions, TheDangerousObstaclesBoundsLightTheSegments) {
  ObstacleArray array;
  for (int i = 0; i < 3; ++i) {
    array.obstacles.emplace_back();
    Obstacle& o = array.obstacles.back();
    o.aabb_min.x = 5.0 + i;
    o.aabb_min.y = -1.0;
    o.aabb_min.z = 0.0;
    o.aabb_max.x = 6.0 + i;
    o.aabb_max.y = 0.5;
    o.aabb_max.z = 1.7;
    o.dangerous = i != 1;
  }
  std::vector<Eigen::AlignedBox2d> boxes(4);  // reused: what it held goes
  dangerousBoxes(array, boxes);
  ASSERT_EQ(boxes.size(), 2u);
  EXPECT_TRUE(boxes[0].min().isApprox(Eigen::Vector2d(5.0, -1.0)));
  EXPECT_TRUE(boxes[0].max().isApprox(Eigen::Vector2d(6.0, 0.5)));
  EXPECT_TRUE(boxes[1].min().isApprox(Eigen::Vector2d(7.0, -1.0)));
  EXPECT_TRUE(boxes[1].max().isApprox(Eigen::Vector2d(8.0, 0.5)));
}

}  // namespace
}  // namespace icanc
