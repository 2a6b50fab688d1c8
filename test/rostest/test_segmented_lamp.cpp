// rostest: the graph of launch/icanc.launch (Zebra) with an 8-segment lamp sees the pedestrian of
// approach_front.yaml walk straight at it. lamp_command must light only the two segments either
// side of straight ahead (low beam: the danger starts within 6 m), light all 8 in the fail-safe
// before clouds flow, and agree with the binary lamp (light_state, lamp_cmd) on every publication;
// ~lamp_segments draws the 8 wedges while subscribed; each command answering an input names it
// and its latency, as the light state does (latency tools). segments_fault.test: an invalid segment list
// is a faulted LightController that lights every segment (and the binary lamp).
#include <map>

#include <gtest/gtest.h>
#include <visualization_msgs/MarkerArray.h>

#include "graph_fixture.hpp"
#include "icanc/LampCommand.h"

namespace icanc {
namespace test {
namespace {

struct CommandRecorder {
  std::mutex mutex;
  std::vector<LampCommand::ConstPtr> commands;
  std::size_t marker_arrays = 0, markers = 0;
  void onCommand(const LampCommand::ConstPtr& m) { std::lock_guard<std::mutex> l(mutex); commands.push_back(m); }
  void onMarkers(const visualization_msgs::MarkerArray::ConstPtr& m) {
    std::lock_guard<std::mutex> l(mutex);
    ++marker_arrays;
    markers = m->markers.size();
  }
};

TEST(SegmentedLamp, LightsOnlyWhereTheDangerIsAndAgreesWithTheBinaryLamp) {
  CommandRecorder cr;
  GraphFixture g("approach_front.yaml");
  ros::Subscriber command_sub = g.nh().subscribe("/icanc/lamp_command", 200, &CommandRecorder::onCommand, &cr);
  ros::Subscriber marker_sub = g.nh().subscribe("/icanc/light_controller/lamp_segments", 5,
                                                &CommandRecorder::onMarkers, &cr);
  ASSERT_TRUE(g.waitForGraph()) << "icanc graph did not come up";
  ASSERT_TRUE(waitFor([&] { return command_sub.getNumPublishers() > 0; }, 10.0));
  ros::WallDuration(0.5).sleep();  // the fail-safe commands before the first cloud

  const ros::Time t0 = g.playScenario();
  ros::WallDuration(0.5).sleep();
  command_sub.shutdown();
  marker_sub.shutdown();

  std::lock_guard<std::mutex> lock(cr.mutex);
  ASSERT_GT(cr.commands.size(), g.scenario().frames() / 2);
  std::map<ros::Time, bool> any_on;  // by stamp: one command per light state
  std::map<ros::Time, LampCommand::ConstPtr> by_stamp;
  std::size_t danger = 0, fail_safe = 0;
  for (const auto& c : cr.commands) {
    ASSERT_EQ(c->levels.size(), 8u) << "reason " << c->reason_text;
    ASSERT_NE(c->reason, LightState::REASON_FAULT);
    bool any = false;
    for (float l : c->levels) any = any || l > 0.0f;
    any_on[c->header.stamp] = any;
    by_stamp[c->header.stamp] = c;
    if (c->reason == LightState::REASON_SENSOR_STALE) {
      ++fail_safe;
      for (float l : c->levels) EXPECT_FLOAT_EQ(l, 1.0f) << "fail-safe must light every segment";
    } else if (c->reason == LightState::REASON_DANGER) {
      ++danger;
      for (int i : {0, 1, 2, 5, 6, 7}) EXPECT_EQ(c->levels[i], 0.0f) << "segment " << i << " lit";
      EXPECT_FLOAT_EQ(c->levels[3], 0.6f) << "the pedestrian ahead, within 15 m: low beam";
      EXPECT_FLOAT_EQ(c->levels[4], 0.6f);
    } else {
      EXPECT_FALSE(any) << c->reason_text;
    }
  }
  EXPECT_GT(danger, 10u);
  EXPECT_GT(fail_safe, 0u);  // before the first cloud

  Recorder& rec = g.recorder();
  std::lock_guard<std::mutex> rec_lock(rec.mutex);
  std::size_t compared = 0, answered = 0;
  for (const auto& s : rec.states) {
    const auto it = any_on.find(s->header.stamp);
    if (it == any_on.end()) continue;
    ++compared;
    EXPECT_EQ(it->second, bool(s->on)) << "at " << (s->header.stamp - t0).toSec() << " s";
    const LampCommand& c = *by_stamp[s->header.stamp];
    EXPECT_EQ(c.input_stamp, s->input_stamp);
    if (s->input_latency_ms > 0.0f) {  // answers an input: its levels published after the state
      ++answered;
      EXPECT_GE(c.input_latency_ms, s->input_latency_ms);
    }
  }
  EXPECT_GT(compared, g.scenario().frames() / 2);
  EXPECT_GT(answered, g.scenario().frames() / 2) << "commands answering an input carry its latency";
  EXPECT_GT(cr.marker_arrays, 0u);
  EXPECT_EQ(cr.markers, 8u);
}

TEST(SegmentedLamp, InvalidSegmentsLightEverySegment) {
  ros::NodeHandle nh;
  CommandRecorder cr;
  ros::Subscriber command_sub = nh.subscribe("/icanc/lamp_command", 50, &CommandRecorder::onCommand, &cr);
  std::mutex mutex;
  std::vector<LightState::ConstPtr> states;
  auto state_sub = nh.subscribe<LightState>("/icanc/light_state", 50, [&](const LightState::ConstPtr& m) {
    std::lock_guard<std::mutex> l(mutex);
    states.push_back(m);
  });
  ASSERT_TRUE(waitFor([&] {
    std::lock_guard<std::mutex> l(cr.mutex);
    return cr.commands.size() >= 5;
  }, 30.0)) << "a faulted LightController must still publish lamp_command";
  std::lock_guard<std::mutex> l(cr.mutex);
  for (const auto& c : cr.commands) {
    EXPECT_EQ(c->reason, LightState::REASON_FAULT);
    EXPECT_EQ(c->levels, std::vector<float>(3, 1.0f)) << "the profile's 3 segments, all ON";
  }
  std::lock_guard<std::mutex> ls(mutex);
  ASSERT_FALSE(states.empty());
  for (const auto& s : states) {
    EXPECT_TRUE(s->on);
    EXPECT_EQ(s->reason, LightState::REASON_FAULT);
  }
}

}  // namespace
}  // namespace test
}  // namespace icanc

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_segmented_lamp");
  ros::AsyncSpinner spinner(2);
  spinner.start();
  return RUN_ALL_TESTS();
}
