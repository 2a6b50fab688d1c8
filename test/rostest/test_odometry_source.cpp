// rostest: the ObstacleDetector takes the vehicle's pose from nav_msgs/Odometry
// (EgoPoseSource, ego_motion/source odometry) at each cloud's stamp. The odometry comes every 13 ms,
// out of step with the clouds' 100 ms, along a constant turn (2 m/s, 0.5 rad/s): only poses
// interpolated at the clouds' stamps (translation and rotation) give that twist back. Odometry
// that lags is extrapolated over ("no odometry at the stamp yet"), odometry that comes while the
// cloud waits for it is used, and a replay that loops (stamps back in time) starts it afresh.
#include <cmath>
#include <cstdint>
#include <map>
#include <mutex>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nav_msgs/Odometry.h>
#include <rosgraph_msgs/Log.h>

#include "graph_fixture.hpp"

namespace icanc {
namespace test {
namespace {

constexpr double kSpeed = 2.0, kYawRate = 0.5;
constexpr std::int64_t kOdomStepNs = 13000000, kFrameStepNs = 100000000;

class OdometrySource : public ::testing::Test {
 protected:
  OdometrySource() : g_("approach_front.yaml") {
    odom_pub_ = g_.nh().advertise<nav_msgs::Odometry>("/test/odom", 200);
    log_sub_ = g_.nh().subscribe<rosgraph_msgs::Log>(
        "/rosout", 200, [this](const rosgraph_msgs::Log::ConstPtr& m) {
          std::lock_guard<std::mutex> lock(mutex_);
          log_.push_back(m->msg);
        });
  }

  // Starts a drive at `start` (time zero of the turn): odometry every kOdomStepNs from there.
  void startDrive(const ros::Time& start) {
    start_ = start;
    next_odom_ = 0;
  }
  ros::Time frameStamp(int k) const { return ros::Time().fromNSec(start_.toNSec() + k * kFrameStepNs); }

  // The odometry of the drive up to `until` (stamps on the kOdomStepNs grid not sent yet).
  void sendOdometryUntil(const ros::Time& until) {
    for (;; ++next_odom_) {
      const ros::Time stamp = ros::Time().fromNSec(start_.toNSec() + next_odom_ * kOdomStepNs);
      if (stamp > until) break;
      const double t = (stamp - start_).toSec(), yaw = kYawRate * t;
      nav_msgs::Odometry o;
      o.header.stamp = stamp;
      o.header.frame_id = "odom";
      o.child_frame_id = "base_link";
      o.pose.pose.position.x = kSpeed / kYawRate * std::sin(yaw);
      o.pose.pose.position.y = kSpeed / kYawRate * (1.0 - std::cos(yaw));
      o.pose.pose.orientation.z = std::sin(0.5 * yaw);
      o.pose.pose.orientation.w = std::cos(0.5 * yaw);
      odom_pub_.publish(o);
    }
    ros::WallDuration(0.1).sleep();  // delivered before the cloud, mostly (the detector waits, bounded)
  }

  // Cloud k of the drive; the array the ObstacleDetector published for it (null when none came).
  ObstacleArray::ConstPtr frame(int k) {
    publishCloud(k);
    return answer(k);
  }
  void publishCloud(int k) { g_.publishFrame(0.1 * (k % 20), frameStamp(k)); }
  ObstacleArray::ConstPtr answer(int k) {
    return g_.recorder().waitForStamp(g_.recorder().detections, frameStamp(k));
  }

  // The next n clouds of the drive, each after its odometry: how many had each ego motion status.
  // Every one measured must give the turn's twist back.
  std::map<std::string, int> drive(int& k, int n);

  bool logged(const std::string& text) {
    std::lock_guard<std::mutex> lock(mutex_);
    for (const auto& m : log_)
      if (m.find(text) != std::string::npos) return true;
    return false;
  }

