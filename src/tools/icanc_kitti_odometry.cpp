// icanc_kitti_odometry: checks the LiDAR odometry on KITTI without GPS. Runs
// LidarOdometry over a KITTI tracking sequence (velodyne frame = vehicle frame, 0.1 s per frame),
// puts every labelled object's centre into `odom` with the estimated poses and, for the labelled
// objects that do not move, reports how far their centre wanders in `odom`: per track the median
// and max distance from its median position, and the median over the tracks.
//
// Which objects do not move is decided from the labels alone, never from the poses under test:
// the distance between two objects that both stand still is the same in every frame whatever the
// vehicle does. A Car/Van/Truck track is static when, among the labelled tracks seen with it for
// at least --min-common frames, those at a constant distance (max deviation from the median
// distance <= --rigid-m) outnumber those whose distance changes, and there is at least one.
//
//   icanc_kitti_odometry [--kitti DIR] [--profile PROFILE.yaml] [--frames N] [--per-track]
//                        [--frame-below H]
// DIR defaults to ../shared/data/kitti_tracking_0000 (skipped with a message when absent);
// PROFILE to config/kitti_hdl64e.yaml (its lidar_odometry section). --frame-below H: the vehicle
// frame H metres below the sensor (1.73: on the road), the scans and ground_max_z_m moved with it:
// the voxel grids, laid from the vehicle frame, then meet the road elsewhere.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "icanc/core/common/percentile.hpp"
#include "icanc/core/common/planar_geometry.hpp"
#include "icanc/core/evaluation/kitti.hpp"
#include "icanc/core/motion/lidar_odometry.hpp"
#include "icanc/core/common/yaml_params.hpp"
#include "thread_cpu_time.hpp"

