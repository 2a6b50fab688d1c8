// missedFrames: the "dropped frames" counter of every nodelet's input diagnostics.
#include <gtest/gtest.h>

#include "icanc/core/input/frame_gaps.hpp"

namespace icanc {
namespace {

TEST(FrameGaps, OnePeriodApartIsNoGap) {
  EXPECT_EQ(missedFrames(10.0, 10.1, 10.0), 0u);
  EXPECT_EQ(missedFrames(10.0, 10.14, 10.0), 0u);  // jitter below 1.5 periods
}

TEST(FrameGaps, CountsTheFramesThatShouldHaveArrived) {
  EXPECT_EQ(missedFrames(10.0, 10.2, 10.0), 1u);
  EXPECT_EQ(missedFrames(10.0, 10.16, 10.0), 1u);  // 1.6 periods: one frame lost
  EXPECT_EQ(missedFrames(10.0, 11.0, 10.0), 9u);
  EXPECT_EQ(missedFrames(0.0, 1.0, 20.0), 19u);
}

TEST(FrameGaps, RepeatedBackwardsStampsAndBadRatesCountNothing) {
  EXPECT_EQ(missedFrames(10.0, 10.0, 10.0), 0u);
  EXPECT_EQ(missedFrames(10.0, 5.0, 10.0), 0u);  // bag loop
  EXPECT_EQ(missedFrames(10.0, 12.0, 0.0), 0u);
  EXPECT_EQ(missedFrames(10.0, 12.0, -1.0), 0u);
}

}  // namespace
}  // namespace icanc
