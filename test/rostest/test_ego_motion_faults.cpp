// rostest: the ObstacleDetector takes the vehicle's motion from tf odom -> base_link at
// each cloud's stamp. Every frame is answered whatever the poses do: measured (the twist in the
// array), missing (extrapolated for max_extrapolation_s, then lost: relative velocities, an error),
// back (a fresh start), jumping (re-based); the faults are counted in /diagnostics.
// TransformWait (transform_wait.test, ego_motion/max_wait_s 1): a cloud whose transform never
// comes waits in the queue without blocking the callback (the next cloud is received and queued
// meanwhile), then goes on in the sensor's frame, counted; the clouds keep their order.
#include <algorithm>
#include <atomic>
#include <cstring>
#include <map>

#include <diagnostic_msgs/DiagnosticArray.h>

#include <gtest/gtest.h>
#include <tf2_ros/transform_broadcaster.h>

#include "graph_fixture.hpp"

namespace icanc {
namespace test {
namespace {

class EgoMotionFaults : public ::testing::Test {
 protected:
  EgoMotionFaults() : g_("approach_front.yaml") {
    diag_ = g_.nh().subscribe<diagnostic_msgs::DiagnosticArray>("/diagnostics", 100,
        [this](const diagnostic_msgs::DiagnosticArray::ConstPtr& m) {
          std::lock_guard<std::mutex> lock(mutex_);
          for (const auto& s : m->status)
            if (s.name.find("obstacle detector") != std::string::npos)
              for (const auto& kv : s.values) {
                counters_[kv.key] = kv.value;
                if (kv.key == "clouds waiting for transforms")
                  most_waiting_ = std::max(most_waiting_.load(), std::stoi(kv.value));
              }
        });
  }

  // The vehicle's pose at `stamp` (odom -> base_link: x metres ahead, yaw) on /tf, then a frame.
  // Returns the array the ObstacleDetector published for it (null when none came).
  ObstacleArray::ConstPtr frame(const ros::Time& stamp, bool with_pose, double x, double yaw = 0.0) {
    if (with_pose) {
      geometry_msgs::TransformStamped t;
      t.header.stamp = stamp;
      t.header.frame_id = "odom";
      t.child_frame_id = "base_link";
      t.transform.translation.x = x;
      t.transform.rotation.z = std::sin(0.5 * yaw);
      t.transform.rotation.w = std::cos(0.5 * yaw);
      tf_.sendTransform(t);
    }
    // Paced by the stamps, as a sensor: the detector refuses stamps that run ahead of (or behind)
    // their receipt, a sensor clock running fast or slow.
    pacer_.wait(stamp);
    g_.publishFrame(1.0, stamp);
    return g_.recorder().waitForStamp(g_.recorder().detections, stamp);
  }
  StampPacer pacer_;

  // Frames with poses at 2 m/s from now until the graph answers (the first may go unanswered
  // while connections settle: bad_input's firstFrame), then `more`. Null when it never answered.
  ObstacleArray::ConstPtr start(ros::Time& stamp, double& x, int more) {
    if (!g_.waitForGraph()) return nullptr;
    stamp = ros::Time::now();
    ObstacleArray::ConstPtr a;
    for (int attempt = 0; attempt < 6 && !a; ++attempt) a = frame(stamp += ros::Duration(0.1), true, x += 0.2);
    for (int i = 0; a && i < more; ++i) a = frame(stamp += ros::Duration(0.1), true, x += 0.2);
    return a;
  }

  long counter(const std::string& key) {
    std::lock_guard<std::mutex> lock(mutex_);
    auto it = counters_.find(key);
    return it == counters_.end() ? -1 : std::stol(it->second);
  }

