// icanc_overlay_figure: renders what the CameraOverlay shows, as a PNG, from a simulated scenario
// and a synthetic night street (no recorded camera data): the scenario's LiDAR frames go through
// the core obstacle detector and the danger rules of its profile up to time t, and the tracked
// boxes are drawn (icanc::drawOverlay) into a night image projected through an
// image_geometry::PinholeCameraModel, as the nodelet does. Prints the image's brightness as the
// IlluminationMonitor measures it.
//
//   icanc_overlay_figure SCENARIO.yaml T_SECONDS OUT.png
//   e.g. icanc_overlay_figure config/scenarios/night_pedestrian_crossing.yaml 2.5 docs/figures/camera_overlay.png
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include <image_geometry/pinhole_camera_model.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <pcl/common/transforms.h>
#include <sensor_msgs/CameraInfo.h>

#include "icanc/core/camera/camera_overlay.hpp"
#include "icanc/core/danger/danger.hpp"
#include "icanc/core/camera/illumination.hpp"
#include "icanc/core/perception/obstacle_detector.hpp"
#include "icanc/core/common/yaml_params.hpp"
#include "icanc/sim/lidar_sim.hpp"
#include "icanc/sim/scenario.hpp"
#include "tool_help.hpp"

namespace {

constexpr int kWidth = 960, kHeight = 540;
constexpr double kFocal = 700.0;

image_geometry::PinholeCameraModel camera() {
  sensor_msgs::CameraInfo info;
  info.header.frame_id = "camera_optical";
  info.width = kWidth;
  info.height = kHeight;
  info.distortion_model = "plumb_bob";
  info.D = {0, 0, 0, 0, 0};
  info.K = {kFocal, 0, kWidth / 2.0, 0, kFocal, kHeight / 2.0, 0, 0, 1};
  info.R = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  info.P = {kFocal, 0, kWidth / 2.0, 0, 0, kFocal, kHeight / 2.0, 0, 0, 0, 1, 0};
  image_geometry::PinholeCameraModel model;
  model.fromCameraInfo(info);
  return model;
}

// The camera behind the windscreen: 1.5 m ahead of base_link, 1.4 m up, looking along +x.
Eigen::Isometry3d cameraFromVehicle() {
  Eigen::Isometry3d vehicle_from_camera = Eigen::Isometry3d::Identity();
  Eigen::Matrix3d r;
  r << 0, 0, 1, -1, 0, 0, 0, -1, 0;  // columns: optical x, y, z in the vehicle frame
  vehicle_from_camera.linear() = r;
  vehicle_from_camera.translation() = Eigen::Vector3d(1.5, 0.0, 1.4);
  return vehicle_from_camera.inverse();
}

// A synthetic night street seen by that camera: dark sky, asphalt, dim lane marks, kerbs and a
// few sodium street lamps glowing at 6 m on the right.
cv::Mat nightStreet(const image_geometry::PinholeCameraModel& model, const Eigen::Isometry3d& cam) {
  cv::Mat image(kHeight, kWidth, CV_8UC3);
  for (int v = 0; v < kHeight; ++v) {
    const double a = static_cast<double>(v) / kHeight;
    image.row(v).setTo(cv::Scalar(22 - 10 * a, 12 - 4 * a, 8));  // sky: deep blue to black
  }
  const auto px = [&](double x, double y, double z) {
    const Eigen::Vector3d c = cam * Eigen::Vector3d(x, y, z);
    const cv::Point2d p = model.project3dToPixel(cv::Point3d(c.x(), c.y(), c.z()));
    return cv::Point(cvRound(p.x), cvRound(p.y));
  };
  const auto quad = [&](double x0, double x1, double y0, double y1, const cv::Scalar& colour) {
    std::vector<cv::Point> pts = {px(x0, y0, 0), px(x1, y0, 0), px(x1, y1, 0), px(x0, y1, 0)};
    cv::fillConvexPoly(image, pts, colour, cv::LINE_AA);
  };
  quad(2.0, 400.0, -12.0, 12.0, cv::Scalar(14, 14, 15));  // verges
  quad(2.0, 400.0, -5.0, 5.0, cv::Scalar(24, 24, 26));    // asphalt
  for (double x = 4.0; x < 120.0; x += 9.0) quad(x, x + 3.0, -0.07, 0.07, cv::Scalar(60, 62, 64));
  quad(2.0, 400.0, -5.1, -4.95, cv::Scalar(45, 45, 45));
  quad(2.0, 400.0, 4.95, 5.1, cv::Scalar(45, 45, 45));
  cv::Mat glow(image.size(), CV_8UC3, cv::Scalar::all(0));
  for (double x = 12.0; x < 100.0; x += 25.0) {
    cv::line(image, px(x, -6.0, 0.0), px(x, -6.0, 6.0), cv::Scalar(30, 30, 32), 2, cv::LINE_AA);
    const int r = std::max(2, cvRound(kFocal * 0.35 / x));
    cv::circle(glow, px(x, -6.0, 6.0), 4 * r, cv::Scalar(40, 110, 200), cv::FILLED, cv::LINE_AA);
    cv::circle(image, px(x, -6.0, 6.0), r, cv::Scalar(170, 225, 255), cv::FILLED, cv::LINE_AA);
  }
  cv::GaussianBlur(glow, glow, cv::Size(0, 0), 12.0);
  image += glow;
  return image;
}

}  // namespace

