// rostest: clouds arrive before the sensor's mount (lidar -> base_link) is on /tf_static.
// The ObstacleDetector waits for it at start-up (bounded), so even the first boxes are published
// in the vehicle frame, the one the DangerDetector judges in; none goes out in the sensor's frame.
#include <thread>

#include <gtest/gtest.h>

#include "graph_fixture.hpp"

namespace icanc {
namespace test {
namespace {

TEST(TfStartup, FirstBoxesWaitForTheLateMount) {
  GraphFixture g("approach_front.yaml", /*publish_mount=*/false);
  ASSERT_TRUE(g.waitForGraph());
  ros::WallDuration(0.5).sleep();  // connections settle, so the first cloud is not lost
  ros::Time stamp = ros::Time::now();
  double t = 0.0;
  // Clouds at 10 Hz; the mount comes 0.4 s after the first one.
  const ros::WallTime first = ros::WallTime::now();
  bool mount_sent = false;
  while ((ros::WallTime::now() - first).toSec() < 3.0) {
    if (!mount_sent && (ros::WallTime::now() - first).toSec() >= 0.4) {
      g.publishMount();
      mount_sent = true;
    }
    g.publishFrame(t += 0.1, stamp += ros::Duration(0.1));
    ros::WallDuration(0.1).sleep();
  }
  ASSERT_TRUE(waitFor([&] { return g.recorder().count(g.recorder().detections) >= 5; }, 10.0));
  std::lock_guard<std::mutex> l(g.recorder().mutex);
  for (const auto& a : g.recorder().detections)
    EXPECT_EQ(a->header.frame_id, g.scenario().vehicle_frame)
        << "array stamped " << a->header.stamp << " went out in " << a->header.frame_id;
}

}  // namespace
}  // namespace test
}  // namespace icanc

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_tf_startup");
  ros::AsyncSpinner spinner(2);
  spinner.start();
  return RUN_ALL_TESTS();
}
