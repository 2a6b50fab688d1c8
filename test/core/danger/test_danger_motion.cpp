// The predictive model by motion state: what stands still is judged by the vehicle's swept path
// (its own footprint plus static_clearance_m along the predicted path), what moves by its
// prediction against the corridor; and the paper's rule's frontal gate. Road-car figures as the
// KITTI profile: half-width 1.2 m, margin 0.3 m, bumper 2 m ahead, stopping margin 5 m, 2 s.
#include <string>

#include <gtest/gtest.h>

#include "icanc/core/danger/danger.hpp"

namespace icanc {
namespace {

constexpr double kEgoSpeed = 8.0;

// A box [x0, x1] x [y0, y1] seen from a vehicle driving straight on at kEgoSpeed; `ground_v` its
// velocity over ground.
ObjectKinematics box(double x0, double x1, double y0, double y1, MotionState motion,
                     Eigen::Vector2d ground_v = Eigen::Vector2d::Zero()) {
  ObjectKinematics o;
  o.aabb_min = Eigen::Vector3d(x0, y0, -1.0);
  o.aabb_max = Eigen::Vector3d(x1, y1, 0.5);
  o.center = 0.5 * (o.aabb_min + o.aabb_max);
  o.ego_velocity = Eigen::Vector2d(kEgoSpeed, 0.0);
  o.velocity << ground_v - o.ego_velocity, 0.0;
  o.motion = motion;
  return o;
}

DangerParams roadCar() {
  DangerParams p;
  p.model = DangerModel::kPredictive;
  p.half_width_m = 1.2;
  p.reaction_time_s = 2.0;
  p.margin_m = 0.3;
  p.vehicle_front_m = 2.0;
  p.stopping_margin_m = 5.0;
  p.static_clearance_m = 0.2;
  return p;
}

TEST(DangerMotion, ParkedCarBesideTheLaneIsNoDanger) {
  // Its near side 1.45 m from the vehicle's axis: inside the corridor (1.2 + 0.3), beside the
  // swept path (1.2 + 0.2).
  const ObjectKinematics parked = box(10.0, 14.5, 1.45, 3.3, MotionState::kStatic);
  EXPECT_LT(sweptPathTimeToReach(parked, roadCar()), 0.0);
  EXPECT_FALSE(assessDanger(parked, roadCar()).dangerous);
  // Its motion unknown, the corridor judges it: the vehicle drives up to it.
  ObjectKinematics unknown = parked;
  unknown.motion = MotionState::kUnknown;
  EXPECT_TRUE(assessDanger(unknown, roadCar()).dangerous);
}

TEST(DangerMotion, CarProtrudingIntoTheLaneIsADanger) {
  // 0.2 m into the swept path, 10 m ahead: the bumper plus clearance (2.2 m) meets it after
  // (10 - 2.2) / 8 = 0.975 s.
  const ObjectKinematics protruding = box(10.0, 14.5, 1.2, 3.0, MotionState::kStatic);
  const DangerAssessment a = assessDanger(protruding, roadCar());
  EXPECT_TRUE(a.dangerous);
  EXPECT_NEAR(a.time_to_corridor_s, 0.975, 0.051);
  EXPECT_DOUBLE_EQ(a.mean_time_to_corridor_s, a.time_to_corridor_s);
  // Something lying in the lane 30 m ahead is reached after 3.5 s: not within the 2 s.
  EXPECT_FALSE(assessDanger(box(30.0, 30.5, -0.5, 0.5, MotionState::kStatic), roadCar()).dangerous);
}

TEST(DangerMotion, StaticObjectIgnoresItsTracksVelocity) {
  // A wall fragment beside the road whose young track reads 2 m/s toward the path: static, it
  // stays where it is.
  const ObjectKinematics wall = box(8.0, 9.0, 2.5, 3.0, MotionState::kStatic, Eigen::Vector2d(0.0, -2.0));
  EXPECT_FALSE(assessDanger(wall, roadCar()).dangerous);
  // The same box moving: the walker steps into the corridor within the reaction time.
  ObjectKinematics walker = wall;
  walker.motion = MotionState::kMoving;
  EXPECT_TRUE(assessDanger(walker, roadCar()).dangerous);
}

TEST(DangerMotion, SweptPathFollowsTheTurn) {
  // Turning left at 0.4 rad/s: a car parked ahead on the right is left behind by the turn, one
  // ahead on the left of the straight path is in the way.
  ObjectKinematics right = box(10.0, 14.5, -3.0, -1.3, MotionState::kStatic);
  right.ego_yaw_rate = 0.4;
  EXPECT_LT(sweptPathTimeToReach(right, roadCar()), 0.0);
  ObjectKinematics left = box(12.0, 14.5, 1.5, 3.3, MotionState::kStatic);
  left.ego_yaw_rate = 0.4;
  EXPECT_GE(sweptPathTimeToReach(left, roadCar()), 0.0);
  left.ego_yaw_rate = 0.0;
  EXPECT_LT(sweptPathTimeToReach(left, roadCar()), 0.0);
}

TEST(DangerMotion, ClearanceIsValidated) {
  DangerParams p = roadCar();
  EXPECT_EQ(validate(p), "");
  p.static_clearance_m = -0.1;
  EXPECT_NE(validate(p).find("static_clearance_m"), std::string::npos);
  p.static_clearance_m = 6.0;
  EXPECT_NE(validate(p).find("static_clearance_m"), std::string::npos);
}

TEST(DangerPaper, BehindTheVehicleIsInNoSection) {
  // The paper's sections split the frontal field of view. A car 5 m behind, receding at the
  // vehicle's speed (relative heading 180 degrees, 10 m/s): not flagged; the same 5 m ahead is.
  DangerParams p;
  p.model = DangerModel::kPaper;
  ObjectKinematics behind;
  behind.aabb_min = Eigen::Vector3d(-7.0, -0.5, -1.0);
  behind.aabb_max = Eigen::Vector3d(-5.0, 0.5, 0.5);
  behind.velocity = Eigen::Vector3d(-10.0, 0.0, 0.0);
  EXPECT_FALSE(assessDanger(behind, p).dangerous);
  ObjectKinematics ahead = behind;
  ahead.aabb_min.x() = 5.0;
  ahead.aabb_max.x() = 7.0;
  EXPECT_TRUE(assessDanger(ahead, p).dangerous);
}

}  // namespace
}  // namespace icanc
