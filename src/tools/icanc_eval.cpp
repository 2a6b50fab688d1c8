// icanc_eval: replays a bag (clouds + /ground_truth, e.g. from icanc_sim_bag or icanc_kitti2bag)
// through the running icanc graph and prints the paper's metrics and more; writes JSON.
// Run it with launch/eval.launch, which starts the same graph as on the vehicle:
//   roslaunch icanc eval.launch bag:=X.bag vehicle:=zebra [json:=out.json] [fov_deg:=45] [rate:=0]
// Options: BAG [--points /points] [--truth /ground_truth] [--ns /icanc] [--rate R] [--fov DEG]
//          [--min-points N] [--match M] [--range M] [--json FILE] [--rows FILE.csv] [--name NAME]
// --rows writes every scored object-frame (outcome, truth, the detection that decided it) as CSV.
// --segments N (0: off) also replays the frames' dangerous boxes through an N-segment lamp over
// +-(--segment-span 120)/2 deg beside the binary lamp and prints its coverage and energy
// (icanc/segment_coverage.hpp; docs/segmented_lamp.md). The lamp sits where the profile puts it
// (light_controller/lamp_position_m, segment_margin_deg, low_beam_below_m of the running graph),
// and at base_link's origin too, one line each, when the profile puts it elsewhere;
// --segment-low-watts W (0: high beam only) also scores the same lamp with a low beam of W in all
// (the catalogue LED: 15 of its 25 W), one more line; --segment-dim-range R[,R...] (none: off)
// scores it dimmed by distance, each segment at (d / R)^2 of its watts for an object d from the
// lamp (at least the profile's min_level), one line per R. Each line also counts the truly
// dangerous object-frames the binary lamp was on for that lie outside the lamp's beam.
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

#include <ros/ros.h>

#include "icanc/core/evaluation/evaluation.hpp"
#include "icanc/core/evaluation/segment_coverage.hpp"
#include "icanc/ros/bag_replay.hpp"
#include "tool_help.hpp"

namespace {
const char* const kUsage =
    "usage: icanc_eval BAG [--points /points] [--truth /ground_truth] [--ns /icanc] [--rate R]\n"
    "                  [--fov DEG] [--min-points N] [--match M] [--range M] [--json FILE]\n"
    "                  [--rows FILE.csv] [--name NAME] [--segments N] [--segment-span DEG]\n"
    "                  [--segment-low-watts W] [--segment-dim-range R[,R...]]\n"
    "Replays BAG through a running icanc graph (launch/eval.launch starts both).\n";
}  // namespace

