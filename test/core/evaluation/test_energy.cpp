// Pins the paper's energy accounting (Section V-D, Table "wattage", Fig. "energy consumed"): every
// number of the figure, the lamp catalogue and its YAML extension, and the on-time integration
// the bag report uses.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <stdexcept>
#include <string>

#include <unistd.h>

#include <gtest/gtest.h>

#include "icanc/core/evaluation/energy.hpp"

namespace icanc {
namespace {

std::string configDir() {
  const std::string here = __FILE__;
  return here.substr(0, here.rfind("/test/core/")) + "/config/";
}

// A YAML file in /tmp, removed at the end of the test.
class TempYaml {
 public:
  explicit TempYaml(const std::string& text) {
    char name[] = "/tmp/icanc_test_lamps_XXXXXX";
    const int fd = mkstemp(name);
    if (fd < 0) throw std::runtime_error("mkstemp failed");
    close(fd);
    path_ = name;
    std::ofstream(path_) << text;
  }
  ~TempYaml() { std::remove(path_.c_str()); }
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

double whOf(const std::vector<EnergyRow>& rows, const std::string& lamp, const std::string& c) {
  for (const auto& r : rows)
    if (r.lamp == lamp && r.case_name == c) return r.wh;
  ADD_FAILURE() << "no row " << lamp << " / " << c;
  return -1.0;
}

TEST(LampCatalogue, PapersWattageTable) {
  const LampCatalogue lamps = paperLampCatalogue();
  ASSERT_EQ(lamps.size(), 3u);
  EXPECT_EQ(lampWatts(findLamp(lamps, "led"), Beam::kLow), 15.0);
  EXPECT_EQ(lampWatts(findLamp(lamps, "led"), Beam::kHigh), 25.0);
  EXPECT_EQ(lampWatts(findLamp(lamps, "halogen"), Beam::kLow), 55.0);
  EXPECT_EQ(lampWatts(findLamp(lamps, "halogen"), Beam::kHigh), 65.0);
  EXPECT_EQ(lampWatts(findLamp(lamps, "goreit_flashlight"), Beam::kHigh), 1.5);
  EXPECT_THROW(lampWatts(findLamp(lamps, "goreit_flashlight"), Beam::kLow), std::invalid_argument);  // N/A
  EXPECT_THROW(findLamp(lamps, "xenon"), std::out_of_range);
}

TEST(DriveCases, PaperRoundingGivesThePapersHours) {
  const std::vector<DriveCase> c = driveCases(DriveScenario(), HoursRounding::kPaper);
  ASSERT_EQ(c.size(), 3u);
  EXPECT_EQ(c[0].name, "worst");
  EXPECT_EQ(c[1].name, "average");
  EXPECT_EQ(c[2].name, "best");
  EXPECT_DOUBLE_EQ(c[0].on_hours, 0.366);  // 22 min = 0.36667 h, the paper truncates
  EXPECT_DOUBLE_EQ(c[1].on_s, 277.2);      // 21 % of 1320 s: "4 minutes and 37 seconds"
  EXPECT_DOUBLE_EQ(c[1].on_hours, 0.077);
  EXPECT_DOUBLE_EQ(c[2].on_s, 141.0);      // 47 objects x 3 s
  EXPECT_DOUBLE_EQ(c[2].on_hours, 0.039);
}

TEST(DriveCases, ExactHoursAndTheMonteCarloFraction) {
  DriveScenario s;
  const std::vector<DriveCase> exact = driveCases(s, HoursRounding::kExact);
  EXPECT_NEAR(exact[0].on_hours, 22.0 / 60.0, 1e-15);
  EXPECT_NEAR(exact[1].on_hours, 0.21 * 22.0 / 60.0, 1e-15);
  EXPECT_NEAR(exact[2].on_hours, 141.0 / 3600.0, 1e-15);
  // The paper's steps with the unrounded Monte Carlo fraction give 280 s -> 0.078 h, not 0.077.
  s.danger_fraction = 0.2118;
  EXPECT_DOUBLE_EQ(driveCases(s, HoursRounding::kPaper)[1].on_hours, 0.078);
  // Best case never exceeds the drive.
  s.dangerous_objects = 1000;
  EXPECT_DOUBLE_EQ(driveCases(s, HoursRounding::kExact)[2].on_s, 1320.0);
  s = DriveScenario();
  s.danger_fraction = 1.5;
  EXPECT_THROW(driveCases(s, HoursRounding::kExact), std::invalid_argument);
  s = DriveScenario();
  s.drive_s = 0.0;
  EXPECT_THROW(driveCases(s, HoursRounding::kExact), std::invalid_argument);
}

TEST(EnergyTable, EveryNumberOfThePapersFigure) {
  const std::vector<EnergyRow> rows =
      energyTable(paperLampCatalogue(), driveCases(DriveScenario(), HoursRounding::kPaper), Beam::kHigh);
  ASSERT_EQ(rows.size(), 9u);
  const double tol = 1e-12;
  EXPECT_NEAR(whOf(rows, "goreit_flashlight", "worst"), 0.549, tol);
  EXPECT_NEAR(whOf(rows, "led", "worst"), 9.15, tol);
  EXPECT_NEAR(whOf(rows, "halogen", "worst"), 23.79, tol);
  EXPECT_NEAR(whOf(rows, "goreit_flashlight", "average"), 0.1155, tol);
  EXPECT_NEAR(whOf(rows, "led", "average"), 1.925, tol);
  EXPECT_NEAR(whOf(rows, "halogen", "average"), 5.005, tol);
  EXPECT_NEAR(whOf(rows, "goreit_flashlight", "best"), 0.0585, tol);
  EXPECT_NEAR(whOf(rows, "led", "best"), 0.975, tol);
  EXPECT_NEAR(whOf(rows, "halogen", "best"), 2.535, tol);
  // The text's savings for an LED headlight: 7.225 Wh (average, "21 % of the energy") and
  // 8.175 Wh (best, "approximately 10 %").
  for (const auto& r : rows) {
    if (r.lamp != "led") continue;
    if (r.case_name == "worst") {
      EXPECT_NEAR(r.saving_wh, 0.0, tol);
    }
    if (r.case_name == "average") {
      EXPECT_NEAR(r.saving_wh, 7.225, tol);
      EXPECT_NEAR(100.0 - r.saving_pct, 21.0, 0.1);
    }
    if (r.case_name == "best") {
      EXPECT_NEAR(r.saving_wh, 8.175, tol);
      EXPECT_NEAR(100.0 - r.saving_pct, 10.7, 0.1);
    }
  }
  // Low beam skips the flashlight, which has none.
  EXPECT_EQ(energyTable(paperLampCatalogue(), driveCases(DriveScenario(), HoursRounding::kPaper),
                        Beam::kLow).size(), 6u);
}

TEST(LampCatalogueYaml, ShippedCatalogueIsThePapersTable) {
  const LampCatalogue shipped = loadLampCatalogue(configDir() + "lamps.yaml", LampCatalogue());
  const LampCatalogue paper = paperLampCatalogue();
  ASSERT_EQ(shipped.size(), paper.size());
  for (std::size_t i = 0; i < paper.size(); ++i) {
    EXPECT_EQ(shipped[i].name, paper[i].name);
    EXPECT_EQ(shipped[i].label, paper[i].label);
    EXPECT_EQ(shipped[i].high_beam_w, paper[i].high_beam_w);
    EXPECT_EQ(shipped[i].low_beam_w, paper[i].low_beam_w);
  }
}

TEST(LampCatalogueYaml, AddsAndReplacesLamps) {
  const TempYaml file(
      "lamps:\n"
      "  - {name: xenon_hid, label: Xenon HID, low_beam_w: 35, high_beam_w: 35}\n"
      "  - {name: led, label: LED (dim), high_beam_w: 20}\n"
      "  - name: laser\n"
      "    high_beam_w: 12.5\n");
  const LampCatalogue lamps = loadLampCatalogue(file.path());
  ASSERT_EQ(lamps.size(), 5u);
  EXPECT_EQ(lamps[0].name, "goreit_flashlight");
  EXPECT_EQ(lamps[1].name, "led");  // replaced in place
  EXPECT_EQ(lamps[1].label, "LED (dim)");
  EXPECT_EQ(lamps[1].high_beam_w, 20.0);
  EXPECT_EQ(lamps[1].low_beam_w, 0.0);
  EXPECT_EQ(lamps[3].name, "xenon_hid");
  EXPECT_EQ(lamps[3].label, "Xenon HID");
  EXPECT_EQ(lamps[4].name, "laser");
  EXPECT_EQ(lamps[4].label, "laser");  // label defaults to the name
  const std::vector<EnergyRow> rows =
      energyTable(lamps, driveCases(DriveScenario(), HoursRounding::kPaper), Beam::kHigh);
  EXPECT_NEAR(whOf(rows, "xenon_hid", "worst"), 35 * 0.366, 1e-12);
  EXPECT_NEAR(whOf(rows, "led", "average"), 20 * 0.077, 1e-12);
}

void expectCatalogueError(const std::string& text, const std::string& needle) {
  const TempYaml file(text);
  try {
    loadLampCatalogue(file.path());
    ADD_FAILURE() << "accepted:\n" << text;
  } catch (const std::runtime_error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find(file.path()), std::string::npos) << what;
    EXPECT_NE(what.find(needle), std::string::npos) << "wanted '" << needle << "' in: " << what;
  }
}

TEST(LampCatalogueYaml, MalformedCataloguesAreRejectedWithFileAndEntry) {
  expectCatalogueError("lamps: [ {name: a, high_beam_w: 3}\n", "");  // YAML syntax
  expectCatalogueError("lamp:\n  - {name: a, high_beam_w: 3}\n", "list 'lamps'");
  expectCatalogueError("lamps: {name: a}\n", "list 'lamps'");
  expectCatalogueError("lamps:\n  - {label: A, high_beam_w: 3}\n", "lamps[0]: needs a name");
  expectCatalogueError("lamps:\n  - {name: a}\n", "lamps[0] (a): needs high_beam_w");
  expectCatalogueError("lamps:\n  - {name: a, high_beam_w: bright}\n", "high_beam_w must be a number");
  expectCatalogueError("lamps:\n  - {name: a, high_beam_w: 0}\n", "high_beam_w must be > 0");
  expectCatalogueError("lamps:\n  - {name: a, high_beam_w: 3, low_beam_w: -1}\n", "low_beam_w must be >= 0");
  expectCatalogueError("lamps:\n  - {name: a, high_beam_W: 3}\n", "unknown key 'high_beam_W'");
  expectCatalogueError("lamps:\n  - {name: a, high_beam_w: 3}\n  - {name: a, high_beam_w: 4}\n",
                       "lamps[1] (a): name given twice");
  expectCatalogueError("lamps:\n  - 42\n", "lamps[0]: must be a map");
  EXPECT_THROW(loadLampCatalogue("/nonexistent/lamps.yaml"), std::runtime_error);
}

TEST(OnTime, IntegratesThePiecewiseConstantState) {
  // off 0-2, on 2-5 (danger), off 5-7, on 7-8 (stale), off 8-10.
  const std::vector<LampSample> s = {
      {0.0, false, 0}, {1.0, false, 0}, {2.0, true, 1}, {3.0, true, 1}, {5.0, false, 0},
      {7.0, true, 2},  {8.0, false, 0}, {10.0, false, 0}};
  const OnTime t = integrateOnTime(s, 10.0);
  EXPECT_DOUBLE_EQ(t.on_s, 4.0);
  EXPECT_DOUBLE_EQ(t.span_s, 10.0);
  EXPECT_DOUBLE_EQ(t.duty, 0.4);
  EXPECT_FALSE(t.on_at_end);
  EXPECT_EQ(t.switches_on, 2u);
  EXPECT_DOUBLE_EQ(t.on_s_by_reason.at(1), 3.0);
  EXPECT_DOUBLE_EQ(t.on_s_by_reason.at(2), 1.0);
}

TEST(OnTime, LampStillOnAtTheEndCountsUntilTheEnd) {
  const std::vector<LampSample> s = {{100.0, false, 0}, {104.0, true, 1}, {104.5, true, 1}};
  const OnTime t = integrateOnTime(s, 110.0);
  EXPECT_DOUBLE_EQ(t.on_s, 6.0);
  EXPECT_DOUBLE_EQ(t.span_s, 10.0);
  EXPECT_TRUE(t.on_at_end);
  EXPECT_EQ(t.switches_on, 1u);
  // An end before the last sample ends at the last sample.
  EXPECT_DOUBLE_EQ(integrateOnTime(s, 0.0).on_s, 0.5);
  // Starting on counts as a switch-on; all on = duty 1.
  const OnTime all = integrateOnTime({{0.0, true, 2}, {2.0, true, 1}}, 4.0);
  EXPECT_DOUBLE_EQ(all.duty, 1.0);
  EXPECT_EQ(all.switches_on, 1u);
}

TEST(OnTime, EmptyAndInvalidSequences) {
  const OnTime none = integrateOnTime({}, 10.0);
  EXPECT_EQ(none.on_s, 0.0);
  EXPECT_EQ(none.span_s, 0.0);
  EXPECT_EQ(none.duty, 0.0);
  EXPECT_THROW(integrateOnTime({{2.0, true, 1}, {1.0, false, 0}}, 3.0), std::invalid_argument);
  EXPECT_THROW(integrateOnTime({{0.0, true, 1}, {std::nan(""), false, 0}}, 3.0), std::invalid_argument);
}

TEST(OnTime, MeasuredEnergyAgainstAlwaysOn) {
  // 10 min on of a 22-minute drive with an LED high beam.
  const OnTime t = integrateOnTime({{0.0, true, 1}, {600.0, false, 0}}, 1320.0);
  const double led = lampWatts(findLamp(paperLampCatalogue(), "led"), Beam::kHigh);
  EXPECT_NEAR(wattHours(led, t.on_s / 3600.0), 25.0 / 6.0, 1e-12);
  EXPECT_NEAR(wattHours(led, t.span_s / 3600.0), 25.0 * 22.0 / 60.0, 1e-12);
}

}  // namespace
}  // namespace icanc