int main(int argc, char** argv) {
  const char* const usage = "usage: icanc_overlay_figure SCENARIO.yaml T_SECONDS OUT.png\n";
  if (icanc::tools::wantsHelp(argc, argv)) return icanc::tools::printUsage(usage, true);
  if (argc != 4) return icanc::tools::printUsage(usage, false);
  try {
    const std::string scenario_path = argv[1];
    const double t_show = std::stod(argv[2]);
    const icanc::sim::Scenario sc = icanc::sim::loadScenario(scenario_path);
    const icanc::Profile profile = icanc::loadProfile(icanc::sim::profilePath(scenario_path, sc.profile));
    const icanc::sim::LidarModel lidar = icanc::sim::LidarModel::byName(sc.lidar);
    std::mt19937_64 rng(sc.seed);
    icanc::ObstacleDetector detector(profile.detector);
    detector.setSensorOrigin(sc.sensor_mount.translation());
    icanc::Cloud scan, vehicle;
    std::size_t k = 0;
    for (; k < sc.frames() && k / sc.rate_hz <= t_show + 1e-9; ++k) {
      const double t = k / sc.rate_hz;
      icanc::sim::renderScan(sc.scene, t, sc.sensorPose(t), lidar, sc.noise, rng, scan);
      pcl::transformPointCloud(scan, vehicle, sc.sensor_mount.matrix());
      detector.process(t, vehicle);
    }
    const double t = (k - 1) / sc.rate_hz;

    std::vector<icanc::OverlayObject> objects;
    int dangerous = 0;
    for (const icanc::Track& track : detector.tracks()) {
      if (!track.confirmed || track.coasted() > 0) continue;
      icanc::ObjectKinematics kin;
      kin.center = track.box.center.cast<double>();
      kin.aabb_min = track.box.min.cast<double>();
      kin.aabb_max = track.box.max.cast<double>();
      kin.velocity = track.velocity();
      kin.velocity_std = track.velocityStdXY();
      const icanc::DangerAssessment a = icanc::assessDanger(kin, profile.danger);
      icanc::OverlayObject o;
      o.id = track.id;
      o.center = track.box.center.cast<double>();
      o.size = track.box.size.cast<double>();
      o.yaw = track.box.yaw;
      o.speed_mps = a.speed_mps;
      o.dangerous = a.dangerous;
      dangerous += a.dangerous;
      objects.push_back(o);
    }
    const image_geometry::PinholeCameraModel model = camera();
    const Eigen::Isometry3d cam = cameraFromVehicle();
    cv::Mat image = nightStreet(model, cam);
    const icanc::IlluminationParams ip = profile.illumination;
    const double brightness = icanc::sceneBrightness(image, icanc::ChannelOrder::kBgr, ip.grid_step_px, ip.percentile);
    const int drawn = icanc::drawOverlay(image, objects, cam, [&model](const cv::Point3d& p) {
      return model.project3dToPixel(p);
    });
    char caption[200];
    std::snprintf(caption, sizeof(caption), "%s  t = %.1f s   %d tracks drawn, %d dangerous   brightness %.3f (%s)",
                  sc.name.c_str(), t, drawn, dangerous, brightness,
                  brightness <= ip.dark_at ? "dark" : brightness >= ip.bright_at ? "bright" : "dim");
    cv::putText(image, caption, cv::Point(10, kHeight - 12), cv::FONT_HERSHEY_SIMPLEX, 0.5,
                cv::Scalar(200, 200, 200), 1, cv::LINE_AA);
    if (!cv::imwrite(argv[3], image)) throw std::runtime_error(std::string("cannot write ") + argv[3]);
    std::printf("%s\n%s\n", caption, argv[3]);
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "icanc_overlay_figure: %s\n", e.what());
    return 1;
  }
}
