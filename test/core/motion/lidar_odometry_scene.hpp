// The simulated street and path shared by the LidarOdometry gtest and its rostest: a street along
// +x with buildings, parked cars and poles, a vehicle that pulls away and turns left into a second
// street, and scans of it from a sensor 1.8 m above base_link.
#pragma once

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include <Eigen/Geometry>

#include "icanc/sim/lidar_sim.hpp"

namespace icanc {
namespace lio_scene {

constexpr float kMountZ = 1.8f;  // sensor above base_link (on the road) [m]

inline sim::SceneObject box(float x, float y, float length, float width, float height,
                            float yaw = 0.0f) {
  sim::SceneObject o;
  o.shape = sim::Shape::kBox;
  o.type = "wall";
  o.position = Eigen::Vector3f(x, y, 0.0f);
  o.size = Eigen::Vector3f(length, width, height);
  o.yaw = yaw;
  return o;
}

inline sim::SceneObject pole(float x, float y) {
  sim::SceneObject o;
  o.shape = sim::Shape::kCylinder;
  o.type = "pole";
  o.position = Eigen::Vector3f(x, y, 0.0f);
  o.size = Eigen::Vector3f(0.3f, 0.3f, 5.0f);
  return o;
}

// A street along +x (buildings with gaps, parked cars, poles) and, where the path below turns
// left by 1 rad, a street along its new heading.
// Two long smooth walls along the road: nothing faces along it, so the scene cannot say how far
// the vehicle went.
inline sim::Scene corridor() {
  sim::Scene scene;
  scene.objects.push_back(box(0.0f, 4.5f, 600.0f, 1.0f, 4.0f));
  scene.objects.push_back(box(0.0f, -4.5f, 600.0f, 1.0f, 4.0f));
  return scene;
}

// Walls 4.5 m either side of the drive of truePose (straight, a 1 rad left turn at 3-5 s, straight
// again), made of 1.2 m pieces every metre of the path: the road turns, and nothing stands across
// it.
inline sim::Scene bendingCorridor();

inline sim::Scene street() {
  sim::Scene scene;
  for (int i = 0; i < 8; ++i) {
    const float x = -30.0f + 12.0f * i;
    if (x < 16.0f) {  // the left side ends where the path turns into it
      scene.objects.push_back(box(x, 12.0f + (i % 3), 9.0f, 6.0f, 8.0f + 2 * (i % 2)));
      scene.objects.push_back(pole(x + 2.0f, 6.5f));
    }
    scene.objects.push_back(box(x + 4.0f, -12.0f - (i % 2), 10.0f, 6.0f, 7.0f));
    scene.objects.push_back(box(x + 7.0f, -6.0f, 4.5f, 1.8f, 1.5f));  // parked car
  }
  const Eigen::Vector2f start(37.5f, 7.4f), along(std::cos(1.0f), std::sin(1.0f)),
      left(-std::sin(1.0f), std::cos(1.0f));
  for (int i = 0; i < 8; ++i) {
    const Eigen::Vector2f p = start + (5.0f * i) * along;
    const Eigen::Vector2f l = p + (12.0f + (i % 2)) * left, r = p - 12.0f * left;
    scene.objects.push_back(box(l.x(), l.y(), 8.0f, 5.0f, 8.0f, 1.0f));
    scene.objects.push_back(box(r.x(), r.y(), 8.0f, 5.0f, 6.0f + (i % 3), 1.0f));
    const Eigen::Vector2f q = p + 6.0f * left;
    if (i % 2 == 0) scene.objects.push_back(pole(q.x(), q.y()));
  }
  return scene;
}

// base_link in the world at time t: pulls away at 4 m/s^2 to `speed` (2 s to 8 m/s), turns left
// at 0.5 rad/s from 3 s to 5 s (a 1 rad turn) when `turn`, integrated finely.
inline Eigen::Isometry3d truePose(double t, double speed = 8.0, bool turn = true) {
  double x = 0.0, y = 0.0, yaw = 0.0;
  const double step = 0.001;
  for (double s = 0.0; s < t - 1e-12; s += step) {
    const double h = std::min(step, t - s);
    const double rate = turn && s >= 3.0 && s < 5.0 ? 0.5 : 0.0;
    const double v = std::min(speed, 4.0 * (s + 0.5 * h));
    x += v * std::cos(yaw + 0.5 * rate * h) * h;
    y += v * std::sin(yaw + 0.5 * rate * h) * h;
    yaw += rate * h;
  }
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() = Eigen::Vector3d(x, y, 0.0);
  pose.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  return pose;
}

// One scan from base_link at `base_pose` (a VLP-16 unless `model` says otherwise).
// The scan in the sensor frame (organized, NaN for no return), as a driver would publish it.
inline sim::Scene bendingCorridor() {
  sim::Scene scene;
  for (double t = -1.0; t < 9.0; t += 0.125) {  // a metre of path per step at 8 m/s
    const Eigen::Isometry3d p = truePose(std::max(0.0, t)) *
                                Eigen::Translation3d(8.0 * std::min(0.0, t), 0.0, 0.0);
    const double yaw = std::atan2(p(1, 0), p(0, 0));
    for (const double side : {-5.0, 5.0}) {
      const Eigen::Vector3d c = p * Eigen::Vector3d(0.0, side, 0.0);
      scene.objects.push_back(box(static_cast<float>(c.x()), static_cast<float>(c.y()), 1.2f, 1.0f,
                                  4.0f, static_cast<float>(yaw)));
    }
  }
  return scene;
}

inline Cloud sensorScan(const sim::Scene& scene, double t, const Eigen::Isometry3d& base_pose,
                        std::mt19937_64& rng, float range_std = 0.05f,
                        const sim::LidarModel& model = sim::LidarModel::vlp16()) {
  Eigen::Isometry3f sensor = base_pose.cast<float>();
  sensor.translation() += sensor.linear() * Eigen::Vector3f(0.0f, 0.0f, kMountZ);
  sim::NoiseParams noise;
  noise.range_std_m = range_std;
  Cloud cloud;
  sim::renderScan(scene, t, sensor, model, noise, rng, cloud);
  return cloud;
}

// The scan in base_link (the sensor's z mount added, no-return rays dropped).
inline std::vector<Eigen::Vector3f> scanAt(const sim::Scene& scene, double t,
                                           const Eigen::Isometry3d& base_pose, std::mt19937_64& rng,
                                           float range_std = 0.05f,
                                           const sim::LidarModel& model = sim::LidarModel::vlp16()) {
  std::vector<Eigen::Vector3f> points;
  for (const Point& p : sensorScan(scene, t, base_pose, rng, range_std, model))
    if (std::isfinite(p.x)) points.emplace_back(p.x, p.y, p.z + kMountZ);
  return points;
}

}  // namespace lio_scene
}  // namespace icanc
