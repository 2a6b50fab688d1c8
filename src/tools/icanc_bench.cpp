// icanc_bench: the classic (paper's PCL chain) and the fast obstacle detector side by side, in one
// process and one run, on the same frames: per-stage and total p50/p99, points per second, the
// ratio classic/fast, and detection quality on the labelled KITTI objects (kitti_score.hpp); the
// LiDAR odometry (profile's lidar_odometry section) alone and after the fast detector.
// Then scaling with points (simulated 16/32/64/128-channel scans) and with objects (the tracker
// alone with 10/100/200/500 objects), and the lamp: the paper's binary LightController against the
// 8-segment lamp (dimmed by distance) per input, with 0/1/5/20 dangerous boxes (the
// segment levels must not come later than the binary command). Timing is steady_clock around each
// stage, single thread; the pipeline's line also gives the thread's CPU time, which time given to
// other processes on the machine does not inflate.
//
//   icanc_bench [--kitti DIR] [--profile PROFILE.yaml] [--frames N] [--smoke]
// DIR defaults to ../shared/data/kitti_tracking_0000 (skipped with a message when absent);
// PROFILE defaults to config/kitti_hdl64e.yaml. The classic chain always runs with the paper's
// reference parameters (voxel 0.2 m, RANSAC 30 it / 0.3 m, 0.6 m, 10..5000 points); the fast one
// with the profile's fast section. --smoke: a few frames of each, a quick check that all runs.
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "icanc/core/common/percentile.hpp"
#include "icanc/core/perception/cloud_decode.hpp"
#include "icanc/core/evaluation/kitti.hpp"
#include "icanc/core/evaluation/kitti_score.hpp"
#include "icanc/core/input/sensor_health.hpp"
#include "icanc/core/motion/lidar_odometry.hpp"
#include "icanc/core/perception/detector_pipeline.hpp"
#include "icanc/core/perception/obstacle_detector.hpp"
#include "icanc/core/common/yaml_params.hpp"
#include "icanc/core/light/light_controller.hpp"
#include "icanc/core/light/segmented_light_controller.hpp"
#include "icanc/sim/lidar_sim.hpp"
#include "thread_cpu_time.hpp"
#include "tool_help.hpp"

