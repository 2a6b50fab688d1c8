// rostest: dynamic_reconfigure on the nodelets of launch/icanc.launch (Zebra profile), through
// the dynamic_reconfigure C++ client. A pedestrian walks toward the vehicle at 1 m/s from 20 m
// (walker_slow.yaml): safe with reaction_time 3 s; raising reaction_time_s makes it dangerous from
// the next frame, and the lamp then runs the newly set tau_s. An invalid combination is refused
// and the client is answered with the values in force; a detector tunable takes effect too. The
// rviz markers on /icanc/markers follow: the walker's box turns red, the lamp marker reports ON.
#include <map>

#include <diagnostic_msgs/DiagnosticArray.h>
#include <dynamic_reconfigure/client.h>
#include <gtest/gtest.h>
#include <visualization_msgs/MarkerArray.h>

#include "graph_fixture.hpp"
#include "icanc/DangerDetectorConfig.h"
#include "icanc/LightControllerConfig.h"
#include "icanc/ObstacleDetectorConfig.h"

namespace icanc {
namespace test {
namespace {

class LiveTuning : public ::testing::Test {
 protected:
  LiveTuning()
      : g_("walker_slow.yaml"),
        danger_("/icanc/danger_detector"),
        light_("/icanc/light_controller"),
        detector_("/icanc/obstacle_detector") {
    diag_sub_ = g_.nh().subscribe<diagnostic_msgs::DiagnosticArray>("/diagnostics", 100,
        [this](const diagnostic_msgs::DiagnosticArray::ConstPtr& m) {
          std::lock_guard<std::mutex> lock(markers_mutex_);
          for (const auto& st : m->status)
            for (const auto& kv : st.values)
              if (kv.key == "reconfigurations rejected") rejected_[st.name] = std::stol(kv.value);
        });
    markers_sub_ = g_.nh().subscribe<visualization_msgs::MarkerArray>("/icanc/markers", 100,
        [this](const visualization_msgs::MarkerArray::ConstPtr& m) {
          std::lock_guard<std::mutex> lock(markers_mutex_);
          for (const auto& k : m->markers) markers_[k.ns + "/" + std::to_string(k.id)] = k;
        });
  }

  // "reconfigurations rejected" of the status whose name contains `status` (0 before a report).
  long rejected(const std::string& status) {
    std::lock_guard<std::mutex> lock(markers_mutex_);
    for (const auto& kv : rejected_)
      if (kv.first.find(status) != std::string::npos) return kv.second;
    return 0;
  }

  // The latest marker of namespace `ns` and id `id` (an empty marker when none arrived).
  visualization_msgs::Marker marker(const std::string& ns, int id) {
    std::lock_guard<std::mutex> lock(markers_mutex_);
    const auto it = markers_.find(ns + "/" + std::to_string(id));
    return it == markers_.end() ? visualization_msgs::Marker() : it->second;
  }

  // Publishes the frame of scenario time t_ (stamped t0 + t_) at the sensor's pace, advances t_
  // by one frame and waits for its danger array.
  ObstacleArray::ConstPtr frame() {
    const ros::Time stamp = t0_ + ros::Duration(t_);
    pacer_.wait(stamp);
    g_.publishFrame(t_, stamp);
    t_ += 1.0 / g_.scenario().rate_hz;
    return g_.recorder().waitForStamp(g_.recorder().arrays, stamp);
  }

  LightState::ConstPtr stateFor(const ros::Time& cloud_stamp) {
    LightState::ConstPtr out;
    waitFor([&] {
      std::lock_guard<std::mutex> lock(g_.recorder().mutex);
      for (const auto& s : g_.recorder().states)
        if (s->input_stamp == cloud_stamp) out = s;
      return out != nullptr;
    }, 5.0);
    return out;
  }

