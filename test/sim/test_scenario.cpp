// Scenario files load with their motion and sensor mount; mistakes are reported by key.
#include <cmath>
#include <cstdio>
#include <fstream>
#include <stdexcept>

#include <gtest/gtest.h>
#include <unistd.h>

#include "icanc/sim/scenario.hpp"

namespace icanc {
namespace sim {
namespace {

std::string repoPath(const std::string& rel) {
  const std::string here = __FILE__;
  return here.substr(0, here.rfind("/test/sim/")) + "/" + rel;
}

std::string writeTemp(const std::string& text) {
  const std::string path = ::testing::TempDir() + "icanc_scenario_test_" + std::to_string(::getpid()) + ".yaml";
  std::ofstream(path) << text;
  return path;
}

TEST(Scenario, ShippedPedestrianApproachLoads) {
  const Scenario s = loadScenario(repoPath("config/scenarios/pedestrian_approach.yaml"));
  EXPECT_EQ(s.lidar, "robosense_m1");
  EXPECT_EQ(s.frames(), 161u);  // 16 s at 10 Hz, both ends
  ASSERT_EQ(s.scene.objects.size(), 4u);
  const SceneObject& walker = s.scene.objects[0];
  EXPECT_EQ(walker.type, "pedestrian");
  EXPECT_EQ(walker.shape, Shape::kCylinder);
  EXPECT_NEAR(walker.positionAt(9.0).x(), 3.0, 1e-5);   // stops 3 m ahead
  EXPECT_NEAR(walker.positionAt(15.0).x(), 3.0, 1e-5);
  EXPECT_NEAR(s.sensorPose(0.0).translation().z(), 0.6, 1e-6);
  EXPECT_NEAR(s.scene.objects[2].yaw, 20.0 * M_PI / 180.0, 1e-6);
}

TEST(Scenario, EgoMotionMovesTheSensor) {
  const Scenario s = loadScenario(writeTemp(
      "duration_s: 2\nsensor: {model: vlp16, mount_xyz: [1, 0, 1.5]}\nego: {velocity: [10, 0, 0]}\n"));
  EXPECT_NEAR(s.sensorPose(1.5).translation().x(), 16.0, 1e-5);
  EXPECT_NEAR(s.sensorPose(1.5).translation().z(), 1.5, 1e-5);
}

// Heading of a pose about +z [rad].
double headingOf(const Eigen::Isometry3f& pose) {
  return std::atan2(pose.linear()(1, 0), pose.linear()(0, 0));
}

TEST(Scenario, ConstantTurnFollowsTheCircle) {
  // 10 m/s at 18 deg/s: radius 10 / (pi / 10) = 31.83 m about (0, R); a quarter circle in 5 s.
  const Scenario s = loadScenario(writeTemp(
      "duration_s: 8\nego: {speed_mps: 10, yaw_rate_deg_s: 18}\n"));
  ASSERT_EQ(s.ego_segments.size(), 1u);
  const double r = 10.0 / (M_PI / 10.0);
  const Eigen::Isometry3f quarter = s.vehiclePose(5.0);
  EXPECT_NEAR(quarter.translation().x(), r, 1e-4);
  EXPECT_NEAR(quarter.translation().y(), r, 1e-4);
  EXPECT_NEAR(headingOf(quarter), M_PI / 2.0, 1e-6);
  for (double t = 0.0; t <= 20.0; t += 0.7) {  // on the circle, heading along it, past the end
    const Eigen::Vector3f p = s.vehiclePose(t).translation();
    EXPECT_NEAR(std::hypot(p.x(), p.y() - r), r, 1e-3) << t;
    EXPECT_NEAR(std::remainder(headingOf(s.vehiclePose(t)) - t * M_PI / 10.0, 2.0 * M_PI), 0.0,
                1e-5) << t;
    EXPECT_NEAR(s.vehiclePose(t).translation().z(), 0.0, 1e-9);
  }
  const EgoTwist twist = s.vehicleTwist(3.0);
  EXPECT_NEAR(twist.linear.x(), 10.0, 1e-6);
  EXPECT_NEAR(twist.linear.y(), 0.0, 1e-6);
  EXPECT_NEAR(twist.yaw_rate, M_PI / 10.0, 1e-6);
  EXPECT_NEAR(s.vehicleVelocity(5.0).x(), 0.0, 1e-5);  // heading +y after the quarter circle
  EXPECT_NEAR(s.vehicleVelocity(5.0).y(), 10.0, 1e-5);
  // Right turn: mirrored.
  const Scenario right =
      loadScenario(writeTemp("ego: {speed_mps: 10, yaw_rate_deg_s: -18}\n"));
  EXPECT_NEAR(right.vehiclePose(5.0).translation().y(), -r, 1e-4);
  EXPECT_NEAR(headingOf(right.vehiclePose(5.0)), -M_PI / 2.0, 1e-6);
}

TEST(Scenario, SegmentsJoinContinuouslyAndTheLastContinues) {
  // Straight 2 s at 8 m/s, a left quarter turn in 5 s at 6 m/s (R = 6 / (pi / 10) = 19.1 m),
  // straight on at 6 m/s.
  const Scenario s = loadScenario(writeTemp(
      "duration_s: 12\nego:\n  segments:\n"
      "    - {duration_s: 2, speed_mps: 8, yaw_rate_deg_s: 0}\n"
      "    - {duration_s: 5, speed_mps: 6, yaw_rate_deg_s: 18}\n"
      "    - {duration_s: 3, speed_mps: 6}\n"));
  ASSERT_EQ(s.ego_segments.size(), 3u);
  const double r = 6.0 / (M_PI / 10.0);
  EXPECT_NEAR(s.vehiclePose(1.0).translation().x(), 8.0, 1e-5);
  EXPECT_NEAR(s.vehiclePose(2.0).translation().x(), 16.0, 1e-5);
  EXPECT_NEAR(s.vehiclePose(7.0).translation().x(), 16.0 + r, 1e-4);
  EXPECT_NEAR(s.vehiclePose(7.0).translation().y(), r, 1e-4);
  EXPECT_NEAR(headingOf(s.vehiclePose(7.0)), M_PI / 2.0, 1e-6);
  EXPECT_NEAR(s.vehiclePose(10.0).translation().x(), 16.0 + r, 1e-4);
  EXPECT_NEAR(s.vehiclePose(10.0).translation().y(), r + 18.0, 1e-4);
  EXPECT_NEAR(s.vehiclePose(12.0).translation().y(), r + 30.0, 1e-4);  // past the last segment
  for (double join : {2.0, 7.0, 10.0}) {  // pose continuous, heading continuous at every join
    const Eigen::Isometry3f before = s.vehiclePose(join - 1e-6), after = s.vehiclePose(join + 1e-6);
    EXPECT_LT((before.translation() - after.translation()).norm(), 1e-4) << join;
    EXPECT_NEAR(headingOf(before), headingOf(after), 1e-5) << join;
  }
  EXPECT_NEAR(s.vehicleTwist(1.9).linear.x(), 8.0, 1e-6);  // at a join: the later segment's
  EXPECT_NEAR(s.vehicleTwist(2.0).linear.x(), 6.0, 1e-6);
  EXPECT_NEAR(s.vehicleTwist(2.0).yaw_rate, M_PI / 10.0, 1e-6);
  EXPECT_NEAR(s.vehicleTwist(8.0).yaw_rate, 0.0, 1e-9);
  EXPECT_NEAR(s.vehicleVelocity(8.0).y(), 6.0, 1e-5);
}

TEST(Path, EmptyThrowsAndNegativeTimeRunsBackwards) {
  EXPECT_THROW(poseAlong({}, 1.0), std::invalid_argument);
  EXPECT_THROW(segmentAt({}, 1.0), std::invalid_argument);
  const std::vector<PathSegment> path = {{1.0, 2.0, 0.5}, {1.0, 4.0, 0.0}};
  const PlanarPose back = poseAlong(path, -1.0);  // the first arc, backwards: mirror of +1 s
  const PlanarPose fwd = poseAlong(path, 1.0);
  EXPECT_NEAR(back.x, -fwd.x, 1e-12);
  EXPECT_NEAR(back.y, fwd.y, 1e-12);
  EXPECT_NEAR(back.theta, -0.5, 1e-12);
  EXPECT_NEAR(std::hypot(fwd.x, fwd.y - 4.0), 4.0, 1e-12);  // R = 2 / 0.5 about (0, 4)
  EXPECT_EQ(segmentAt(path, -3.0).speed_mps, 2.0);
  EXPECT_EQ(segmentAt(path, 50.0).speed_mps, 4.0);
  const PlanarPose later = poseAlong(path, 3.0);  // 2 s on the straight at heading 0.5 rad
  EXPECT_NEAR(later.x - fwd.x, 8.0 * std::cos(0.5), 1e-12);
  EXPECT_NEAR(later.y - fwd.y, 8.0 * std::sin(0.5), 1e-12);
}

TEST(Scenario, SpeedChangesEvenlyToAStop) {
  // 1 s at 10 m/s, braking evenly to a stop in 2 s (5 m/s^2: 10 m), then standing.
  const Scenario s = loadScenario(writeTemp(
      "duration_s: 6\nego:\n  segments:\n"
      "    - {duration_s: 1, speed_mps: 10}\n"
      "    - {duration_s: 2, speed_mps: 10, end_speed_mps: 0}\n"
      "    - {duration_s: 3, speed_mps: 0}\n"));
  EXPECT_NEAR(s.vehiclePose(2.0).translation().x(), 10.0 + 7.5, 1e-5);
  EXPECT_NEAR(s.vehiclePose(3.0).translation().x(), 20.0, 1e-5);
  EXPECT_NEAR(s.vehiclePose(5.5).translation().x(), 20.0, 1e-5);
  EXPECT_NEAR(s.vehiclePose(5.5).translation().y(), 0.0, 1e-6);
  EXPECT_NEAR(s.vehicleTwist(2.0).linear.x(), 5.0, 1e-6);
  EXPECT_NEAR(s.vehicleTwist(2.9).linear.x(), 0.5, 1e-5);
  EXPECT_NEAR(s.vehicleTwist(4.0).linear.x(), 0.0, 1e-9);
  EXPECT_NEAR(s.vehicleVelocity(2.5).x(), 2.5, 1e-5);
  // A last segment that changes speed holds its end speed past its end.
  const std::vector<PathSegment> ramp = {{2.0, 2.0, 0.0, 4.0}};
  EXPECT_NEAR(speedAlong(ramp, 1.0), 3.0, 1e-12);
  EXPECT_NEAR(speedAlong(ramp, 5.0), 4.0, 1e-12);
  EXPECT_NEAR(poseAlong(ramp, 5.0).x, 6.0 + 12.0, 1e-9);
}

TEST(Path, ArcWithAChangingSpeedMatchesFineIntegration) {
  // Speeding up 2 -> 8 m/s over 3 s while turning at 0.4 rad/s and at 1e-4 rad/s (the series of
  // the closed form near no turn), against a fine midpoint integration.
  for (const double w : {0.4, 1e-4, -0.7}) {
    const std::vector<PathSegment> path = {{3.0, 2.0, w, 8.0}};
    double x = 0.0, y = 0.0, theta = 0.0;
    const int steps = 300000;
    const double h = 3.0 / steps;
    for (int i = 0; i < steps; ++i) {
      const double tm = (i + 0.5) * h, v = 2.0 + 2.0 * tm, th = theta + 0.5 * w * h;
      x += v * std::cos(th) * h;
      y += v * std::sin(th) * h;
      theta += w * h;
    }
    const PlanarPose p = poseAlong(path, 3.0);
    EXPECT_NEAR(p.x, x, 1e-6) << w;
    EXPECT_NEAR(p.y, y, 1e-6) << w;
    EXPECT_NEAR(p.theta, 3.0 * w, 1e-12) << w;
  }
}

TEST(Scenario, ObjectFollowsItsPath) {
  // A car heading -x from (50, 3.5) from t = 1 s: 2 s straight at 10 m/s, then a left arc at
  // 10 m/s, 18 deg/s (R = 31.83 m, about (30, 3.5 - R)).
  const Scenario s = loadScenario(writeTemp(
      "objects:\n  - {type: car, position: [50, 3.5, 0], yaw_deg: 180, start_s: 1, stop_s: 8,\n"
      "     path: [{duration_s: 2, speed_mps: 10}, {duration_s: 9, speed_mps: 10,"
      " yaw_rate_deg_s: 18}]}\n"));
  ASSERT_EQ(s.scene.objects.size(), 1u);
  const SceneObject& car = s.scene.objects[0];
  ASSERT_EQ(car.path.size(), 2u);
  const double r = 10.0 / (M_PI / 10.0);
  EXPECT_TRUE(car.positionAt(0.5).isApprox(Eigen::Vector3f(50.0f, 3.5f, 0.0f)));  // not started
  EXPECT_NEAR(car.yawAt(0.5), M_PI, 1e-6);
  EXPECT_NEAR(car.positionAt(2.0).x(), 40.0, 1e-4);
  EXPECT_TRUE(car.velocityAt(2.0).isApprox(Eigen::Vector3f(-10.0f, 0.0f, 0.0f), 1e-5f));
  // After the quarter arc (t = 3 + 5 s = stop_s): heading -y at (30 - R, 3.5 - R), then holds.
  EXPECT_NEAR(car.positionAt(8.0).x(), 30.0 - r, 1e-3);
  EXPECT_NEAR(car.positionAt(8.0).y(), 3.5 - r, 1e-3);
  EXPECT_NEAR(car.yawAt(8.0), 1.5 * M_PI, 1e-5);
  EXPECT_TRUE(car.positionAt(12.0).isApprox(car.positionAt(8.0)));
  EXPECT_TRUE(car.velocityAt(8.0).isZero());
  const Eigen::Vector3f v = car.velocityAt(5.5);  // on the arc: tangent, 10 m/s, heading 225 deg
  EXPECT_NEAR(v.norm(), 10.0, 1e-4);
  EXPECT_NEAR(std::atan2(v.y(), v.x()), -0.75 * M_PI, 1e-5);
  // The truth boxes turn with it.
  const std::vector<ObjectTruth> truths =
      objectTruths(s.scene, 5.5, Eigen::Isometry3f::Identity());
  EXPECT_NEAR(std::remainder(truths[0].yaw - 1.25 * M_PI, 2.0 * M_PI), 0.0, 1e-5);
}

TEST(Scenario, ConstantVelocityStaysAsBefore) {
  const Scenario s = loadScenario(writeTemp("ego: {velocity: [3, -1, 0]}\n"));
  EXPECT_TRUE(s.ego_segments.empty());
  EXPECT_TRUE(s.vehiclePose(2.0).translation().isApprox(Eigen::Vector3f(6.0f, -2.0f, 0.0f)));
  EXPECT_TRUE(s.vehiclePose(2.0).linear().isIdentity());
  EXPECT_TRUE(s.vehicleVelocity(2.0).isApprox(Eigen::Vector3f(3.0f, -1.0f, 0.0f)));
  EXPECT_EQ(s.vehicleTwist(2.0).yaw_rate, 0.0f);
  // A straight segment is the same motion as the velocity along +x.
  const Scenario straight = loadScenario(writeTemp("ego: {speed_mps: 3}\n"));
  EXPECT_TRUE(straight.vehiclePose(2.0).translation().isApprox(Eigen::Vector3f(6.0f, 0.0f, 0.0f)));
  EXPECT_TRUE(straight.vehiclePose(2.0).linear().isIdentity(1e-6f));
}

TEST(Scenario, MistakesNameTheKey) {
  const auto error = [](const std::string& yaml) {
    try {
      loadScenario(writeTemp(yaml));
    } catch (const std::runtime_error& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_NE(error("sensor: {model: hdl65}\n").find("sensor.model"), std::string::npos);
  EXPECT_NE(error("duration_s: -1\n").find("duration_s"), std::string::npos);
  EXPECT_NE(error("objects:\n  - {shape: cone}\n").find("shape"), std::string::npos);
  EXPECT_NE(error("objects:\n  - {size: [1, 0, 1]}\n").find("size"), std::string::npos);
  EXPECT_NE(error("objects:\n  - {position: [1, 2]}\n").find("position"), std::string::npos);
  EXPECT_NE(error("noise: {dropout_prob: 2}\n").find("noise"), std::string::npos);
  EXPECT_NE(error("[1, 2]\n").find("mapping"), std::string::npos);
  // The ego path.
  EXPECT_NE(error("ego: {velocity: [1, 0, 0], speed_mps: 1}\n").find("ego: give one of"),
            std::string::npos);
  EXPECT_NE(error("ego: {speed_mps: 1, segments: [{duration_s: 1, speed_mps: 1}]}\n")
                .find("ego: give one of"), std::string::npos);
  EXPECT_NE(error("ego: {yaw_rate_deg_s: 10}\n").find("ego.yaw_rate_deg_s"), std::string::npos);
  EXPECT_NE(error("ego: {speed_mps: -1}\n").find("ego.speed_mps"), std::string::npos);
  EXPECT_NE(error("ego: {speed_mps: 5, yaw_rate_deg_s: 400}\n").find("ego.yaw_rate_deg_s"),
            std::string::npos);
  EXPECT_NE(error("ego: {speed_mps: 5, yaw_rate_deg_s: .nan}\n").find("ego.yaw_rate_deg_s"),
            std::string::npos);
  EXPECT_NE(error("ego: {speed: 5}\n").find("ego.speed: unknown key"), std::string::npos);
  EXPECT_NE(error("ego: {segments: []}\n").find("ego.segments"), std::string::npos);
  EXPECT_NE(error("ego: {segments: 3}\n").find("ego.segments"), std::string::npos);
  EXPECT_NE(error("ego: {segments: [{speed_mps: 1}]}\n")
                .find("ego.segments[0].duration_s: missing"), std::string::npos);
  EXPECT_NE(error("ego: {segments: [{duration_s: 1}]}\n")
                .find("ego.segments[0].speed_mps: missing"), std::string::npos);
  EXPECT_NE(error("ego: {segments: [{duration_s: 1, speed_mps: 1}, {duration_s: 0, speed_mps: 1}]}")
                .find("ego.segments[1].duration_s"), std::string::npos);
  EXPECT_NE(error("ego: {segments: [{duration_s: 1, speed_mps: 1, yaw_rate: 3}]}\n")
                .find("ego.segments[0].yaw_rate: unknown key"), std::string::npos);
  EXPECT_NE(error("ego: {segments: [5]}\n").find("ego.segments[0]"), std::string::npos);
  EXPECT_NE(error("ego: {segments: [{duration_s: 1, speed_mps: 1, end_speed_mps: -2}]}\n")
                .find("ego.segments[0].end_speed_mps"), std::string::npos);
  EXPECT_NE(error("objects:\n  - {velocity: [1, 0, 0], path: [{duration_s: 1, speed_mps: 1}]}\n")
                .find("objects[1].path: give either velocity or path"), std::string::npos);
  EXPECT_NE(error("objects:\n  - {path: [{duration_s: 1, speed_mps: 200}]}\n")
                .find("objects[1].path[0].speed_mps"), std::string::npos);
}

}  // namespace
}  // namespace sim
}  // namespace icanc
