// Pins the segmented lamp's energy: the paper's 22-minute drive with an 8-segment 25 W
// LED lamp, best case, below the paper's binary LED best case (0.975 Wh), by the same rounding;
// and the measured integration of LampCommand levels.
#include <gtest/gtest.h>

#include "icanc/core/evaluation/segment_energy.hpp"

namespace icanc {
namespace {

const EnergyRow& row(const std::vector<EnergyRow>& rows, const std::string& lamp, const std::string& c) {
  for (const auto& r : rows)
    if (r.lamp == lamp && r.case_name == c) return r;
  throw std::out_of_range(lamp + " " + c);
}

TEST(SegmentEnergy, EightSegmentLedBestCaseBelowThePapers0975Wh) {
  const auto cases = driveCases(DriveScenario(), HoursRounding::kPaper);
  const auto binary = energyTable(paperLampCatalogue(), cases, Beam::kHigh);
  EXPECT_NEAR(row(binary, "led", "best").wh, 0.975, 1e-9);  // the paper's figure
  // 8 x 3.125 W; each dangerous object lights 2 adjacent segments (docs/segmented_lamp.md).
  const auto seg = segmentedEnergyTable(paperLampCatalogue(), cases, Beam::kHigh, 8, 2);
  const EnergyRow& best = row(seg, "led", "best");
  EXPECT_NEAR(best.wh, 0.039 * 2 * 3.125, 1e-9);  // 0.24375 Wh
  EXPECT_LT(best.wh, 0.975);
  EXPECT_NEAR(row(seg, "led", "average").wh, 0.077 * 2 * 3.125, 1e-9);
  EXPECT_NEAR(row(seg, "led", "worst").wh, 9.15, 1e-9);  // always on: every segment
  EXPECT_NEAR(best.saving_pct, 100.0 * (9.15 - 0.24375) / 9.15, 1e-9);
  // One segment lit per object: an eighth of the binary lamp.
  EXPECT_NEAR(row(segmentedEnergyTable(paperLampCatalogue(), cases, Beam::kHigh, 8, 1), "led", "best").wh,
              0.975 / 8.0, 1e-9);
}

TEST(SegmentEnergy, AllSegmentsLitIsTheBinaryLamp) {
  const auto cases = driveCases(DriveScenario(), HoursRounding::kExact);
  const auto binary = energyTable(paperLampCatalogue(), cases, Beam::kHigh);
  const auto seg = segmentedEnergyTable(paperLampCatalogue(), cases, Beam::kHigh, 4, 9);
  ASSERT_EQ(binary.size(), seg.size());
  for (std::size_t i = 0; i < seg.size(); ++i) EXPECT_DOUBLE_EQ(seg[i].wh, binary[i].wh);
  EXPECT_THROW(segmentedEnergyTable(paperLampCatalogue(), cases, Beam::kHigh, 0, 1), std::invalid_argument);
}

TEST(SegmentEnergy, IntegratesLevelsTimesWatts) {
  const std::vector<double> watts{3.0, 3.0, 6.0};
  const std::vector<LevelSample> samples{
      {0.0, {0.0f, 0.0f, 0.0f}},
      {10.0, {1.0f, 0.0f, 0.0f}},   // 3 W for 10 s
      {20.0, {0.5f, 0.0f, 1.0f}},   // 7.5 W for 10 s
      {30.0, {1.0f}},               // a fault command: all on, 12 W for 10 s
      {40.0, {0.0f, 0.0f, 0.0f}}};
  const SegmentEnergy e = integrateSegmentEnergy(samples, 50.0, watts);
  EXPECT_NEAR(e.wh, (30.0 + 75.0 + 120.0) / 3600.0, 1e-12);
  EXPECT_NEAR(e.wh_all_on, 12.0 * 50.0 / 3600.0, 1e-12);
  EXPECT_DOUBLE_EQ(e.span_s, 50.0);
  EXPECT_DOUBLE_EQ(e.any_on_s, 30.0);
  // One segment at 0 / 1 is the binary lamp's on-time.
  const std::vector<LevelSample> one{{0.0, {1.0f}}, {2.0, {0.0f}}, {5.0, {1.0f}}};
  const OnTime t = integrateOnTime({{0.0, true}, {2.0, false}, {5.0, true}}, 6.0);
  EXPECT_NEAR(integrateSegmentEnergy(one, 6.0, {25.0}).wh, wattHours(25.0, t.on_s / 3600.0), 1e-12);
  EXPECT_THROW(integrateSegmentEnergy({{1.0, {1.0f}}, {0.5, {1.0f}}}, 2.0, {1.0}), std::invalid_argument);
  EXPECT_THROW(integrateSegmentEnergy(one, 6.0, {}), std::invalid_argument);
}

}  // namespace
}  // namespace icanc
