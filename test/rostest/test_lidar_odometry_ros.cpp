// rostest: the LidarOdometry nodelet in the icanc.launch graph. Simulated clouds (sensor frame
// test_lidar, 1.8 m above base_link by a static tf this test broadcasts) of a vehicle pulling away
// and turning in a street are published at 10 Hz; the nodelet's nav_msgs/Odometry and tf odom ->
// base_link must be stamped with the clouds' stamps and follow the true path; a malformed cloud is
// skipped without stopping it. In a corridor, the vehicle's speed on twist_topic carries the pose.
// With ego_motion/source not "lidar" it stays idle.
#include <algorithm>
#include <cstdio>
#include <limits>
#include <mutex>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <diagnostic_msgs/DiagnosticArray.h>
#include <geometry_msgs/TwistStamped.h>
#include <nav_msgs/Odometry.h>
#include <pcl_conversions/pcl_conversions.h>
#include <ros/ros.h>
#include <sensor_msgs/PointCloud2.h>
#include <tf2_eigen/tf2_eigen.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/static_transform_broadcaster.h>
#include <tf2_ros/transform_listener.h>

#include "../core/motion/lidar_odometry_scene.hpp"

namespace icanc {
namespace {

using namespace lio_scene;

struct OdomRecorder {
  std::mutex mutex;
  std::vector<nav_msgs::Odometry::ConstPtr> msgs;
  void onOdom(const nav_msgs::Odometry::ConstPtr& m) {
    std::lock_guard<std::mutex> lock(mutex);
    msgs.push_back(m);
  }
};

double yawOf(const Eigen::Isometry3d& pose) { return std::atan2(pose(1, 0), pose(0, 0)); }

bool waitForSubscriber(const ros::Publisher& pub, double seconds) {
  const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(seconds);
  while (pub.getNumSubscribers() == 0 && ros::WallTime::now() < end)
    ros::WallDuration(0.05).sleep();
  return pub.getNumSubscribers() > 0;
}

TEST(LidarOdometryNodelet, PublishesTfAndOdometryAlongTheTruePath) {
  ros::NodeHandle nh;
  ros::Publisher pub = nh.advertise<sensor_msgs::PointCloud2>("/test/points", 5);
  OdomRecorder rec;
  ros::Subscriber sub = nh.subscribe("/icanc/lidar_odom", 100, &OdomRecorder::onOdom, &rec);
  tf2_ros::Buffer buffer;
  tf2_ros::TransformListener listener(buffer);
  tf2_ros::StaticTransformBroadcaster mount_broadcaster;  // the sensor mount, as a vehicle has it
  geometry_msgs::TransformStamped mount;
  mount.header.stamp = ros::Time::now();
  mount.header.frame_id = "base_link";
  mount.child_frame_id = "test_lidar";
  mount.transform.translation.z = kMountZ;
  mount.transform.rotation.w = 1.0;
  mount_broadcaster.sendTransform(mount);
  // The manager (one connection for both nodelets, which share the cloud) subscribes, and the
  // odometry advertises lidar_odom once it is running.
  ASSERT_TRUE(waitForSubscriber(pub, 30.0)) << "nothing subscribed to the clouds";
  const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(30.0);
  while (sub.getNumPublishers() == 0 && ros::WallTime::now() < end) ros::WallDuration(0.05).sleep();
  ASSERT_GT(sub.getNumPublishers(), 0u) << "LidarOdometry did not advertise lidar_odom";
  ros::WallDuration(0.5).sleep();

  const sim::Scene scene = street();
  std::mt19937_64 rng(21);
  const ros::Time t0 = ros::Time::now();
  const int frames = 60;
  const int bad_frame = 20;
  ros::Rate rate(10.0);
  for (int f = 0; f <= frames && ros::ok(); ++f) {
    const double t = 0.1 * f;
    sensor_msgs::PointCloud2 msg;
    pcl::toROSMsg(sensorScan(scene, t, truePose(t), rng), msg);
    msg.header.frame_id = "test_lidar";
    msg.header.stamp = t0 + ros::Duration(t);
    if (f == bad_frame) msg.fields.resize(2);  // no z field: malformed, skipped
    pub.publish(msg);
    rate.sleep();
  }
  ros::WallDuration(1.0).sleep();

  std::lock_guard<std::mutex> lock(rec.mutex);
  ASSERT_GE(rec.msgs.size(), static_cast<std::size_t>(frames * 9 / 10)) << "odometry lost";
  for (const auto& m : rec.msgs) {
    EXPECT_EQ(m->header.frame_id, "odom");
    EXPECT_EQ(m->child_frame_id, "base_link");
    const double t = (m->header.stamp - t0).toSec();
    EXPECT_NEAR(t * 10.0, std::round(t * 10.0), 1e-3) << "stamp not a cloud's";
    EXPECT_NE(std::lround(t * 10.0), bad_frame) << "the malformed cloud got a pose";
    Eigen::Isometry3d pose;
    tf2::fromMsg(m->pose.pose, pose);
    const Eigen::Isometry3d truth = truePose(t);
    // As the core gtest: within 1.2 m and 0.06 rad over the 44 m path.
    EXPECT_LT((pose.translation() - truth.translation()).norm(), 1.2) << "t = " << t;
    EXPECT_LT(std::fabs(yawOf(pose) - yawOf(truth)), 0.06) << "t = " << t;
    EXPECT_GT(m->pose.covariance[0], 0.0);
    EXPECT_GT(m->twist.covariance[35], 0.0);
  }
  const auto& last = rec.msgs.back();
  EXPECT_NEAR((last->header.stamp - t0).toSec(), 0.1 * frames, 1e-3);
  EXPECT_NEAR(last->twist.twist.linear.x, 8.0, 0.8);  // straight again at 8 m/s
  // The tf at the last stamp is the odometry's pose.
  geometry_msgs::TransformStamped tf;
  ASSERT_NO_THROW(
      tf = buffer.lookupTransform("odom", "base_link", last->header.stamp, ros::Duration(2.0)));
  EXPECT_NEAR(tf.transform.translation.x, last->pose.pose.position.x, 1e-6);
  EXPECT_NEAR(tf.transform.translation.y, last->pose.pose.position.y, 1e-6);
  EXPECT_NEAR(tf.transform.rotation.z, last->pose.pose.orientation.z, 1e-6);
}

// The corridor (nothing faces along it) with the vehicle's speed on the profile's twist_topic
// (/vehicle/twist, geometry_msgs/TwistStamped at 50 Hz as a CAN bridge sends it, 1 % over): the
// pose follows the vehicle, where without it the odometry says "not moving" (the core gtest
// MeasuredSpeedCarriesItAlongACorridor: 24 m off). Its stamps start 100 s before the street's:
// time going backwards restarts the odometry at identity. One speed is not a number, one is
// 500 m/s and one has stamp 0: dropped and counted, the rest goes on.
TEST(LidarOdometryNodelet, TheVehicleSpeedCarriesItWhereTheSceneCannot) {
  ros::NodeHandle nh;
  std::string twist_topic;
  ASSERT_TRUE(nh.getParam("/icanc/lidar_odometry/twist_topic", twist_topic));
  ASSERT_EQ(twist_topic, "/vehicle/twist");
  ros::Publisher pub = nh.advertise<sensor_msgs::PointCloud2>("/test/points", 5);
  ros::Publisher speed_pub = nh.advertise<geometry_msgs::TwistStamped>(twist_topic, 50);
  std::mutex diag_mutex;
  double invalid_twists = -1.0;  // the odometry's diagnostics counter, last published
  ros::Subscriber diag = nh.subscribe<diagnostic_msgs::DiagnosticArray>(
      "/diagnostics", 20, [&](const diagnostic_msgs::DiagnosticArray::ConstPtr& m) {
        for (const auto& status : m->status)
          for (const auto& kv : status.values)
            if (kv.key == "invalid vehicle speeds") {
              std::lock_guard<std::mutex> l(diag_mutex);
              invalid_twists = std::stod(kv.value);
            }
      });
  OdomRecorder rec;
  ros::Subscriber sub = nh.subscribe("/icanc/lidar_odom", 100, &OdomRecorder::onOdom, &rec);
  ASSERT_TRUE(waitForSubscriber(pub, 30.0));
  ASSERT_TRUE(waitForSubscriber(speed_pub, 30.0)) << "LidarOdometry did not subscribe to the speed";
  ros::WallDuration(0.5).sleep();

  const sim::Scene scene = corridor();
  std::mt19937_64 rng(23);
  const ros::Time t0 = ros::Time::now() - ros::Duration(100.0);
  const int frames = 40;
  ros::Rate rate(50.0);
  for (int k = 0; k <= 5 * frames && ros::ok(); ++k) {  // 50 Hz speed, a cloud every 5th
    const double t = 0.02 * k;
    geometry_msgs::TwistStamped speed;
    speed.header.stamp = t0 + ros::Duration(t);
    speed.header.frame_id = "base_link";
    speed.twist.linear.x = 1.01 * std::min(8.0, 4.0 * t);
    if (k == 52) speed.twist.linear.x = std::numeric_limits<double>::quiet_NaN();
    if (k == 73) speed.twist.linear.x = 500.0;
    if (k == 91) speed.header.stamp = ros::Time();  // unstamped
    speed_pub.publish(speed);
    if (k % 5 == 0) {
      sensor_msgs::PointCloud2 msg;
      pcl::toROSMsg(sensorScan(scene, t, truePose(t, 8.0, false), rng), msg);
      msg.header.frame_id = "test_lidar";
      msg.header.stamp = t0 + ros::Duration(t);
      pub.publish(msg);
    }
    rate.sleep();
  }
  ros::WallDuration(1.0).sleep();

  std::lock_guard<std::mutex> lock(rec.mutex);
  std::size_t seen = 0;
  double worst = 0.0;
  for (const auto& m : rec.msgs) {
    const double t = (m->header.stamp - t0).toSec();
    if (t < -1e-6 || t > 0.1 * frames + 1e-6) continue;  // the street test's
    ++seen;
    Eigen::Isometry3d pose;
    tf2::fromMsg(m->pose.pose, pose);
    worst = std::max(worst, (pose.translation() - truePose(t, 8.0, false).translation()).norm());
  }
  ASSERT_GE(seen, static_cast<std::size_t>(frames * 9 / 10)) << "odometry lost";
  std::printf("[ MEASURE ] corridor with the vehicle speed: worst error %.2f m over 24 m\n", worst);
  EXPECT_LT(worst, 0.6);
  EXPECT_NEAR(rec.msgs.back()->twist.twist.linear.x, 8.08, 0.4);
  // The three samples that are no measurement, counted in diagnostics (published at 1 Hz).
  const ros::WallTime until = ros::WallTime::now() + ros::WallDuration(5.0);
  while (ros::WallTime::now() < until) {
    {
      std::lock_guard<std::mutex> l(diag_mutex);
      if (invalid_twists >= 3.0) break;
    }
    ros::WallDuration(0.1).sleep();
  }
  std::lock_guard<std::mutex> l(diag_mutex);
  EXPECT_EQ(invalid_twists, 3.0);
}

TEST(LidarOdometryNodelet, IdleUnlessTheSourceIsLidar) {
  ros::NodeHandle nh;
  std::string source;
  nh.param<std::string>("/icanc/ego_motion/source", source, "");
  ASSERT_NE(source, "lidar");
  ros::Publisher pub = nh.advertise<sensor_msgs::PointCloud2>("/test/points", 5);
  OdomRecorder rec;
  ros::Subscriber sub = nh.subscribe("/icanc/lidar_odom", 100, &OdomRecorder::onOdom, &rec);
  ASSERT_TRUE(waitForSubscriber(pub, 30.0)) << "the detector never subscribed";
  ros::WallDuration(3.0).sleep();  // time for the odometry nodelet to come up (and stay idle)
  EXPECT_EQ(sub.getNumPublishers(), 0u) << "an idle LidarOdometry advertises nothing";
  const sim::Scene scene = street();
  std::mt19937_64 rng(22);
  for (int f = 0; f < 10; ++f) {
    sensor_msgs::PointCloud2 msg;
    pcl::toROSMsg(sensorScan(scene, 0.1 * f, truePose(0.1 * f), rng), msg);
    msg.header.frame_id = "test_lidar";
    msg.header.stamp = ros::Time::now();
    pub.publish(msg);
    ros::WallDuration(0.1).sleep();
  }
  ros::WallDuration(0.5).sleep();
  std::lock_guard<std::mutex> lock(rec.mutex);
  EXPECT_TRUE(rec.msgs.empty());
}

}  // namespace
}  // namespace icanc

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_lidar_odometry_ros");
  ros::AsyncSpinner spinner(2);
  spinner.start();
  return RUN_ALL_TESTS();
}