  GraphFixture g_;
  dynamic_reconfigure::Client<DangerDetectorConfig> danger_;
  dynamic_reconfigure::Client<LightControllerConfig> light_;
  dynamic_reconfigure::Client<ObstacleDetectorConfig> detector_;
  std::mutex markers_mutex_;
  std::map<std::string, visualization_msgs::Marker> markers_;
  std::map<std::string, long> rejected_;
  ros::Time t0_ = ros::Time::now();
  double t_ = 0.0;
  StampPacer pacer_;
  // Declared last, so destroyed first: a subscriber's destructor waits for a running callback,
  // which then never writes into members already freed (ASan caught it at fixture teardown).
  ros::Subscriber markers_sub_, diag_sub_;
};

TEST_F(LiveTuning, ChangesTakeEffectOnTheNextFrameAndInvalidOnesAreRefused) {
  ASSERT_TRUE(g_.waitForGraph()) << "icanc graph did not come up";
  DangerDetectorConfig danger;
  LightControllerConfig light;
  ObstacleDetectorConfig detector;
  ASSERT_TRUE(danger_.getCurrentConfiguration(danger, ros::Duration(10.0)));
  ASSERT_TRUE(light_.getCurrentConfiguration(light, ros::Duration(10.0)));
  ASSERT_TRUE(detector_.getCurrentConfiguration(detector, ros::Duration(10.0)));
  // The servers start from the loaded profile (config/zebra.yaml), not the .cfg defaults.
  EXPECT_DOUBLE_EQ(danger.reaction_time_s, 3.0);
  EXPECT_DOUBLE_EQ(danger.half_width_m, 0.7);
  EXPECT_EQ(danger.model, "paper");
  EXPECT_DOUBLE_EQ(light.tau_s, 3.0);
  EXPECT_EQ(detector.cluster_min_points, 10);

  // Tracked and moving toward, but 15+ m away: safe at 1 m/s * 3 s.
  ObstacleArray::ConstPtr a;
  for (int k = 0; k < 30; ++k) a = frame();
  ASSERT_TRUE(a);
  ASSERT_EQ(a->obstacles.size(), 1u) << "the walker is not tracked";
  EXPECT_EQ(a->num_dangerous, 0u);
  EXPECT_NEAR(a->obstacles[0].speed, 1.0, 0.3);
  const double distance = a->obstacles[0].closest_distance;
  const int walker_id = static_cast<int>(a->obstacles[0].id);
  EXPECT_TRUE(waitFor([&] { return marker("obstacles", walker_id).color.g > 0.5f; }, 3.0))
      << "no green box for the safe walker on /icanc/markers";
  EXPECT_DOUBLE_EQ(marker("sections", 0).points.at(0).y, 0.7) << "section boundary at +half_width";

  // An invalid combination (recheck_below_s > tau_s) is refused: old values in force and answered.
  light.recheck_below_s = 5.0;
  ASSERT_TRUE(light_.setConfiguration(light));
  EXPECT_DOUBLE_EQ(light.recheck_below_s, 1.0);
  EXPECT_DOUBLE_EQ(light.tau_s, 3.0);

  // Values outside what validate() accepts are refused and counted, not clamped into
  // the .cfg's range (stale_timeout_s -5 used to become 0 = watchdog off, and count as accepted).
  const long light_rejected = rejected("light controller");
  for (double bad : {-5.0, 0.0, 1e9}) {
    light.stale_timeout_s = bad;
    ASSERT_TRUE(light_.setConfiguration(light));
    EXPECT_DOUBLE_EQ(light.stale_timeout_s, 0.3) << "stale_timeout_s " << bad << " not refused";
  }
  const long danger_rejected = rejected("danger detector");
  danger.half_width_m = -1.0;
  ASSERT_TRUE(danger_.setConfiguration(danger));
  EXPECT_DOUBLE_EQ(danger.half_width_m, 0.7);
  danger.reaction_time_s = 1e9;
  ASSERT_TRUE(danger_.setConfiguration(danger));
  EXPECT_DOUBLE_EQ(danger.reaction_time_s, 3.0);
  EXPECT_TRUE(waitFor([&] {
    return rejected("light controller") >= light_rejected + 3 &&
           rejected("danger detector") >= danger_rejected + 2;
  }, 5.0)) << "rejections not counted: light " << rejected("light controller") << ", danger "
           << rejected("danger detector");

  // A longer timer, then a reaction time that covers the walker's distance: dangerous from the
  // very next frame, and the lamp's timer starts at the new tau.
  light.tau_s = 6.0;
  ASSERT_TRUE(light_.setConfiguration(light));
  EXPECT_DOUBLE_EQ(light.tau_s, 6.0);
  danger.reaction_time_s = 25.0;
  ASSERT_TRUE(danger_.setConfiguration(danger));
  EXPECT_DOUBLE_EQ(danger.reaction_time_s, 25.0);
  a = frame();
  ASSERT_TRUE(a);
  std::printf("walker at %.2f m, %.2f m/s: %u dangerous after reaction_time_s 3 -> 25\n", distance,
              a->obstacles.empty() ? 0.0 : a->obstacles[0].speed, a->num_dangerous);
  EXPECT_EQ(a->num_dangerous, 1u) << "not dangerous on the frame after the change";
  const LightState::ConstPtr s = stateFor(a->header.stamp);
  ASSERT_TRUE(s);
  EXPECT_TRUE(s->on);
  EXPECT_EQ(s->reason, LightState::REASON_DANGER);
  EXPECT_GT(s->time_left, 5.0) << "the timer should run the new tau_s (6 s), not 3 s";
  EXPECT_TRUE(waitFor([&] { return marker("obstacles", walker_id).color.r > 0.9f; }, 3.0))
      << "the dangerous walker's box is not red";
  EXPECT_TRUE(waitFor([&] { return marker("lamp", 1).text.find("lamp ON: danger") == 0; }, 3.0))
      << marker("lamp", 1).text;

  // Back to 3 s: safe again from the next frame.
  danger.reaction_time_s = 3.0;
  ASSERT_TRUE(danger_.setConfiguration(danger));
  a = frame();
  ASSERT_TRUE(a);
  EXPECT_EQ(a->num_dangerous, 0u);

  // A detector tunable: clusters must have 4000 points, the walker has far fewer: its track
  // ends within max_missed_frames + 1 frames.
  detector.cluster_min_points = 4000;
  ASSERT_TRUE(detector_.setConfiguration(detector));
  EXPECT_EQ(detector.cluster_min_points, 4000);
  for (int k = 0; k < 5; ++k) a = frame();
  ASSERT_TRUE(a);
  EXPECT_TRUE(a->obstacles.empty()) << "cluster_min_points not applied";
  // min_points above max_points is refused (validate(ClusterParams)).
  const long detector_rejected = rejected("obstacle detector");
  detector.cluster_min_points = 6000;
  ASSERT_TRUE(detector_.setConfiguration(detector));
  EXPECT_EQ(detector.cluster_min_points, 4000);
  // Out of validate()'s range is refused, not clamped by the .cfg (a tolerance of -1 used
  // to become 0.05 and count as accepted).
  detector.cluster_tolerance_m = -1.0;
  ASSERT_TRUE(detector_.setConfiguration(detector));
  EXPECT_NEAR(detector.cluster_tolerance_m, 0.6, 1e-6);  // a float in the core
  EXPECT_TRUE(waitFor([&] { return rejected("obstacle detector") >= detector_rejected + 2; }, 5.0))
      << "rejections not counted: detector " << rejected("obstacle detector");
}

}  // namespace
}  // namespace test
}  // namespace icanc

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_live_tuning");
  ros::AsyncSpinner spinner(2);
  spinner.start();
  return RUN_ALL_TESTS();
}
