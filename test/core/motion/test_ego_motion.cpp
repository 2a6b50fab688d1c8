// The vehicle's own motion between frames (EgoMotion), the relative velocity it implies,
// and the constant-turn prediction of the vehicle the danger model uses.
#include <cmath>

#include <gtest/gtest.h>

#include "icanc/core/motion/ego_motion.hpp"

namespace icanc {
namespace {

// The vehicle's pose in odom after t seconds on a constant-turn arc from the origin.
Eigen::Isometry3d arcPose(double speed, double yaw_rate, double t) {
  return predictEgoPose(Eigen::Vector2d(speed, 0.0), yaw_rate, t).toIsometry();
}

EgoMotionParams source(EgoMotionSource s) {
  EgoMotionParams p;
  p.source = s;
  return p;
}

TEST(EgoMotion, ParsesSourcesAndValidates) {
  EXPECT_EQ(parseEgoMotionSource("tf"), EgoMotionSource::kTf);
  EXPECT_EQ(parseEgoMotionSource("odometry"), EgoMotionSource::kOdometry);
  EXPECT_EQ(parseEgoMotionSource("lidar"), EgoMotionSource::kLidar);
  EXPECT_EQ(parseEgoMotionSource("none"), EgoMotionSource::kNone);
  EXPECT_EQ(parseEgoMotionSource("TF"), EgoMotionSource::kInvalid);
  EXPECT_EQ(validate(EgoMotionParams()), "");
  EgoMotionParams p;
  p.source = EgoMotionSource::kInvalid;
  EXPECT_NE(validate(p).find("ego_motion/source"), std::string::npos);
  p = EgoMotionParams();
  p.max_speed_mps = 0.0;
  EXPECT_NE(validate(p).find("max_speed_mps"), std::string::npos);
  p = EgoMotionParams();
  p.max_wait_s = 2.0;
  EXPECT_NE(validate(p).find("max_wait_s"), std::string::npos);
  p = EgoMotionParams();
  p.replay_max_wait_s = 5.0;  // beyond the replay's 5 s answer timeout
  EXPECT_NE(validate(p).find("replay_max_wait_s"), std::string::npos);
  p.replay_max_wait_s = -0.1;
  EXPECT_NE(validate(p).find("replay_max_wait_s"), std::string::npos);
}

TEST(EgoPrediction, QuarterCircleAndStraightLine) {
  const double radius = 20.0, speed = 10.0, w = speed / radius;
  const PlanarPose quarter = predictEgoPose(Eigen::Vector2d(speed, 0.0), w, M_PI / 2 / w);
  EXPECT_NEAR(quarter.position.x(), radius, 1e-9);
  EXPECT_NEAR(quarter.position.y(), radius, 1e-9);
  EXPECT_NEAR(quarter.yaw, M_PI / 2, 1e-12);
  const PlanarPose right = predictEgoPose(Eigen::Vector2d(speed, 0.0), -w, M_PI / 2 / w);
  EXPECT_NEAR(right.position.y(), -radius, 1e-9);
  const PlanarPose straight = predictEgoPose(Eigen::Vector2d(3.0, 1.0), 0.0, 2.0);
  EXPECT_TRUE(straight.position.isApprox(Eigen::Vector2d(6.0, 2.0)));
  EXPECT_EQ(straight.yaw, 0.0);
}

TEST(EgoMotion, NoneSourceIsTheStandingVehicle) {
  EgoMotion ego(source(EgoMotionSource::kNone));
  const Eigen::Isometry3d pose = arcPose(10.0, 0.3, 1.0);
  const EgoStep step = ego.update(1.0, &pose);
  EXPECT_EQ(step.status, EgoStep::Status::kNone);
  EXPECT_TRUE(step.motion.isApprox(Eigen::Isometry3d::Identity()));
  EXPECT_EQ(step.linear_velocity, Eigen::Vector3d::Zero());
}

// Poses along a left turn: the twist is recovered exactly and the motion maps where a static
// point was seen in the previous frame to where it is seen now.
TEST(EgoMotion, RecoversTheTwistAndTheFrameMotionOnATurn) {
  EgoMotion ego(source(EgoMotionSource::kTf));
  const double speed = 8.0, w = 0.4, dt = 0.1;
  const Eigen::Vector3d landmark(15.0, -4.0, 0.5);  // in odom
  Eigen::Isometry3d pose = arcPose(speed, w, 0.0);
  EXPECT_EQ(ego.update(0.0, &pose).status, EgoStep::Status::kFirst);
  for (int i = 1; i <= 10; ++i) {
    const Eigen::Isometry3d previous = pose;
    pose = arcPose(speed, w, i * dt);
    const EgoStep step = ego.update(i * dt, &pose);
    ASSERT_EQ(step.status, EgoStep::Status::kMeasured) << i;
    EXPECT_NEAR(step.linear_velocity.x(), speed, 1e-9);
    EXPECT_NEAR(step.linear_velocity.y(), 0.0, 1e-9);
    EXPECT_NEAR(step.yaw_rate_rad_s, w, 1e-9);
    const Eigen::Vector3d seen_before = previous.inverse() * landmark;
    const Eigen::Vector3d seen_now = pose.inverse() * landmark;
    EXPECT_TRUE((step.motion * seen_before).isApprox(seen_now, 1e-9)) << i;
  }
}

TEST(EgoMotion, ExtrapolatesAMissingPoseThenDropsTheMotion) {
  EgoMotionParams p = source(EgoMotionSource::kTf);
  p.max_extrapolation_s = 0.25;
  EgoMotion ego(p);
  const double speed = 10.0, w = -0.2;
  Eigen::Isometry3d pose = arcPose(speed, w, 0.0);
  ego.update(0.0, &pose);
  pose = arcPose(speed, w, 0.1);
  ego.update(0.1, &pose);
  // Missing at 0.2: the last twist over dt is the true motion on this arc.
  const EgoStep carried = ego.update(0.2, nullptr);
  EXPECT_EQ(carried.status, EgoStep::Status::kExtrapolated);
  const Eigen::Isometry3d truth = arcPose(speed, w, 0.2).inverse() * arcPose(speed, w, 0.1);
  EXPECT_TRUE(carried.motion.isApprox(truth, 1e-9));
  EXPECT_NEAR(carried.yaw_rate_rad_s, w, 1e-9);
  // A pose back at 0.3 continues from the extrapolated one: measured.
  pose = arcPose(speed, w, 0.3);
  const EgoStep back = ego.update(0.3, &pose);
  EXPECT_EQ(back.status, EgoStep::Status::kMeasured);
  EXPECT_NEAR(back.linear_velocity.x(), speed, 1e-6);
  // Missing for longer than 0.25 s: lost, no motion, no twist; the next pose starts afresh.
  EXPECT_EQ(ego.update(0.4, nullptr).status, EgoStep::Status::kExtrapolated);
  EXPECT_EQ(ego.update(0.5, nullptr).status, EgoStep::Status::kExtrapolated);
  const EgoStep lost = ego.update(0.6, nullptr);
  EXPECT_EQ(lost.status, EgoStep::Status::kLost);
  EXPECT_TRUE(lost.motion.isApprox(Eigen::Isometry3d::Identity()));
  EXPECT_EQ(lost.yaw_rate_rad_s, 0.0);
  EXPECT_EQ(ego.update(0.7, nullptr).status, EgoStep::Status::kNone);
  pose = arcPose(speed, w, 0.8);
  EXPECT_EQ(ego.update(0.8, &pose).status, EgoStep::Status::kFirst);
}

TEST(EgoMotion, AJumpIsReplacedByTheLastTwistAndReBased) {
  EgoMotion ego(source(EgoMotionSource::kOdometry));
  Eigen::Isometry3d pose = arcPose(5.0, 0.0, 0.0);
  ego.update(0.0, &pose);
  pose = arcPose(5.0, 0.0, 0.1);
  ego.update(0.1, &pose);
  // The odometry relocalises 50 m away: beyond 70 m/s over 0.1 s, so not motion.
  Eigen::Isometry3d reset = Eigen::Isometry3d::Identity();
  reset.translation() << -50.0, 3.0, 0.0;
  const EgoStep jump = ego.update(0.2, &reset);
  EXPECT_EQ(jump.status, EgoStep::Status::kJump);
  EXPECT_NEAR(jump.motion.translation().x(), -0.5, 1e-9);  // 5 m/s over 0.1 s, carried
  Eigen::Isometry3d next = reset;
  next.translation().x() += 0.5;
  const EgoStep after = ego.update(0.3, &next);
  EXPECT_EQ(after.status, EgoStep::Status::kMeasured);
  EXPECT_NEAR(after.linear_velocity.x(), 5.0, 1e-9);
  // A sudden spin is a jump too.
  Eigen::Isometry3d spun = next;
  spun.linear() = Eigen::AngleAxisd(1.0, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  EXPECT_EQ(ego.update(0.4, &spun).status, EgoStep::Status::kJump);
}

TEST(EgoMotion, TimeGoingBackwardsStartsAfresh) {
  EgoMotion ego(source(EgoMotionSource::kTf));
  Eigen::Isometry3d pose = arcPose(5.0, 0.1, 3.0);
  ego.update(3.0, &pose);
  pose = arcPose(5.0, 0.1, 3.1);
  EXPECT_EQ(ego.update(3.1, &pose).status, EgoStep::Status::kMeasured);
  pose = arcPose(5.0, 0.1, 0.0);
  EXPECT_EQ(ego.update(0.0, &pose).status, EgoStep::Status::kFirst);
  const Eigen::Isometry3d bad = Eigen::Isometry3d(Eigen::Matrix4d::Constant(NAN));
  EXPECT_EQ(ego.update(0.1, &bad).status, EgoStep::Status::kExtrapolated);  // NaN pose: missing
}

TEST(RelativeVelocity, AParkedCarSweepsPastATurningVehicle) {
  // 5 m/s forward turning left at 0.5 rad/s: the vehicle-fixed point at (10, 0) moves at (5, 5).
  const Eigen::Vector3d rel = relativeVelocity(Eigen::Vector3d::Zero(), Eigen::Vector3d(10, 0, 0),
                                               Eigen::Vector3d(5, 0, 0), 0.5);
  EXPECT_TRUE(rel.isApprox(Eigen::Vector3d(-5.0, -5.0, 0.0)));
  // A walker crossing at 1.5 m/s seen from a vehicle going straight at 10 m/s.
  const Eigen::Vector3d walker = relativeVelocity(Eigen::Vector3d(0, 1.5, 0), Eigen::Vector3d(8, -2, 0),
                                                  Eigen::Vector3d(10, 0, 0), 0.0);
  EXPECT_TRUE(walker.isApprox(Eigen::Vector3d(-10.0, 1.5, 0.0)));
}

}  // namespace
}  // namespace icanc
