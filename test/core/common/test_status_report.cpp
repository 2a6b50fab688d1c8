// FaultGrowth: which fault kind grew since the last report names a diagnostics status.
#include <gtest/gtest.h>

#include "icanc/core/common/status_report.hpp"

namespace icanc {
namespace {

TEST(FaultGrowth, TheFirstKindThatGrewSinceTheLastReportIsNamed) {
  FaultGrowth faults;
  EXPECT_EQ(faults.firstGrown({0, 0, 0}), -1);  // nothing yet
  EXPECT_EQ(faults.firstGrown({0, 2, 1}), 1);   // two grew: the first in order names it
  EXPECT_EQ(faults.firstGrown({0, 2, 1}), -1);  // none grew since: OK again
  EXPECT_EQ(faults.firstGrown({0, 2, 3}), 2);   // the counts of the last report were kept
  EXPECT_EQ(faults.firstGrown({5, 2, 3}), 0);
  EXPECT_EQ(faults.firstGrown({5, 2, 3}), -1);
}

}  // namespace
}  // namespace icanc
