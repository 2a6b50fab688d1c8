// rostest (params_at_load.test): a string for light_controller/tau_s, a string for
// danger_detector/half_width_m and 2.5 for the integer obstacle_detector/cluster/min_points. None
// falls back to its default in silence (ParamReader used nh.param(key, v, v)): each nodelet
// refuses to start, and the LightController, although it cannot run its state machine, still
// publishes lamp ON (REASON_FAULT) on lamp_cmd and light_state and an ERROR in /diagnostics that
// names the key and the reason.
#include <diagnostic_msgs/DiagnosticArray.h>
#include <gtest/gtest.h>
#include <std_msgs/Bool.h>

#include "graph_fixture.hpp"
#include "icanc/ros/bag_replay.hpp"

namespace icanc {
namespace test {
namespace {

TEST(ParamsAtLoad, WrongTypesAreRefusedAndTheLampFailsSafe) {
  ros::NodeHandle nh;
  std::mutex mutex;
  LightState::ConstPtr state;
  std_msgs::Bool::ConstPtr lamp;
  std::string error;
  auto state_sub = nh.subscribe<LightState>("/icanc/light_state", 10, [&](const LightState::ConstPtr& m) {
    std::lock_guard<std::mutex> l(mutex);
    state = m;
  });
  auto lamp_sub = nh.subscribe<std_msgs::Bool>("/icanc/lamp_cmd", 10, [&](const std_msgs::Bool::ConstPtr& m) {
    std::lock_guard<std::mutex> l(mutex);
    lamp = m;
  });
  auto diag_sub = nh.subscribe<diagnostic_msgs::DiagnosticArray>("/diagnostics", 10,
      [&](const diagnostic_msgs::DiagnosticArray::ConstPtr& m) {
        std::lock_guard<std::mutex> l(mutex);
        for (const auto& s : m->status)
          if (s.name.find("light controller") != std::string::npos &&
              s.level == diagnostic_msgs::DiagnosticStatus::ERROR)
            error = s.message;
      });
  ASSERT_TRUE(waitFor([&] {
    std::lock_guard<std::mutex> l(mutex);
    return state && lamp && !error.empty();
  }, 30.0)) << "the faulted LightController must still publish lamp_cmd, light_state and diagnostics";
  {
    std::lock_guard<std::mutex> l(mutex);
    EXPECT_TRUE(lamp->data);
    EXPECT_TRUE(state->on);
    EXPECT_EQ(state->reason, LightState::REASON_FAULT);
    EXPECT_EQ(state->reason_text, "fault");
    EXPECT_NE(error.find("/icanc/light_controller/tau_s"), std::string::npos) << error;
    EXPECT_NE(error.find("must be a number (got a string)"), std::string::npos) << error;
  }
  // Steady: the lamp command keeps coming (the Arduino's command timeout would otherwise fire).
  std::size_t before = 0, after = 0;
  auto count_sub = nh.subscribe<std_msgs::Bool>("/icanc/lamp_cmd", 100, [&](const std_msgs::Bool::ConstPtr& m) {
    std::lock_guard<std::mutex> l(mutex);
    EXPECT_TRUE(m->data);
    ++after;
  });
  ros::WallDuration(2.0).sleep();
  {
    std::lock_guard<std::mutex> l(mutex);
    EXPECT_GE(after - before, 10u) << "lamp_cmd not published at a steady rate while faulted";
  }
  // The other two refused to start: no subscriber on the cloud topic, no danger output.
  ros::Publisher points = nh.advertise<sensor_msgs::PointCloud2>("/test/points", 1);
  ros::WallDuration(2.0).sleep();
  EXPECT_EQ(points.getNumSubscribers(), 0u) << "obstacle_detector started with cluster/min_points 2.5";
  ros::master::V_TopicInfo topics;
  ASSERT_TRUE(ros::master::getTopics(topics));
  for (const auto& t : topics)
    EXPECT_NE(t.name, "/icanc/obstacles_danger") << "danger_detector started with half_width_m 'wide'";
}

// The evaluator (icanc_eval, the eval rostests) reads the graph's parameters as its nodelets do:
// what they would refuse stops it with the key's message, rather than a region of interest
// with its corners swapped scoring detection over nothing.
TEST(ParamsAtLoad, TheEvaluatorRefusesWhatTheGraphRefuses) {
  ros::NodeHandle nh;
  const auto refused = [](const std::string& ns) {
    EvalParams params;
    SegmentLampParams lamp;
    try {
      readGraphParams(ns, params);
      readLampPlacement(ns, lamp);
    } catch (const std::runtime_error& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_EQ(refused("/eval_defaults"), "");  // nothing set: every default is valid
  nh.setParam("/eval_roi/obstacle_detector/prep/roi_min", std::vector<double>{60.0, -20.0, -2.0});
  nh.setParam("/eval_roi/obstacle_detector/prep/roi_max", std::vector<double>{-10.0, 20.0, 2.0});
  const std::string roi = refused("/eval_roi");
  EXPECT_NE(roi.find("/eval_roi/obstacle_detector: prep.roi_min.x must be <"), std::string::npos)
      << roi;
  nh.setParam("/eval_lamp/light_controller/lamp_position_m", std::vector<double>{50.0, 0.0, 0.0});
  const std::string lamp = refused("/eval_lamp");
  EXPECT_NE(lamp.find("/eval_lamp/light_controller: light.lamp_position_m"), std::string::npos)
      << lamp;
}

}  // namespace
}  // namespace test
}  // namespace icanc

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_params_at_load");
  ros::AsyncSpinner spinner(2);
  spinner.start();
  return RUN_ALL_TESTS();
}
