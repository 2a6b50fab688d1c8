#include "icanc/core/evaluation/energy.hpp"

#include <algorithm>
#include <cmath>
#include <set>
#include <sstream>
#include <stdexcept>

#include <yaml-cpp/yaml.h>

namespace icanc {
namespace {

[[noreturn]] void fail(const std::string& where, const std::string& why) {
  throw std::runtime_error(where + ": " + why);
}

double readWatts(const YAML::Node& entry, const std::string& key, const std::string& where) {
  const YAML::Node node = entry[key];
  if (!node.IsScalar()) fail(where, key + " must be a number");
  double w = 0.0;
  try {
    w = node.as<double>();
  } catch (const YAML::Exception&) {
    fail(where, key + " must be a number (got '" + node.Scalar() + "')");
  }
  if (!std::isfinite(w)) fail(where, key + " must be finite");
  return w;
}

double hoursToThreeDecimals(double seconds, bool truncate) {
  const double thousandths = seconds / 3600.0 * 1000.0;
  // The small epsilon keeps values such as 0.5 h (500.0 thousandths) whole after the division.
  return (truncate ? std::floor(thousandths + 1e-9) : std::round(thousandths)) / 1000.0;
}

}  // namespace

LampCatalogue paperLampCatalogue() {
  return {
      {"goreit_flashlight", "Goreit flashlight", 1.5, 0.0},
      {"led", "LED", 25.0, 15.0},
      {"halogen", "Halogen", 65.0, 55.0},
  };
}

LampCatalogue loadLampCatalogue(const std::string& path, const LampCatalogue& base) {
  YAML::Node root;
  try {
    root = YAML::LoadFile(path);
  } catch (const YAML::Exception& e) {
    fail(path, e.what());
  }
  if (!root.IsMap() || !root["lamps"] || !root["lamps"].IsSequence())
    fail(path, "expected a map with a list 'lamps' of {name, label, high_beam_w, low_beam_w}");

  LampCatalogue catalogue = base;
  std::set<std::string> seen;
  const YAML::Node lamps = root["lamps"];
  for (std::size_t i = 0; i < lamps.size(); ++i) {
    std::string where = path + ": lamps[" + std::to_string(i) + "]";
    const YAML::Node entry = lamps[i];
    if (!entry.IsMap()) fail(where, "must be a map");
    for (const auto& kv : entry) {
      const std::string key = kv.first.as<std::string>();
      if (key != "name" && key != "label" && key != "high_beam_w" && key != "low_beam_w")
        fail(where, "unknown key '" + key + "' (name, label, high_beam_w, low_beam_w)");
    }
    if (!entry["name"] || !entry["name"].IsScalar() || entry["name"].Scalar().empty())
      fail(where, "needs a name");
    Lamp lamp;
    lamp.name = entry["name"].Scalar();
    where += " (" + lamp.name + ")";
    if (!seen.insert(lamp.name).second) fail(where, "name given twice");
    lamp.label = entry["label"] && entry["label"].IsScalar() ? entry["label"].Scalar() : lamp.name;
    if (!entry["high_beam_w"]) fail(where, "needs high_beam_w [W]");
    lamp.high_beam_w = readWatts(entry, "high_beam_w", where);
    if (!(lamp.high_beam_w > 0.0)) fail(where, "high_beam_w must be > 0");
    if (entry["low_beam_w"]) {
      lamp.low_beam_w = readWatts(entry, "low_beam_w", where);
      if (lamp.low_beam_w < 0.0) fail(where, "low_beam_w must be >= 0 (0: no low beam)");
    }
    auto it = std::find_if(catalogue.begin(), catalogue.end(),
                           [&](const Lamp& l) { return l.name == lamp.name; });
    if (it != catalogue.end())
      *it = lamp;
    else
      catalogue.push_back(lamp);
  }
  return catalogue;
}

const Lamp& findLamp(const LampCatalogue& catalogue, const std::string& name) {
  for (const auto& l : catalogue)
    if (l.name == name) return l;
  std::string known;
  for (const auto& l : catalogue) known += (known.empty() ? "" : ", ") + l.name;
  throw std::out_of_range("no lamp '" + name + "' (known: " + known + ")");
}

const char* toString(Beam beam) { return beam == Beam::kHigh ? "high" : "low"; }

double lampWatts(const Lamp& lamp, Beam beam) {
  const double w = beam == Beam::kHigh ? lamp.high_beam_w : lamp.low_beam_w;
  if (!(w > 0.0))
    throw std::invalid_argument("lamp '" + lamp.name + "' has no " + toString(beam) + " beam");
  return w;
}

std::string validate(const DriveScenario& s) {
  std::ostringstream why;
  if (!(s.drive_s > 0.0) || !std::isfinite(s.drive_s))
    why << "drive_s must be > 0 (got " << s.drive_s << ")";
  else if (!(s.danger_fraction >= 0.0 && s.danger_fraction <= 1.0))
    why << "danger_fraction must be in [0, 1] (got " << s.danger_fraction << ")";
  else if (s.dangerous_objects < 0)
    why << "dangerous_objects must be >= 0 (got " << s.dangerous_objects << ")";
  else if (!(s.tau_s >= 0.0) || !std::isfinite(s.tau_s))
    why << "tau_s must be >= 0 (got " << s.tau_s << ")";
  return why.str();
}

std::vector<DriveCase> driveCases(const DriveScenario& s, HoursRounding rounding) {
  const std::string why = validate(s);
  if (!why.empty()) throw std::invalid_argument("drive scenario: " + why);
  const bool paper = rounding == HoursRounding::kPaper;

  DriveCase worst{"worst", s.drive_s, s.drive_s / 3600.0};
  DriveCase average{"average", s.danger_fraction * s.drive_s, s.danger_fraction * s.drive_s / 3600.0};
  const double best_s = std::min(s.drive_s, s.dangerous_objects * s.tau_s);
  DriveCase best{"best", best_s, best_s / 3600.0};
  if (paper) {
    worst.on_hours = hoursToThreeDecimals(worst.on_s, /*truncate=*/true);    // 0.3667 -> 0.366
    average.on_hours = hoursToThreeDecimals(std::round(average.on_s), false); // 277 s -> 0.077
    best.on_hours = hoursToThreeDecimals(best.on_s, false);                   // 141 s -> 0.039
  }
  return {worst, average, best};
}

std::vector<EnergyRow> energyTable(const LampCatalogue& catalogue,
                                   const std::vector<DriveCase>& cases, Beam beam) {
  std::vector<EnergyRow> rows;
  for (const auto& lamp : catalogue) {
    const double w = beam == Beam::kHigh ? lamp.high_beam_w : lamp.low_beam_w;
    if (!(w > 0.0)) continue;
    const double baseline = cases.empty() ? 0.0 : wattHours(w, cases.front().on_hours);
    for (const auto& c : cases) {
      EnergyRow r;
      r.lamp = lamp.name;
      r.label = lamp.label;
      r.case_name = c.name;
      r.watts = w;
      r.on_hours = c.on_hours;
      r.wh = wattHours(w, c.on_hours);
      r.saving_wh = baseline - r.wh;
      r.saving_pct = baseline > 0.0 ? 100.0 * r.saving_wh / baseline : 0.0;
      rows.push_back(r);
    }
  }
  return rows;
}

void checkSampleTimes(const std::vector<double>& times, double end_s) {
  for (std::size_t k = 0; k < times.size(); ++k) {
    if (!std::isfinite(times[k]))
      throw std::invalid_argument("lamp sample " + std::to_string(k) + ": time is not finite");
    if (k > 0 && times[k] < times[k - 1]) {
      std::ostringstream why;
      why << "lamp sample " << k << ": time goes backwards (" << times[k - 1] << " s -> "
          << times[k] << " s)";
      throw std::invalid_argument(why.str());
    }
  }
  if (!std::isfinite(end_s)) throw std::invalid_argument("lamp samples: end time is not finite");
}

OnTime integrateOnTime(const std::vector<LampSample>& samples, double end_s) {
  OnTime out;
  if (samples.empty()) return out;
  std::vector<double> times;
  for (const LampSample& s : samples) times.push_back(s.t_s);
  checkSampleTimes(times, end_s);
  const double end = std::max(end_s, samples.back().t_s);
  bool was_on = false;
  for (std::size_t k = 0; k < samples.size(); ++k) {
    const LampSample& s = samples[k];
    if (s.on && !was_on) ++out.switches_on;
    was_on = s.on;
    if (!s.on) continue;
    const double until = k + 1 < samples.size() ? samples[k + 1].t_s : end;
    out.on_s += until - s.t_s;
    out.on_s_by_reason[s.reason] += until - s.t_s;
  }
  out.span_s = end - samples.front().t_s;
  out.duty = out.span_s > 0.0 ? out.on_s / out.span_s : 0.0;
  out.on_at_end = samples.back().on;
  return out;
}

}  // namespace icanc
