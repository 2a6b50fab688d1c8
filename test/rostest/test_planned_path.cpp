// rostest: the DangerDetector nodelet with ~predictive/path_topic. Obstacle arrays are
// published on its input as the ObstacleDetector would: an S-bend where the vehicle still turns
// right (-0.15 rad/s at 10 m/s) and the road already bends left, a car parked on the right of the
// road. Along the planner's path the car is beside the road; along the twist it is in the turn.
// A stale, unstamped, far or untransformable path is not used, and each reason is counted.
#include <cmath>
#include <map>
#include <mutex>
#include <string>

#include <diagnostic_msgs/DiagnosticArray.h>
#include <gtest/gtest.h>
#include <nav_msgs/Path.h>
#include <ros/ros.h>
#include <tf2_ros/static_transform_broadcaster.h>

#include "graph_fixture.hpp"
#include "icanc/ObstacleArray.h"

namespace icanc {
namespace {

using test::waitFor;

constexpr double kRadius = 66.7, kSpeed = 10.0, kYawRate = -0.15;

// The point of the left bend s metres ahead, offset metres to its left (vehicle frame).
void onBend(double s, double offset, double& x, double& y) {
  const double a = s / kRadius;
  x = (kRadius - offset) * std::sin(a);
  y = kRadius - (kRadius - offset) * std::cos(a);
}

class PlannedPath : public ::testing::Test {
 protected:
  PlannedPath() {
    obstacles_pub_ = nh_.advertise<ObstacleArray>("/icanc/obstacles", 10);
    path_pub_ = nh_.advertise<nav_msgs::Path>("/test/planned_path", 10, true);
    danger_sub_ = nh_.subscribe<ObstacleArray>("/icanc/obstacles_danger", 50,
        [this](const ObstacleArray::ConstPtr& m) {
          std::lock_guard<std::mutex> lock(mutex_);
          judged_[m->header.stamp] = m->obstacles.empty() ? -1 : m->obstacles[0].dangerous;
        });
    diag_sub_ = nh_.subscribe<diagnostic_msgs::DiagnosticArray>("/diagnostics", 100,
        [this](const diagnostic_msgs::DiagnosticArray::ConstPtr& m) {
          std::lock_guard<std::mutex> lock(mutex_);
          for (const auto& s : m->status)
            if (s.name.find("danger detector") != std::string::npos)
              for (const auto& kv : s.values) diag_[kv.key] = kv.value;
        });
    // odom = base_link (the vehicle at the origin of odom for the whole test).
    geometry_msgs::TransformStamped t;
    t.header.frame_id = "odom";
    t.child_frame_id = "base_link";
    t.transform.rotation.w = 1.0;
    tf_.sendTransform(t);
  }

  // The parked car of the S-bend, judged at `stamp`; true once its array came back.
  int judge(const ros::Time& stamp) {
    ObstacleArray a;
    a.header.stamp = stamp;
    a.header.frame_id = "base_link";
    a.ego_twist.linear.x = kSpeed;
    a.ego_twist.angular.z = kYawRate;
    Obstacle o;
    o.id = 7;
    o.hits = 20;
    double x, y;
    onBend(16.0, -3.3, x, y);
    o.pose.position.x = x;
    o.pose.position.y = y;
    o.pose.orientation.w = 1.0;
    o.aabb_min.x = x - 2.2;
    o.aabb_max.x = x + 2.2;
    o.aabb_min.y = y - 0.9;
    o.aabb_max.y = y + 0.9;
    o.aabb_min.z = -0.8;
    o.aabb_max.z = 0.8;
    // Standing still: minus the velocity of the vehicle-fixed point where it is.
    o.velocity.x = -kSpeed + kYawRate * y;
    o.velocity.y = -kYawRate * x;
    a.obstacles.push_back(o);
    obstacles_pub_.publish(a);
    int result = -2;
    waitFor([&] {
      std::lock_guard<std::mutex> lock(mutex_);
      const auto it = judged_.find(stamp);
      if (it == judged_.end()) return false;
      result = it->second;
      return true;
    }, 10.0);
    return result;
  }

