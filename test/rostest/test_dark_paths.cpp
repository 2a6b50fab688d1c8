// rostest: the dark paths in the whole graph (launch/icanc.launch). A scene without
// danger keeps the lamp OFF; then
// - clouds whose stamp is frozen, zero, or alternates between two clocks: each frame is rejected
//   (counted, WARN in the detector's diagnostics), so the LightController's watchdog lights the
//   lamp (REASON_SENSOR_STALE) instead of the tracker seeing dt = 0 or a reset every frame (speed
//   0, nothing ever dangerous, lamp OFF: what main did); so are clouds whose stamps advance at 5
//   or 0.4 times the receipt clock (a sensor clock running fast or slow), once a second shows it;
// - clouds with no valid return (all NaN, all (0, 0, 0), all out of range: a covered LiDAR): the
//   arrays say sensor_blind, the lamp is ON with REASON_SENSOR_BLIND, both nodelets' diagnostics
//   say ERROR; the lamp goes OFF again once the returns come back;
// - a sensor half covered (the right half of its field of view NaN, on a cover 0.3 m away, or
//   dropped from the message): the rest of the frame is a clear road, but that sector is blind;
// - (zero_health_shares.test) shares of 0, which would switch the blind check off: refused.
#include <diagnostic_msgs/DiagnosticArray.h>
#include <gtest/gtest.h>
#include <sensor_msgs/point_cloud2_iterator.h>

#include <functional>
#include <limits>
#include <map>

#include "graph_fixture.hpp"

namespace icanc {
namespace test {
namespace {

class DarkPaths : public ::testing::Test {
 protected:
  DarkPaths() : g_("approach_front.yaml") {
    diag_ = g_.nh().subscribe<diagnostic_msgs::DiagnosticArray>("/diagnostics", 100,
        [this](const diagnostic_msgs::DiagnosticArray::ConstPtr& m) {
          std::lock_guard<std::mutex> lock(mutex_);
          for (const auto& s : m->status) {
            for (const char* name : {"obstacle detector", "light controller"}) {
              if (s.name.find(name) == std::string::npos) continue;
              levels_[name].push_back({s.level, s.message});
              for (const auto& kv : s.values) counters_[kv.key] = kv.value;
            }
          }
        });
  }

  // Good frame of the scene at t = 0.2 s: a standing pedestrian 16 m ahead, a bin 7 m off the
  // path, nothing dangerous.
  void good(const ros::Time& stamp) { g_.publishFrame(0.2, stamp); }

  std::vector<LightState::ConstPtr> states() {
    std::lock_guard<std::mutex> l(g_.recorder().mutex);
    return g_.recorder().states;
  }
  LightState::ConstPtr lastState() {
    std::lock_guard<std::mutex> l(g_.recorder().mutex);
    return g_.recorder().states.empty() ? nullptr : g_.recorder().states.back();
  }
  LightState::ConstPtr answerTo(const ros::Time& stamp) {
    for (const auto& s : states())
      if (s->input_stamp == stamp) return s;
    return nullptr;
  }

  // 10 Hz good frames until the lamp answers OFF (the graph is up and the scene is safe).
  void settleOff(ros::Time& stamp) {
    ros::Time last;
    bool off = false;
    for (int i = 0; i < 60 && !off; ++i) {
      good(last = (stamp += ros::Duration(0.1)));
      ros::WallDuration(0.1).sleep();
      const LightState::ConstPtr s = answerTo(last);
      off = s && !s->on && s->reason == LightState::REASON_OFF;
    }
    ASSERT_TRUE(off) << "the lamp never answered OFF to the safe scene";
  }

  // Sends `frames` clouds at 10 Hz, made by make(i).
  void stream(int frames, const std::function<void(int)>& make) {
    for (int i = 0; i < frames; ++i) {
      make(i);
      ros::WallDuration(0.1).sleep();
    }
  }

