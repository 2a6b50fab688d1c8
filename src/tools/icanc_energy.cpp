// icanc_energy: headlight energy (paper Section V-D). Wh = lamp watts x hours on.
//
// Paper cases (default): the paper's 22-minute drive, worst (always on) / average (on for the
// Monte Carlo danger fraction of the drive) / best (47 dangerous objects x tau = 3 s), for every
// lamp of the catalogue, twice: as the paper rounds (fraction 21 %, hours to three decimals: the
// numbers of its energy figure) and exactly (the fraction from a Monte Carlo run, unrounded).
//
//   icanc_energy [--lamps config/lamps.yaml] [--beam high|low] [--drive-min 22] [--objects 47]
//                [--tau 3] [--danger-fraction F] [--seed 1] [--csv out.csv]
//
// --danger-fraction replaces the Monte Carlo run for the exact table (the paper table always uses
// the paper's 0.21).
//
// Segmented lamp (docs/segmented_lamp.md): beside each table, every lamp split evenly
// into --segments N (8) segments, each dangerous object lighting --segments-lit K (2) of them in
// the average and best cases (the worst case is every segment always on). --csv writes them too,
// after the binary rows (columns segments, segments_lit: 1, 1 for the binary lamp).
//
// From a bag: the lamp's actual on-time from icanc/LightState messages (header stamps; each state
// holds until the next message), Wh per lamp and the saving against always-on over the same span.
//
//   icanc_energy --bag BAG [--topic /icanc/light_state] [--lamps FILE] [--beam high] [--csv out.csv]
//
// A bag from icanc_sim_bag holds only the clouds: record the replay's light states, e.g.
//   rosbag record -O run.bag /icanc/light_state   (while roslaunch icanc replay.launch bag:=...)
// or use scripts/utilisation, which records them. When the bag also holds icanc/LampCommand on
// --lamp-topic (/icanc/lamp_command), the segmented lamp's Wh beside the binary lamp's: each
// catalogue lamp split evenly over the command's segments, each segment watts x level.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include <rosbag/bag.h>
#include <rosbag/view.h>

#include "icanc/LampCommand.h"
#include "icanc/LightState.h"
#include "icanc/core/evaluation/energy.hpp"
#include "icanc/core/evaluation/segment_energy.hpp"
#include "icanc/core/evaluation/monte_carlo.hpp"

