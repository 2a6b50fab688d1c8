// Pins the paper's danger rules (Section III, Fig. "Current Danger Detector design", Listing 1).
#include <cmath>

#include <gtest/gtest.h>

#include "icanc/core/danger/danger.hpp"

namespace icanc {
namespace {

Eigen::Vector3d velocityAt(double heading_deg, double speed) {
  const double r = heading_deg * M_PI / 180.0;
  return Eigen::Vector3d(speed * std::cos(r), speed * std::sin(r), 0.0);
}

ObjectKinematics boxAt(double x, double y, double half, const Eigen::Vector3d& v) {
  ObjectKinematics o;
  o.center = Eigen::Vector3d(x, y, 0.0);
  o.aabb_min = o.center - Eigen::Vector3d(half, half, 0.85);
  o.aabb_max = o.center + Eigen::Vector3d(half, half, 0.85);
  o.velocity = v;
  return o;
}

TEST(GetSection, BoundariesAtPlusMinusHalfWidthExactly) {
  const double w = 0.7;
  EXPECT_EQ(getSection(0.7, w), Section::kLeft);    // y >= w
  EXPECT_EQ(getSection(0.6999, w), Section::kFront);
  EXPECT_EQ(getSection(0.0, w), Section::kFront);
  EXPECT_EQ(getSection(-0.6999, w), Section::kFront);
  EXPECT_EQ(getSection(-0.7, w), Section::kRight);  // y <= -w
  EXPECT_EQ(getSection(25.0, w), Section::kLeft);
  EXPECT_EQ(getSection(-25.0, w), Section::kRight);
}

TEST(HeadingDeg, DirectionsOfTheDesignNotes) {
  EXPECT_NEAR(headingDeg({1, 0, 0}), 0.0, 1e-9);    // straight ahead, away
  EXPECT_NEAR(headingDeg({0, 1, 0}), 90.0, 1e-9);   // left
  EXPECT_NEAR(headingDeg({-1, 0, 0}), 180.0, 1e-9); // toward the vehicle
  EXPECT_NEAR(headingDeg({0, -1, 0}), 270.0, 1e-9); // right
  EXPECT_NEAR(headingDeg({1, -1e-12, 0}), 360.0 - 5.7e-11, 1e-6);
  EXPECT_LT(headingDeg({1, -1e-12, 0}), 360.0);
  EXPECT_EQ(headingDeg({0, 0, 3}), 0.0);  // no planar motion
}

TEST(HeadingDeg, EqualsThePapersAngleBetweenVectorsFormula) {
  // theta = acos(u.v / |u||v|) with u = +x gives [0, 180]; the other half is 360 - theta.
  const Eigen::Vector2d u(1, 0);
  for (double deg = 0.5; deg < 360.0; deg += 7.3) {
    const Eigen::Vector3d v3 = velocityAt(deg, 2.5);
    const Eigen::Vector2d v = v3.head<2>();
    const double theta = std::acos(u.dot(v) / (u.norm() * v.norm())) * 180.0 / M_PI;
    const double expected = v.y() >= 0 ? theta : 360.0 - theta;
    EXPECT_NEAR(headingDeg(v3), expected, 1e-9) << deg;
  }
}

// The message's heading (REP-103 radians, (-pi, pi]) is the paper's direction: pi is 180 degrees.
TEST(HeadingRad, DirectionsInRadiansWithPiTowardTheVehicle) {
  EXPECT_NEAR(headingRad({1, 0, 0}), 0.0, 1e-12);            // away
  EXPECT_NEAR(headingRad({0, 1, 0}), M_PI / 2.0, 1e-12);     // left
  EXPECT_NEAR(headingRad({0, -1, 0}), -M_PI / 2.0, 1e-12);   // right
  EXPECT_EQ(headingRad({-1, 0, 0}), M_PI);                   // toward the vehicle
  EXPECT_EQ(headingRad({-1, -0.0, 0}), M_PI);                // atan2 gives -pi here: not in range
  EXPECT_EQ(headingRad({-1, -1e-9, 0}), M_PI);               // -pi once stored as float32
  EXPECT_NEAR(headingRad({-1, -1e-6, 0}), -M_PI + 1e-6, 1e-12);
  EXPECT_GT(float(headingRad({-1, -1e-6, 0})), -float(M_PI));
  EXPECT_EQ(headingRad({0, 0, 3}), 0.0);  // no planar motion
  for (double deg = 0.5; deg < 360.0; deg += 7.3) {
    const Eigen::Vector3d v = velocityAt(deg, 2.5);
    const double rad = headingRad(v);
    EXPECT_GT(rad, -M_PI) << deg;
    EXPECT_LE(rad, M_PI) << deg;
    EXPECT_NEAR(std::fmod(rad * 180.0 / M_PI + 360.0, 360.0), headingDeg(v), 1e-9) << deg;
  }
}

TEST(IsMovingTowardMe, NarrowerWindowKeepsTheCentres) {
  // 90 degree windows (DangerParams::heading_window_deg): right [45, 135], left [225, 315],
  // front [135, 225].
  EXPECT_FALSE(isMovingTowardMe(44.999, Section::kRight, 90.0));
  EXPECT_TRUE(isMovingTowardMe(45.0, Section::kRight, 90.0));
  EXPECT_TRUE(isMovingTowardMe(135.0, Section::kRight, 90.0));
  EXPECT_FALSE(isMovingTowardMe(135.001, Section::kRight, 90.0));
  EXPECT_FALSE(isMovingTowardMe(224.999, Section::kLeft, 90.0));
  EXPECT_TRUE(isMovingTowardMe(315.0, Section::kLeft, 90.0));
  EXPECT_FALSE(isMovingTowardMe(134.999, Section::kFront, 90.0));
  EXPECT_TRUE(isMovingTowardMe(225.0, Section::kFront, 90.0));
  EXPECT_FALSE(isMovingTowardMe(225.001, Section::kFront, 90.0));
}

TEST(AssessDanger, HeadingWindowParameterIsUsedAndValidated) {
  ObjectKinematics o;  // 2 m ahead, moving toward at 1 m/s but 60 degrees off the axis
  o.center = Eigen::Vector3d(2.25, 0.0, 0.0);
  o.aabb_min = Eigen::Vector3d(2.0, -0.25, 0.0);
  o.aabb_max = Eigen::Vector3d(2.5, 0.25, 1.7);
  o.velocity = Eigen::Vector3d(std::cos(M_PI * 240.0 / 180.0), std::sin(M_PI * 240.0 / 180.0), 0.0);
  DangerParams p;
  EXPECT_TRUE(assessDanger(o, p).dangerous) << "heading 240 is inside the paper's [105, 255]";
  p.heading_window_deg = 90.0;
  EXPECT_FALSE(assessDanger(o, p).moving_toward) << "and outside [135, 225]";
  EXPECT_FALSE(assessDanger(o, p).dangerous);
  EXPECT_EQ(validate(p), "");
  p.heading_window_deg = 0.0;
  EXPECT_NE(validate(p).find("heading_window_deg"), std::string::npos);
  p.heading_window_deg = 181.0;
  EXPECT_NE(validate(p).find("heading_window_deg"), std::string::npos);
}

TEST(IsMovingTowardMe, ThreeWindowsAtTheirEdges) {
  // Right section: [15, 165].
  EXPECT_FALSE(isMovingTowardMe(14.999, Section::kRight));
  EXPECT_TRUE(isMovingTowardMe(15.0, Section::kRight));
  EXPECT_TRUE(isMovingTowardMe(165.0, Section::kRight));
  EXPECT_FALSE(isMovingTowardMe(165.001, Section::kRight));
  // Left section: [195, 345].
  EXPECT_FALSE(isMovingTowardMe(194.999, Section::kLeft));
  EXPECT_TRUE(isMovingTowardMe(195.0, Section::kLeft));
  EXPECT_TRUE(isMovingTowardMe(345.0, Section::kLeft));
  EXPECT_FALSE(isMovingTowardMe(345.001, Section::kLeft));
  // Front section: [105, 255].
  EXPECT_FALSE(isMovingTowardMe(104.999, Section::kFront));
  EXPECT_TRUE(isMovingTowardMe(105.0, Section::kFront));
  EXPECT_TRUE(isMovingTowardMe(180.0, Section::kFront));
  EXPECT_TRUE(isMovingTowardMe(255.0, Section::kFront));
  EXPECT_FALSE(isMovingTowardMe(255.001, Section::kFront));
  // Moving away or parallel is never toward.
  for (Section s : {Section::kLeft, Section::kFront, Section::kRight}) {
    EXPECT_FALSE(isMovingTowardMe(0.0, s)) << toString(s);
  }
  EXPECT_FALSE(isMovingTowardMe(90.0, Section::kLeft));    // left, moving further left
  EXPECT_FALSE(isMovingTowardMe(270.0, Section::kRight));  // right, moving further right
}

TEST(IsMovingTowardMe, EachWindowSpans150Degrees) {
  for (Section s : {Section::kLeft, Section::kFront, Section::kRight}) {
    int inside = 0;
    for (int tenth = 0; tenth < 3600; ++tenth) inside += isMovingTowardMe(tenth / 10.0, s);
    EXPECT_EQ(inside, 1501) << toString(s);  // 150 deg, both edges included, at 0.1 deg steps
  }
}

TEST(GetSpeedOfObject, PlanarNorm) {
  EXPECT_DOUBLE_EQ(getSpeedOfObject({3, 4, 0}), 5.0);
  EXPECT_DOUBLE_EQ(getSpeedOfObject({3, 4, 12}), 5.0);  // vertical box jitter is not speed
}

TEST(ClosestPointDistance, ClampsTheOriginIntoTheBox) {
  EXPECT_DOUBLE_EQ(closestPointDistance({4, -1, -1}, {5, 1, 1}), 4.0);  // ahead, spans y and z
  EXPECT_DOUBLE_EQ(closestPointDistance({3, 4, 0}, {5, 6, 1}), 5.0);    // corner (3, 4, 0)
  EXPECT_DOUBLE_EQ(closestPointDistance({3, 4, 12}, {5, 6, 13}), 13.0); // z counts (paper)
  EXPECT_DOUBLE_EQ(closestPointDistance({-1, -1, -1}, {1, 1, 1}), 0.0); // contains the origin
}

TEST(AssessDanger, ThresholdIsSpeedTimesReactionTime) {
  DangerParams p;
  p.half_width_m = 0.7;
  p.reaction_time_s = 3.0;
  // Approaching head-on at 2 m/s: threshold 6 m. Closest face at exactly 6 m -> dangerous.
  const double half = 0.25;
  auto at = [&](double face_x) {
    return assessDanger(boxAt(face_x + half, 0.0, half, velocityAt(180.0, 2.0)), p);
  };
  EXPECT_TRUE(at(6.0).dangerous);
  EXPECT_DOUBLE_EQ(at(6.0).threshold_m, 6.0);
  EXPECT_TRUE(at(5.9).dangerous);
  EXPECT_FALSE(at(6.01).dangerous);
  EXPECT_EQ(at(6.0).section, Section::kFront);
  // Same place, moving away: never dangerous.
  EXPECT_FALSE(assessDanger(boxAt(3.0, 0.0, half, velocityAt(0.0, 2.0)), p).dangerous);
  // Standing still: threshold 0, not dangerous however close.
  EXPECT_FALSE(assessDanger(boxAt(1.5, 0.0, half, Eigen::Vector3d::Zero()), p).dangerous);
}

TEST(AssessDanger, SideSectionsNeedTheirOwnWindow) {
  DangerParams p;
  p.half_width_m = 1.2;
  p.reaction_time_s = 2.0;
  // Left at y = 3, moving right (270 deg) at 3 m/s: threshold 6 m, distance ~ sqrt(4^2+2.75^2).
  const auto left = assessDanger(boxAt(4.0, 3.0, 0.25, velocityAt(270.0, 3.0)), p);
  EXPECT_EQ(left.section, Section::kLeft);
  EXPECT_TRUE(left.moving_toward);
  EXPECT_TRUE(left.dangerous);
  // The same object seen on the right moving right is going away from the path.
  const auto right = assessDanger(boxAt(4.0, -3.0, 0.25, velocityAt(270.0, 3.0)), p);
  EXPECT_EQ(right.section, Section::kRight);
  EXPECT_FALSE(right.moving_toward);
  EXPECT_FALSE(right.dangerous);
}

TEST(AssessDanger, TheClosestPointDecidesTheSection) {
  // The paper's reference code takes the section of the box's point closest to the vehicle, not
  // of its centre. A 4.7 m x 1.9 m car centred 1.5 m right (y = -1.5) with w = 1.2: its centre is
  // right of the path (y <= -w), its near edge at y = -0.55 is inside it, so it is in front.
  DangerParams p;
  p.half_width_m = 1.2;
  p.reaction_time_s = 2.0;
  ObjectKinematics car;
  car.center = Eigen::Vector3d(10.0, -1.5, 0.0);
  car.aabb_min = car.center - Eigen::Vector3d(2.35, 0.95, 0.75);
  car.aabb_max = car.center + Eigen::Vector3d(2.35, 0.95, 0.75);
  car.velocity = velocityAt(180.0, 5.0);  // oncoming at 5 m/s: threshold 10 m, distance 7.65 m
  EXPECT_DOUBLE_EQ(closestPoint(car.aabb_min, car.aabb_max).y(), -0.55);
  const DangerAssessment a = assessDanger(car, p);
  EXPECT_EQ(a.section, Section::kFront);
  // The front window [105, 255] holds an oncoming heading (the right one, [15, 165], does not).
  EXPECT_TRUE(a.moving_toward);
  EXPECT_TRUE(a.dangerous);
  // Once its near edge is at -w it is right of the path, and oncoming is not toward the path.
  car.center.y() = -2.15;
  car.aabb_min.y() = -3.1;
  car.aabb_max.y() = -1.2;
  EXPECT_EQ(assessDanger(car, p).section, Section::kRight);
  EXPECT_FALSE(assessDanger(car, p).dangerous);
  // A box straddling the path (closest y = 0) is in front whatever its centre.
  car.aabb_min.y() = -3.0;
  car.aabb_max.y() = 0.4;
  EXPECT_EQ(assessDanger(car, p).section, Section::kFront);
}

TEST(DangerParams, ValidateNamesTheParameter) {
  EXPECT_EQ(validate(DangerParams{}), "");
  EXPECT_NE(validate(DangerParams{0.0, 3.0}).find("half_width_m"), std::string::npos);
  EXPECT_NE(validate(DangerParams{0.7, -1.0}).find("reaction_time_s"), std::string::npos);
}

}  // namespace
}  // namespace icanc