namespace {

using icanc::percentile;

using icanc::tools::threadCpuMs;

using Track = std::map<int, Eigen::Vector3d>;  // frame -> centre in the velodyne frame

// Tracks of parked objects, from the labels alone (see the file comment).
std::set<int> staticTracks(const std::map<int, Track>& tracks,
                           const std::map<int, std::string>& type, int min_common, double rigid_m) {
  std::set<int> out;
  for (const auto& a : tracks) {
    const std::string& t = type.at(a.first);
    if (t != "Car" && t != "Van" && t != "Truck") continue;
    int rigid = 0, moving = 0;
    for (const auto& b : tracks) {
      if (b.first == a.first) continue;
      std::vector<double> d;
      for (const auto& fa : a.second) {
        const auto fb = b.second.find(fa.first);
        if (fb != b.second.end()) d.push_back((fa.second - fb->second).head<2>().norm());
      }
      if (static_cast<int>(d.size()) < min_common) continue;
      const double med = percentile(d, 0.5);
      double dev = 0.0;
      for (double v : d) dev = std::max(dev, std::fabs(v - med));
      (dev <= rigid_m ? rigid : moving) += 1;
    }
    if (rigid > 0 && rigid > moving) out.insert(a.first);
  }
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  std::string dir = "../shared/data/kitti_tracking_0000";
  std::string profile = "config/kitti_hdl64e.yaml";
  int max_frames = 1 << 30, min_common = 5;
  double rigid_m = 0.5, frame_below = 0.0;
  bool per_track = false;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--kitti" && i + 1 < argc)
      dir = argv[++i];
    else if (a == "--profile" && i + 1 < argc)
      profile = argv[++i];
    else if (a == "--frames" && i + 1 < argc)
      max_frames = std::atoi(argv[++i]);
    else if (a == "--min-common" && i + 1 < argc)
      min_common = std::atoi(argv[++i]);
    else if (a == "--rigid-m" && i + 1 < argc)
      rigid_m = std::atof(argv[++i]);
    else if (a == "--per-track")
      per_track = true;
    else if (a == "--frame-below" && i + 1 < argc)
      frame_below = std::atof(argv[++i]);
    else {
      std::fprintf(stderr,
                   "usage: icanc_kitti_odometry [--kitti DIR] [--profile PROFILE.yaml] "
                   "[--frames N] [--min-common N] [--rigid-m M] [--per-track] [--frame-below H]\n");
      return 2;
    }
  }
  if (!std::ifstream(dir + "/calib/0000.txt").good()) {
    std::printf(
        "icanc_kitti_odometry: skipped, no KITTI sequence at %s "
        "(see ../shared/data/kitti_tracking_0000)\n",
        dir.c_str());
    return 0;
  }
  try {
    icanc::LidarOdometryParams params = icanc::loadProfile(profile).lidar_odometry;
    params.ground_max_z_m += frame_below;
    const float dz = static_cast<float>(frame_below);
    const Eigen::Vector3d shift(0.0, 0.0, frame_below);  // labels into the moved frame
    icanc::LidarOdometry odometry(params);
    const auto calib = icanc::kitti::readCalib(dir + "/calib/0000.txt");
    const auto boxes =
        icanc::kitti::toVelodyne(icanc::kitti::readLabels(dir + "/label_02/0000.txt"), calib);

    std::vector<Eigen::Isometry3d> poses;
    std::vector<double> ms, cpu_ms, down_ms, reg_ms, map_ms, iterations, reg_points, map_points, observability;
    icanc::Cloud cloud;
    double length = 0.0;
    for (int f = 0; f < max_frames; ++f) {
      const std::string path = icanc::kitti::velodynePath(dir, f);
      if (!std::ifstream(path).good()) break;
      icanc::kitti::readVelodyne(path, cloud);
      const double t0 = icanc::odometryNowMs(), c0 = threadCpuMs();
      const Eigen::Isometry3d pose = odometry.registerFrom(0.1 * f, [&](auto&& sink) {
        for (const auto& p : cloud) sink(p.x, p.y, p.z + dz);
      });
      ms.push_back(icanc::odometryNowMs() - t0);
      cpu_ms.push_back(threadCpuMs() - c0);
      const icanc::LidarOdometryStats& s = odometry.lastStats();
      down_ms.push_back(s.downsample_ms);
      reg_ms.push_back(s.register_ms);
      map_ms.push_back(s.map_ms);
      iterations.push_back(s.iterations);
      reg_points.push_back(static_cast<double>(s.registration_points));
      map_points.push_back(static_cast<double>(s.map_points));
      if (s.result == icanc::LidarOdometryStats::Result::kRegistered ||
          s.result == icanc::LidarOdometryStats::Result::kDegenerate)  // registration attempted
        observability.push_back(s.horizontal_observability);
      if (!poses.empty()) length += (pose.translation() - poses.back().translation()).norm();
      poses.push_back(pose);
    }
    const auto& c = odometry.counters();
    const Eigen::Vector3d end = poses.empty() ? Eigen::Vector3d(Eigen::Vector3d::Zero())
                                              : Eigen::Vector3d(poses.back().translation());
    const double yaw = poses.empty() ? 0.0 : icanc::yawOf(poses.back().linear());
    std::printf("icanc_kitti_odometry: %s, profile %s\n", dir.c_str(), profile.c_str());
    std::printf(
        "frames %llu: registered %llu, degenerate %llu, extrapolated %llu, resets %llu; "
        "wall ms per frame p50 %.2f p99 %.2f, thread CPU ms p50 %.2f p99 %.2f\n",
        static_cast<unsigned long long>(c.frames), static_cast<unsigned long long>(c.registered),
        static_cast<unsigned long long>(c.degenerate),
        static_cast<unsigned long long>(c.extrapolated), static_cast<unsigned long long>(c.resets),
        percentile(ms, 0.5), percentile(ms, 0.99), percentile(cpu_ms, 0.5),
        percentile(cpu_ms, 0.99));
    std::printf(
        "p50 per stage: downsample %.2f ms, registration %.2f ms, map %.2f ms; p50 "
        "iterations %.0f, registration points %.0f, map points %.0f\n",
        percentile(down_ms, 0.5), percentile(reg_ms, 0.5), percentile(map_ms, 0.5),
        percentile(iterations, 0.5), percentile(reg_points, 0.5), percentile(map_points, 0.5));
    std::printf("horizontal observability (frames registered or degenerate): min %.3f, p1 %.3f, p50 %.3f\n",
                percentile(observability, 0.0), percentile(observability, 0.01), percentile(observability, 0.5));
    std::printf("trajectory length %.2f m, end (%.2f, %.2f, %.2f) m, final yaw %.1f deg\n", length,
                end.x(), end.y(), end.z(), yaw * 180.0 / M_PI);

    std::map<int, Track> tracks;
    std::map<int, std::string> type;
    for (const auto& b : boxes) {
      if (b.frame >= static_cast<int>(poses.size())) continue;
      tracks[b.track_id][b.frame] = b.center + shift;
      type[b.track_id] = b.type;
    }
    const std::set<int> still = staticTracks(tracks, type, min_common, rigid_m);
    std::vector<double> medians, maxima;
    if (per_track)
      std::printf(
          "| track | type | frames | median spread [m] | max spread [m] |\n| --- | --- | --- | --- "
          "| --- |\n");
    for (int id : still) {
      std::vector<Eigen::Vector3d> odom;
      for (const auto& fc : tracks[id]) odom.push_back(poses[fc.first] * fc.second);
      std::vector<double> xs, ys, zs;
      for (const auto& p : odom) {
        xs.push_back(p.x());
        ys.push_back(p.y());
        zs.push_back(p.z());
      }
      const Eigen::Vector3d median(percentile(xs, 0.5), percentile(ys, 0.5), percentile(zs, 0.5));
      std::vector<double> d;
      for (const auto& p : odom) d.push_back((p - median).norm());
      medians.push_back(percentile(d, 0.5));
      maxima.push_back(*std::max_element(d.begin(), d.end()));
      if (per_track)
        std::printf("| %d | %s | %zu | %.2f | %.2f |\n", id, type[id].c_str(), odom.size(),
                    medians.back(), maxima.back());
    }
    std::printf(
        "static labelled tracks (Car/Van/Truck, judged from the labels): %zu of %zu; centre "
        "spread in odom: median of the per-track medians %.2f m (target <= 0.3), median of "
        "the per-track maxima %.2f m, largest %.2f m\n",
        still.size(), tracks.size(), percentile(medians, 0.5), percentile(maxima, 0.5),
        maxima.empty() ? 0.0 : *std::max_element(maxima.begin(), maxima.end()));
  } catch (const std::exception& e) {
    std::fprintf(stderr, "icanc_kitti_odometry: %s\n", e.what());
    return 1;
  }
  return 0;
}