  void publishPath(const ros::Time& stamp, const std::string& frame, double offset) {
    nav_msgs::Path p;
    p.header.stamp = stamp;
    p.header.frame_id = frame;
    for (double s = -5.0; s <= 60.0; s += 1.0) {
      geometry_msgs::PoseStamped pose;
      pose.header = p.header;
      onBend(s, offset, pose.pose.position.x, pose.pose.position.y);
      pose.pose.orientation.w = 1.0;
      p.poses.push_back(pose);
    }
    path_pub_.publish(p);
    ros::WallDuration(0.2).sleep();  // delivered before the arrays that follow
  }

  std::string diag(const std::string& key) {
    std::lock_guard<std::mutex> lock(mutex_);
    const auto it = diag_.find(key);
    return it == diag_.end() ? "" : it->second;
  }

  ros::NodeHandle nh_;
  ros::Publisher obstacles_pub_, path_pub_;
  ros::Subscriber danger_sub_, diag_sub_;
  tf2_ros::StaticTransformBroadcaster tf_;
  std::mutex mutex_;
  std::map<ros::Time, int> judged_;
  std::map<std::string, std::string> diag_;
};

TEST_F(PlannedPath, TheCarBesideTheRoadIsDangerousAlongTheTwistOnly) {
  ASSERT_TRUE(waitFor([&] {
    return obstacles_pub_.getNumSubscribers() > 0 && danger_sub_.getNumPublishers() > 0 &&
           path_pub_.getNumSubscribers() > 0;
  }, 30.0));
  ros::WallDuration(0.5).sleep();
  ros::Time t(100.0);
  // The first array can be lost while the connection settles: arrays until one is answered.
  // (A tf1-era frame id, "/odom", is the same frame.)
  publishPath(t, "/odom", 0.0);
  int first = -2;
  for (int i = 0; i < 6 && first == -2; ++i) first = judge(t += ros::Duration(0.1));
  ASSERT_NE(first, -2) << "the DangerDetector answered no array";
  // Along the path (fresh for 1 s): never dangerous.
  for (int i = 0; i < 5; ++i) EXPECT_EQ(judge(t += ros::Duration(0.1)), 0) << i;
  // 5 s later the path is stale: along the twist the car is in the turn (on after on_frames).
  int dangerous = 0;
  t += ros::Duration(5.0);
  for (int i = 0; i < 5; ++i) dangerous += judge(t += ros::Duration(0.1)) == 1;
  EXPECT_GE(dangerous, 3);
  // Unusable paths, each counted by its reason (and the twist used): unstamped, the vehicle 5 m
  // off it, a frame tf does not know.
  publishPath(ros::Time(0), "odom", 0.0);
  judge(t += ros::Duration(0.1));
  publishPath(t + ros::Duration(0.1), "odom", 5.0);
  judge(t += ros::Duration(0.1));
  publishPath(t + ros::Duration(0.1), "no_such_frame", 0.0);
  judge(t += ros::Duration(0.1));
  EXPECT_TRUE(waitFor([&] {
    return !diag("no usable path: path unstamped (header.stamp 0)").empty() &&
           !diag("no usable path: path refused: the vehicle is not on it (nearest point too far)").empty() &&
           !diag("no usable path: no transform no_such_frame -> base_link at the stamp").empty();
  }, 5.0));
  EXPECT_EQ(diag("path topic"), "/test/planned_path");
  EXPECT_GE(std::stoi(diag("arrays along the planned path").empty() ? "0" : diag("arrays along the planned path")), 5);
  EXPECT_GE(std::stoi(diag("no usable path: path stamp farther than path_max_age_s from the obstacles'").empty()
                          ? "0"
                          : diag("no usable path: path stamp farther than path_max_age_s from the obstacles'")),
            5);
}

}  // namespace
}  // namespace icanc

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_planned_path");
  ros::AsyncSpinner spinner(2);
  spinner.start();
  return RUN_ALL_TESTS();
}
