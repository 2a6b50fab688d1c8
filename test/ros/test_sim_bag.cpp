// icanc_sim_bag's ego motion topics: for a vehicle that turns, /odom (nav_msgs/Odometry)
// is written at every cloud stamp with the pose of base_link in odom equal to /tf's and to the
// closed-form circle, and the twist in base_link (speed along x, yaw rate about z); /planned_path
// (nav_msgs/Path) at every cloud stamp holds the path driven, seen from the vehicle there.
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nav_msgs/Odometry.h>
#include <nav_msgs/Path.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/PointCloud2.h>
#include <tf2_msgs/TFMessage.h>
#include <unistd.h>

namespace {

double yawOf(const geometry_msgs::Quaternion& q) {
  return std::atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z));
}

// 2 s straight at 8 m/s, then a left circle at 8 m/s and 30 deg/s (R = 15.28 m about (16, R)),
// rendered into a bag whose path is returned.
std::string turningBag(const std::string& name) {
  const std::string dir = ::testing::TempDir() + name + std::to_string(::getpid());
  const std::string scenario = dir + ".yaml";
  const std::string bag_path = dir + ".bag";
  // 2 s straight at 8 m/s, then a left circle at 8 m/s and 30 deg/s (R = 15.28 m about (16, R)).
  std::ofstream(scenario) << "name: turn\nduration_s: 4\nrate_hz: 5\nprofile: zebra\n"
                             "sensor: {model: vlp16, mount_xyz: [0, 0, 1]}\n"
                             "ego:\n  segments:\n    - {duration_s: 2, speed_mps: 8}\n"
                             "    - {duration_s: 2, speed_mps: 8, yaw_rate_deg_s: 30}\n"
                             "objects:\n  - {position: [10, 5, 0]}\n";
  const std::string profile = std::string(ICANC_SOURCE_DIR) + "/config/zebra.yaml";
  const std::string command = std::string(ICANC_SIM_BAG) + " " + scenario + " " + bag_path +
                              " --profile " + profile + " > /dev/null";
  EXPECT_EQ(std::system(command.c_str()), 0) << command;
  return bag_path;
}

// The closed-form pose of that drive at t: x, y, yaw.
std::array<double, 3> turningPose(double t) {
  const double w = 30.0 * M_PI / 180.0, r = 8.0 / w;
  const double turned = t < 2.0 ? 0.0 : w * (t - 2.0);
  return {t < 2.0 ? 8.0 * t : 16.0 + r * std::sin(turned), t < 2.0 ? 0.0 : r * (1.0 - std::cos(turned)),
          turned};
}

TEST(SimBag, OdometryFollowsTheTurningVehicleAtEveryCloudStamp) {
  const std::string bag_path = turningBag("icanc_sim_bag_turn_");
  rosbag::Bag bag(bag_path, rosbag::bagmode::Read);
  std::vector<ros::Time> clouds;
  std::vector<nav_msgs::Odometry> odoms;
  std::vector<geometry_msgs::TransformStamped> tfs;
  for (const rosbag::MessageInstance& m : rosbag::View(bag)) {
    if (m.getTopic() == "/points")
      clouds.push_back(m.instantiate<sensor_msgs::PointCloud2>()->header.stamp);
    if (m.getTopic() == "/odom") odoms.push_back(*m.instantiate<nav_msgs::Odometry>());
    if (m.getTopic() == "/tf")
      tfs.push_back(m.instantiate<tf2_msgs::TFMessage>()->transforms.at(0));
  }
  ASSERT_EQ(clouds.size(), 21u);
  ASSERT_EQ(odoms.size(), clouds.size());
  ASSERT_EQ(tfs.size(), clouds.size());
  const double w = 30.0 * M_PI / 180.0;
  for (std::size_t k = 0; k < clouds.size(); ++k) {
    const nav_msgs::Odometry& o = odoms[k];
    const double t = 0.2 * double(k);
    EXPECT_EQ(o.header.stamp, clouds[k]);
    EXPECT_EQ(o.header.frame_id, "odom");
    EXPECT_EQ(o.child_frame_id, "base_link");
    EXPECT_NEAR(o.pose.pose.position.x, tfs[k].transform.translation.x, 1e-9);
    EXPECT_NEAR(o.pose.pose.position.y, tfs[k].transform.translation.y, 1e-9);
    EXPECT_NEAR(yawOf(o.pose.pose.orientation), yawOf(tfs[k].transform.rotation), 1e-9);
    const std::array<double, 3> truth = turningPose(t);
    EXPECT_NEAR(o.pose.pose.position.x, truth[0], 1e-4) << t;
    EXPECT_NEAR(o.pose.pose.position.y, truth[1], 1e-4) << t;
    EXPECT_NEAR(yawOf(o.pose.pose.orientation), truth[2], 1e-5) << t;
    EXPECT_NEAR(o.twist.twist.linear.x, 8.0, 1e-6);  // in base_link: always straight ahead
    EXPECT_NEAR(o.twist.twist.linear.y, 0.0, 1e-6);
    EXPECT_NEAR(o.twist.twist.angular.z, t < 2.0 ? 0.0 : w, 1e-6) << t;  // at 2 s: the arc's
  }
  bag.close();
  std::remove(bag_path.c_str());
}

TEST(SimBag, PlannedPathIsThePathDrivenSeenFromEachCloudsPose) {
  const std::string bag_path = turningBag("icanc_sim_bag_path_");
  rosbag::Bag bag(bag_path, rosbag::bagmode::Read);
  std::vector<ros::Time> clouds;
  std::vector<nav_msgs::Path> paths;
  for (const rosbag::MessageInstance& m : rosbag::View(bag)) {
    if (m.getTopic() == "/points")
      clouds.push_back(m.instantiate<sensor_msgs::PointCloud2>()->header.stamp);
    if (m.getTopic() == "/planned_path") paths.push_back(*m.instantiate<nav_msgs::Path>());
  }
  ASSERT_EQ(clouds.size(), 21u);
  ASSERT_EQ(paths.size(), clouds.size());
  for (std::size_t k = 0; k < clouds.size(); ++k) {
    const nav_msgs::Path& p = paths[k];
    EXPECT_EQ(p.header.stamp, clouds[k]);
    EXPECT_EQ(p.header.frame_id, "base_link");
    ASSERT_GE(p.poses.size(), 31u);  // 6 s ahead every 0.2 s (and up to 1 s behind)
    const double t = 0.2 * double(k);
    // The vehicle itself is on it (a pose at the origin), and its last pose is where the vehicle
    // is 6 s later, seen from its pose at t.
    bool through_vehicle = false;
    for (const geometry_msgs::PoseStamped& pose : p.poses)
      through_vehicle = through_vehicle || std::hypot(pose.pose.position.x, pose.pose.position.y) < 1e-4;
    EXPECT_TRUE(through_vehicle) << t;
    const std::array<double, 3> now = turningPose(t), end = turningPose(t + 6.0);
    const double dx = end[0] - now[0], dy = end[1] - now[1], c = std::cos(now[2]), s = std::sin(now[2]);
    EXPECT_NEAR(p.poses.back().pose.position.x, c * dx + s * dy, 1e-3) << t;
    EXPECT_NEAR(p.poses.back().pose.position.y, -s * dx + c * dy, 1e-3) << t;
    EXPECT_NEAR(std::remainder(yawOf(p.poses.back().pose.orientation) - (end[2] - now[2]), 2.0 * M_PI), 0.0, 1e-4)
        << t;
  }
  bag.close();
  std::remove(bag_path.c_str());
}

}  // namespace