namespace {

using icanc::percentile;

using icanc::Cloud;
using icanc::ObstacleDetector;
using icanc::ObstacleDetectorParams;
using icanc::StageTimes;

struct Series {
  std::vector<double> prep, ground, cluster, motion, track, total;
  double points = 0.0;  // input points summed over the frames
  void add(const StageTimes& t, std::size_t n) {
    prep.push_back(t.prep_ms);
    ground.push_back(t.ground_ms);
    cluster.push_back(t.cluster_ms);
    motion.push_back(t.motion_ms);
    track.push_back(t.track_ms);
    total.push_back(t.total_ms());
    points += n;
  }
  double sumMs() const {
    double s = 0.0;
    for (double v : total) s += v;
    return s;
  }
  double mpps() const { return sumMs() > 0 ? points / (sumMs() * 1e3) : 0.0; }  // Mpoints/s
};

void printStages(const Series& classic, const Series& fast) {
  std::printf("| stage | classic p50 | classic p99 | fast p50 | fast p99 | classic/fast p50 |\n");
  std::printf("| --- | --- | --- | --- | --- | --- |\n");
  const auto row = [](const char* name, const std::vector<double>& c, const std::vector<double>& f) {
    const double c50 = percentile(c, 0.5), f50 = percentile(f, 0.5);
    std::printf("| %s | %.2f | %.2f | %.2f | %.2f | %.1fx |\n", name, c50, percentile(c, 0.99), f50,
                percentile(f, 0.99), f50 > 0 ? c50 / f50 : 0.0);
  };
  row("preparation", classic.prep, fast.prep);
  row("ground", classic.ground, fast.ground);
  row("clusters + boxes", classic.cluster, fast.cluster);
  row("free-space motion", classic.motion, fast.motion);
  row("tracking", classic.track, fast.track);
  row("**total**", classic.total, fast.total);
  std::printf("points per second: classic %.2f M, fast %.2f M (%.1fx); p99 ratio %.1fx\n",
              classic.mpps(), fast.mpps(), classic.mpps() > 0 ? fast.mpps() / classic.mpps() : 0.0,
              percentile(fast.total, 0.99) > 0
                  ? percentile(classic.total, 0.99) / percentile(fast.total, 0.99)
                  : 0.0);
}

void printScore(const char* name, const icanc::kitti::DetectionScore& s) {
  std::printf("%-8s recall %d/%d (%.1f %%):", name, s.foundTotal(), s.labelledTotal(),
              100.0 * s.recall());
  for (const auto& kv : s.labelled) {
    const auto f = s.found.find(kv.first);
    std::printf(" %s %d/%d", kv.first.c_str(), f == s.found.end() ? 0 : f->second, kv.second);
  }
  std::printf("; precision %d/%d (%.1f %%)\n", s.correct, s.detections, 100.0 * s.precision());
}

bool runKitti(const std::string& dir, const ObstacleDetectorParams& classic_params,
              const ObstacleDetectorParams& fast_params,
              const icanc::LidarOdometryParams& odometry_params, int max_frames) {
  if (!std::ifstream(dir + "/calib/0000.txt").good()) {
    std::printf("KITTI: skipped, no sequence at %s (see ../shared/data/kitti_tracking_0000)\n\n",
                dir.c_str());
    return false;
  }
  const auto calib = icanc::kitti::readCalib(dir + "/calib/0000.txt");
  const auto boxes = icanc::kitti::toVelodyne(icanc::kitti::readLabels(dir + "/label_02/0000.txt"), calib);
  std::map<int, std::vector<icanc::kitti::VeloBox>> by_frame;
  for (const auto& b : boxes) by_frame[b.frame].push_back(b);

  ObstacleDetector classic(classic_params), fast(fast_params);
  ObstacleDetector decode_then_fast(fast_params), fused(fast_params);
  std::vector<double> decode_then_ms, fused_ms, odometry_ms, interleaved_ms, fast_odometry_ms,
      fast_odometry_cpu_ms;
  std::vector<double> odometry_downsample_ms, odometry_register_ms, odometry_map_ms;
  // LiDAR odometry as its nodelet runs it, reading the same PointCloud2 buffer: alone,
  // and the fast detector then the odometry on each frame (one core serving both nodelets).
  icanc::LidarOdometry odometry(odometry_params), odometry_after_fast(odometry_params);
  ObstacleDetector fast_before_odometry(fast_params);
  Series cs, fs;
  icanc::kitti::DetectionScore cscore, fscore;
  Cloud cloud, decoded;
  int frames = 0;
  for (int f = 0; f < max_frames; ++f) {
    const std::string path = icanc::kitti::velodynePath(dir, f);
    if (!std::ifstream(path).good()) break;
    icanc::kitti::readVelodyne(path, cloud);
    StageTimes t;
    classic.process(0.1 * f, cloud, &t);
    cs.add(t, cloud.size());
    fast.process(0.1 * f, cloud, &t);
    fs.add(t, cloud.size());
    // As the nodelet gets it: a PointCloud2-shaped buffer (x y z + 4 bytes, the KITTI layout),
    // decoded into a cloud then detected, or read by the fast path's first pass directly.
    const icanc::RawCloud raw = icanc::rawView(cloud);
    const Eigen::Affine3f identity = Eigen::Affine3f::Identity();
    double t0 = icanc::fastNowMs();
    icanc::decodeXYZ(raw, identity, 10000000, decoded);
    decode_then_fast.process(0.1 * f, decoded);
    decode_then_ms.push_back(icanc::fastNowMs() - t0);
    t0 = icanc::fastNowMs();
    icanc::DecodePlan plan;
    if (icanc::planDecode(raw, 10000000, plan) == icanc::DecodeError::kNone)
      fused.processFrom(0.1 * f, [&](auto&& sink) { icanc::forEachXYZ(raw, plan, identity, sink); });
    fused_ms.push_back(icanc::fastNowMs() - t0);
    if (plan.width > 0) {
      const auto source = [&](auto&& sink) { icanc::forEachXYZ(raw, plan, identity, sink); };
      // As the nodelet reads it: only every input_stride-th point decoded.
      // (Both odometry instances have read as many frames: the same phase.)
      const icanc::DecodePlan thinned_plan =
          icanc::everyNthPoint(plan, odometry_params.input_stride, odometry.sourcePhase());
      const auto thinned = [&](auto&& sink) { icanc::forEachXYZ(raw, thinned_plan, identity, sink); };
      constexpr auto kBySource = icanc::LidarOdometry::Thinning::kBySource;
      t0 = icanc::fastNowMs();
      odometry.registerFrom(0.1 * f, thinned, kBySource);
      odometry_ms.push_back(icanc::fastNowMs() - t0);
      odometry_downsample_ms.push_back(odometry.lastStats().downsample_ms);
      odometry_register_ms.push_back(odometry.lastStats().register_ms);
      odometry_map_ms.push_back(odometry.lastStats().map_ms);
      t0 = icanc::fastNowMs();
      fast_before_odometry.processFrom(0.1 * f, source);
      odometry_after_fast.registerFrom(0.1 * f, thinned, kBySource);
      interleaved_ms.push_back(icanc::fastNowMs() - t0);
    }
    cscore.add(icanc::kitti::scoreFrame(by_frame[f], cloud, classic.detections()));
    fscore.add(icanc::kitti::scoreFrame(by_frame[f], cloud, fast.detections()));
    ++frames;
  }
  // The pipeline as the nodelet manager runs it: each cloud read, then the
  // fast detector with tracking and the LiDAR odometry on it, one detector and one odometry, on
  // one core. Above, the same pair runs between five other detectors and odometries on the same
  // frame, which take turns evicting each other's grids and map from the cache.
  {
    ObstacleDetector detector(fast_params);
    icanc::LidarOdometry pipeline_odometry(odometry_params);
    for (int f = 0; f < frames; ++f) {
      icanc::kitti::readVelodyne(icanc::kitti::velodynePath(dir, f), cloud);
      const icanc::RawCloud raw = icanc::rawView(cloud);
      const Eigen::Affine3f identity = Eigen::Affine3f::Identity();
      const double t0 = icanc::fastNowMs(), c0 = icanc::tools::threadCpuMs();
      icanc::DecodePlan plan;
      if (icanc::planDecode(raw, 10000000, plan) != icanc::DecodeError::kNone) continue;
      detector.processFrom(0.1 * f, [&](auto&& sink) { icanc::forEachXYZ(raw, plan, identity, sink); });
      const icanc::DecodePlan thinned_plan = icanc::everyNthPoint(
          plan, odometry_params.input_stride, pipeline_odometry.sourcePhase());
      pipeline_odometry.registerFrom(
          0.1 * f, [&](auto&& sink) { icanc::forEachXYZ(raw, thinned_plan, identity, sink); },
          icanc::LidarOdometry::Thinning::kBySource);
      fast_odometry_ms.push_back(icanc::fastNowMs() - t0);
      fast_odometry_cpu_ms.push_back(icanc::tools::threadCpuMs() - c0);
    }
  }
  // The detector's pass as its nodelet makes it, the paper's system (no ego motion): the layout
  // check, the fast detector with tracking and, in the same pass over the PointCloud2 buffer,
  // the blind-sensor check's returns (12 sectors); beside it the same without the count.
  std::vector<double> pass_cpu_ms[2];  // with the count, without
  {
    icanc::DetectorPipeline pipelines[2] = {
        icanc::DetectorPipeline(fast_params, icanc::EgoMotionParams(), 10000000),
        icanc::DetectorPipeline(fast_params, icanc::EgoMotionParams(), 10000000)};
    icanc::ReturnCounter returns;
    const icanc::SensorHealthParams health;
    for (int f = 0; f < frames; ++f) {
      icanc::kitti::readVelodyne(icanc::kitti::velodynePath(dir, f), cloud);
      const icanc::RawCloud raw = icanc::rawView(cloud);
      for (int k = 0; k < 2; ++k) {
        const double c0 = icanc::tools::threadCpuMs();
        icanc::DecodePlan plan;
        if (pipelines[k].plan(raw, plan) != icanc::DecodeError::kNone) break;
        icanc::DetectorPipelineInput in;
        in.stamp_s = 0.1 * f;
        in.frame = "base_link";
        in.raw = &raw;
        in.plan = &plan;
        if (k == 0) {
          returns.begin(health);
          in.returns = &returns;
        }
        pipelines[k].process(in);
        if (k == 0 && returns.valid() == 0) break;  // read, so the count is not optimised away
        pass_cpu_ms[k].push_back(icanc::tools::threadCpuMs() - c0);
      }
    }
  }
  // The data named as read (the heading said "0000 (HDL-64E)" whatever DIR was given).
  std::printf("## KITTI tracking, sequence 0000 (calib, labels, velodyne) read from %s: %d frames of "
              "%.0f points on average, times in ms\n\n", dir.c_str(), frames,
              frames ? cs.points / frames : 0.0);
  printStages(cs, fs);
  std::printf("from the PointCloud2 buffer (nodelet input), fast path with tracking: decode then "
              "detect p50 %.2f p99 %.2f ms; fused decode p50 %.2f p99 %.2f ms\n",
              percentile(decode_then_ms, 0.5), percentile(decode_then_ms, 0.99),
              percentile(fused_ms, 0.5), percentile(fused_ms, 0.99));
  std::printf("LiDAR odometry (lidar_odometry section, from the PointCloud2 buffer): p50 %.2f p99 "
              "%.2f ms\n",
              percentile(odometry_ms, 0.5), percentile(odometry_ms, 0.99));
  std::printf("fast detector with tracking + LiDAR odometry, as the nodelet manager runs them (each "
              "cloud read, then the two): p50 %.2f p99 %.2f ms (the thread's CPU time: p50 %.2f "
              "p99 %.2f ms); between the other detectors above: p50 %.2f p99 %.2f ms\n",
              percentile(fast_odometry_ms, 0.5), percentile(fast_odometry_ms, 0.99),
              percentile(fast_odometry_cpu_ms, 0.5), percentile(fast_odometry_cpu_ms, 0.99),
              percentile(interleaved_ms, 0.5), percentile(interleaved_ms, 0.99));
  std::printf("the detector's pass as its nodelet makes it (layout check, fast detector with "
              "tracking, no ego motion), thread CPU time: with the blind-sensor count in the same "
              "pass p50 %.2f p99 %.2f ms, without p50 %.2f p99 %.2f ms\n",
              percentile(pass_cpu_ms[0], 0.5), percentile(pass_cpu_ms[0], 0.99),
              percentile(pass_cpu_ms[1], 0.5), percentile(pass_cpu_ms[1], 0.99));
  std::printf("LiDAR odometry p50 per stage: reading and downsampling %.2f, registration %.2f, "
              "map %.2f ms\n",
              percentile(odometry_downsample_ms, 0.5), percentile(odometry_register_ms, 0.5),
              percentile(odometry_map_ms, 0.5));
  printScore("classic", cscore);
  printScore("fast", fscore);
  std::printf("\n");
  return true;
}

icanc::sim::LidarModel hdl32e() {
  icanc::sim::LidarModel m = icanc::sim::LidarModel::hdl64e();
  m.name = "hdl32e";
  m.vertical_angles_deg.clear();
  for (int i = 0; i < 32; ++i) m.vertical_angles_deg.push_back(10.67f - i * 1.333f);
  m.horizontal_resolution_deg = 0.16f;
  return m;
}

// A street: road, parked cars both sides, pedestrians crossing, oncoming cars.
icanc::sim::Scene street(int objects, std::mt19937_64& rng) {
  icanc::sim::Scene scene;
  std::uniform_real_distribution<float> x(-10.0f, 55.0f), y(-18.0f, 18.0f), v(-2.0f, 2.0f);
  for (int i = 0; i < objects; ++i) {
    icanc::sim::SceneObject o;
    o.id = static_cast<std::uint32_t>(i + 1);
    const bool car = i % 2 == 0;
    o.type = car ? "car" : "pedestrian";
    o.shape = car ? icanc::sim::Shape::kBox : icanc::sim::Shape::kCylinder;
    o.size = car ? Eigen::Vector3f(4.5f, 1.8f, 1.5f) : Eigen::Vector3f(0.5f, 0.5f, 1.7f);
    do {
      o.position = Eigen::Vector3f(x(rng), y(rng), 0.0f);
    } while (o.position.head<2>().norm() < 5.0f);
    o.velocity = Eigen::Vector3f(v(rng), v(rng), 0.0f);
    scene.objects.push_back(o);
  }
  return scene;
}

void runSimulated(const ObstacleDetectorParams& classic_params,
                  const ObstacleDetectorParams& fast_params, int frames) {
  std::printf("## Simulated scans (20 cars and pedestrians, sensor 1.73 m above the road), ms\n\n");
  std::printf("| channels | points | classic p50 | classic p99 | fast p50 | fast p99 | classic/fast p50 | fast Mpoints/s |\n");
  std::printf("| --- | --- | --- | --- | --- | --- | --- | --- |\n");
  const std::vector<icanc::sim::LidarModel> models = {
      icanc::sim::LidarModel::vlp16(), hdl32e(), icanc::sim::LidarModel::hdl64e(),
      icanc::sim::LidarModel::carla128()};
  for (const auto& model : models) {
    std::mt19937_64 rng(1);
    const icanc::sim::Scene scene = street(20, rng);
    Eigen::Isometry3f pose = Eigen::Isometry3f::Identity();
    pose.translation().z() = 1.73f;
    ObstacleDetector classic(classic_params), fast(fast_params);
    Series cs, fs;
    Cloud cloud;
    for (int f = 0; f < frames; ++f) {
      icanc::sim::renderScan(scene, 0.1 * f, pose, model, icanc::sim::NoiseParams(), rng, cloud);
      std::size_t n = 0;
      for (const auto& p : cloud) n += std::isfinite(p.x);
      StageTimes t;
      classic.process(0.1 * f, cloud, &t);
      cs.add(t, n);
      fast.process(0.1 * f, cloud, &t);
      fs.add(t, n);
    }
    const double c50 = percentile(cs.total, 0.5), f50 = percentile(fs.total, 0.5);
    std::printf("| %zu | %.0f | %.2f | %.2f | %.2f | %.2f | %.1fx | %.1f |\n", model.channels(),
                cs.points / frames, c50, percentile(cs.total, 0.99), f50,
                percentile(fs.total, 0.99), f50 > 0 ? c50 / f50 : 0.0, fs.mpps());
  }
  std::printf("\n");
}

void runTracking(const icanc::TrackerParams& params, int frames) {
  std::printf("## Tracking alone (objects 3 m apart, moving, 10 Hz), ms per frame\n\n");
  std::printf("| objects | p50 | p99 |\n| --- | --- | --- |\n");
  for (int objects : {10, 100, 200, 500}) {
    std::mt19937_64 rng(2);
    std::normal_distribution<float> noise(0.0f, 0.05f);
    std::uniform_real_distribution<float> speed(-1.5f, 1.5f);
    const int side = static_cast<int>(std::ceil(std::sqrt(objects)));
    std::vector<Eigen::Vector2f> pos, vel;
    for (int i = 0; i < objects; ++i) {
      pos.emplace_back(3.0f * (i % side), 3.0f * (i / side) - 1.5f * side);
      vel.emplace_back(speed(rng), speed(rng));
    }
    icanc::MultiObjectTracker tracker(params);
    std::vector<icanc::Box3D> detections(objects);
    std::vector<double> ms;
    for (int f = 0; f < frames; ++f) {
      for (int i = 0; i < objects; ++i) {
        const Eigen::Vector2f c = pos[i] + vel[i] * (0.1f * f);
        icanc::Box3D& b = detections[i];
        b.center = Eigen::Vector3f(c.x() + noise(rng), c.y() + noise(rng), -1.0f);
        b.size = Eigen::Vector3f(1.0f, 0.8f, 1.6f);
        b.min = b.center - 0.5f * b.size;
        b.max = b.center + 0.5f * b.size;
        b.num_points = 100;
      }
      const double t0 = icanc::fastNowMs();
      tracker.update(0.1 * f, detections);
      if (f > 0) ms.push_back(icanc::fastNowMs() - t0);
    }
    std::printf("| %d | %.3f | %.3f |\n", objects, percentile(ms, 0.5), percentile(ms, 0.99));
  }
  std::printf("\n");
}

// Per input: LightController::onInput (the binary lamp) against SegmentedLightController::onInput
// + levels() (8 segments of 15 deg over +-60, dimmed by distance), boxes spread ahead at 3-25 m.
// Microseconds per input, over batches of 100 inputs.
void runLamp(const icanc::LightControllerParams& light, int batches) {
  std::printf("## The lamp per input: binary vs 8 segments (dimmed), microseconds per input\n\n");
  std::printf("| dangerous boxes | binary p50 | p99 | 8 segments p50 | p99 | ratio p50 |\n"
              "| --- | --- | --- | --- | --- | --- |\n");
  icanc::SegmentLampParams lamp;
  for (int i = 0; i < 8; ++i) {
    icanc::LampSegment seg;
    seg.azimuth_min_deg = -60.0 + 15.0 * i;
    seg.azimuth_max_deg = seg.azimuth_min_deg + 15.0;
    seg.watts = 25.0 / 8.0;
    lamp.segments.push_back(seg);
  }
  lamp.full_power_range_m = 15.0;
  icanc::LightControllerParams offline = light;
  offline.watchdog_enabled = false;
  constexpr int kPerBatch = 100;
  for (int n : {0, 1, 5, 20}) {
    std::mt19937_64 rng(3);
    std::uniform_real_distribution<double> x(3.0, 25.0), y(-8.0, 8.0);
    std::vector<Eigen::AlignedBox2d> boxes;
    for (int i = 0; i < n; ++i) {
      const Eigen::Vector2d c(x(rng), y(rng));
      boxes.emplace_back(c - Eigen::Vector2d(0.3, 0.3), c + Eigen::Vector2d(0.3, 0.3));
    }
    icanc::LightController binary(offline);
    icanc::SegmentedLightController segmented(offline, lamp);
    std::vector<double> binary_us, segmented_us;
    float sink = 0.0f;
    double now = 0.0;
    for (int b = 0; b < batches; ++b) {
      double t0 = icanc::fastNowMs();
      for (int k = 0; k < kPerBatch; ++k) binary.onInput(now + 0.1 * k, !boxes.empty(), false);
      binary_us.push_back((icanc::fastNowMs() - t0) * 1e3 / kPerBatch);
      t0 = icanc::fastNowMs();
      for (int k = 0; k < kPerBatch; ++k) {
        segmented.onInput(now + 0.1 * k, boxes, false);
        sink += segmented.levels().front();
      }
      segmented_us.push_back((icanc::fastNowMs() - t0) * 1e3 / kPerBatch);
      now += 0.1 * kPerBatch;
    }
    const double b50 = percentile(binary_us, 0.5), s50 = percentile(segmented_us, 0.5);
    std::printf("| %d | %.3f | %.3f | %.3f | %.3f | %.1fx |%s\n", n, b50, percentile(binary_us, 0.99), s50,
                percentile(segmented_us, 0.99), b50 > 0.0 ? s50 / b50 : 0.0, sink < 0.0f ? " " : "");
  }
  std::printf("\n");
}

}  // namespace

