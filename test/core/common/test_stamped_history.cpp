// StampedHistory: the stamped samples TwistHistory and EgoPoseSource keep over the last seconds,
// restarted when time goes back, bracketed around a stamp.
#include "icanc/core/common/stamped_history.hpp"

#include <initializer_list>
#include <limits>

#include <gtest/gtest.h>

namespace icanc {
namespace {

using History = StampedHistory<int>;

// A history of these stamps, valued 0, 1, 2, ... in the order they come.
History filled(std::initializer_list<double> stamps, double horizon_s = 10.0) {
  History h(horizon_s);
  int value = 0;
  for (double t : stamps) h.add(t, value++);
  return h;
}

TEST(StampedHistory, RestartsWhenAStampGoesBack) {
  History h(10.0);
  EXPECT_EQ(h.add(5.0, 1), History::Added::kAdded);
  EXPECT_EQ(h.add(5.1, 2), History::Added::kAdded);
  EXPECT_EQ(h.add(5.1, 3), History::Added::kAdded);  // an equal stamp is no restart
  EXPECT_EQ(h.size(), 3u);
  EXPECT_EQ(h.add(1.0, 4), History::Added::kRestarted);  // bag loop
  ASSERT_EQ(h.size(), 1u);
  EXPECT_EQ(h.front().stamp_s, 1.0);
  EXPECT_EQ(h.front().value, 4);
  EXPECT_EQ(h.back().value, 4);
  EXPECT_EQ(h.bracket(5.05).at_or_before->value, 4);  // the samples of before the loop are gone
  EXPECT_EQ(h.add(1.2, 5), History::Added::kAdded);
  EXPECT_EQ(h.size(), 2u);
}

TEST(StampedHistory, DropsWhatIsBeyondTheHorizonBehindTheNewest) {
  History h(1.0);
  h.add(0.0, 0);
  h.add(0.5, 1);
  h.add(1.0, 2);  // 0.0 is exactly the horizon behind: kept
  EXPECT_EQ(h.size(), 3u);
  EXPECT_EQ(h.front().stamp_s, 0.0);
  h.add(1.25, 3);  // 0.0 is now beyond it, 0.5 within
  ASSERT_EQ(h.size(), 3u);
  EXPECT_EQ(h.front().stamp_s, 0.5);
  EXPECT_EQ(h.back().stamp_s, 1.25);
  h.add(9.0, 4);  // a gap wider than the horizon: the newest alone
  ASSERT_EQ(h.size(), 1u);
  EXPECT_EQ(h.front().value, 4);
  History stream(1.0);
  for (int i = 0; i <= 500; ++i) stream.add(0.02 * i, i);  // 10 s at 50 Hz
  EXPECT_GE(stream.size(), 50u);
  EXPECT_LE(stream.size(), 51u);
  EXPECT_GE(stream.front().stamp_s, 9.0 - 1e-9);
}

TEST(StampedHistory, BracketsAStampBeforeBetweenOnAndAfterTheSamples) {
  const History h = filled({1.0, 2.0, 3.0});
  auto b = h.bracket(0.5);  // before the first
  EXPECT_EQ(b.at_or_before, nullptr);
  ASSERT_NE(b.after, nullptr);
  EXPECT_EQ(b.after->value, 0);
  b = h.bracket(1.5);  // between
  ASSERT_NE(b.at_or_before, nullptr);
  ASSERT_NE(b.after, nullptr);
  EXPECT_EQ(b.at_or_before->value, 0);
  EXPECT_EQ(b.after->value, 1);
  b = h.bracket(2.0);  // exactly on a sample: that one, then the next
  ASSERT_NE(b.at_or_before, nullptr);
  ASSERT_NE(b.after, nullptr);
  EXPECT_EQ(b.at_or_before->stamp_s, 2.0);
  EXPECT_EQ(b.at_or_before->value, 1);
  EXPECT_EQ(b.after->value, 2);
  b = h.bracket(1.0);  // exactly on the first
  ASSERT_NE(b.at_or_before, nullptr);
  EXPECT_EQ(b.at_or_before->value, 0);
  b = h.bracket(3.0);  // exactly on the last: nothing after it
  ASSERT_NE(b.at_or_before, nullptr);
  EXPECT_EQ(b.at_or_before->value, 2);
  EXPECT_EQ(b.after, nullptr);
  b = h.bracket(3.5);  // after the last
  ASSERT_NE(b.at_or_before, nullptr);
  EXPECT_EQ(b.at_or_before->value, 2);
  EXPECT_EQ(b.after, nullptr);
}

TEST(StampedHistory, BracketsNothingWhenEmptyOrTheStampIsNaN) {
  const History empty(1.0);
  EXPECT_TRUE(empty.empty());
  EXPECT_EQ(empty.bracket(1.0).at_or_before, nullptr);
  EXPECT_EQ(empty.bracket(1.0).after, nullptr);
  const History h = filled({1.0, 2.0});
  EXPECT_FALSE(h.empty());
  const auto b = h.bracket(std::numeric_limits<double>::quiet_NaN());
  EXPECT_EQ(b.at_or_before, nullptr);
  EXPECT_EQ(b.after, nullptr);
}

TEST(StampedHistory, KeepsEqualStampsInTheOrderTheyCame) {
  const History h = filled({1.0, 2.0, 2.0, 2.0, 3.0});
  EXPECT_EQ(h.size(), 5u);
  auto b = h.bracket(2.0);  // on the stamp: the last that came with it, then the next stamp
  ASSERT_NE(b.at_or_before, nullptr);
  ASSERT_NE(b.after, nullptr);
  EXPECT_EQ(b.at_or_before->value, 3);
  EXPECT_EQ(b.after->value, 4);
  b = h.bracket(1.5);  // just before them: the first that came with it
  ASSERT_NE(b.after, nullptr);
  EXPECT_EQ(b.after->value, 1);
  b = h.bracket(2.5);
  ASSERT_NE(b.at_or_before, nullptr);
  EXPECT_EQ(b.at_or_before->value, 3);
}

}  // namespace
}  // namespace icanc
