// icanc_kitti_detect: runs the ObstacleDetector (core library, no ROS) over a KITTI tracking
// sequence and prints frames per second, per-stage times, obstacles per frame, and the detection
// score of icanc::kitti::scoreFrame (the rule every tool uses): labelled objects found, precision
// in the labelled field of view, and how many labelled objects lie outside the detector's ROI
// (cropped before detection: missed whatever the method).
//
//   icanc_kitti_detect SEQUENCE_DIR [PROFILE.yaml] [--method classic|fast] [--frames N]
//                      [--boxes FILE.csv]
// SEQUENCE_DIR holds velodyne/, label_02/ and calib/ (e.g. ../shared/data/kitti_tracking_0000).
// --method overrides the profile's obstacle_detector/method; --boxes writes every detection of
// every frame (velodyne frame) as CSV.
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <string>
#include <vector>

#include "icanc/core/common/percentile.hpp"
#include "icanc/core/evaluation/kitti.hpp"
#include "icanc/core/evaluation/kitti_score.hpp"
#include "icanc/core/perception/obstacle_detector.hpp"
#include "icanc/core/common/yaml_params.hpp"
#include "tool_help.hpp"

namespace {

using icanc::percentile;

}  // namespace

int main(int argc, char** argv) {
  const char* const usage =
      "usage: icanc_kitti_detect SEQUENCE_DIR [PROFILE.yaml] [--method classic|fast] [--frames N] "
      "[--boxes FILE.csv]\n";
  if (icanc::tools::wantsHelp(argc, argv)) return icanc::tools::printUsage(usage, true);
  if (argc < 2) {
    return icanc::tools::printUsage(usage, false);
  }
  const std::string dir = argv[1];
  std::string profile_path, method, boxes_path;
  int max_frames = 1 << 30;
  for (int i = 2; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--frames" && i + 1 < argc) max_frames = std::atoi(argv[++i]);
    else if (a == "--method" && i + 1 < argc) method = argv[++i];
    else if (a == "--boxes" && i + 1 < argc) boxes_path = argv[++i];
    else if (a.rfind("--", 0) == 0) return icanc::tools::printUsage(usage, false);
    else profile_path = a;
  }
  try {
    icanc::ObstacleDetectorParams params;
    if (!profile_path.empty()) params = icanc::loadProfile(profile_path).detector;
    if (!method.empty()) {
      params.method = icanc::parseDetectorMethod(method);
      if (params.method == icanc::DetectorMethod::kInvalid) {
        std::fprintf(stderr, "icanc_kitti_detect: --method must be classic or fast (got '%s')\n",
                     method.c_str());
        return 2;
      }
    }
    icanc::ObstacleDetector detector(params);
    const auto calib = icanc::kitti::readCalib(dir + "/calib/0000.txt");
    const auto boxes = icanc::kitti::toVelodyne(icanc::kitti::readLabels(dir + "/label_02/0000.txt"), calib);
    std::map<int, std::vector<icanc::kitti::VeloBox>> by_frame;
    for (const auto& b : boxes) by_frame[b.frame].push_back(b);
    const Eigen::AlignedBox2d roi(params.prep.roi_min.head<2>().cast<double>(),
                                  params.prep.roi_max.head<2>().cast<double>());
    std::FILE* csv = nullptr;
    if (!boxes_path.empty()) {
      csv = std::fopen(boxes_path.c_str(), "w");
      if (!csv) {
        std::fprintf(stderr, "icanc_kitti_detect: cannot write %s\n", boxes_path.c_str());
        return 1;
      }
      std::fprintf(csv, "frame,x,y,z,length,width,height,yaw_rad,points\n");
    }

    std::vector<double> prep, ground, cluster, track, total;
    std::size_t frames = 0, detections = 0, confirmed = 0;
    icanc::kitti::DetectionScore score;
    icanc::Cloud cloud;
    for (int f = 0; f < max_frames; ++f) {
      const std::string path = icanc::kitti::velodynePath(dir, f);
      if (!std::ifstream(path).good()) break;
      icanc::kitti::readVelodyne(path, cloud);
      icanc::StageTimes t;
      detector.process(0.1 * f, cloud, &t);
      prep.push_back(t.prep_ms);
      ground.push_back(t.ground_ms);
      cluster.push_back(t.cluster_ms);
      track.push_back(t.track_ms);
      total.push_back(t.total_ms());
      ++frames;
      detections += detector.detections().size();
      for (const auto& tr : detector.tracks()) confirmed += tr.confirmed;
      score.add(icanc::kitti::scoreFrame(by_frame[f], cloud, detector.detections(), &roi));
      if (csv)
        for (const auto& d : detector.detections())
          std::fprintf(csv, "%d,%.3f,%.3f,%.3f,%.3f,%.3f,%.3f,%.4f,%d\n", f, d.center.x(), d.center.y(),
                       d.center.z(), d.size.x(), d.size.y(), d.size.z(), d.yaw, d.num_points);
    }
    if (csv) std::fclose(csv);
    if (frames == 0) {
      std::fprintf(stderr, "no velodyne frames in %s/velodyne\n", dir.c_str());
      return 1;
    }
    double sum = 0.0;
    for (double v : total) sum += v;
    std::printf("KITTI %s: %zu frames, profile %s, method %s\n", dir.c_str(), frames,
                profile_path.empty() ? "(defaults)" : profile_path.c_str(),
                icanc::toString(params.method));
    std::printf("stage        p50 ms   p99 ms\n");
    const auto row = [](const char* name, const std::vector<double>& v) {
      std::printf("%-10s %8.2f %8.2f\n", name, percentile(v, 0.5), percentile(v, 0.99));
    };
    row("prep", prep);
    row("ground", ground);
    row("cluster", cluster);
    row("track", track);
    row("total", total);
    std::printf("frames per second (detector only, mean): %.1f\n", 1000.0 * frames / sum);
    std::printf("clusters per frame: %.1f, confirmed tracks per frame: %.1f\n",
                double(detections) / frames, double(confirmed) / frames);
    std::printf("labelled objects found: %d of %d (%.1f %%)\n", score.foundTotal(),
                score.labelledTotal(), 100.0 * score.recall());
    for (const auto& kv : score.labelled) {
      const auto found = score.found.find(kv.first);
      const auto outside = score.outside_roi.find(kv.first);
      std::printf("  %-10s %d of %d (outside the ROI: %d)\n", kv.first.c_str(),
                  found == score.found.end() ? 0 : found->second, kv.second,
                  outside == score.outside_roi.end() ? 0 : outside->second);
    }
    std::printf("labelled objects outside the ROI (x %.1f..%.1f, y %.1f..%.1f m): %d of %d\n",
                roi.min().x(), roi.max().x(), roi.min().y(), roi.max().y(), score.outsideRoiTotal(),
                score.labelledTotal());
    std::printf("precision (detections ahead within 45 deg and 40 m inside a label box grown by "
                "0.5 m): %d of %d (%.1f %%)\n", score.correct, score.detections,
                100.0 * score.precision());
    if (csv) std::printf("boxes: %s\n", boxes_path.c_str());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "icanc_kitti_detect: %s\n", e.what());
    return 1;
  }
  return 0;
}