namespace {

void usage(std::FILE* out = stderr) {
  std::fprintf(out,
               "usage: icanc_energy [--lamps FILE] [--beam high|low] [--drive-min 22] [--objects 47]\n"
               "                    [--tau 3] [--danger-fraction F] [--seed 1] [--csv out.csv]\n"
               "                    [--segments 8] [--segments-lit 2]\n"
               "       icanc_energy --bag BAG [--topic /icanc/light_state] [--lamps FILE]\n"
               "                    [--lamp-topic /icanc/lamp_command] [--beam high|low] [--csv out.csv]\n");
}

double toDouble(const std::string& flag, const char* text) {
  char* end = nullptr;
  const double v = std::strtod(text, &end);
  if (end == text || *end != '\0') throw std::invalid_argument(flag + " wants a number, got '" + text + "'");
  return v;
}

std::size_t toCount(const std::string& flag, const char* text, double max) {
  const double v = toDouble(flag, text);
  if (!(v >= 1.0 && v <= max && v == std::floor(v)))
    throw std::invalid_argument(flag + " wants a whole number in [1, " + std::to_string(int(max)) + "]");
  return static_cast<std::size_t>(v);
}

struct Options {
  std::string lamps_path, csv_path, bag_path, topic = "/icanc/light_state";
  std::string lamp_topic = "/icanc/lamp_command";
  std::size_t segments = 8, segments_lit = 2;
  icanc::Beam beam = icanc::Beam::kHigh;
  icanc::DriveScenario drive;
  bool fraction_given = false;
  double fraction = 0.0;
  std::uint64_t seed = 1;
};

std::FILE* openCsv(const std::string& path) {
  std::FILE* f = std::fopen(path.c_str(), "w");
  if (!f) throw std::runtime_error("cannot write " + path);
  return f;
}

void printTable(const std::vector<icanc::EnergyRow>& rows, const char* hours_format) {
  std::printf("  %-20s %6s  %-8s %9s %10s %10s %8s\n", "lamp", "W", "case", "hours", "Wh",
              "saved Wh", "saved");
  for (const auto& r : rows) {
    char hours[32];
    std::snprintf(hours, sizeof(hours), hours_format, r.on_hours);
    std::printf("  %-20s %6g  %-8s %9s %10.4f %10.4f %7.1f%%\n", r.label.c_str(), r.watts,
                r.case_name.c_str(), hours, r.wh, r.saving_wh, r.saving_pct);
  }
}

int paperCases(const Options& o, const icanc::LampCatalogue& lamps) {
  icanc::DriveScenario paper = o.drive;
  paper.danger_fraction = 0.21;  // the paper's "approximately 21 %"
  const auto paper_cases = icanc::driveCases(paper, icanc::HoursRounding::kPaper);

  icanc::DriveScenario exact = o.drive;
  std::string fraction_source;
  if (o.fraction_given) {
    exact.danger_fraction = o.fraction;
    fraction_source = "given";
  } else {
    icanc::MonteCarloParams mc;  // the paper's configuration: n = 60, 1000 trials, alpha = 1
    mc.seed = o.seed;
    exact.danger_fraction = icanc::runMonteCarlo(mc).mean_of_averages;
    char text[96];
    std::snprintf(text, sizeof(text), "Monte Carlo, n = 60, 1000 trials, seed %llu",
                  static_cast<unsigned long long>(o.seed));
    fraction_source = text;
  }
  const auto exact_cases = icanc::driveCases(exact, icanc::HoursRounding::kExact);

  std::printf("Headlight energy, paper Section V-D: a %.4g-minute drive, %s beam\n",
              o.drive.drive_s / 60.0, icanc::toString(o.beam));
  std::printf("worst: always on; average: on for the danger fraction of the drive (one object a\n"
              "second); best: %d dangerous objects x tau = %g s\n\n", o.drive.dangerous_objects,
              o.drive.tau_s);

  const auto paper_rows = icanc::energyTable(lamps, paper_cases, o.beam);
  std::printf("As the paper computes it (fraction 0.21; hours to three decimals: %.0f s -> %.3f h, "
              "%.1f s -> %.0f s -> %.3f h, %.0f s -> %.3f h):\n",
              paper_cases[0].on_s, paper_cases[0].on_hours, paper_cases[1].on_s,
              std::round(paper_cases[1].on_s), paper_cases[1].on_hours, paper_cases[2].on_s,
              paper_cases[2].on_hours);
  printTable(paper_rows, "%.3f");

  const auto exact_rows = icanc::energyTable(lamps, exact_cases, o.beam);
  std::printf("\nExact (fraction %.4f, %s; hours unrounded):\n", exact.danger_fraction,
              fraction_source.c_str());
  printTable(exact_rows, "%.5f");

  std::printf("\nSegmented lamp: each lamp as %zu equal segments, %zu lit per dangerous "
              "object (worst: all always on)\n", o.segments, o.segments_lit);
  const auto seg_paper_rows = icanc::segmentedEnergyTable(lamps, paper_cases, o.beam, o.segments, o.segments_lit);
  const auto seg_exact_rows = icanc::segmentedEnergyTable(lamps, exact_cases, o.beam, o.segments, o.segments_lit);
  std::printf("As the paper rounds:\n");
  printTable(seg_paper_rows, "%.3f");
  std::printf("Exact:\n");
  printTable(seg_exact_rows, "%.5f");

  if (!o.csv_path.empty()) {
    // segments, segments_lit: 1, 1 for the binary lamp; the segmented rows beside it.
    std::FILE* f = openCsv(o.csv_path);
    std::fprintf(f, "rounding,lamp,label,beam,watts,case,danger_fraction,on_hours,wh,saving_wh,saving_pct,"
                    "segments,segments_lit\n");
    const auto dump = [&](const char* rounding, const std::vector<icanc::EnergyRow>& rows, double fraction,
                          std::size_t segments, std::size_t lit) {
      for (const auto& r : rows)
        std::fprintf(f, "%s,%s,%s,%s,%g,%s,%.6f,%.6f,%.6f,%.6f,%.3f,%zu,%zu\n", rounding, r.lamp.c_str(),
                     r.label.c_str(), icanc::toString(o.beam), r.watts, r.case_name.c_str(), fraction,
                     r.on_hours, r.wh, r.saving_wh, r.saving_pct, segments, lit);
    };
    dump("paper", paper_rows, paper.danger_fraction, 1, 1);
    dump("exact", exact_rows, exact.danger_fraction, 1, 1);
    dump("paper", seg_paper_rows, paper.danger_fraction, o.segments, o.segments_lit);
    dump("exact", seg_exact_rows, exact.danger_fraction, o.segments, o.segments_lit);
    std::fclose(f);
    std::printf("\nwrote %s\n", o.csv_path.c_str());
  }
  return 0;
}

// The segmented lamp's levels on o.lamp_topic, beside the binary lamp's on-time `binary`.
void segmentedFromBag(const Options& o, const rosbag::Bag& bag, const icanc::LampCatalogue& lamps,
                      const icanc::OnTime& binary) {
  rosbag::View view(bag, rosbag::TopicQuery(std::vector<std::string>{o.lamp_topic}));
  std::vector<icanc::LevelSample> samples;
  std::size_t segments = 0;
  for (const rosbag::MessageInstance& m : view) {
    const icanc::LampCommand::ConstPtr c = m.instantiate<icanc::LampCommand>();
    if (!c) throw std::runtime_error(o.lamp_topic + " in " + o.bag_path + " is not icanc/LampCommand");
    const double t = c->header.stamp.isZero() ? m.getTime().toSec() : c->header.stamp.toSec();
    samples.push_back({t, c->levels});
    if (c->reason != icanc::LightState::REASON_FAULT && !segments) segments = c->levels.size();
  }
  if (samples.empty()) {
    std::printf("\n(no icanc/LampCommand on %s: no segmented lamp in this bag)\n", o.lamp_topic.c_str());
    return;
  }
  if (!segments) segments = samples.front().levels.size();
  const icanc::SegmentEnergy e0 =
      icanc::integrateSegmentEnergy(samples, samples.back().t_s, std::vector<double>(segments, 1.0));
  std::printf("\nSegmented lamp from %s (%zu commands, %zu segments): any segment on %.2f s; "
              "lit segment-seconds %.2f of %.2f\n", o.lamp_topic.c_str(), samples.size(), segments,
              e0.any_on_s, e0.wh * 3600.0, e0.wh_all_on * 3600.0);
  std::printf("  %-20s %6s %12s %14s %10s\n", "lamp", "W", "Wh binary", "Wh segmented", "ratio");
  for (const auto& lamp : lamps) {
    const double w = o.beam == icanc::Beam::kHigh ? lamp.high_beam_w : lamp.low_beam_w;
    if (!(w > 0.0)) continue;
    const double binary_wh = icanc::wattHours(w, binary.on_s / 3600.0);
    const double seg_wh = icanc::integrateSegmentEnergy(samples, samples.back().t_s,
                                                        std::vector<double>(segments, w / segments)).wh;
    std::printf("  %-20s %6g %12.5f %14.5f %9.1f%%\n", lamp.label.c_str(), w, binary_wh, seg_wh,
                binary_wh > 0.0 ? 100.0 * seg_wh / binary_wh : 0.0);
  }
}

int fromBag(const Options& o, const icanc::LampCatalogue& lamps) {
  rosbag::Bag bag(o.bag_path, rosbag::bagmode::Read);
  rosbag::View view(bag, rosbag::TopicQuery(std::vector<std::string>{o.topic}));
  std::vector<icanc::LampSample> samples;
  for (const rosbag::MessageInstance& m : view) {
    const icanc::LightState::ConstPtr s = m.instantiate<icanc::LightState>();
    if (!s) throw std::runtime_error(o.topic + " in " + o.bag_path + " is not icanc/LightState");
    const double t = s->header.stamp.isZero() ? m.getTime().toSec() : s->header.stamp.toSec();
    samples.push_back({t, bool(s->on), int(s->reason)});
  }
  if (samples.empty()) {
    rosbag::View all(bag);
    std::set<std::string> topics;
    for (const auto* c : all.getConnections()) topics.insert(c->topic);
    std::string list;
    for (const auto& t : topics) list += " " + t;
    throw std::runtime_error("no icanc/LightState on " + o.topic + " in " + o.bag_path +
                             " (topics:" + (list.empty() ? " none" : list) +
                             "). A bag from icanc_sim_bag holds only the clouds: record the replay's "
                             "light_state, e.g. with scripts/utilisation.");
  }
  const icanc::OnTime t = icanc::integrateOnTime(samples, samples.back().t_s);

  std::printf("Lamp on-time from %s (%s, %zu states)\n", o.bag_path.c_str(), o.topic.c_str(),
              samples.size());
  std::printf("  span          %.2f s (first to last state, header stamps)\n", t.span_s);
  std::printf("  on            %.2f s, duty cycle %.1f %%, switched on %zu times%s\n", t.on_s,
              100.0 * t.duty, t.switches_on, t.on_at_end ? ", on at the end" : "");
  const auto reason = [&](int r) {
    const auto it = t.on_s_by_reason.find(r);
    return it == t.on_s_by_reason.end() ? 0.0 : it->second;
  };
  std::printf("  on for danger %.2f s; fail-safe (sensor stale / no input yet) %.2f s\n",
              reason(icanc::LightState::REASON_DANGER), reason(icanc::LightState::REASON_SENSOR_STALE));

  std::printf("\n  %-20s %6s %12s %14s %10s %8s %16s\n", "lamp", "W", "Wh on-time", "Wh always-on",
              "saved Wh", "saved", "22-min drive Wh");
  std::FILE* f = o.csv_path.empty() ? nullptr : openCsv(o.csv_path);
  if (f)
    std::fprintf(f, "lamp,label,beam,watts,span_s,on_s,danger_on_s,duty,wh,wh_always_on,saving_wh,saving_pct\n");
  for (const auto& lamp : lamps) {
    const double w = o.beam == icanc::Beam::kHigh ? lamp.high_beam_w : lamp.low_beam_w;
    if (!(w > 0.0)) continue;
    const double wh = icanc::wattHours(w, t.on_s / 3600.0);
    const double always = icanc::wattHours(w, t.span_s / 3600.0);
    const double saved = always - wh;
    const double pct = always > 0.0 ? 100.0 * saved / always : 0.0;
    // The same duty cycle over the paper's drive, for comparison with its three cases.
    const double drive_wh = icanc::wattHours(w, t.duty * o.drive.drive_s / 3600.0);
    std::printf("  %-20s %6g %12.5f %14.5f %10.5f %7.1f%% %16.4f\n", lamp.label.c_str(), w, wh,
                always, saved, pct, drive_wh);
    if (f)
      std::fprintf(f, "%s,%s,%s,%g,%.4f,%.4f,%.4f,%.5f,%.6f,%.6f,%.6f,%.3f\n", lamp.name.c_str(),
                   lamp.label.c_str(), icanc::toString(o.beam), w, t.span_s, t.on_s,
                   reason(icanc::LightState::REASON_DANGER), t.duty, wh, always, saved, pct);
  }
  if (f) {
    std::fclose(f);
    std::printf("\nwrote %s\n", o.csv_path.c_str());
  }
  segmentedFromBag(o, bag, lamps, t);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  try {
    for (int i = 1; i < argc; ++i) {
      const std::string a = argv[i];
      if (a == "-h" || a == "--help") { usage(stdout); return 0; }
      if (i + 1 >= argc) throw std::invalid_argument("unknown argument or missing value: " + a);
      const char* v = argv[++i];
      if (a == "--lamps") o.lamps_path = v;
      else if (a == "--csv") o.csv_path = v;
      else if (a == "--bag") o.bag_path = v;
      else if (a == "--topic") o.topic = v;
      else if (a == "--lamp-topic") o.lamp_topic = v;
      else if (a == "--segments") o.segments = toCount(a, v, 32);
      else if (a == "--segments-lit") o.segments_lit = toCount(a, v, 32);
      else if (a == "--drive-min") o.drive.drive_s = 60.0 * toDouble(a, v);
      else if (a == "--objects") o.drive.dangerous_objects = int(toDouble(a, v));
      else if (a == "--tau") o.drive.tau_s = toDouble(a, v);
      else if (a == "--seed") o.seed = std::uint64_t(toDouble(a, v));
      else if (a == "--danger-fraction") { o.fraction = toDouble(a, v); o.fraction_given = true; }
      else if (a == "--beam") {
        const std::string b = v;
        if (b == "high") o.beam = icanc::Beam::kHigh;
        else if (b == "low") o.beam = icanc::Beam::kLow;
        else throw std::invalid_argument("--beam is high or low, got '" + b + "'");
      } else {
        throw std::invalid_argument("unknown argument: " + a);
      }
    }
    const std::string why = icanc::validate(o.drive);
    if (!why.empty()) throw std::invalid_argument(why);
    if (o.fraction_given && !(o.fraction >= 0.0 && o.fraction <= 1.0))
      throw std::invalid_argument("--danger-fraction must be in [0, 1]");
  } catch (const std::exception& e) {
    std::fprintf(stderr, "icanc_energy: %s\n", e.what());
    usage();
    return 2;
  }
  try {
    const icanc::LampCatalogue lamps = o.lamps_path.empty()
        ? icanc::paperLampCatalogue()
        : icanc::loadLampCatalogue(o.lamps_path);
    return o.bag_path.empty() ? paperCases(o, lamps) : fromBag(o, lamps);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "icanc_energy: %s\n", e.what());
    return 1;
  }
}