  // The states published in the last `window_s` seconds of wall time are all ON with `reason`.
  ::testing::AssertionResult lampOnLately(std::uint8_t reason, double window_s) {
    const ros::Time since = ros::Time::now() - ros::Duration(window_s);
    int n = 0;
    for (const auto& s : states()) {
      if (s->header.stamp < since) continue;
      ++n;
      if (!s->on || s->reason != reason)
        return ::testing::AssertionFailure() << "state at " << s->header.stamp << ": on " << int(s->on)
                                             << ", reason '" << s->reason_text << "'";
    }
    if (n == 0) return ::testing::AssertionFailure() << "no state in the last " << window_s << " s";
    return ::testing::AssertionSuccess() << n << " states";
  }

  long counter(const std::string& key) {
    std::lock_guard<std::mutex> lock(mutex_);
    const auto it = counters_.find(key);
    return it == counters_.end() ? -1 : std::stol(it->second);
  }
  bool levelSeen(const std::string& status, std::uint8_t level, const std::string& text) {
    std::lock_guard<std::mutex> lock(mutex_);
    for (const auto& l : levels_[status])
      if (l.first == level && l.second.find(text) != std::string::npos) return true;
    return false;
  }
  void clearLevels() {
    std::lock_guard<std::mutex> lock(mutex_);
    levels_.clear();
  }