int main(int argc, char** argv) {
  // The arguments are checked before ros::init and the master: --help and bad usage answer at once.
  if (icanc::tools::wantsHelp(argc, argv)) return icanc::tools::printUsage(kUsage, true);
  std::vector<std::string> args;
  ros::removeROSArgs(argc, argv, args);
  if (args.size() < 2 || args.size() % 2 != 0 || args[1].rfind("--", 0) == 0) {
    return icanc::tools::printUsage(kUsage, false);
  }
  icanc::ReplayOptions replay;
  icanc::EvalParams params;
  replay.bag = args[1];
  std::string json, rows_csv, name = replay.bag.substr(replay.bag.rfind('/') + 1);
  int segments = 0;
  double segment_span_deg = 120.0, segment_low_watts = 0.0;
  std::vector<double> segment_dim_ranges;
  if (name.size() > 4 && name.compare(name.size() - 4, 4, ".bag") == 0) name.resize(name.size() - 4);
  for (std::size_t i = 2; i + 1 < args.size(); i += 2) {
    const std::string& k = args[i];
    const std::string& v = args[i + 1];
    if (k == "--points") replay.points_topic = v;
    else if (k == "--truth") replay.truth_topic = v;
    else if (k == "--ns") replay.ns = v;
    else if (k == "--rate") replay.rate = std::atof(v.c_str());
    else if (k == "--fov") params.fov_half_angle_deg = std::atof(v.c_str());
    else if (k == "--min-points") params.min_points = std::atoi(v.c_str());
    else if (k == "--match") params.match_distance_m = std::atof(v.c_str());
    else if (k == "--range") params.max_range_m = std::atof(v.c_str());
    else if (k == "--json") json = v;
    else if (k == "--rows") rows_csv = v;
    else if (k == "--name") name = v;
    else if (k == "--segments") segments = std::atoi(v.c_str());
    else if (k == "--segment-span") segment_span_deg = std::atof(v.c_str());
    else if (k == "--segment-low-watts") segment_low_watts = std::atof(v.c_str());
    else if (k == "--segment-dim-range") {
      for (std::size_t at = 0; at < v.size();) {
        const std::size_t comma = std::min(v.find(',', at), v.size());
        const double range = std::atof(v.substr(at, comma - at).c_str());
        if (range > 0.0) segment_dim_ranges.push_back(range);
        at = comma + 1;
      }
    }
    else {
      std::fprintf(stderr, "icanc_eval: unknown option %s\n", k.c_str());
      return icanc::tools::printUsage(kUsage, false);
    }
  }
  ros::init(argc, argv, "icanc_eval", ros::init_options::AnonymousName);
  ros::NodeHandle nh;
  ros::AsyncSpinner spinner(2);
  spinner.start();
  try {
    icanc::readGraphParams(replay.ns, params);  // light controller, danger detector
    const auto frames = icanc::replayBag(nh, replay);
    std::vector<icanc::ScoredRow> rows;
    const icanc::EvalReport report = icanc::evaluate(frames, params, &rows);
    std::printf("%s", icanc::toTable(report, name).c_str());
    std::fflush(stdout);
    if (!json.empty()) {
      std::ofstream(json) << icanc::toJson(report, name) << "\n";
      std::printf("wrote %s\n", json.c_str());
    }
    if (!rows_csv.empty()) {
      std::ofstream(rows_csv) << icanc::toCsv(rows);
      std::printf("wrote %s\n", rows_csv.c_str());
    }
    // The lamp where the profile puts it on high beam only; with --segment-low-watts, also with its
    // low beam; and, for comparison, at base_link's origin when the profile puts it elsewhere.
    struct Variant {
      bool at_origin;
      double low_watts;
      double dim_range_m;
    };
    std::vector<Variant> variants;
    if (segments > 0) {
      icanc::SegmentLampParams placed;
      icanc::readLampPlacement(replay.ns, placed);
      if (!placed.lamp_position_m.isZero()) variants.push_back({true, 0.0, 0.0});
      variants.push_back({false, 0.0, 0.0});
      if (segment_low_watts != 0.0) variants.push_back({false, segment_low_watts, 0.0});
      for (const double range : segment_dim_ranges) variants.push_back({false, 0.0, range});
    }
    for (const Variant& v : variants) {
      icanc::SegmentLampParams lamp =
          icanc::evenLamp(segments, segment_span_deg, icanc::kPaperLampWatts, v.low_watts);
      icanc::readLampPlacement(replay.ns, lamp);  // the profile's lamp position, margin, low-beam range
      if (v.at_origin) lamp.lamp_position_m.setZero();
      lamp.full_power_range_m = v.dim_range_m;
      const std::string why = icanc::validate(lamp);
      if (!why.empty()) throw std::invalid_argument("--segments/--segment-span/--segment-low-watts/--segment-dim-range: " + why);
      icanc::LightControllerParams light;
      light.tau_s = params.lamp_tau_s;
      light.recheck_below_s = params.lamp_recheck_below_s;
      const icanc::SegmentCoverage c = icanc::segmentCoverage(frames, light, lamp, params.min_points, &rows);
      std::printf("segmented lamp %s: %d segments over +-%.0f deg, lamp at (%.2f, %.2f) m%s, margin %.1f deg, "
                  "low beam %.3g W below %.3g m, dimmed to (d / %.3g m)^2 (0: not) from %.3g: coverage %zu / %zu "
                  "= %.4f of the binary lamp's dangerous object-frames in its beam (%zu outside it), of "
                  "those flagged dangerous %zu / %zu; energy %.6f / %.6f Wh = %.4f of the binary\n",
                  name.c_str(), segments, 0.5 * segment_span_deg, lamp.lamp_position_m.x(),
                  lamp.lamp_position_m.y(), v.at_origin ? " (base_link, for comparison)" : " (profile)",
                  lamp.segment_margin_deg, v.low_watts, lamp.low_beam_below_m, lamp.full_power_range_m,
                  lamp.min_level, c.covered_object_frames, c.binary_tp_object_frames, c.coverage,
                  c.outside_beam_object_frames, c.flagged_covered_object_frames, c.flagged_object_frames,
                  c.segmented_wh, c.binary_wh, c.energy_ratio);
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "icanc_eval: %s\n", e.what());
    ros::shutdown();
    return 1;
  }
  ros::shutdown();
  return 0;
}
