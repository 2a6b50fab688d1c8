// StampCheck: frames whose stamp is zero, repeats, goes backwards or jumps ahead are rejected,
// so they never reach the tracker as dt = 0 or a reset (issue 21).
#include <gtest/gtest.h>

#include "icanc/core/input/stamp_check.hpp"

namespace icanc {
namespace {

TEST(StampCheck, SteadyStampsAreAccepted) {
  StampCheck check;
  for (int i = 0; i < 20; ++i) EXPECT_EQ(check.check(100.0 + 0.1 * i), StampVerdict::kOk) << i;
  EXPECT_EQ(check.count(StampVerdict::kOk), 20u);
  EXPECT_EQ(check.rejected(), 0u);
}

TEST(StampCheck, ZeroStampIsRejectedAndLeavesTheTimeline) {
  StampCheck check;
  EXPECT_EQ(check.check(0.0), StampVerdict::kZero);  // even as the first frame
  EXPECT_EQ(check.check(10.0), StampVerdict::kOk);
  EXPECT_EQ(check.check(0.0), StampVerdict::kZero);
  EXPECT_EQ(check.check(10.1), StampVerdict::kOk);  // compared with 10.0, not with 0
  EXPECT_EQ(check.check(-1.0), StampVerdict::kZero);
  EXPECT_EQ(check.count(StampVerdict::kZero), 3u);
}

TEST(StampCheck, FrozenClockIsRejectedEveryFrame) {
  StampCheck check;
  EXPECT_EQ(check.check(5.0), StampVerdict::kOk);
  for (int i = 0; i < 10; ++i) EXPECT_EQ(check.check(5.0), StampVerdict::kRepeated);
  EXPECT_EQ(check.count(StampVerdict::kRepeated), 10u);
  EXPECT_EQ(check.check(5.1), StampVerdict::kOk);  // the clock runs again
}

TEST(StampCheck, BackwardsIsRejectedAndTheNewTimelineAcceptedFromItsSecondFrame) {
  StampCheck check;
  EXPECT_EQ(check.check(50.0), StampVerdict::kOk);
  EXPECT_EQ(check.check(50.1), StampVerdict::kOk);
  EXPECT_EQ(check.check(10.0), StampVerdict::kBackwards);  // bag loop
  EXPECT_EQ(check.check(10.1), StampVerdict::kOk);
  EXPECT_EQ(check.check(10.2), StampVerdict::kOk);
}

TEST(StampCheck, AbsurdJumpIsRejected) {
  StampCheck check(StampCheckParams{2.0});
  EXPECT_EQ(check.check(10.0), StampVerdict::kOk);
  EXPECT_EQ(check.check(12.0), StampVerdict::kOk);  // exactly max_jump_s
  EXPECT_EQ(check.check(1e9), StampVerdict::kJump);
  EXPECT_EQ(check.check(1e9 + 0.1), StampVerdict::kOk);
  EXPECT_EQ(check.count(StampVerdict::kJump), 1u);
}

TEST(StampCheck, TwoAlternatingClocksAreRejectedFrameAfterFrame) {
  StampCheck check;
  EXPECT_EQ(check.check(1000.0), StampVerdict::kOk);  // nothing to compare the first with
  for (int i = 1; i < 40; ++i) {
    const double stamp = (i % 2 ? 20.0 : 1000.0) + 0.1 * i;
    EXPECT_NE(check.check(stamp), StampVerdict::kOk) << i;
  }
  EXPECT_EQ(check.count(StampVerdict::kOk), 1u);
  EXPECT_EQ(check.count(StampVerdict::kBackwards), 20u);
  EXPECT_EQ(check.count(StampVerdict::kJump), 19u);
}

TEST(StampCheck, Validate) {
  EXPECT_EQ(validate(StampCheckParams()), "");
  EXPECT_NE(validate(StampCheckParams{0.0}).find("stamp_check/max_jump_s"), std::string::npos);
  EXPECT_NE(validate(StampCheckParams{-1.0}), "");
  EXPECT_NE(validate(StampCheckParams{1e9}), "");
}

}  // namespace
}  // namespace icanc
