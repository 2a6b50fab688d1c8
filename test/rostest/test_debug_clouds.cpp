// rostest: the ObstacleDetector of launch/icanc.launch publishes ~ground_points and
// ~obstacle_points only while someone subscribes (debug_clouds.test: classic chain,
// debug_clouds_fast.test: fast path). Without a subscriber its diagnostics count no frame with
// them; with one, both clouds come in the input cloud's frame with its stamp, their points are
// no more than the frame's valid returns, the road lies where the sensor's mount puts it, and the
// pedestrian ahead is among the obstacle points.
#include <algorithm>
#include <string>

#include <diagnostic_msgs/DiagnosticArray.h>
#include <gtest/gtest.h>

#include "graph_fixture.hpp"

namespace icanc {
namespace test {
namespace {

const char* const kStatus = "icanc/obstacle_detector: obstacle detector";
const char* const kCounter = "frames with ground/obstacle points published";

class DebugClouds : public ::testing::Test {
 protected:
  DebugClouds() : g_("approach_front.yaml") {
    diag_sub_ = g_.nh().subscribe<diagnostic_msgs::DiagnosticArray>("/diagnostics", 100,
        [this](const diagnostic_msgs::DiagnosticArray::ConstPtr& m) {
          std::lock_guard<std::mutex> lock(mutex_);
          for (const auto& st : m->status)
            if (st.name == kStatus)
              for (const auto& kv : st.values)
                if (kv.key == kCounter) counter_ = std::stol(kv.value), ++reports_;
        });
  }

  // Publishes the standing scene (t = 1 s) stamped now and waits for its detections.
  ObstacleArray::ConstPtr frame() {
    const ros::Time stamp = ros::Time::now();
    g_.publishFrame(1.0, stamp);
    const ObstacleArray::ConstPtr out = g_.recorder().waitForStamp(g_.recorder().detections, stamp);
    ros::WallDuration(0.1).sleep();
    return out;
  }

  // The counter of the next diagnostics report (-1 when none came).
  long nextCounter() {
    long seen = 0;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      seen = reports_;
    }
    waitFor([&] {
      std::lock_guard<std::mutex> lock(mutex_);
      return reports_ > seen;
    }, 3.0);
    std::lock_guard<std::mutex> lock(mutex_);
    return reports_ > seen ? counter_ : -1;
  }

  GraphFixture g_;
  std::mutex mutex_;
  long counter_ = -1, reports_ = 0;
  std::vector<sensor_msgs::PointCloud2::ConstPtr> ground_, obstacles_;
  ros::Subscriber diag_sub_;
};

TEST_F(DebugClouds, OnlyWhileSubscribedInTheCloudsFrameAndConsistentWithIt) {
  ASSERT_TRUE(g_.waitForGraph()) << "icanc graph did not come up";
  std::string method;
  ASSERT_TRUE(ros::param::get("/icanc/obstacle_detector/method", method));
  for (int k = 0; k < 5; ++k) ASSERT_TRUE(frame()) << "no detections for frame " << k;
  EXPECT_EQ(nextCounter(), 0) << method << ": ground/obstacle points built without a subscriber";

  std::mutex clouds_mutex;
  const auto keep = [&](std::vector<sensor_msgs::PointCloud2::ConstPtr>& into) {
    return [&](const sensor_msgs::PointCloud2::ConstPtr& m) {
      std::lock_guard<std::mutex> lock(clouds_mutex);
      into.push_back(m);
    };
  };
  ros::Subscriber ground_sub = g_.nh().subscribe<sensor_msgs::PointCloud2>(
      "/icanc/obstacle_detector/ground_points", 10, keep(ground_));
  ros::Subscriber obstacle_sub = g_.nh().subscribe<sensor_msgs::PointCloud2>(
      "/icanc/obstacle_detector/obstacle_points", 10, keep(obstacles_));
  ASSERT_TRUE(waitFor([&] {
    return ground_sub.getNumPublishers() > 0 && obstacle_sub.getNumPublishers() > 0;
  }, 10.0));
  ros::WallDuration(0.5).sleep();  // the publisher's side of the connection

  // The frame whose two clouds both came (the first ones may precede the connection).
  ObstacleArray::ConstPtr array;
  sensor_msgs::PointCloud2::ConstPtr ground, obstacles;
  for (int k = 0; k < 10 && !(ground && obstacles); ++k) {
    array = frame();
    ASSERT_TRUE(array);
    waitFor([&] {
      std::lock_guard<std::mutex> lock(clouds_mutex);
      for (const auto& c : ground_) if (c->header.stamp == array->header.stamp) ground = c;
      for (const auto& c : obstacles_) if (c->header.stamp == array->header.stamp) obstacles = c;
      return ground && obstacles;
    }, 2.0);
  }
  ASSERT_TRUE(ground && obstacles) << method << ": no ground/obstacle points with a subscriber";
  EXPECT_GT(nextCounter(), 0) << method;

  const std::string sensor_frame = g_.scenario().sensor_frame;
  EXPECT_EQ(ground->header.frame_id, sensor_frame);
  EXPECT_EQ(obstacles->header.frame_id, sensor_frame);
  Cloud ground_points, obstacle_points;
  pcl::fromROSMsg(*ground, ground_points);
  pcl::fromROSMsg(*obstacles, obstacle_points);
  std::printf("%s: %zu valid returns, %zu ground points, %zu obstacle points\n", method.c_str(),
              static_cast<std::size_t>(array->valid_points), ground_points.size(), obstacle_points.size());
  ASSERT_GT(ground_points.size(), 100u) << method;
  ASSERT_GT(obstacle_points.size(), 20u) << method;
  EXPECT_LE(ground_points.size() + obstacle_points.size(), array->valid_points) << method;

  // In the sensor's frame: the road at minus its mount height under it, the pedestrian (at
  // 15 m from the vehicle at t = 1 s) ahead of it at the mount's x less.
  const Eigen::Vector3f mount = g_.scenario().sensor_mount.translation();
  std::vector<float> ground_z;
  for (const Point& p : ground_points.points) ground_z.push_back(p.z);
  std::nth_element(ground_z.begin(), ground_z.begin() + ground_z.size() / 2, ground_z.end());
  EXPECT_NEAR(ground_z[ground_z.size() / 2], -mount.z(), 0.15) << method << ": road not under the sensor";
  const sim::SceneObject& walker = g_.scenario().scene.objects.front();
  const Eigen::Vector3f at = walker.positionAt(1.0) - mount;
  const std::size_t on_walker = std::count_if(
      obstacle_points.points.begin(), obstacle_points.points.end(),
      [&](const Point& p) { return std::hypot(p.x - at.x(), p.y - at.y()) < 0.6f; });
  EXPECT_GE(on_walker, 5u) << method << ": the pedestrian's points are not among the obstacle points";
}

}  // namespace
}  // namespace test
}  // namespace icanc

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_debug_clouds");
  ros::AsyncSpinner spinner(2);
  spinner.start();
  return RUN_ALL_TESTS();
}
