// rostest: the graph of launch/icanc.launch (Zebra) with an 8-segment lamp sees the pedestrian of
// approach_front.yaml walk straight at it. lamp_command must light only the two segments either
// side of straight ahead (low beam: the danger starts within 6 m), light all 8 in the fail-safe
// before clouds flow, and agree with the binary lamp (light_state, lamp_cmd) on every publication;
// ~lamp_segments draws the 8 wedges while subscribed; each command answering an input names it
// and its latency, as the light state does (latency tools). segments_fault.test: an invalid segment list
// is a faulted LightController that lights every segment (and the binary lamp).
// segmented_lamp_outside.test: a dangerous object outside every segment (a pedestrian 75 deg
// left, the lamp covers +-60 deg) lights every segment while the binary lamp is ON.
#include <algorithm>
#include <cmath>
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

// The graph with no clouds (segmented_lamp_outside.test: points_topic /none), so the
// DangerDetector publishes nothing; the test publishes the LightController's input itself: a
// pedestrian 8 m from the lamp at 75 deg left, flagged dangerous, at 10 Hz for 2 s. No segment of
// the 8 x 15 deg lamp over +-60 deg sees it (+ the 2 deg margin): every LampCommand published
// while the binary lamp (light_state.on, which lamp_cmd carries in the same publication) is ON
// must light a segment, and the commands for this danger must light all 8 at high beam.
TEST(SegmentedLamp, DangerOutsideEverySegmentLightsEverySegment) {
  ros::NodeHandle nh;
  CommandRecorder cr;
  std::mutex mutex;
  std::vector<LightState::ConstPtr> states;
  std::vector<ObstacleArray::ConstPtr> inputs;  // all on obstacles_danger
  ros::Subscriber command_sub = nh.subscribe("/icanc/lamp_command", 500, &CommandRecorder::onCommand, &cr);
  ros::Subscriber state_sub = nh.subscribe<LightState>("/icanc/light_state", 500, [&](const LightState::ConstPtr& m) {
    std::lock_guard<std::mutex> l(mutex);
    states.push_back(m);
  });
  ros::Subscriber input_sub = nh.subscribe<ObstacleArray>("/icanc/obstacles_danger", 100,
                                                          [&](const ObstacleArray::ConstPtr& m) {
    std::lock_guard<std::mutex> l(mutex);
    inputs.push_back(m);
  });
  ros::Publisher input_pub = nh.advertise<ObstacleArray>("/icanc/obstacles_danger", 10);
  ASSERT_TRUE(waitFor([&] {
    return command_sub.getNumPublishers() > 0 && state_sub.getNumPublishers() > 0 &&
           input_pub.getNumSubscribers() > 1;  // the LightController and input_sub
  }, 30.0)) << "icanc graph did not come up";
  ros::WallDuration(0.5).sleep();

  const double lamp_x = 0.5, range = 8.0, azimuth = 75.0 * M_PI / 180.0;  // zebra lamp_position_m
  const double cx = lamp_x + range * std::cos(azimuth), cy = range * std::sin(azimuth);
  const int published = 20;
  ros::WallRate rate(10.0);
  for (int k = 0; k < published && ros::ok(); ++k) {
    ObstacleArray a;
    a.header.stamp = ros::Time::now();
    a.header.frame_id = "base_link";
    a.cloud_receive_time = a.header.stamp;
    a.valid_points = 20000;
    Obstacle o;
    o.id = 7;
    o.pose.position.x = cx;
    o.pose.position.y = cy;
    o.pose.position.z = 0.85;
    o.pose.orientation.w = 1.0;
    o.dimensions.x = o.dimensions.y = 0.6;
    o.dimensions.z = 1.7;
    o.aabb_min.x = cx - 0.3;
    o.aabb_min.y = cy - 0.3;
    o.aabb_max.x = cx + 0.3;
    o.aabb_max.y = cy + 0.3;
    o.aabb_max.z = 1.7;
    o.section = Obstacle::SECTION_LEFT;
    o.closest_distance = range - 0.3;
    o.moving_toward = true;
    o.dangerous = true;
    o.age = o.hits = 10 + k;
    a.obstacles.push_back(o);
    a.num_dangerous = 1;
    input_pub.publish(a);
    rate.sleep();
  }
  ros::WallDuration(0.5).sleep();  // then no input: the sensor-stale fail-safe
  command_sub.shutdown();
  state_sub.shutdown();
  input_sub.shutdown();

  std::lock_guard<std::mutex> lc(cr.mutex);
  std::lock_guard<std::mutex> ls(mutex);
  ASSERT_EQ(inputs.size(), std::size_t(published)) << "only this test's arrays may reach the LightController";
  for (const auto& a : inputs) ASSERT_TRUE(a->obstacles.size() == 1 && a->obstacles[0].id == 7);
  std::map<ros::Time, LampCommand::ConstPtr> by_stamp;
  std::size_t danger_commands = 0;
  for (const auto& c : cr.commands) {
    ASSERT_EQ(c->levels.size(), 8u) << "reason " << c->reason_text;
    by_stamp[c->header.stamp] = c;
    if (c->reason != LightState::REASON_DANGER) continue;
    ++danger_commands;
    EXPECT_EQ(c->levels, std::vector<float>(8, 1.0f)) << "a danger outside every segment lights all 8";
  }
  std::size_t compared = 0, danger_states = 0;
  for (const auto& s : states) {
    danger_states += s->reason == LightState::REASON_DANGER;
    const auto it = by_stamp.find(s->header.stamp);
    if (it == by_stamp.end()) continue;
    ++compared;
    if (!s->on) continue;
    const auto& levels = it->second->levels;
    EXPECT_TRUE(std::any_of(levels.begin(), levels.end(), [](float l) { return l > 0.0f; }))
        << "lamp_cmd ON (" << s->reason_text << ") but LampCommand " << it->second->reason_text
        << " with every level 0";
  }
  EXPECT_GT(danger_states, 10u) << "the binary lamp must be ON for the danger";
  EXPECT_GT(danger_commands, 10u) << "the segmented lamp must be ON for the danger";
  EXPECT_GT(compared, 20u);
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