  GraphFixture g_;
  std::mutex mutex_;
  std::map<std::string, std::vector<std::pair<std::uint8_t, std::string>>> levels_;
  std::map<std::string, std::string> counters_;
  ros::Subscriber diag_;
};

TEST_F(DarkPaths, StampsThatDoNotAdvanceLightTheLamp) {
  ASSERT_TRUE(g_.waitForGraph());
  ros::Time stamp = ros::Time::now();
  settleOff(stamp);
  using Diag = diagnostic_msgs::DiagnosticStatus;

  struct Case {
    const char* what;
    const char* counter;
    std::function<ros::Time(int)> stamp_of;  // frame i's stamp
    int frames;                              // at 10 Hz
  };
  const char* const rate = "stamps rejected: stamps advance at a rate off the receipt clock (sensor clock fast or slow)";
  const ros::Time frozen = stamp + ros::Duration(0.1);
  const std::vector<Case> cases = {
      {"frozen stamp", "stamps rejected: stamp repeats the previous frame's",
       [&](int) { return frozen; }, 20},
      {"zero stamp", "stamps rejected: zero stamp", [&](int) { return ros::Time(); }, 20},
      // Two clocks 100 s apart, alternating: every frame goes backwards or jumps.
      {"alternating clocks", "stamps rejected: stamp went backwards",
       [&](int i) { return stamp + ros::Duration(0.1 * (i + 1) - (i % 2 ? 100.0 : 0.0)); }, 20},
      // A sensor clock running fast (stamps 0.5 s apart every 0.1 s: speeds 5 times too low) or
      // slow (0.04 s apart): rejected once a second of receipts shows it, so 3 s of it.
      {"fast clock", rate, [&](int i) { return stamp + ros::Duration(0.5 * (i + 1)); }, 30},
      {"slow clock", rate, [&](int i) { return stamp + ros::Duration(0.04 * (i + 1)); }, 30},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.what);
    clearLevels();
    const long before = std::max(0L, counter(c.counter));
    ros::Time last;
    stream(c.frames, [&](int i) { good(last = c.stamp_of(i)); });
    // Not a clear road: the lamp has been ON (watchdog) for the last second of the 2 s.
    EXPECT_TRUE(lampOnLately(LightState::REASON_SENSOR_STALE, 1.0));
    EXPECT_TRUE(waitFor([&] { return counter(c.counter) >= before + 10; }, 3.0))
        << c.counter << " = " << counter(c.counter);
    EXPECT_TRUE(waitFor([&] { return levelSeen("obstacle detector", Diag::WARN, "stamps rejected"); }, 3.0))
        << "no WARN 'cloud stamps rejected' in the detector's diagnostics";
    // Good stamps again (past every stamp sent): OFF again within a few frames.
    stamp = std::max(stamp + ros::Duration(5.0), last + ros::Duration(0.1));
    settleOff(stamp);
  }
}

// A blind cloud: organized, 32 x 1000, every point (v, 0, 0) (all NaN when v is NaN).
sensor_msgs::PointCloud2::Ptr blindCloud(const std::string& frame, const ros::Time& stamp, float v) {
  auto msg = boost::make_shared<sensor_msgs::PointCloud2>();
  msg->header.frame_id = frame;
  msg->header.stamp = stamp;
  sensor_msgs::PointCloud2Modifier mod(*msg);
  mod.setPointCloud2FieldsByString(1, "xyz");
  mod.resize(32000);
  msg->height = 32;
  msg->width = 1000;
  msg->row_step = msg->width * msg->point_step;
  for (sensor_msgs::PointCloud2Iterator<float> x(*msg, "x"); x != x.end(); ++x) {
    x[0] = v;
    x[1] = x[2] = std::isnan(v) ? v : 0.0f;
  }
  return msg;
}

TEST_F(DarkPaths, BlindSensorLightsTheLampWithItsReason) {
  ASSERT_TRUE(g_.waitForGraph());
  ros::Time stamp = ros::Time::now();
  settleOff(stamp);
  using Diag = diagnostic_msgs::DiagnosticStatus;
  const std::string frame = g_.scenario().sensor_frame;

  struct Case {
    const char* what;
    float v;
  };
  const std::vector<Case> cases = {{"all NaN", std::numeric_limits<float>::quiet_NaN()},
                                   {"all (0, 0, 0)", 0.0f},
                                   {"all out of range", 5000.0f},
                                   {"all on the window", 0.01f}};
  for (const Case& c : cases) {
    SCOPED_TRACE(c.what);
    clearLevels();
    ros::Time last;
    stream(15, [&](int) { g_.publishRaw(blindCloud(frame, last = (stamp += ros::Duration(0.1)), c.v)); });
    ASSERT_TRUE(waitFor([&] { return answerTo(last) != nullptr; }, 5.0)) << "blind frames unanswered";
    const LightState::ConstPtr s = answerTo(last);
    EXPECT_TRUE(s->on);
    EXPECT_EQ(s->reason, LightState::REASON_SENSOR_BLIND);
    EXPECT_EQ(s->reason_text, "sensor blind");
    EXPECT_TRUE(lampOnLately(LightState::REASON_SENSOR_BLIND, 1.0));
    {
      std::lock_guard<std::mutex> l(g_.recorder().mutex);
      ASSERT_FALSE(g_.recorder().arrays.empty());
      EXPECT_TRUE(g_.recorder().arrays.back()->sensor_blind);
      EXPECT_EQ(g_.recorder().arrays.back()->valid_points, 0u);
    }
    EXPECT_TRUE(waitFor([&] { return levelSeen("obstacle detector", Diag::ERROR, "sensor blind"); }, 3.0))
        << "no ERROR 'sensor blind' in the detector's diagnostics";
    EXPECT_TRUE(waitFor([&] { return levelSeen("light controller", Diag::ERROR, "sensor blind"); }, 3.0))
        << "no ERROR 'sensor blind' in the light controller's diagnostics";
    EXPECT_GE(counter("sensor blind frames"), 1);
    // The returns come back: OFF again (once the window's mean share recovers).
    settleOff(stamp);
    {
      std::lock_guard<std::mutex> l(g_.recorder().mutex);
      EXPECT_FALSE(g_.recorder().arrays.back()->sensor_blind);
      EXPECT_GT(g_.recorder().arrays.back()->valid_points, 1000u);
    }
  }
}

// zero_health_shares.test: sensor_health/min_frame_share and min_window_share 0 would never call
// the sensor blind (an all-NaN cloud: lamp off, diagnostics OK). The ObstacleDetector refuses
// them at load: it never subscribes, so the LightController's watchdog keeps the lamp ON.
TEST_F(DarkPaths, ZeroHealthSharesAreRefusedAndTheLampStaysOn) {
  ASSERT_TRUE(waitFor([&] { return lastState() != nullptr; }, 30.0)) << "no light_state";
  ros::Time stamp = ros::Time::now();
  const std::string frame = g_.scenario().sensor_frame;
  stream(20, [&](int) {
    g_.publishRaw(blindCloud(frame, stamp += ros::Duration(0.1), std::numeric_limits<float>::quiet_NaN()));
  });
  EXPECT_TRUE(lampOnLately(LightState::REASON_SENSOR_STALE, 1.5));
  std::lock_guard<std::mutex> l(g_.recorder().mutex);
  EXPECT_TRUE(g_.recorder().arrays.empty()) << "the ObstacleDetector ran with the blind check off";
}

// The right half of the Zebra's forward field of view (azimuth -60..0 deg) covered.
TEST_F(DarkPaths, HalfCoveredSensorLightsTheLamp) {
  ASSERT_TRUE(g_.waitForGraph());
  ros::Time stamp = ros::Time::now();
  settleOff(stamp);
  using Diag = diagnostic_msgs::DiagnosticStatus;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const auto covered = [](const Point& p) { return p.y < 0.0f && p.x > 0.0f; };
  struct Case {
    const char* what;
    std::function<void(Cloud&)> edit;
  };
  const std::vector<Case> cases = {
      {"NaN", [&](Cloud& c) { for (Point& p : c) if (covered(p)) p.x = p.y = p.z = nan; }},
      {"on a cover 0.3 m away", [&](Cloud& c) {
         for (Point& p : c)
           if (covered(p)) p.getVector3fMap() *= 0.3f / p.getVector3fMap().norm();
       }},
      {"dropped", [&](Cloud& c) {
         Cloud kept;
         for (const Point& p : c)
           if (!covered(p)) kept.push_back(p);  // unorganized: height 1, every point valid
         c = kept;
       }},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.what);
    clearLevels();
    const long before = std::max(0L, counter("sensor blind sector frames"));
    ros::Time last;
    // 2.5 s: a cover that returns is blind once the window (10 frames) says it lasts.
    stream(25, [&](int) { g_.publishFrame(0.2, last = (stamp += ros::Duration(0.1)), c.edit); });
    ASSERT_TRUE(waitFor([&] { return answerTo(last) != nullptr; }, 5.0)) << "covered frames unanswered";
    const LightState::ConstPtr s = answerTo(last);
    EXPECT_TRUE(s->on);
    EXPECT_EQ(s->reason, LightState::REASON_SENSOR_BLIND);
    EXPECT_TRUE(lampOnLately(LightState::REASON_SENSOR_BLIND, 1.0));
    {
      std::lock_guard<std::mutex> l(g_.recorder().mutex);
      ASSERT_FALSE(g_.recorder().arrays.empty());
      EXPECT_TRUE(g_.recorder().arrays.back()->sensor_blind);
      EXPECT_GT(g_.recorder().arrays.back()->valid_points, 1000u) << "half the frame still returns";
    }
    EXPECT_TRUE(waitFor([&] { return levelSeen("obstacle detector", Diag::ERROR, "sensor blind in a sector"); }, 3.0))
        << "no ERROR 'sensor blind in a sector' in the detector's diagnostics";
    EXPECT_TRUE(waitFor([&] { return counter("sensor blind sector frames") >= before + 10; }, 3.0));
    settleOff(stamp);
  }
}

}  // namespace
}  // namespace test
}  // namespace icanc

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_dark_paths");
  ros::AsyncSpinner spinner(2);
  spinner.start();
  return RUN_ALL_TESTS();
}
