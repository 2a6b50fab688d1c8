// Headlight energy accounting (paper Section V-D "Energy Conservation"): energy = lamp watts x
// hours on, for the paper's lamp table, its three cases of a 22-minute night drive, and for the
// lamp on-time measured from a sequence of lamp states (e.g. icanc/LightState from a bag).
//
// The paper's numbers and how they arise (Fig. "energy consumed", Table "wattage"):
//   worst   always on for the drive: 22 min = 0.36667 h, written 0.366 h (truncated);
//           1.5 / 25 / 65 W x 0.366 h = 0.549 / 9.15 / 23.79 Wh (flashlight / LED / halogen).
//   average on for the fraction of the drive the Monte Carlo gives ("approximately 21 %",
//           assuming one random object per second): 0.21 x 1320 s = 277.2 s, written
//           "4 minutes and 37 seconds, or .077 hours" (277 s = 0.07694 h, rounded);
//           0.077 h -> 0.1155 / 1.925 / 5.005 Wh. With the unrounded Monte Carlo fraction 0.2118
//           the same steps give 280 s = 0.078 h; exactly, 0.2118 x 0.36667 h = 0.07766 h.
//   best    47 dangerous objects counted on the drive, each lighting the lamp for tau = 3 s:
//           141 s = 0.03917 h, written 0.039 h -> 0.0585 / 0.975 / 2.535 Wh.
// HoursRounding::kPaper reproduces those steps (hours to three decimals, the drive truncated,
// the others rounded, the average's seconds rounded to whole seconds first); kExact keeps every
// value unrounded.
#pragma once

#include <cstddef>
#include <map>
#include <string>
#include <vector>

namespace icanc {

struct Lamp {
  std::string name;          // key, e.g. "led"
  std::string label;         // for tables and plots, e.g. "LED"
  double high_beam_w = 0.0;  // > 0
  double low_beam_w = 0.0;   // 0 when the lamp has no low beam (the Goreit flashlight)
};
using LampCatalogue = std::vector<Lamp>;

// The paper's Table "wattage": Goreit flashlight 1.5 W (high only), LED 15 / 25 W, halogen
// 55 / 65 W (low / high beam), in the order of the paper's figure.
LampCatalogue paperLampCatalogue();

// Adds the lamps of a YAML file to `base`, a lamp of the same name replacing the base's in place,
// new ones appended in file order. Format:
//   lamps:
//     - {name: led, label: LED, low_beam_w: 15, high_beam_w: 25}
//     - {name: xenon_hid, label: Xenon HID, high_beam_w: 35}   # low_beam_w optional, label too
// Throws std::runtime_error naming the file, the entry and the problem: unreadable YAML, no
// `lamps` list, an entry without a name or high_beam_w, a non-number, a wattage <= 0 (low beam
// < 0), an unknown key, a name given twice.
LampCatalogue loadLampCatalogue(const std::string& path,
                                const LampCatalogue& base = paperLampCatalogue());

// The lamp called `name`; throws std::out_of_range listing the known names.
const Lamp& findLamp(const LampCatalogue& catalogue, const std::string& name);

enum class Beam { kHigh, kLow };
const char* toString(Beam beam);
// The lamp's wattage on that beam; throws std::invalid_argument when it has none.
double lampWatts(const Lamp& lamp, Beam beam);

// Wh = W x h.
inline double wattHours(double watts, double hours) { return watts * hours; }

// The paper's drive (Section V-D).
struct DriveScenario {
  double drive_s = 22.0 * 60.0;  // Newark to Wilmington near midnight, 22 minutes
  double danger_fraction = 0.21; // average case: fraction of objects deemed dangerous (paper 21 %)
  int dangerous_objects = 47;    // best case: objects counted as dangerous on the drive
  double tau_s = 3.0;            // best case: light timer per object (objects > tau apart)
};
std::string validate(const DriveScenario& scenario);

enum class HoursRounding { kExact, kPaper };

struct DriveCase {
  std::string name;      // "worst", "average", "best"
  double on_s = 0.0;     // lamp on-time [s] before any rounding to hours
  double on_hours = 0.0; // what the energy is computed with (rounded per HoursRounding)
};

// The three cases, worst (always on) / average (danger_fraction of the drive) / best
// (dangerous_objects x tau, at most the drive). Throws std::invalid_argument on a bad scenario.
std::vector<DriveCase> driveCases(const DriveScenario& scenario, HoursRounding rounding);

struct EnergyRow {
  std::string lamp, label, case_name;
  double watts = 0.0;
  double on_hours = 0.0;
  double wh = 0.0;
  double saving_wh = 0.0;    // against the first case (the worst case: always on)
  double saving_pct = 0.0;
};

// One row per lamp and case (lamps outer, in catalogue order), on the given beam; lamps without
// that beam are skipped.
std::vector<EnergyRow> energyTable(const LampCatalogue& catalogue,
                                   const std::vector<DriveCase>& cases, Beam beam);

// ---- Measured on-time from lamp states --------------------------------------------------------

// The lamp state from time t_s on (until the next sample). `reason` is free for the caller
// (icanc/LightState's REASON_* codes in the tools).
struct LampSample {
  double t_s = 0.0;
  bool on = false;
  int reason = 0;
};

struct OnTime {
  double on_s = 0.0;      // total time on
  double span_s = 0.0;    // first sample to end_s: the always-on baseline
  double duty = 0.0;      // on_s / span_s (0 for an empty span)
  bool on_at_end = false; // the last state is on (counted up to end_s)
  std::size_t switches_on = 0;            // off -> on transitions (the first sample on counts)
  std::map<int, double> on_s_by_reason;   // on-time split by the reason of each on sample
};

// Integrates the piecewise-constant lamp state: each sample's state lasts until the next sample,
// the last one until end_s (a lamp still on at the end counts until then; an end_s earlier than
// the last sample is taken as the last sample's time). Throws std::invalid_argument when times decrease or are not finite.
OnTime integrateOnTime(const std::vector<LampSample>& samples, double end_s);

// Throws std::invalid_argument when the sample times decrease or are not finite, or end_s is not
// finite (the checks of integrateOnTime, shared with the segment lamp's integration).
void checkSampleTimes(const std::vector<double>& times, double end_s);

}  // namespace icanc
