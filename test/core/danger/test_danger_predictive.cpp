// The predictive danger model (corridor prediction over the reaction time) and its
// per-track hysteresis, against the paper's rule on the same objects. Zebra profile: corridor
// |y| <= 0.7 + 0.3 m, 0 <= x <= 0.5 + 1.0 m, reaction time 3 s.
#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

#include <gtest/gtest.h>

#include "icanc/core/danger/danger.hpp"

namespace icanc {
namespace {

ObjectKinematics boxAt(double x, double y, double half, double vx, double vy, double sigma = 0.0) {
  ObjectKinematics o;
  o.center = Eigen::Vector3d(x, y, 0.0);
  o.aabb_min = o.center - Eigen::Vector3d(half, half, 0.85);
  o.aabb_max = o.center + Eigen::Vector3d(half, half, 0.85);
  o.velocity = Eigen::Vector3d(vx, vy, 0.0);
  o.velocity_std = Eigen::Vector2d(sigma, sigma);
  return o;
}

DangerParams zebra(DangerModel model) {
  DangerParams p;  // defaults: half_width 0.7, reaction 3 s, margin 0.3, front 0.5, stopping 1.0
  p.model = model;
  return p;
}

TEST(DangerModel, ParsesNamesAndRejectsUnknown) {
  EXPECT_EQ(parseDangerModel("paper"), DangerModel::kPaper);
  EXPECT_EQ(parseDangerModel("predictive"), DangerModel::kPredictive);
  EXPECT_EQ(parseDangerModel("Predictive"), DangerModel::kInvalid);
  EXPECT_STREQ(toString(DangerModel::kPredictive), "predictive");
  DangerParams p;
  EXPECT_EQ(p.model, DangerModel::kPaper);  // the paper's rule stays the default
  EXPECT_EQ(validate(p), "");
  p.model = parseDangerModel("bogus");
  EXPECT_NE(validate(p).find("danger.model"), std::string::npos);
  p = DangerParams();
  p.off_frames = 0;
  EXPECT_NE(validate(p).find("off_frames"), std::string::npos);
  p = DangerParams();
  p.time_step_s = 0.0;
  EXPECT_NE(validate(p).find("time_step_s"), std::string::npos);
}

TEST(DangerPredictive, PedestrianWalkingTowardIsDangerousBeforeThePapersRule) {
  // Front edge at 4.25 m, 1.2 m/s toward: reaches x = 1.5 m after 2.29 s < 3 s.
  const ObjectKinematics o = boxAt(4.5, 0.0, 0.25, -1.2, 0.0);
  const DangerAssessment pred = assessDanger(o, zebra(DangerModel::kPredictive));
  EXPECT_TRUE(pred.dangerous);
  EXPECT_NEAR(pred.time_to_corridor_s, 2.3, 0.051);
  // The paper's rule: distance 4.25 m > 1.2 * 3 = 3.6 m, not yet.
  EXPECT_FALSE(assessDanger(o, zebra(DangerModel::kPaper)).dangerous);
  // Farther away it does not reach the corridor within 3 s.
  EXPECT_FALSE(assessDanger(boxAt(5.5, 0.0, 0.25, -1.2, 0.0), zebra(DangerModel::kPredictive)).dangerous);
}

TEST(DangerPredictive, StandingInThePathIsDangerous) {
  const ObjectKinematics o = boxAt(1.2, 0.3, 0.25, 0.0, 0.0);
  const DangerAssessment pred = assessDanger(o, zebra(DangerModel::kPredictive));
  EXPECT_TRUE(pred.dangerous);
  EXPECT_DOUBLE_EQ(pred.time_to_corridor_s, 0.0);
  EXPECT_FALSE(assessDanger(o, zebra(DangerModel::kPaper)).dangerous);  // speed 0: threshold 0
  // The box extent counts, not its centre: centre 1.15 m to the side, edge 0.9 m inside 1.0 m.
  EXPECT_TRUE(assessDanger(boxAt(1.0, 1.15, 0.25, 0.0, 0.0), zebra(DangerModel::kPredictive)).dangerous);
  EXPECT_FALSE(assessDanger(boxAt(1.0, 1.35, 0.25, 0.0, 0.0), zebra(DangerModel::kPredictive)).dangerous);
}

TEST(DangerPredictive, WalkingParallelOutsideTheCorridorIsNot) {
  // Edge at y = 1.75 m, corridor half-width 1.0 m; walking past along -x with a settled filter.
  EXPECT_FALSE(assessDanger(boxAt(3.0, 2.0, 0.25, -1.2, 0.0, 0.1), zebra(DangerModel::kPredictive)).dangerous);
  EXPECT_FALSE(assessDanger(boxAt(3.0, -2.0, 0.25, 1.2, 0.0, 0.1), zebra(DangerModel::kPredictive)).dangerous);
  // The same walker turning toward the path (0.5 m/s sideways) enters it within 3 s.
  EXPECT_TRUE(assessDanger(boxAt(3.0, 2.0, 0.25, -0.5, -0.5, 0.1), zebra(DangerModel::kPredictive)).dangerous);
}

TEST(DangerPredictive, UncertainNewTrackNearThePathErrsTowardDanger) {
  // Edge 0.15 m beside the corridor (within its length), estimated at rest.
  const ObjectKinematics settled = boxAt(1.2, 1.4, 0.25, 0.0, 0.0, 0.0);
  const ObjectKinematics fresh = boxAt(1.2, 1.4, 0.25, 0.0, 0.0, 5.0);  // initial_velocity_std
  EXPECT_FALSE(assessDanger(settled, zebra(DangerModel::kPredictive)).dangerous);
  EXPECT_TRUE(assessDanger(fresh, zebra(DangerModel::kPredictive)).dangerous);
  // ... but only near: the growth is capped (0.5 m), a fresh track 4 m to the side stays safe,
  // and so does one 0.15 m beside and 0.75 m beyond the corridor's end.
  EXPECT_FALSE(assessDanger(boxAt(1.2, 4.0, 0.25, 0.0, 0.0, 5.0), zebra(DangerModel::kPredictive)).dangerous);
  EXPECT_FALSE(assessDanger(boxAt(2.5, 1.4, 0.25, 0.0, 0.0, 5.0), zebra(DangerModel::kPredictive)).dangerous);
  DangerParams no_uncertainty = zebra(DangerModel::kPredictive);
  no_uncertainty.velocity_std_k = 0.0;
  EXPECT_FALSE(assessDanger(fresh, no_uncertainty).dangerous);
}

TEST(DangerPredictive, UncertaintyGrowsEachAxisByItsOwnSigma) {
  // Edge 0.15 m beside the corridor: an uncertain closing speed (x) does not pull it sideways
  // into the path; an uncertain lateral speed (y) does.
  ObjectKinematics beside = boxAt(1.2, 1.4, 0.25, 0.0, 0.0);
  beside.velocity_std = Eigen::Vector2d(5.0, 0.0);
  EXPECT_FALSE(assessDanger(beside, zebra(DangerModel::kPredictive)).dangerous);
  beside.velocity_std = Eigen::Vector2d(0.0, 5.0);
  const DangerAssessment a = assessDanger(beside, zebra(DangerModel::kPredictive));
  EXPECT_TRUE(a.dangerous);
  EXPECT_NEAR(a.time_to_corridor_s, 0.05, 1e-9);  // 5 m/s * 0.05 s = 0.25 m >= 0.15 m
}

// Walls meeting ahead (a U open toward the vehicle, as a corridor's side walls and its end merged
// into one cluster): its axis-aligned box spans the path, its parts do not. The vehicle drives at
// 0.5 m/s toward the end wall 8 m ahead.
TEST(DangerPredictive, AConcaveFootprintIsJudgedByItsPartsNotItsBox) {
  const DangerParams p = zebra(DangerModel::kPredictive);
  ObjectKinematics u;
  u.aabb_min = Eigen::Vector3d(2.0, -3.2, 0.0);
  u.aabb_max = Eigen::Vector3d(8.2, 3.2, 2.5);
  u.center = 0.5 * (u.aabb_min + u.aabb_max);
  u.velocity = Eigen::Vector3d(-0.5, 0.0, 0.0);
  u.velocity_std = Eigen::Vector2d(0.0, 0.0);  // settled: the times below are exact
  EXPECT_TRUE(assessDanger(u, p).dangerous);  // the box alone: 0.5 m from the corridor's end
  for (double x = 2.0; x < 8.0; x += 1.0) {   // the side walls, in 1 m parts
    u.footprint.emplace_back(Eigen::Vector2d(x, 3.0), Eigen::Vector2d(x + 1.0, 3.2));
    u.footprint.emplace_back(Eigen::Vector2d(x, -3.2), Eigen::Vector2d(x + 1.0, -3.0));
  }
  for (double y = -3.2; y < 3.2; y += 1.0)  // the end wall
    u.footprint.emplace_back(Eigen::Vector2d(8.0, y), Eigen::Vector2d(8.2, std::min(3.2, y + 1.0)));
  EXPECT_FALSE(assessDanger(u, p).dangerous);
  // The same U with a table standing in the path 2.5 m ahead: that part is dangerous.
  u.footprint.emplace_back(Eigen::Vector2d(2.5, -0.4), Eigen::Vector2d(3.3, 0.4));
  const DangerAssessment a = assessDanger(u, p);
  EXPECT_TRUE(a.dangerous);
  EXPECT_NEAR(a.time_to_corridor_s, 2.0, 1e-9);  // (2.5 - 1.5) m at 0.5 m/s
  // The paper's rule keeps its closest point of the axis-aligned box (2.0 m: 0.5 * 3 = 1.5 m).
  EXPECT_DOUBLE_EQ(assessDanger(u, zebra(DangerModel::kPaper)).distance_m, 2.0);
}

// footprint_margin_m: a box seen 0.1 m smaller than the object (KITTI's labels reach 0.2 m beyond
// what the LiDAR sees) beside the path is caught when the margin makes up for it, at t = 0.
TEST(DangerPredictive, FootprintMarginGrowsTheBoxOnEverySide) {
  DangerParams p = zebra(DangerModel::kPredictive);
  const ObjectKinematics beside = boxAt(1.0, 1.35, 0.25, 0.0, 0.0);  // edge at y = 1.1 m
  EXPECT_FALSE(assessDanger(beside, p).dangerous);
  p.footprint_margin_m = 0.15;
  const DangerAssessment a = assessDanger(beside, p);
  EXPECT_TRUE(a.dangerous);
  EXPECT_DOUBLE_EQ(a.time_to_corridor_s, 0.0);
  EXPECT_FALSE(assessDanger(boxAt(1.0, 1.45, 0.25, 0.0, 0.0), p).dangerous);  // edge 1.2 m
  p.footprint_margin_m = -0.1;
  EXPECT_NE(validate(p).find("footprint_margin_m"), std::string::npos);
}

TEST(DangerPredictive, StaticObjectWhileTheVehicleMovesOnlyInTheFutureFootprint) {
  // The vehicle drives at 2 m/s: a static object approaches at -2 m/s.
  const DangerParams p = zebra(DangerModel::kPredictive);
  EXPECT_TRUE(assessDanger(boxAt(6.0, 0.0, 0.25, -2.0, 0.0), p).dangerous);    // 4.25 m: 2.1 s
  EXPECT_FALSE(assessDanger(boxAt(10.0, 0.0, 0.25, -2.0, 0.0), p).dangerous);  // 8.25 m: 4.1 s
  EXPECT_FALSE(assessDanger(boxAt(6.0, 3.0, 0.25, -2.0, 0.0), p).dangerous);   // beside the path
  EXPECT_FALSE(assessDanger(boxAt(-1.0, 0.0, 0.25, -2.0, 0.0), p).dangerous);  // behind, receding
  EXPECT_TRUE(assessDanger(boxAt(10.0, 0.0, 0.25, -4.0, 0.0), p).dangerous);   // at 4 m/s: 2.06 s
}

TEST(DangerHysteresis, HoldsThroughOneSafeFrameAndDropsAfterOffFrames) {
  DangerParams p = zebra(DangerModel::kPredictive);
  p.on_frames = 2;
  p.off_frames = 3;
  p.immediate_ttc_s = 1.5;
  DangerHysteresis h(p);
  DangerAssessment far_danger, safe, urgent;
  far_danger.dangerous = true;
  far_danger.time_to_corridor_s = 2.5;
  urgent.dangerous = true;
  urgent.time_to_corridor_s = urgent.mean_time_to_corridor_s = 0.5;
  EXPECT_FALSE(h.update(7, far_danger, 0.0));  // first positive frame: not yet
  EXPECT_TRUE(h.update(7, far_danger, 0.1));   // second: on
  EXPECT_TRUE(h.update(7, safe, 0.2));         // one safe frame: held
  EXPECT_TRUE(h.update(7, far_danger, 0.3));   // back
  EXPECT_TRUE(h.update(7, safe, 0.4));
  EXPECT_TRUE(h.update(7, safe, 0.5));
  EXPECT_FALSE(h.update(7, safe, 0.6));        // third consecutive safe frame: off
  EXPECT_TRUE(h.update(8, urgent, 0.6));       // about to enter: on at once
  EXPECT_EQ(h.size(), 2u);
  EXPECT_FALSE(h.update(9, safe, 5.0));        // ids 7 and 8 not seen for > 1 s: forgotten
  EXPECT_EQ(h.size(), 1u);
  EXPECT_FALSE(h.update(8, far_danger, 5.1));  // a forgotten id starts again
}

// The immediate case reads the mean prediction: what only the velocity's uncertainty brings into
// the corridor within immediate_ttc_s (a young track's sigma of 0.5 m/s beside the path) waits for
// a second frame; what steps in itself is on at once. Zebra standing: corridor |y| <= 1.0 m,
// 0 <= x <= 1.5 m.
TEST(DangerHysteresis, OnAtOnceOnlyWhenTheMeanPredictionEnters) {
  const DangerParams p = zebra(DangerModel::kPredictive);
  // Standing 0.2 m beside the corridor, sigma 0.5 m/s: the grown footprint reaches it at 0.4 s,
  // the mean never.
  const DangerAssessment uncertain = assessDanger(boxAt(1.0, 1.3, 0.1, 0.0, 0.0, 0.5), p);
  EXPECT_TRUE(uncertain.dangerous);
  EXPECT_NEAR(uncertain.time_to_corridor_s, 0.4, 1e-9);
  EXPECT_EQ(uncertain.mean_time_to_corridor_s, -1.0);
  // Stepping in at 1 m/s from 0.5 m beside it, the same sigma: the mean enters at 0.5 s.
  const DangerAssessment stepping = assessDanger(boxAt(1.0, 1.6, 0.1, 0.0, -1.0, 0.5), p);
  EXPECT_NEAR(stepping.mean_time_to_corridor_s, 0.5, 1e-9);
  EXPECT_LE(stepping.time_to_corridor_s, stepping.mean_time_to_corridor_s);
  DangerHysteresis h(p);
  EXPECT_FALSE(h.update(1, uncertain, 0.0));  // the uncertainty alone: not yet
  EXPECT_TRUE(h.update(1, uncertain, 0.1));   // confirmed by a second frame
  EXPECT_TRUE(h.update(2, stepping, 0.1));    // at once
  // The paper's rule fills neither time.
  EXPECT_EQ(assessDanger(boxAt(1.0, 1.6, 0.1, 0.0, -1.0), zebra(DangerModel::kPaper)).mean_time_to_corridor_s, -1.0);
}

// The vehicle predicted along its own twist. A road car (corridor |y| <= 1.2 + 0.3 m,
// 0 <= x <= 2 + 5 m, 2 s) at 10 m/s on a left bend of radius 50 m.
DangerParams roadCar() {
  DangerParams p;
  p.model = DangerModel::kPredictive;
  p.half_width_m = 1.2;
  p.reaction_time_s = 2.0;
  p.vehicle_front_m = 2.0;
  p.stopping_margin_m = 5.0;
  return p;
}

// A static object at `center` (vehicle frame) seen from the vehicle on the bend: its relative
// velocity is minus the velocity of the vehicle-fixed point there, and the array carries the twist.
ObjectKinematics staticOnBend(const Eigen::Vector2d& center, double half_x, double half_y,
                              double speed, double yaw_rate) {
  ObjectKinematics o = boxAt(center.x(), center.y(), 0.0, 0.0, 0.0);
  o.aabb_min << center.x() - half_x, center.y() - half_y, -0.8;
  o.aabb_max << center.x() + half_x, center.y() + half_y, 0.8;
  o.velocity << -speed + yaw_rate * center.y(), -yaw_rate * center.x(), 0.0;
  o.ego_velocity << speed, 0.0;
  o.ego_yaw_rate = yaw_rate;
  return o;
}

// The point of the bend `s` metres ahead, `offset` metres to its left, in the vehicle frame.
Eigen::Vector2d onBend(double radius, double s, double offset) {
  const double a = s / radius;
  return Eigen::Vector2d((radius - offset) * std::sin(a), radius - (radius - offset) * std::cos(a));
}

TEST(DangerPredictiveEgoPath, AParkedCarOnTheInsideOfABendIsNotDangerous) {
  const double radius = 50.0, speed = 10.0, w = speed / radius;
  // Parked 3.5 m to the left of the path, 14 m along the bend: off to the left, and sweeping to
  // the right across the view at w x r as the vehicle turns toward it (KITTI 0000's false alarms).
  const Eigen::Vector2d car = onBend(radius, 14.0, 3.5);
  ASSERT_GT(car.y(), 4.0);
  const ObjectKinematics seen = staticOnBend(car, 2.2, 0.9, speed, w);
  const DangerAssessment along_the_bend = assessDanger(seen, roadCar());
  EXPECT_FALSE(along_the_bend.dangerous) << along_the_bend.time_to_corridor_s;
  // The same relative motion taken as a straight drive (no twist, the paper's relative frame):
  // it sweeps into the straight corridor.
  ObjectKinematics straight = seen;
  straight.ego_velocity.setZero();
  straight.ego_yaw_rate = 0.0;
  EXPECT_TRUE(assessDanger(straight, roadCar()).dangerous);
}

TEST(DangerPredictiveEgoPath, AWalkerStandingInTheLaneOfTheBendIsDangerous) {
  const double radius = 50.0, speed = 10.0, w = speed / radius;
  const Eigen::Vector2d walker = onBend(radius, 16.0, 0.0);  // in the lane, 16 m along the bend
  ASSERT_GT(walker.y(), 2.0);  // off the straight corridor
  const ObjectKinematics seen = staticOnBend(walker, 0.3, 0.3, speed, w);
  const DangerAssessment a = assessDanger(seen, roadCar());
  EXPECT_TRUE(a.dangerous);
  EXPECT_GT(a.time_to_corridor_s, 0.5);  // reached at (16 - 7.3) / 10 s, not at once
  EXPECT_LT(a.time_to_corridor_s, 1.2);
  // Straight ahead with the relative velocity of a straight drive, it passes beside.
  ObjectKinematics straight = boxAt(walker.x(), walker.y(), 0.3, -speed, 0.0);
  EXPECT_FALSE(assessDanger(straight, roadCar()).dangerous);
}

TEST(DangerPredictiveEgoPath, GoingStraightTheTwistChangesNothing) {
  // The velocity over ground and the vehicle's own straight motion: the same relative motion.
  ObjectKinematics walker = boxAt(8.0, -3.0, 0.3, -10.0, 1.5);
  const DangerAssessment relative = assessDanger(walker, roadCar());
  walker.ego_velocity << 10.0, 0.0;
  const DangerAssessment with_twist = assessDanger(walker, roadCar());
  EXPECT_EQ(relative.dangerous, with_twist.dangerous);
  EXPECT_NEAR(relative.time_to_corridor_s, with_twist.time_to_corridor_s, 1e-9);
  EXPECT_TRUE(relative.dangerous);
}

TEST(DangerPredictiveEgoPath, ATurnedPartIsTestedAsARectangleNotByItsBounds) {
  // The vehicle turns on the spot (no speed) at 0.5 rad/s; a thin static bar along y = 2.47 m,
  // every point of it at least 2.47 m from the vehicle's origin, never reaches the corridor (all of
  // it within 1.80 m of the origin: corner (1.5, 1.0)). At a heading change of 45 degrees the bar
  // runs diagonally past the corridor's corner, and its axis-aligned bounds, [1.0, 3.0] x
  // [0.5, 2.5], overlap the corridor: the bounds alone would flag it.
  DangerParams p = zebra(DangerModel::kPredictive);  // corridor |y| <= 1.0, 0 <= x <= 1.5, 3 s
  const double w = 0.5;
  ObjectKinematics bar;
  bar.center << 0.355, 2.475, 0.0;
  bar.aabb_min << -1.06, 2.45, -0.5;
  bar.aabb_max << 1.77, 2.50, 0.5;
  bar.velocity << w * bar.center.y(), -w * bar.center.x(), 0.0;  // static: minus w x r
  bar.ego_yaw_rate = w;
  EXPECT_FALSE(assessDanger(bar, p).dangerous) << assessDanger(bar, p).time_to_corridor_s;
  // The same bar 0.8 m nearer (y = 1.7 m) sweeps over the corridor's corner: flagged.
  bar.center.y() -= 0.8;
  bar.aabb_min.y() -= 0.8;
  bar.aabb_max.y() -= 0.8;
  bar.velocity << w * bar.center.y(), -w * bar.center.x(), 0.0;
  const DangerAssessment nearer = assessDanger(bar, p);
  EXPECT_TRUE(nearer.dangerous);
  EXPECT_GT(nearer.time_to_corridor_s, 0.5);  // after a turn, not at once
}

// The static-world prior (static_prior_k) as the non-negative garrote.
TEST(DangerPredictiveStaticPrior, TheGarroteZeroesNoiseAndBarelyTouchesClearMotion) {
  EXPECT_EQ(staticPriorShrink(0.3, 0.4), 0.0);    // within k sigma: standing still
  EXPECT_EQ(staticPriorShrink(-0.4, 0.4), 0.0);   // at the threshold: continuous, 0
  EXPECT_NEAR(staticPriorShrink(0.8, 0.4), 0.6, 1e-12);    // 0.8 * (1 - 1/4)
  EXPECT_NEAR(staticPriorShrink(-0.8, 0.4), -0.6, 1e-12);  // the sign kept
  EXPECT_NEAR(staticPriorShrink(9.837, 1.52), 9.602, 1e-3);  // the soft threshold gave 8.317
  EXPECT_EQ(staticPriorShrink(1.5, 0.0), 1.5);    // k 0 or sigma 0: off
  EXPECT_EQ(staticPriorShrink(1.5, -1.0), 1.5);
  // Never more than the soft threshold takes, never past zero.
  for (double v = -5.0; v <= 5.0; v += 0.125) {
    const double s = staticPriorShrink(v, 0.5);
    EXPECT_LE(std::abs(v) - std::abs(s), 0.5 + 1e-12) << v;
    EXPECT_GE(s * v, 0.0) << v;
    EXPECT_LE(std::abs(s), std::abs(v)) << v;
  }
}

// The Model 3's corridor: |y| <= 1.2 + 0.3 m, 0 <= x <= 2.4 + 5 m, 2 s, k 2, the vehicle at 10 m/s.
DangerParams model3Predictive() {
  DangerParams p = roadCar();
  p.vehicle_front_m = 2.4;
  p.velocity_std_k = 1.0;
  p.uncertainty_cap_m = 0.5;
  p.footprint_margin_m = 0.05;
  p.static_prior_k = 2.0;
  return p;
}

TEST(DangerPredictiveStaticPrior, SomethingDrivingAheadAtTheVehiclesSpeedIsNotSlowedIntoTheCorridor) {
  // night_parked_cars at 11.4 s: a young track (sigma 0.76 m/s) 9.8 m ahead, its edge in the
  // corridor, moving with the vehicle (-0.16 m/s relative, 9.84 over ground). Soft-thresholded to
  // 8.32 m/s it closed 3.4 m in 2 s and was flagged; the garrote keeps 9.60.
  const DangerParams p = model3Predictive();
  // The box x 9.82-10.24, y -3.09 to -1.25 m standing still (a parked car's corner in the lane) is
  // reached within 2 s.
  ObjectKinematics box = staticOnBend(Eigen::Vector2d(10.03, -2.17), 0.21, 0.92, 10.0, 0.0);
  box.velocity_std = Eigen::Vector2d(0.76, 0.76);
  EXPECT_TRUE(assessDanger(box, p).dangerous);
  box.velocity.x() = -0.163;  // moving with the vehicle
  EXPECT_FALSE(assessDanger(box, p).dangerous);
}

TEST(DangerPredictiveStaticPrior, AParkedCarsVelocityNoiseIsTakenAsStandingStill) {
  // A parked car's side 0.5 m outside the corridor, 10 m ahead, its young track reading 0.3 m/s
  // toward the lane (sigma 0.2 m/s): within 2 sigma, so it stands (the footprint grows by the
  // sigma alone, 0.35 m by the time it has passed); without the prior it drifts 0.44 m more, in.
  DangerParams p = model3Predictive();
  ObjectKinematics parked = staticOnBend(Eigen::Vector2d(12.3, -2.9), 2.3, 0.9, 10.0, 0.0);
  parked.velocity.y() = 0.3;
  parked.velocity_std = Eigen::Vector2d(0.2, 0.2);
  EXPECT_FALSE(assessDanger(parked, p).dangerous);
  p.static_prior_k = 0.0;
  EXPECT_TRUE(assessDanger(parked, p).dangerous);
}

// The planner's path: a left bend of `radius` from the vehicle on (arc points every metre).
std::shared_ptr<const EgoPath> leftBendPath(double radius, double length) {
  std::vector<Eigen::Vector2d> points;
  for (double s = 0.0; s <= length; s += 1.0) points.push_back(onBend(radius, s, 0.0));
  auto path = std::make_shared<EgoPath>();
  EXPECT_EQ(path->set(points, 2.0, M_PI / 2.0), EgoPath::Refused::kNone);
  return path;
}

TEST(DangerPredictivePlannedPath, AnSBendsParkedCarIsBesideThePathNotInTheTurnsCorridor) {
  // The vehicle still turns right (-0.15 rad/s at 10 m/s) where the road already bends left
  // (KITTI 0000's S-bend): a car parked on the right of the road, 3.3 m from the path's centre
  // line (its box, axis-aligned in the vehicle frame, 2 m off it where the bend has turned the
  // road by 0.24 rad), lies where the constant right turn goes.
  const double speed = 10.0, w = -0.15, radius = 66.7;
  const ObjectKinematics twist_only = staticOnBend(onBend(radius, 16.0, -3.3), 2.2, 0.9, speed, w);
  ASSERT_TRUE(assessDanger(twist_only, roadCar()).dangerous);
  ObjectKinematics planned = twist_only;
  planned.ego_path = leftBendPath(radius, 40.0);
  const DangerAssessment a = assessDanger(planned, roadCar());
  EXPECT_FALSE(a.dangerous) << a.time_to_corridor_s;
}

TEST(DangerPredictivePlannedPath, AWalkerInTheLaneOfThePathIsDangerous) {
  const double speed = 10.0, w = -0.15, radius = 66.7;
  const ObjectKinematics twist_only = staticOnBend(onBend(radius, 15.0, 0.0), 0.3, 0.3, speed, w);
  ASSERT_FALSE(assessDanger(twist_only, roadCar()).dangerous);  // left of the right turn
  ObjectKinematics planned = twist_only;
  planned.ego_path = leftBendPath(radius, 40.0);
  const DangerAssessment a = assessDanger(planned, roadCar());
  EXPECT_TRUE(a.dangerous);
  EXPECT_GT(a.time_to_corridor_s, 0.5);  // reached at about (15 - 7.3) / 10 s
  EXPECT_LT(a.time_to_corridor_s, 1.2);
}

TEST(DangerPredictivePlannedPath, BeyondThePathsEndTheTwistsTurnGoesOn) {
  // Turning left at 0.3 rad/s and 10 m/s; a walker standing in the lane of that turn 15 m on.
  const double speed = 10.0, w = 0.3, radius = speed / w;
  const ObjectKinematics twist_only = staticOnBend(onBend(radius, 15.0, 0.0), 0.3, 0.3, speed, w);
  ASSERT_TRUE(assessDanger(twist_only, roadCar()).dangerous);
  // A planner's path straight on for 40 m: the walker is beside it.
  const auto straightPath = [](double length) {
    auto path = std::make_shared<EgoPath>();
    EXPECT_EQ(path->set({{0.0, 0.0}, {length, 0.0}}, 2.0, M_PI / 2.0), EgoPath::Refused::kNone);
    return path;
  };
  ObjectKinematics planned = twist_only;
  planned.ego_path = straightPath(40.0);
  EXPECT_FALSE(assessDanger(planned, roadCar()).dangerous);
  // A path that ends 3 m ahead (a recording's last frames): on from there at the twist's turn.
  planned.ego_path = straightPath(3.0);
  EXPECT_TRUE(assessDanger(planned, roadCar()).dangerous);
}

TEST(DangerPredictivePlannedPath, ThePathIsFollowedOnlyWhileMovingForward) {
  const double radius = 66.7;
  ObjectKinematics reversing = boxAt(-8.0, 0.0, 0.3, 0.0, 0.0);
  reversing.velocity << 2.0, 0.0, 0.0;  // a static walker behind, the vehicle reversing at 2 m/s
  reversing.ego_velocity << -2.0, 0.0;
  const DangerAssessment twist = assessDanger(reversing, roadCar());
  reversing.ego_path = leftBendPath(radius, 40.0);
  const DangerAssessment planned = assessDanger(reversing, roadCar());
  EXPECT_EQ(planned.dangerous, twist.dangerous);
  EXPECT_DOUBLE_EQ(planned.time_to_corridor_s, twist.time_to_corridor_s);
}

}  // namespace
}  // namespace icanc
