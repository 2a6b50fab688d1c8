// The DangerDetector's planned-path parameters: out-of-range values stop the nodelet at
// load with a message naming the key (PlannedPathSource::validate), as every other parameter.
#include <limits>

#include <gtest/gtest.h>

#include "icanc/ros/planned_path_source.hpp"

namespace icanc {
namespace {

TEST(PlannedPathParams, TheDefaultsAreValid) {
  EXPECT_EQ(PlannedPathSource::validate(PlannedPathSource::Params()), "");
}

TEST(PlannedPathParams, AgesAndOffsetsOutOfRangeNameTheirKey) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (double bad : {0.0, -1.0, 10.5, nan}) {
    PlannedPathSource::Params p;
    p.max_age_s = bad;
    EXPECT_NE(PlannedPathSource::validate(p).find("path_max_age_s"), std::string::npos) << bad;
    p = PlannedPathSource::Params();
    p.max_offset_m = bad;
    EXPECT_NE(PlannedPathSource::validate(p).find("path_max_offset_m"), std::string::npos) << bad;
  }
}

}  // namespace
}  // namespace icanc