  GraphFixture g_;
  ros::Publisher odom_pub_;
  ros::Time start_;
  std::int64_t next_odom_ = 0;
  std::mutex mutex_;
  std::vector<std::string> log_;
  ros::Subscriber log_sub_;  // last: destroyed first
};

#define EXPECT_TURN(a)                                                         \
  do {                                                                         \
    EXPECT_NEAR((a)->ego_twist.linear.x, kSpeed, 2e-3);                       \
    EXPECT_NEAR((a)->ego_twist.linear.y, 0.0, 2e-3);                          \
    EXPECT_NEAR((a)->ego_twist.angular.z, kYawRate, 2e-3);                    \
  } while (0)

std::map<std::string, int> OdometrySource::drive(int& k, int n) {
  std::map<std::string, int> seen;
  for (int i = 0; i < n; ++i) {
    sendOdometryUntil(frameStamp(++k) + ros::Duration(0.02));
    const ObstacleArray::ConstPtr a = frame(k);
    if (!a) {
      ADD_FAILURE() << "cloud " << k << " was not answered";
      ++seen["unanswered"];
      continue;
    }
    ++seen[a->ego_motion_status];
    if (a->ego_motion_status == "measured") EXPECT_TURN(a);
  }
  return seen;
}

TEST_F(OdometrySource, PosesInterpolatedAtTheCloudsStampsWaitedForAndRestartedOnALoop) {
  ASSERT_TRUE(g_.waitForGraph());
  ASSERT_TRUE(waitFor([&] { return odom_pub_.getNumSubscribers() > 0; }, 30.0));
  ASSERT_TRUE(waitFor([&] { return log_sub_.getNumPublishers() > 0; }, 30.0));
  startDrive(ros::Time::now());

  // The first clouds may go unanswered while connections settle (bad_input's firstFrame).
  int k = 0;
  ObstacleArray::ConstPtr a;
  for (int attempt = 0; attempt < 6 && !a; ++attempt) {
    sendOdometryUntil(frameStamp(++k) + ros::Duration(0.02));
    a = frame(k);
  }
  ASSERT_TRUE(a) << "the graph never answered";
  EXPECT_EQ(a->ego_motion_source, "odometry");

  // Measured: every cloud's stamp between two odometry messages, or on one (1.3 s = 100 * 13 ms).
  // On a loaded machine the odometry may come after the wait: that cloud is extrapolated.
  std::map<std::string, int> seen = drive(k, 15);
  EXPECT_GE(seen["measured"], 10) << "first " << seen["first"] << ", none " << seen["none"]
                                  << ", extrapolated " << seen["extrapolated"];

  // Lagging: no odometry at the clouds' stamps yet; extrapolated with the twist, then it comes.
  a = frame(++k);
  ASSERT_TRUE(a);
  EXPECT_EQ(a->ego_motion_status, "extrapolated");
  EXPECT_TURN(a);  // the last twist, carried
  EXPECT_TRUE(waitFor([&] { return logged("no odometry at the stamp yet"); }, 5.0));
  for (int i = 0; i < 3 && a && a->ego_motion_status != "measured"; ++i) {
    sendOdometryUntil(frameStamp(++k) + ros::Duration(0.02));
    a = frame(k);
  }
  ASSERT_TRUE(a);
  EXPECT_EQ(a->ego_motion_status, "measured");
  EXPECT_TURN(a);

  // Waited for: the odometry at a cloud's stamp comes after the cloud (within ego_motion/max_wait_s,
  // 1 s in odometry_source.test). It must reach EgoPoseSource while the cloud's callback waits.
  publishCloud(++k);
  ros::WallDuration(0.05).sleep();
  sendOdometryUntil(frameStamp(k) + ros::Duration(0.02));
  a = answer(k);
  ASSERT_TRUE(a);
  EXPECT_EQ(a->ego_motion_status, "measured");
  EXPECT_TURN(a);

  // A replay that loops: clouds and odometry from 10 s back, the turn from its start again. The
  // odometry kept is forgotten (every stamp of the loop is older than it); the drive is measured.
  // The loop's first cloud is dropped (its stamp went backwards: StampCheck), the next starts afresh.
  startDrive(start_ - ros::Duration(10.0));
  k = 0;
  sendOdometryUntil(frameStamp(++k) + ros::Duration(0.02));
  publishCloud(k);
  seen = drive(k, 6);
  EXPECT_GE(seen["measured"], 3) << "first " << seen["first"] << ", none " << seen["none"]
                                 << ", extrapolated " << seen["extrapolated"];
}

}  // namespace
}  // namespace test
}  // namespace icanc

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_odometry_source");
  ros::AsyncSpinner spinner(2);
  spinner.start();
  return RUN_ALL_TESTS();
}
