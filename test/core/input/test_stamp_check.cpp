// StampCheck: frames whose stamp is zero, repeats, goes backwards or jumps ahead are rejected,
// so they never reach the tracker as dt = 0 or a reset.
#include <cmath>
#include <random>

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

// Stamps advancing at `factor` times the receipt clock (frames received every 0.1 s), from
// `stamp0` / `receipt0`; returns the verdicts.
std::vector<StampVerdict> stream(StampCheck& check, int frames, double factor, double& stamp,
                                 double& receipt) {
  std::vector<StampVerdict> out;
  for (int i = 0; i < frames; ++i) {
    stamp += 0.1 * factor;
    receipt += 0.1;
    out.push_back(check.check(stamp, receipt));
  }
  return out;
}

// A sensor clock running fast (stamps 0.5 or 0.9 s apart, every 0.1 s) or slow (0.04 s apart)
// passes every per-frame test, but once a window of receipt time shows it, every frame is
// rejected until the stamps advance with the receipts again.
TEST(StampCheck, ClockRunningFastOrSlowIsRejectedWithinAWindow) {
  for (const double factor : {5.0, 9.0, 0.4, 2.2, 0.45}) {
    SCOPED_TRACE(factor);
    StampCheck check;
    double stamp = 1000.0, receipt = 50.0;
    stream(check, 20, 1.0, stamp, receipt);  // a healthy second or two first
    const std::vector<StampVerdict> v = stream(check, 40, factor, stamp, receipt);
    const int window_frames = int(std::ceil(kStampRateWindowS / 0.1)) + 1;
    for (std::size_t i = window_frames; i < v.size(); ++i)
      EXPECT_EQ(v[i], StampVerdict::kRate) << "frame " << i << " after the clock went off";
    EXPECT_FALSE(factor > 1.0 ? check.rateRatio() <= kMaxStampRate : check.rateRatio() >= 1.0 / kMaxStampRate);
    // Right again: accepted once a window holds only right stamps.
    const std::vector<StampVerdict> back = stream(check, 30, 1.0, stamp, receipt);
    for (std::size_t i = window_frames; i < back.size(); ++i) EXPECT_EQ(back[i], StampVerdict::kOk) << i;
    EXPECT_GE(check.count(StampVerdict::kRate), 40u - window_frames);
  }
}

// What transport does to receipts is no wrong clock: jitter of +-40 ms per frame, a 300 ms stall
// then a burst, frames lost (stamps and receipts skip alike), a clock within the factor.
TEST(StampCheck, ReceiptJitterBurstsAndLostFramesAreNoWrongClock) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> jitter(-0.04, 0.04);
  StampCheck check;
  double stamp = 500.0, receipt = 0.0;
  for (int i = 0; i < 300; ++i) {
    stamp += (i % 37 == 0) ? 0.3 : 0.1;  // now and then two frames lost
    receipt = 20.0 + (stamp - 500.0) + 0.05 + jitter(rng);
    // Frames 100 to 103 held up in a driver's buffer, then delivered in one burst.
    if (i >= 100 && i <= 103) receipt = 20.0 + (stamp + 0.1 * (103 - i) - 500.0) + 0.09;
    EXPECT_NE(check.check(stamp, receipt), StampVerdict::kRate) << i << " ratio " << check.rateRatio();
  }
  EXPECT_NEAR(check.rateRatio(), 1.0, 0.1);
  for (int i = 0; i < 100; ++i) {  // a clock 1.8 times fast: within the factor
    stamp += 0.18;
    EXPECT_EQ(check.check(stamp, receipt += 0.1), StampVerdict::kOk) << i;
  }
}

// Without a receipt time (a replay on sim time) or a stream (pauses between frames) the rate is not
// judged; a new timeline (stamps going backwards, a bag loop) starts a new window instead of a
// wrong ratio.
TEST(StampCheck, RateIsJudgedOnlyWithReceiptsAndRestartsWithTheTimeline) {
  StampCheck no_receipts;
  for (int i = 1; i < 100; ++i) EXPECT_EQ(no_receipts.check(100.0 + 0.5 * i), StampVerdict::kOk);
  EXPECT_TRUE(std::isnan(no_receipts.rateRatio()));
  // Frames sent one at a time with pauses (stamps 0.1 s apart, receipts 0.6 s apart): no stream.
  StampCheck by_hand;
  for (int i = 1; i < 30; ++i) EXPECT_EQ(by_hand.check(100.0 + 0.1 * i, 5.0 + 0.6 * i), StampVerdict::kOk);
  StampCheck check;
  double stamp = 1000.0, receipt = 10.0;
  stream(check, 30, 1.0, stamp, receipt);
  EXPECT_NEAR(check.rateRatio(), 1.0, 1e-6);
  stamp = 200.0;  // the bag looped
  EXPECT_EQ(check.check(stamp, receipt += 0.1), StampVerdict::kBackwards);
  const std::vector<StampVerdict> v = stream(check, 30, 1.0, stamp, receipt);
  for (std::size_t i = 0; i < v.size(); ++i) EXPECT_EQ(v[i], StampVerdict::kOk) << i;
}

TEST(StampCheck, Validate) {
  EXPECT_EQ(validate(StampCheckParams()), "");
  EXPECT_NE(validate(StampCheckParams{0.0}).find("stamp_check/max_jump_s"), std::string::npos);
  EXPECT_NE(validate(StampCheckParams{-1.0}), "");
  EXPECT_NE(validate(StampCheckParams{1e9}), "");
}

}  // namespace
}  // namespace icanc
