// Pins the ground-truth danger definition: corridor geometry and time to corridor.
#include <cmath>

#include <gtest/gtest.h>

#include "icanc/core/evaluation/ground_truth.hpp"

namespace icanc {
namespace {

CorridorParams corridor() {
  CorridorParams c;
  c.half_width_m = 1.0;
  c.margin_m = 0.5;          // |y| <= 1.5
  c.vehicle_front_m = 1.0;
  c.stopping_margin_m = 4.0; // 0 <= x <= 5
  c.horizon_s = 2.0;
  return c;
}

TruthPose box(double x, double y, double l, double w, double yaw_deg, double t = 0.0) {
  TruthPose p;
  p.t = t;
  p.center = Eigen::Vector2d(x, y);
  p.size = Eigen::Vector2d(l, w);
  p.yaw = yaw_deg * M_PI / 180.0;
  return p;
}

TEST(InCorridor, FootprintEdgesAgainstTheRectangle) {
  const CorridorParams c = corridor();
  EXPECT_TRUE(inCorridor(box(3.0, 0.0, 0.5, 0.5, 0), c));
  EXPECT_TRUE(inCorridor(box(3.0, 1.75, 0.5, 0.5, 0), c));    // touches y = 1.5
  EXPECT_FALSE(inCorridor(box(3.0, 1.76, 0.5, 0.5, 0), c));
  EXPECT_TRUE(inCorridor(box(5.25, 0.0, 0.5, 0.5, 0), c));    // touches x = 5
  EXPECT_FALSE(inCorridor(box(5.26, 0.0, 0.5, 0.5, 0), c));
  EXPECT_FALSE(inCorridor(box(-0.26, 0.0, 0.5, 0.5, 0), c));  // behind the origin
  // A long car parked alongside, rotated: its corner reaches in.
  EXPECT_FALSE(inCorridor(box(3.0, 3.0, 4.0, 1.8, 0), c));
  EXPECT_TRUE(inCorridor(box(3.0, 3.0, 4.0, 1.8, 45), c));
  // A unit square turned 45 deg, moved off the corridor's corner (5, 1.5) by a along both axes:
  // its bounding box (half size 0.707) overlaps the corridor for a < 0.707, the square itself only
  // for a * sqrt(2) <= 0.5 (its edge midpoint faces the corner). Only the footprint's own axes
  // separate the two at a = 0.45.
  EXPECT_FALSE(inCorridor(box(5.45, 1.95, 1.0, 1.0, 45), c));
  EXPECT_TRUE(inCorridor(box(5.3, 1.8, 1.0, 1.0, 45), c));
}

TEST(TimeToCorridor, CrossingPedestrianEntersWithinTheHorizon) {
  const CorridorParams c = corridor();
  std::vector<TruthPose> walk;  // from y = 4 toward -4 at 1.5 m/s, x = 3
  for (int k = 0; k <= 60; ++k) walk.push_back(box(3.0, 4.0 - 0.15 * k, 0.5, 0.5, 0, 0.1 * k));
  // Enters when its near edge reaches y = 1.5: centre y = 1.75 -> t = 1.5 s.
  EXPECT_NEAR(timeToCorridor(walk, 0.0, c), 1.5, 1e-9);
  EXPECT_NEAR(timeToCorridor(walk, 1.0, c), 0.5, 1e-9);
  EXPECT_DOUBLE_EQ(timeToCorridor(walk, 2.0, c), 0.0);  // already in
  std::vector<TruthPose> slow;  // same path at 0.5 m/s: 4.5 s away, beyond the 2 s horizon
  for (int k = 0; k <= 100; ++k) slow.push_back(box(3.0, 4.0 - 0.05 * k, 0.5, 0.5, 0, 0.1 * k));
  EXPECT_DOUBLE_EQ(timeToCorridor(slow, 0.0, c), -1.0);
  EXPECT_NEAR(timeToCorridor(slow, 2.5, c), 2.0, 1e-9);  // exactly at the horizon
}

TEST(CorridorParams, ValidateNamesTheParameter) {
  EXPECT_EQ(validate(CorridorParams{}), "");
  CorridorParams c;
  c.horizon_s = 0.0;
  EXPECT_NE(validate(c).find("horizon_s"), std::string::npos);
}

}  // namespace
}  // namespace icanc
