// The planner's path as the predictive danger model follows it (EgoPath): the part ahead of the
// vehicle, moved to it, walked by arc length; paths the vehicle is not on are refused.
#include <cmath>
#include <limits>
#include <vector>

#include <gtest/gtest.h>

#include "icanc/core/motion/ego_path.hpp"

namespace icanc {
namespace {

constexpr double kHalfPi = M_PI / 2.0;

TEST(EgoPath, KeepsThePartAheadOfTheVehicleMovedToIt) {
  // A straight path along y = 0.5 that starts 3 m behind the vehicle.
  EgoPath path;
  ASSERT_EQ(path.set({{-3.0, 0.5}, {0.0, 0.5}, {4.0, 0.5}, {20.0, 0.5}}, 2.0, kHalfPi),
            EgoPath::Refused::kNone);
  EXPECT_NEAR(path.length(), 20.0, 1e-9);  // from the vehicle's abeam point on
  const PlanarPose ahead = path.at(10.0);
  EXPECT_NEAR(ahead.position.x(), 10.0, 1e-9);
  EXPECT_NEAR(ahead.position.y(), 0.0, 1e-9);  // the path's shape from where the vehicle is
  EXPECT_NEAR(ahead.yaw, 0.0, 1e-12);
  const PlanarPose start = path.at(-1.0);
  EXPECT_NEAR(start.position.norm(), 0.0, 1e-12);
}

TEST(EgoPath, FollowsTheCornersAndGoesStraightOnBeyondTheEnd) {
  EgoPath path;
  ASSERT_EQ(path.set({{0.0, 0.0}, {5.0, 0.0}, {5.0, 0.0}, {5.0, 5.0}}, 2.0, kHalfPi),
            EgoPath::Refused::kNone);  // a repeated point is dropped
  const PlanarPose side = path.at(7.5);
  EXPECT_NEAR(side.position.x(), 5.0, 1e-9);
  EXPECT_NEAR(side.position.y(), 2.5, 1e-9);
  EXPECT_NEAR(side.yaw, kHalfPi, 1e-9);
  const PlanarPose beyond = path.at(12.0);
  EXPECT_NEAR(beyond.position.x(), 5.0, 1e-9);
  EXPECT_NEAR(beyond.position.y(), 7.0, 1e-9);
  EXPECT_NEAR(beyond.yaw, kHalfPi, 1e-9);
}

TEST(EgoPath, RefusesAPathTheVehicleIsNotOn) {
  EgoPath path;
  EXPECT_EQ(path.set({{1.0, 0.0}}, 2.0, kHalfPi), EgoPath::Refused::kTooShort);
  EXPECT_EQ(path.set({{1.0, 0.0}, {1.0, 0.0}}, 2.0, kHalfPi), EgoPath::Refused::kTooShort);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(path.set({{0.0, 0.0}, {nan, 1.0}}, 2.0, kHalfPi), EgoPath::Refused::kNotFinite);
  // The next lane over, 5 m to the left.
  EXPECT_EQ(path.set({{0.0, 5.0}, {30.0, 5.0}}, 2.0, kHalfPi), EgoPath::Refused::kTooFar);
  // Leading back the way the vehicle came.
  EXPECT_EQ(path.set({{0.0, 0.0}, {-30.0, 0.0}}, 2.0, kHalfPi), EgoPath::Refused::kHeading);
  EXPECT_TRUE(path.empty());
  EXPECT_STREQ(toString(EgoPath::Refused::kTooFar), "the vehicle is not on it (nearest point too far)");
}

TEST(EgoPath, AtItsEndTheVehicleGoesOnInItsLastDirection) {
  EgoPath path;
  ASSERT_EQ(path.set({{-10.0, 0.0}, {-5.0, 0.0}, {0.0, 0.0}}, 2.0, kHalfPi), EgoPath::Refused::kNone);
  const PlanarPose on = path.at(3.0);
  EXPECT_NEAR(on.position.x(), 3.0, 1e-9);
  EXPECT_NEAR(on.position.y(), 0.0, 1e-9);
}

}  // namespace
}  // namespace icanc
