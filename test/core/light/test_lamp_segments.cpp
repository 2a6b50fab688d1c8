// Pins the segmented lamp model: validation, the paper's default segment, the azimuth range under
// which a box is seen from the lamp (REP-103: +y left, counter-clockwise positive) and coverage.
#include <gtest/gtest.h>

#include "icanc/core/light/lamp_segments.hpp"

namespace icanc {
namespace {

LampSegment segment(double lo, double hi, double watts = 3.125, double low = 0.0) {
  LampSegment s;
  s.azimuth_min_deg = lo;
  s.azimuth_max_deg = hi;
  s.watts = watts;
  s.low_watts = low;
  return s;
}

Eigen::AlignedBox2d box(double x0, double y0, double x1, double y1) {
  return Eigen::AlignedBox2d(Eigen::Vector2d(x0, y0), Eigen::Vector2d(x1, y1));
}

TEST(LampSegments, EmptyListIsThePapersOneLamp) {
  const SegmentLampParams p;
  EXPECT_EQ(validate(p), "");
  const auto s = effectiveSegments(p);
  ASSERT_EQ(s.size(), 1u);
  EXPECT_DOUBLE_EQ(s[0].azimuth_min_deg, -180.0);
  EXPECT_DOUBLE_EQ(s[0].azimuth_max_deg, 180.0);
  EXPECT_DOUBLE_EQ(s[0].watts, kPaperLampWatts);
}

TEST(LampSegments, ValidationNamesTheSegmentAndKey) {
  SegmentLampParams p;
  p.segments = {segment(-10, 10), segment(0, 20)};  // overlaps are allowed
  EXPECT_EQ(validate(p), "");
  p.segments[1] = segment(20, 10);
  EXPECT_NE(validate(p).find("segments[1].azimuth_min_deg"), std::string::npos) << validate(p);
  p.segments[1] = segment(-200, 10);
  EXPECT_NE(validate(p).find("segments[1]"), std::string::npos);
  p.segments[1] = segment(0, 10, 0.0);
  EXPECT_NE(validate(p).find("segments[1].watts"), std::string::npos);
  p.segments[1] = LampSegment();  // keys missing: NaN
  EXPECT_NE(validate(p).find("segments[1].azimuth"), std::string::npos);
  p.segments[1] = segment(0, 10, 3.0, 4.0);
  EXPECT_NE(validate(p).find("segments[1].low_watts"), std::string::npos);
  p.segments.assign(kMaxLampSegments + 1, segment(-10, 10));
  EXPECT_NE(validate(p).find("at most 32"), std::string::npos);
  p.segments.clear();
  p.segment_margin_deg = -1.0;
  EXPECT_NE(validate(p).find("segment_margin_deg"), std::string::npos);
  p.segment_margin_deg = 2.0;
  p.lamp_position_m.x() = std::numeric_limits<float>::quiet_NaN();
  EXPECT_NE(validate(p).find("lamp_position_m"), std::string::npos);
  p.lamp_position_m.x() = 0.0f;
  p.full_power_range_m = -1.0;
  EXPECT_NE(validate(p).find("full_power_range_m"), std::string::npos);
  p.full_power_range_m = 20.0;
  p.min_level = 0.0;
  EXPECT_NE(validate(p).find("min_level"), std::string::npos);
  p.min_level = 0.05;
  EXPECT_EQ(validate(p), "");
  p.segments = {segment(-10, 10, 3.0, 1.0)};  // a low beam and dimming: one or the other
  EXPECT_NE(validate(p).find("segments[0].low_watts"), std::string::npos) << validate(p);
  LampSegment s;
  EXPECT_EQ(setSegmentKey(s, "watts", 2.0), "");
  EXPECT_DOUBLE_EQ(s.watts, 2.0);
  EXPECT_NE(setSegmentKey(s, "wats", 2.0).find("unknown key 'wats'"), std::string::npos);
}

TEST(LampSegments, AzimuthRangeFollowsRep103) {
  const Eigen::Vector2d origin(0.0, 0.0);
  // Straight ahead, 10 m, 2 m wide: +-5.71 deg.
  AzimuthRange r = azimuthRange(box(10, -1, 11, 1), origin);
  EXPECT_NEAR(r.lo_deg, -5.7106, 1e-3);
  EXPECT_NEAR(r.hi_deg, 5.7106, 1e-3);
  // On the left (+y): positive azimuths.
  r = azimuthRange(box(0, 5, 1, 6), origin);
  EXPECT_NEAR(r.lo_deg, 78.69, 1e-2);
  EXPECT_NEAR(r.hi_deg, 90.0, 1e-9);
  // Behind, across +-180: an unwrapped range around 180.
  r = azimuthRange(box(-6, -1, -5, 1), origin);
  EXPECT_NEAR(r.lo_deg, 180.0 - 11.31, 1e-2);
  EXPECT_NEAR(r.hi_deg, 180.0 + 11.31, 1e-2);
  // A box holding the lamp: every direction.
  r = azimuthRange(box(-1, -1, 1, 1), origin);
  EXPECT_DOUBLE_EQ(r.hi_deg - r.lo_deg, 360.0);
  // Seen from a lamp at the bumper's right corner (x 2, y -0.8), a box ahead of it is at 0.
  r = azimuthRange(box(12, -1.3, 13, -0.3), Eigen::Vector2d(2.0, -0.8));
  EXPECT_NEAR(r.lo_deg + r.hi_deg, 0.0, 1e-9);
}

TEST(LampSegments, CoverageWithMarginAndWrap) {
  const LampSegment right = segment(-30, -10), ahead = segment(-10, 10), all = segment(-180, 180);
  const AzimuthRange small{2.0, 6.0};
  EXPECT_TRUE(covers(ahead, small, 0.0));
  EXPECT_FALSE(covers(right, small, 0.0));
  EXPECT_FALSE(covers(right, small, 11.9));
  EXPECT_TRUE(covers(right, small, 12.0));  // 2 - 12 = -10: touches the segment's edge
  EXPECT_FALSE(covers(segment(170, 180), AzimuthRange{-178, -175}, 0.0));
  EXPECT_TRUE(covers(segment(170, 180), AzimuthRange{-178, -175}, 3.0));  // across +-180
  EXPECT_TRUE(covers(segment(-180, -170), AzimuthRange{168.0, 191.0}, 0.0));
  for (double lo = -200.0; lo < 200.0; lo += 7.0) EXPECT_TRUE(covers(all, AzimuthRange{lo, lo + 1.0}, 0.0));
}

}  // namespace
}  // namespace icanc