namespace {
const char* const kUsage =
    "usage: icanc_bench [--kitti DIR] [--profile PROFILE.yaml] [--frames N] [--smoke]\n";
}  // namespace

int main(int argc, char** argv) {
  if (icanc::tools::wantsHelp(argc, argv)) return icanc::tools::printUsage(kUsage, true);
  std::string dir = "../shared/data/kitti_tracking_0000";
  std::string profile = "config/kitti_hdl64e.yaml";
  int frames = 1 << 30;
  bool smoke = false;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--kitti" && i + 1 < argc) dir = argv[++i];
    else if (a == "--profile" && i + 1 < argc) profile = argv[++i];
    else if (a == "--frames" && i + 1 < argc) frames = std::atoi(argv[++i]);
    else if (a == "--smoke") smoke = true;
    else {
      return icanc::tools::printUsage(kUsage, false);
    }
  }
  if (smoke) frames = std::min(frames, 5);
  try {
    const icanc::Profile loaded = icanc::loadProfile(profile);
    ObstacleDetectorParams classic = loaded.detector;
    classic.method = icanc::DetectorMethod::kClassic;
    classic.prep.voxel_leaf_m = 0.2f;  // the paper's reference parameters, whatever the profile
    classic.ground = icanc::GroundParams();  // where the road is comes from the profile
    classic.ground.expected_height_m = loaded.detector.ground.expected_height_m;
    classic.ground.max_height_error_m = loaded.detector.ground.max_height_error_m;
    classic.ground.max_iterations = 30;
    classic.ground.distance_threshold_m = 0.3f;
    classic.cluster = icanc::ClusterParams();
    classic.cluster.tolerance_m = 0.6f;
    classic.cluster.min_points = 10;
    classic.cluster.max_points = 5000;
    classic.cluster.grazing = loaded.detector.cluster.grazing;  // the profile's column rule
    ObstacleDetectorParams fast = loaded.detector;
    fast.method = icanc::DetectorMethod::kFast;
    std::printf("icanc_bench: profile %s, one thread\n\n", profile.c_str());
    runKitti(dir, classic, fast, loaded.lidar_odometry, frames);
    runSimulated(classic, fast, smoke ? 3 : 30);
    runTracking(loaded.detector.tracker, smoke ? 5 : 100);
    runLamp(loaded.light, smoke ? 5 : 200);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "icanc_bench: %s\n", e.what());
    return 1;
  }
  return 0;
}