  GraphFixture g_;
  tf2_ros::TransformBroadcaster tf_;
  std::mutex mutex_;
  std::map<std::string, std::string> counters_;
  std::atomic<int> most_waiting_{0};
  ros::Subscriber diag_;  // last: destroyed first
};

TEST_F(EgoMotionFaults, EveryFrameIsAnsweredWhateverThePosesDo) {
  ros::Time stamp;
  const ros::Duration dt(0.1);
  double x = 0.0;
  // Measured: 2 m/s ahead (0.2 m per 0.1 s).
  ObstacleArray::ConstPtr a = start(stamp, x, 5);
  ASSERT_TRUE(a) << "the graph never answered";
  EXPECT_EQ(a->ego_motion_source, "tf");
  EXPECT_EQ(a->ego_motion_status, "measured");
  EXPECT_NEAR(a->ego_twist.linear.x, 2.0, 1e-3);

  // Missing: extrapolated with the last twist, then lost after max_extrapolation_s (0.5 s).
  std::map<std::string, int> seen;
  for (int i = 0; i < 8; ++i) {
    a = frame(stamp += dt, false, x += 0.2);
    ASSERT_TRUE(a) << "frame " << i << " without a pose was not answered";
    ++seen[a->ego_motion_status];
  }
  EXPECT_GE(seen["extrapolated"], 4);
  EXPECT_EQ(seen["lost"], 1);
  EXPECT_EQ(a->ego_motion_status, "none");  // after lost: relative, until poses return
  EXPECT_EQ(a->ego_twist.linear.x, 0.0);

  // Back: a fresh start, then measured again. A source silent for kMissesBeforeNoWait clouds is
  // no longer waited for (EgoPoseSource), so the first pose back, sent just before its cloud, may
  // reach the detector's tf buffer after the cloud on a loaded machine: that cloud goes without it
  // ("none", relative) and the next one finds its pose.
  int without_pose = 0;
  for (a = frame(stamp += dt, true, x += 0.2); a && a->ego_motion_status == "none" && without_pose < 3;
       a = frame(stamp += dt, true, x += 0.2))
    ++without_pose;
  ASSERT_TRUE(a);
  EXPECT_EQ(a->ego_motion_status, "first") << "after " << without_pose << " frames without the pose";
  a = frame(stamp += dt, true, x += 0.2);
  ASSERT_TRUE(a);
  EXPECT_EQ(a->ego_motion_status, "measured");

  // A relocalisation 100 m away: a jump, re-based; the next step is measured from there.
  a = frame(stamp += dt, true, x += 100.0);
  ASSERT_TRUE(a);
  EXPECT_EQ(a->ego_motion_status, "jump");
  EXPECT_NEAR(a->ego_twist.linear.x, 2.0, 1e-3);  // the last twist carried over the jump
  a = frame(stamp += dt, true, x += 0.2);
  ASSERT_TRUE(a);
  EXPECT_EQ(a->ego_motion_status, "measured");

  // Counted in diagnostics (published at 1 Hz).
  // The last report counts the jump, so every fault is in it.
  EXPECT_TRUE(waitFor([&] { return counter("ego motion frames: jump") == 1; }, 5.0));
  EXPECT_EQ(counter("ego motion frames: lost"), 1);
  // Two restarts of the tracks: at the loss (relative from then on) and when poses came back; the
  // first frame starts the tracks, it does not restart them.
  EXPECT_EQ(counter("ego motion restarts of the tracks"), 2);
  EXPECT_GE(counter("ego motion frames: extrapolated"), 4);
}

// The mount of "lidar_without_tf" never comes: four such clouds 0.1 s apart each wait max_wait_s
// (1 s here), while the next ones, and then a cloud whose transforms are all there, are received
// and queued behind them (a diagnostics report, at 1 Hz, sees several waiting at once); then each
// goes on in its own frame (counted) and the good one right after them, in base_link.
TEST_F(EgoMotionFaults, CloudWithoutItsTransformWaitsWithoutBlockingTheNext) {
  ros::Time stamp;
  const ros::Duration dt(0.1);
  double x = 0.0;
  ObstacleArray::ConstPtr a = start(stamp, x, 3);
  ASSERT_TRUE(a) << "the graph never answered";
  ASSERT_EQ(a->ego_motion_status, "measured");
  ASSERT_TRUE(waitFor([&] { return counter("transform waits timed out") >= 0; }, 5.0))
      << "no counter for transforms that did not come in time";
  const long received_before = counter("clouds received");
  const long failures_before = counter("transform failures");
  const long timeouts_before = counter("transform waits timed out");

  sensor_msgs::PointCloud2 orphan;
  orphan.height = 1;
  orphan.width = 1000;
  orphan.point_step = 12;
  orphan.row_step = 12000;
  orphan.fields.resize(3);
  for (int i = 0; i < 3; ++i) {
    orphan.fields[i].name = std::string(1, static_cast<char>('x' + i));
    orphan.fields[i].offset = 4 * i;
    orphan.fields[i].datatype = sensor_msgs::PointField::FLOAT32;
    orphan.fields[i].count = 1;
  }
  orphan.data.assign(12000, 0);
  for (std::size_t k = 0; k < 1000; ++k) {
    const float p[3] = {5.0f + 0.001f * k, 0.0f, 0.5f};
    std::memcpy(&orphan.data[12 * k], p, sizeof(p));
  }
  orphan.header.frame_id = "lidar_without_tf";
  std::vector<ros::Time> orphans;
  const ros::WallTime sent = ros::WallTime::now();
  for (int i = 0; i < 4; ++i) {
    orphan.header.stamp = stamp += dt;
    orphans.push_back(orphan.header.stamp);
    g_.publishRaw(boost::make_shared<sensor_msgs::PointCloud2>(orphan));
    ros::WallDuration(0.1).sleep();
  }
  const ros::Time good_stamp = stamp += dt;
  ObstacleArray::ConstPtr good = frame(good_stamp, true, x += 1.0);
  const double answered_s = (ros::WallTime::now() - sent).toSec();

  ASSERT_TRUE(good) << "the cloud behind them was not answered";
  EXPECT_EQ(good->header.frame_id, "base_link");
  EXPECT_GE(answered_s, 1.3) << "the clouds did not wait for their transform";
  {
    std::lock_guard<std::mutex> l(g_.recorder().mutex);
    const auto& d = g_.recorder().detections;
    const auto at = [&](const ros::Time& s) {
      return std::find_if(d.begin(), d.end(), [&](const ObstacleArray::ConstPtr& m) { return m->header.stamp == s; });
    };
    for (const ros::Time& s : orphans) {
      ASSERT_NE(at(s), d.end()) << "the cloud stamped " << s << " without its transform was not answered";
      EXPECT_EQ((*at(s))->header.frame_id, "lidar_without_tf");
      EXPECT_LT(at(s), at(good_stamp)) << "the clouds went out of order";
    }
  }
  EXPECT_GE(most_waiting_.load(), 2) << "no report saw clouds waiting together: the callback blocked";
  EXPECT_TRUE(waitFor([&] {
    return counter("transform failures") == failures_before + 4 &&
           counter("transform waits timed out") == timeouts_before + 4 &&
           counter("clouds received") >= received_before + 5;
  }, 5.0)) << "transform failures " << counter("transform failures") << ", waits timed out "
           << counter("transform waits timed out");
}

}  // namespace
}  // namespace test
}  // namespace icanc

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_ego_motion_faults");
  ros::AsyncSpinner spinner(2);
  spinner.start();
  return RUN_ALL_TESTS();
}
