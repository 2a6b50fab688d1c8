// FaultGrowth: which fault kind grew since the last report names a diagnostics status.
// addCountsByKind: a count a kind as values of a status, and their sum.
#include <gtest/gtest.h>

#include "icanc/core/common/status_report.hpp"

namespace icanc {
namespace {

enum class Fault { kFirst, kSecond, kThird };

const char* toString(Fault f) {
  switch (f) {
    case Fault::kFirst: return "first";
    case Fault::kSecond: return "second";
    case Fault::kThird: return "third";
  }
  return "?";
}

TEST(FaultGrowth, TheFirstKindThatGrewSinceTheLastReportIsNamed) {
  FaultGrowth faults;
  EXPECT_EQ(faults.firstGrown({0, 0, 0}), -1);  // nothing yet
  EXPECT_EQ(faults.firstGrown({0, 2, 1}), 1);   // two grew: the first in order names it
  EXPECT_EQ(faults.firstGrown({0, 2, 1}), -1);  // none grew since: OK again
  EXPECT_EQ(faults.firstGrown({0, 2, 3}), 2);   // the counts of the last report were kept
  EXPECT_EQ(faults.firstGrown({5, 2, 3}), 0);
  EXPECT_EQ(faults.firstGrown({5, 2, 3}), -1);
}

TEST(AddCountsByKind, AddsAValueAKindInTheMapsOrderAndReturnsTheSum) {
  StatusReport stat;
  const std::map<Fault, std::uint64_t> counts = {{Fault::kThird, 4}, {Fault::kFirst, 2}};
  EXPECT_EQ(addCountsByKind(stat, "invalid clouds: ", counts), 6u);
  ASSERT_EQ(stat.values.size(), 2u);
  EXPECT_EQ(stat.values[0].first, "invalid clouds: first");
  EXPECT_EQ(stat.values[0].second, "2");
  EXPECT_EQ(stat.values[1].first, "invalid clouds: third");
  EXPECT_EQ(stat.values[1].second, "4");
  EXPECT_EQ(stat.value("invalid clouds: second"), "");  // a kind never counted: no value
  EXPECT_EQ(stat.level, StatusLevel::kOk);              // the summary is the caller's
}

TEST(AddCountsByKind, NoCountsAddNothingAndSumToZero) {
  StatusReport stat;
  EXPECT_EQ(addCountsByKind(stat, "x: ", std::map<Fault, std::uint64_t>()), 0u);
  EXPECT_TRUE(stat.values.empty());
}

}  // namespace
}  // namespace icanc
