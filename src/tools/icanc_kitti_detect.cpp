// icanc_kitti_detect: runs the ObstacleDetector (core library, no ROS) over a KITTI tracking
// sequence and prints frames per second, per-stage times, obstacles per frame and how many
// labelled objects a cluster found (a cluster centre inside the label box grown by 0.5 m; labels
// of Car/Van/Cyclist/Pedestrian within 40 m with at least 20 LiDAR points inside).
//
//   icanc_kitti_detect SEQUENCE_DIR [PROFILE.yaml] [--frames N]
// SEQUENCE_DIR holds velodyne/, label_02/ and calib/ (e.g. ../shared/data/kitti_tracking_0000).
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <string>
#include <vector>

#include "icanc/core/evaluation/kitti.hpp"
#include "icanc/core/perception/obstacle_detector.hpp"
#include "icanc/core/common/yaml_params.hpp"
#include "tool_help.hpp"

namespace {

double percentile(std::vector<double> v, double p) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<std::size_t>(p * (v.size() - 1) + 0.5))];
}

std::string frameName(const std::string& dir, int frame) {
  char name[64];
  std::snprintf(name, sizeof(name), "/velodyne/%06d.bin", frame);
  const std::string bin = dir + name;
  return std::ifstream(bin).good() ? bin : bin + ".xz";
}

}  // namespace

int main(int argc, char** argv) {
  const char* const usage = "usage: icanc_kitti_detect SEQUENCE_DIR [PROFILE.yaml] [--frames N]\n";
  if (icanc::tools::wantsHelp(argc, argv)) return icanc::tools::printUsage(usage, true);
  if (argc < 2) {
    return icanc::tools::printUsage(usage, false);
  }
  const std::string dir = argv[1];
  std::string profile_path;
  int max_frames = 1 << 30;
  for (int i = 2; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--frames" && i + 1 < argc) max_frames = std::atoi(argv[++i]);
    else profile_path = a;
  }
  try {
    icanc::ObstacleDetectorParams params;
    if (!profile_path.empty()) params = icanc::loadProfile(profile_path).detector;
    icanc::ObstacleDetector detector(params);
    const auto calib = icanc::kitti::readCalib(dir + "/calib/0000.txt");
    const auto boxes = icanc::kitti::toVelodyne(icanc::kitti::readLabels(dir + "/label_02/0000.txt"), calib);
    std::map<int, std::vector<icanc::kitti::VeloBox>> by_frame;
    for (const auto& b : boxes) by_frame[b.frame].push_back(b);

    std::vector<double> prep, ground, cluster, track, total;
    std::size_t frames = 0, detections = 0, confirmed = 0, labelled = 0, found = 0;
    std::map<std::string, std::pair<int, int>> per_type;  // found, labelled
    icanc::Cloud cloud;
    for (int f = 0; f < max_frames; ++f) {
      const std::string path = frameName(dir, f);
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

      for (const auto& label : by_frame[f]) {
        if (label.type != "Car" && label.type != "Van" && label.type != "Cyclist" &&
            label.type != "Pedestrian")
          continue;
        if (label.center.head<2>().norm() > 40.0) continue;
        int inside = 0;
        for (const auto& p : cloud) inside += icanc::kitti::contains(label, Eigen::Vector3d(p.x, p.y, p.z));
        if (inside < 20) continue;
        ++labelled;
        ++per_type[label.type].second;
        for (const auto& d : detector.detections()) {
          if (icanc::kitti::contains(label, d.center.cast<double>(), 0.5)) {
            ++found;
            ++per_type[label.type].first;
            break;
          }
        }
      }
    }
    if (frames == 0) {
      std::fprintf(stderr, "no velodyne frames in %s/velodyne\n", dir.c_str());
      return 1;
    }
    double sum = 0.0;
    for (double v : total) sum += v;
    std::printf("KITTI %s: %zu frames, profile %s\n", dir.c_str(), frames,
                profile_path.empty() ? "(defaults)" : profile_path.c_str());
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
    std::printf("labelled objects found: %zu of %zu (%.1f %%)\n", found, labelled,
                labelled ? 100.0 * found / labelled : 0.0);
    for (const auto& kv : per_type)
      std::printf("  %-10s %d of %d\n", kv.first.c_str(), kv.second.first, kv.second.second);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "icanc_kitti_detect: %s\n", e.what());
    return 1;
  }
  return 0;
}
