// TwistHistory: the vehicle's measured speed and yaw rate looked up at a cloud's stamp.
#include "icanc/core/motion/measured_twist.hpp"

#include <cmath>
#include <limits>

#include <gtest/gtest.h>

namespace icanc {
namespace {

MeasuredTwist twist(double v, double w = std::numeric_limits<double>::quiet_NaN()) {
  return measuredTwist(v, w);
}

TEST(TwistHistory, InterpolatesBetweenTheSamplesAroundTheStamp) {
  TwistHistory h;
  EXPECT_EQ(h.add(10.00, twist(8.0, 0.1)), TwistHistory::Added::kAdded);
  EXPECT_EQ(h.add(10.02, twist(9.0, 0.3)), TwistHistory::Added::kAdded);
  MeasuredTwist v;
  ASSERT_TRUE(h.at(10.005, 0.1, v));
  EXPECT_NEAR(v.forward_mps, 8.25, 1e-9);
  EXPECT_NEAR(v.yaw_rate_rad_s, 0.15, 1e-9);
  ASSERT_TRUE(h.at(10.02, 0.1, v));
  EXPECT_NEAR(v.forward_mps, 9.0, 1e-9);
}

TEST(TwistHistory, NearestWithinTheAgeElseNone) {
  TwistHistory h;
  h.add(10.0, twist(8.0));
  MeasuredTwist v;
  ASSERT_TRUE(h.at(10.15, 0.2, v));  // newest, 0.15 s old
  EXPECT_EQ(v.forward_mps, 8.0);
  EXPECT_TRUE(std::isnan(v.yaw_rate_rad_s));  // a source without a gyro
  ASSERT_TRUE(h.at(9.9, 0.2, v));  // a cloud stamped before the first sample
  EXPECT_EQ(v.forward_mps, 8.0);
  v.forward_mps = -1.0;
  EXPECT_FALSE(h.at(10.25, 0.2, v));  // too old: the wheel speed stopped coming
  EXPECT_EQ(v.forward_mps, -1.0);
  EXPECT_FALSE(TwistHistory().at(10.0, 0.2, v));
  // A gap wider than the age on one side: the near sample alone, not a line across the gap.
  h.add(12.0, twist(0.0));
  ASSERT_TRUE(h.at(11.9, 0.2, v));
  EXPECT_EQ(v.forward_mps, 0.0);
}

TEST(TwistHistory, RejectsWhatIsNoMeasurementAndRestartsWhenTimeGoesBack) {
  TwistHistory h(2.0, 100.0, 5.0);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_EQ(h.add(1.0, twist(nan)), TwistHistory::Added::kInvalid);
  EXPECT_EQ(h.add(nan, twist(3.0)), TwistHistory::Added::kInvalid);
  EXPECT_EQ(h.add(1.0, twist(150.0)), TwistHistory::Added::kInvalid);
  EXPECT_EQ(h.add(1.0, twist(3.0, inf)), TwistHistory::Added::kInvalid);
  EXPECT_EQ(h.add(1.0, twist(3.0, 7.0)), TwistHistory::Added::kInvalid);
  EXPECT_EQ(h.size(), 0u);
  h.add(5.0, twist(-2.0, 0.0));  // reversing is a speed
  h.add(5.1, twist(-2.0, 0.0));
  EXPECT_EQ(h.add(1.0, twist(4.0, 0.0)), TwistHistory::Added::kRestarted);  // bag loop
  EXPECT_EQ(h.size(), 1u);
  MeasuredTwist v;
  EXPECT_FALSE(h.at(5.05, 0.2, v));
  ASSERT_TRUE(h.at(1.0, 0.2, v));
  EXPECT_EQ(v.forward_mps, 4.0);
}

TEST(TwistHistory, KeepsOnlyTheHorizon) {
  TwistHistory h(1.0);
  for (int i = 0; i <= 500; ++i) h.add(0.02 * i, twist(5.0));  // 10 s at 50 Hz
  EXPECT_LE(h.size(), 51u);
  EXPECT_GE(h.size(), 50u);
}

}  // namespace
}  // namespace icanc
