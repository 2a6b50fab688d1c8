// Tracks kept in the fixed frame. Seen from a vehicle that drives and turns, a parked car
// keeps a velocity over ground of about zero and a walker its own walking velocity, when the tracker
// is given the vehicle's motion between frames; without it (the paper's relative tracking) the
// parked car sweeps past at the vehicle's speed.
#include <algorithm>
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "icanc/core/motion/ego_motion.hpp"
#include "icanc/core/perception/box.hpp"
#include "icanc/core/tracking/tracker.hpp"

namespace icanc {
namespace {

Eigen::Isometry3d arcPose(double speed, double yaw_rate, double t) {
  return predictEgoPose(Eigen::Vector2d(speed, 0.0), yaw_rate, t).toIsometry();
}

// An axis-aligned box of this size around `center` (vehicle frame), as a detection.
Box3D boxAround(const Eigen::Vector3d& center, const Eigen::Vector3f& size) {
  Box3D b;
  b.center = center.cast<float>();
  b.size = size;
  b.min = b.center - 0.5f * size;
  b.max = b.center + 0.5f * size;
  b.num_points = 100;
  return b;
}

struct Velocities {
  Eigen::Vector3d parked_velocity;  // the parked car's track, last frame
  Eigen::Vector3d walker_velocity;  // the walker's
};

// 3 s at 10 Hz, the vehicle at 8 m/s turning left at 0.25 rad/s; a parked car and a walker
// crossing (odom: +y at 1.4 m/s) ahead. With `ego`, the tracker gets the frame motion.
Velocities drive(bool ego) {
  TrackerParams params;
  params.anchor = TrackAnchor::kCentre;
  params.gate_distance_m = 3.5;
  MultiObjectTracker tracker(params);
  EgoMotionParams ego_params;
  ego_params.source = EgoMotionSource::kTf;
  EgoMotion motion(ego_params);
  const Eigen::Vector3d parked(30.0, 12.0, 0.8);
  Velocities run;
  for (int i = 0; i <= 30; ++i) {
    const double t = 0.1 * i;
    const Eigen::Isometry3d pose = arcPose(8.0, 0.25, t);
    const Eigen::Vector3d walker(22.0, -6.0 + 1.4 * t, 0.9);
    const std::vector<Box3D> detections{
        boxAround(pose.inverse() * parked, Eigen::Vector3f(4.5f, 1.8f, 1.5f)),
        boxAround(pose.inverse() * walker, Eigen::Vector3f(0.5f, 0.5f, 1.8f))};
    const EgoStep step = motion.update(t, &pose);
    tracker.update(t, detections, TrackerView(),
                   ego ? step.motion : Eigen::Isometry3d::Identity());
  }
  const Eigen::Isometry3d pose = arcPose(8.0, 0.25, 3.0);
  for (const Track& track : tracker.tracks()) {
    // Compare in odom's axes: the filter's velocity is in the vehicle frame's.
    const Eigen::Vector3d v = pose.linear() * track.velocity();
    (track.box.size.x() > 2.0f ? run.parked_velocity : run.walker_velocity) = v;
  }
  EXPECT_EQ(tracker.tracks().size(), 2u);
  return run;
}

TEST(TrackerEgoMotion, AParkedCarStandsStillAndAWalkerWalksSeenFromATurningVehicle) {
  const Velocities run = drive(true);
  EXPECT_LT(run.parked_velocity.head<2>().norm(), 0.1) << run.parked_velocity.transpose();
  EXPECT_NEAR(run.walker_velocity.x(), 0.0, 0.1);
  EXPECT_NEAR(run.walker_velocity.y(), 1.4, 0.1);
}

TEST(TrackerEgoMotion, WithoutTheMotionTheStaticWorldSweepsPast) {
  const Velocities run = drive(false);
  EXPECT_GT(run.parked_velocity.head<2>().norm(), 5.0) << run.parked_velocity.transpose();
}

TEST(TrackerEgoMotion, ChangingFrameMovesBoxAndFilterTogether) {
  TrackerParams params;
  params.anchor = TrackAnchor::kCentre;
  MultiObjectTracker tracker(params);
  Box3D box = boxAround(Eigen::Vector3d(10.0, 0.0, 0.5), Eigen::Vector3f(2.0f, 1.0f, 1.0f));
  box.footprint.push_back({Eigen::Vector2f(9.0f, -0.5f), Eigen::Vector2f(11.0f, 0.5f)});
  tracker.update(0.0, {box});
  // The vehicle turned 90 deg left on the spot: what was ahead is now on the right.
  Eigen::Isometry3d motion = Eigen::Isometry3d::Identity();
  motion.linear() = Eigen::AngleAxisd(-M_PI / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  tracker.update(0.1, {}, TrackerView(), motion);
  ASSERT_EQ(tracker.tracks().size(), 1u);
  const Track& track = tracker.tracks().front();
  EXPECT_TRUE(track.box.center.isApprox(Eigen::Vector3f(0.0f, -10.0f, 0.5f), 1e-5f));
  EXPECT_TRUE(track.filter.position().isApprox(Eigen::Vector3d(0.0, -10.0, 0.5), 1e-9));
  EXPECT_NEAR(track.box.min.x(), -0.5f, 1e-5f);  // the 2 m x 1 m box now lies across
  EXPECT_NEAR(track.box.max.y(), -9.0f, 1e-5f);
  ASSERT_EQ(track.box.footprint.size(), 1u);
  EXPECT_NEAR(track.box.footprint[0].min.y(), -11.0f, 1e-5f);
}

// The outline of a car (length x width) parked at `centre` with `yaw` in odom, as the vehicle at
// `pose` sees it: points 0.1 m apart on its four sides, fitted like a cluster.
Box3D parkedCarSeenFrom(const Eigen::Isometry3d& pose, const Eigen::Vector2d& centre, double yaw,
                        double length, double width) {
  Cloud cloud;
  const Eigen::Rotation2Dd turn(yaw);
  const auto add = [&](double along, double across) {
    const Eigen::Vector2d odom = centre + turn * Eigen::Vector2d(along, across);
    const Eigen::Vector3d p = pose.inverse() * Eigen::Vector3d(odom.x(), odom.y(), 0.8);
    cloud.push_back(Point(float(p.x()), float(p.y()), float(p.z())));
  };
  for (double a = -0.5 * length; a <= 0.5 * length + 1e-9; a += 0.1) {
    add(a, -0.5 * width);
    add(a, 0.5 * width);
  }
  for (double c = -0.5 * width; c <= 0.5 * width + 1e-9; c += 0.1) {
    add(-0.5 * length, c);
    add(0.5 * length, c);
  }
  return fitBox(cloud, nullptr, 1.0f);
}

// The tracker measures the faces nearest the sensor (the shipped anchor). A car parked
// at 35 deg to the road, seen from a vehicle turning at 0.25 rad/s: its axis-aligned box in the
// vehicle frame changes shape every frame (its faces there move at about 1 m/s), yet it stands
// still. Its faces are measured along axes fixed to the ground.
TEST(TrackerEgoMotion, AParkedYawedCarKeepsStillWhileTheVehicleTurnsNearestFaces) {
  TrackerParams params;  // anchor nearest_face
  params.gate_distance_m = 3.5;
  MultiObjectTracker tracker(params);
  EgoMotionParams ego_params;
  ego_params.source = EgoMotionSource::kTf;
  EgoMotion motion(ego_params);
  const Eigen::Vector2d parked(25.0, 9.0);
  double worst = 0.0;
  for (int i = 0; i <= 30; ++i) {
    const double t = 0.1 * i;
    const Eigen::Isometry3d pose = arcPose(6.0, 0.25, t);
    const std::vector<Box3D> detections{parkedCarSeenFrom(pose, parked, 0.6, 4.5, 1.8)};
    const EgoStep step = motion.update(t, &pose);
    tracker.update(t, detections, TrackerView(), step.motion);
    ASSERT_EQ(tracker.tracks().size(), 1u) << "t " << t;
    if (i >= 5) worst = std::max(worst, tracker.tracks().front().velocity().head<2>().norm());
  }
  EXPECT_LT(worst, 0.1);
  // Seen along its 4.5 m side, its faces are measured along its own sides: yaw 0.6 in odom, the
  // vehicle's heading after 3 s at 0.25 rad/s taken off.
  EXPECT_NEAR(tracker.tracks().front().face_axes_yaw, 0.6 - 0.75, 0.02);
}

// The hull travels with the box: a car driving at 8 m/s across the view of a vehicle turning at
// 0.25 rad/s, its faces measured along its ground-fixed axes, keeps its velocity over ground.
TEST(TrackerEgoMotion, ADrivingCarKeepsItsVelocityWhileTheVehicleTurnsNearestFaces) {
  TrackerParams params;
  params.gate_distance_m = 3.5;
  MultiObjectTracker tracker(params);
  EgoMotionParams ego_params;
  ego_params.source = EgoMotionSource::kTf;
  EgoMotion motion(ego_params);
  const double yaw = 0.6;
  const Eigen::Vector2d heading(std::cos(yaw), std::sin(yaw));
  for (int i = 0; i <= 30; ++i) {
    const double t = 0.1 * i;
    const Eigen::Isometry3d pose = arcPose(6.0, 0.25, t);
    const Eigen::Vector2d car = Eigen::Vector2d(20.0, 0.0) + 8.0 * t * heading;
    const EgoStep step = motion.update(t, &pose);
    tracker.update(t, {parkedCarSeenFrom(pose, car, yaw, 4.5, 1.8)}, TrackerView(), step.motion);
    ASSERT_EQ(tracker.tracks().size(), 1u) << "t " << t;
  }
  const Eigen::Isometry3d pose = arcPose(6.0, 0.25, 3.0);
  const Eigen::Vector3d v = pose.linear() * tracker.tracks().front().velocity();  // odom axes
  EXPECT_NEAR(v.x(), 8.0 * heading.x(), 0.1);
  EXPECT_NEAR(v.y(), 8.0 * heading.y(), 0.1);
}

// The hull moves with the box when the frame changes: a diagonal wall turned to lie along x keeps
// tight bounds (the rotated corners of its axis-aligned box would make it a 2.8 m square), and the
// face axes turn with it.
TEST(TrackerEgoMotion, ChangingFrameKeepsTheHullsTightBounds) {
  TrackerParams params;
  params.anchor = TrackAnchor::kCentre;
  MultiObjectTracker tracker(params);
  Cloud cloud;  // a wall from (8, 0) to (10, 2)
  for (int k = 0; k <= 20; ++k) cloud.push_back(Point(8.0f + 0.1f * k, 0.1f * k, 0.5f));
  tracker.update(0.0, {fitBox(cloud)});
  Eigen::Isometry3d motion = Eigen::Isometry3d::Identity();
  motion.linear() = Eigen::AngleAxisd(-M_PI / 4, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  tracker.update(0.1, {}, TrackerView(), motion);
  ASSERT_EQ(tracker.tracks().size(), 1u);
  const Box3D& box = tracker.tracks().front().box;
  EXPECT_NEAR(box.max.x() - box.min.x(), 2.0f * std::sqrt(2.0f), 1e-4f);
  EXPECT_NEAR(box.max.y() - box.min.y(), 0.0f, 1e-4f);
  EXPECT_NEAR(tracker.tracks().front().face_axes_yaw, -M_PI / 4, 1e-6);
}

}  // namespace
}  // namespace icanc
