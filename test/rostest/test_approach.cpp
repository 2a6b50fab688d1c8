// rostest: the three nodelets from launch/icanc.launch (Zebra profile) see a pedestrian approach
// from the front at 2 m/s. The lamp must be off while it is far, switch on for danger within two
// frames of the object reaching speed * reaction_time, and switch off tau after the last reset.
#include <cmath>

#include <gtest/gtest.h>

#include "graph_fixture.hpp"

namespace icanc {
namespace test {
namespace {

TEST(Approach, LampOnAtSpeedTimesReactionTimeAndOffTauAfterDangerEnds) {
  GraphFixture g("approach_front.yaml");
  ASSERT_TRUE(g.waitForGraph()) << "icanc graph did not come up";
  double reaction = 0.0, tau = 0.0;
  ASSERT_TRUE(ros::param::get("/icanc/danger_detector/reaction_time_s", reaction));
  ASSERT_TRUE(ros::param::get("/icanc/light_controller/tau_s", tau));

  const sim::SceneObject& walker = g.scenario().scene.objects.front();
  const double speed = -walker.velocity.x();
  const double radius = 0.5 * walker.size.x();
  const auto front_distance = [&](double t) { return walker.positionAt(t).x() - radius; };
  // The moment the closest point reaches speed * reaction_time.
  const double t_cross = walker.start_s + (walker.position.x() - radius - speed * reaction) / speed;

  const ros::Time t0 = g.playScenario();
  ros::WallDuration(0.5).sleep();

  Recorder& rec = g.recorder();
  std::lock_guard<std::mutex> lock(rec.mutex);
  ASSERT_GT(rec.arrays.size(), g.scenario().frames() * 9 / 10) << "frames lost in the graph";

  // Off once input flows, before any danger.
  std::size_t i = 0;
  while (i < rec.states.size() && rec.states[i]->on) ++i;
  ASSERT_LT(i, rec.states.size()) << "lamp never off";
  const double t_first_off = (rec.states[i]->header.stamp - t0).toSec();
  EXPECT_LT(t_first_off, 2.0) << "lamp should go off as soon as clouds flow (fail-safe before)";

  // First switch-on for danger.
  while (i < rec.states.size() && !(rec.states[i]->on && rec.states[i]->reason == LightState::REASON_DANGER)) {
    EXPECT_FALSE(rec.states[i]->on) << "lamp on without danger at " << (rec.states[i]->header.stamp - t0).toSec();
    ++i;
  }
  ASSERT_LT(i, rec.states.size()) << "lamp never switched on for danger";
  const double t_on = (rec.states[i]->cloud_stamp - t0).toSec();
  std::printf("threshold %.2f m reached at t = %.2f s; lamp on for the cloud of t = %.2f s "
              "(object at %.2f m)\n", speed * reaction, t_cross, t_on, front_distance(t_on));
  EXPECT_LE(t_on, t_cross + 0.2 + 1e-3) << "lamp later than two frames after the threshold";
  EXPECT_GE(front_distance(t_on), speed * reaction - 2 * speed / g.scenario().rate_hz);
  EXPECT_LE(front_distance(t_on), speed * reaction + 1.0) << "lamp on too early (far object)";

  // The dangerous obstacle carries the approaching motion.
  for (const auto& a : rec.arrays) {
    if (a->header.stamp != rec.states[i]->cloud_stamp) continue;
    ASSERT_GE(a->num_dangerous, 1u);
    for (const auto& o : a->obstacles) {
      if (!o.dangerous) continue;
      EXPECT_NEAR(o.speed, speed, 0.4);
      // Toward the vehicle: heading pi, within 20 degrees either side (the wrap at -pi).
      EXPECT_NEAR(std::remainder(o.heading - M_PI, 2.0 * M_PI), 0.0, 20.0 * M_PI / 180.0);
      EXPECT_GT(o.heading, -M_PI);
      EXPECT_LE(o.heading, float(M_PI));
      EXPECT_EQ(o.section, Obstacle::SECTION_FRONT);
    }
  }

  // Danger ends after the object stops; the lamp goes off tau after the last timer reset.
  double t_last_danger = -1.0;
  for (const auto& a : rec.arrays)
    if (a->num_dangerous > 0) t_last_danger = (a->header.stamp - t0).toSec();
  ros::Time last_trigger = rec.states[i]->cloud_stamp;
  while (i < rec.states.size() && rec.states[i]->on) {
    last_trigger = rec.states[i]->cloud_stamp;
    ++i;
  }
  ASSERT_LT(i, rec.states.size()) << "lamp never switched off again";
  const double t_off = (rec.states[i]->header.stamp - t0).toSec();
  const double t_trigger = (last_trigger - t0).toSec();
  std::printf("last danger t = %.2f s, last timer reset for the cloud of t = %.2f s, lamp off at "
              "t = %.2f s (tau %.1f s)\n", t_last_danger, t_trigger, t_off, tau);
  EXPECT_GT(t_last_danger, walker.stop_s - 1.0) << "danger should last until the object stops";
  EXPECT_GE(t_off, t_trigger + tau);
  EXPECT_LE(t_off, t_trigger + tau + 0.15 * latencySlack());  // processing latency
  EXPECT_GT(t_off, t_last_danger);
  EXPECT_LE(t_off, t_last_danger + tau + 0.15 * latencySlack());
  // And it stays off while clouds flow: the stopped object is no danger. (After the last cloud the
  // watchdog switches the lamp on: that is the fail-safe, not danger.)
  const double t_end = (g.scenario().frames() - 1) / g.scenario().rate_hz;
  for (; i < rec.states.size(); ++i) {
    const double t = (rec.states[i]->header.stamp - t0).toSec();
    if (t < t_end + 0.25) {
      EXPECT_FALSE(rec.states[i]->on) << t;
    }
  }
}

}  // namespace
}  // namespace test
}  // namespace icanc

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_approach");
  ros::AsyncSpinner spinner(2);
  spinner.start();
  return RUN_ALL_TESTS();
}
