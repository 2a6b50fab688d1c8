// Pins the LiDAR simulator: sensor presets, ray geometry against ground / boxes / cylinders,
// occlusion, object motion and ground truth, noise statistics and determinism.
#include <chrono>
#include <cmath>
#include <iostream>
#include <limits>
#include <random>
#include <stdexcept>

#include <gtest/gtest.h>

#include "icanc/sim/lidar_sim.hpp"

namespace icanc {
namespace sim {
namespace {

constexpr double kDeg = M_PI / 180.0;

bool valid(const Point& p) { return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z); }
double rangeOf(const Point& p) { return std::sqrt(double(p.x) * p.x + double(p.y) * p.y + double(p.z) * p.z); }
std::size_t countValid(const Cloud& c) {
  std::size_t n = 0;
  for (const Point& p : c.points) n += valid(p) ? 1 : 0;
  return n;
}

Eigen::Isometry3f poseAt(float x, float y, float z, float yaw = 0.0f) {
  Eigen::Isometry3f pose = Eigen::Isometry3f::Identity();
  pose.translation() = Eigen::Vector3f(x, y, z);
  pose.linear() = Eigen::AngleAxisf(yaw, Eigen::Vector3f::UnitZ()).toRotationMatrix();
  return pose;
}

// A small test sensor with a level channel (0 deg) and 1 deg columns, column 180 at azimuth 0.
LidarModel testModel() {
  LidarModel m;
  m.name = "test";
  m.vertical_angles_deg = {2.0f, 0.0f, -2.0f};
  m.horizontal_resolution_deg = 1.0f;
  m.min_range_m = 0.5f;
  m.max_range_m = 100.0f;
  return m;
}
constexpr std::size_t kLevelRow = 1;

std::size_t columnAt(const LidarModel& m, double azimuth_deg) {
  for (std::size_t c = 0; c < m.columns(); ++c) {
    if (std::abs(m.azimuthDeg(c) - azimuth_deg) < 1e-6) return c;
  }
  ADD_FAILURE() << "no column at azimuth " << azimuth_deg << " in " << m.name;
  return 0;
}

const Point& at(const Cloud& c, std::size_t row, std::size_t col) { return c.points[row * c.width + col]; }

SceneObject box(std::uint32_t id, float x, float y, Eigen::Vector3f size, float yaw = 0.0f) {
  SceneObject o;
  o.id = id;
  o.type = "box";
  o.shape = Shape::kBox;
  o.size = size;
  o.yaw = yaw;
  o.position = Eigen::Vector3f(x, y, 0.0f);
  return o;
}

SceneObject cylinder(std::uint32_t id, float x, float y, float diameter, float height) {
  SceneObject o = box(id, x, y, Eigen::Vector3f(diameter, diameter, height));
  o.type = "pedestrian";
  o.shape = Shape::kCylinder;
  return o;
}

Cloud render(const Scene& scene, const LidarModel& m, const Eigen::Isometry3f& pose,
             const NoiseParams& noise = {}, std::uint64_t seed = 1, double t = 0.0) {
  std::mt19937_64 rng(seed);
  Cloud cloud;
  renderScan(scene, t, pose, m, noise, rng, cloud);
  return cloud;
}

// ---------------------------------------------------------------------------------------------
// Presets

TEST(LidarModel, Vlp16) {
  const LidarModel m = LidarModel::vlp16();
  EXPECT_EQ(m.name, "vlp16");
  ASSERT_EQ(m.channels(), 16u);
  for (std::size_t i = 0; i < 16; ++i) EXPECT_NEAR(m.vertical_angles_deg[i], 15.0 - 2.0 * i, 1e-5);
  EXPECT_EQ(m.columns(), 1800u);
  EXPECT_NEAR(m.azimuthStepDeg(), 0.2, 1e-9);
  EXPECT_NEAR(m.azimuthDeg(0), -180.0, 1e-9);
  EXPECT_NEAR(m.azimuthDeg(900), 0.0, 1e-4);
  EXPECT_FLOAT_EQ(m.rate_hz, 10.0f);
  EXPECT_FLOAT_EQ(m.max_range_m, 100.0f);
}

TEST(LidarModel, Hdl64e) {
  const LidarModel m = LidarModel::hdl64e();
  ASSERT_EQ(m.channels(), 64u);
  EXPECT_NEAR(m.vertical_angles_deg.front(), 2.0, 1e-5);
  EXPECT_NEAR(m.vertical_angles_deg[31], -8.33, 1e-5);
  EXPECT_NEAR(m.vertical_angles_deg[32], -8.83, 1e-5);
  EXPECT_NEAR(m.vertical_angles_deg.back(), -24.9, 1e-5);
  // Even spacing inside each block, strictly descending overall.
  for (std::size_t i = 1; i < 32; ++i) {
    EXPECT_NEAR(m.vertical_angles_deg[i - 1] - m.vertical_angles_deg[i], 10.33 / 31.0, 1e-4);
    EXPECT_NEAR(m.vertical_angles_deg[31 + i] - m.vertical_angles_deg[32 + i], 16.07 / 31.0, 1e-4);
  }
  EXPECT_EQ(m.columns(), 2118u);  // round(360 / 0.17)
  EXPECT_NEAR(m.azimuthStepDeg(), 0.17, 0.001);
  EXPECT_FLOAT_EQ(m.max_range_m, 120.0f);
  EXPECT_GT(m.channels() * m.columns(), 130000u);
}

TEST(LidarModel, Carla128MatchesThePapersSensor) {
  const LidarModel m = LidarModel::carla128();
  ASSERT_EQ(m.channels(), 128u);
  EXPECT_NEAR(m.vertical_angles_deg.front(), 10.0, 1e-5);
  EXPECT_NEAR(m.vertical_angles_deg.back(), -30.0, 1e-5);
  EXPECT_NEAR(m.vertical_angles_deg[1] - m.vertical_angles_deg[2], 40.0 / 127.0, 1e-5);
  EXPECT_EQ(m.columns(), 500u);
  EXPECT_NEAR(m.horizontal_resolution_deg, 0.72, 1e-5);
  EXPECT_NEAR(m.pointsPerSecond(), 640000.0, 6400.0);
  EXPECT_FLOAT_EQ(m.max_range_m, 100.0f);
}

TEST(LidarModel, RobosenseM1IsForwardSolidState) {
  const LidarModel m = LidarModel::robosenseM1();
  ASSERT_EQ(m.channels(), 126u);
  EXPECT_NEAR(m.vertical_angles_deg.front(), 12.5, 1e-5);
  EXPECT_NEAR(m.vertical_angles_deg.back(), -12.5, 1e-5);
  EXPECT_EQ(m.columns(), 601u);  // -60..+60 every 0.2 deg, both ends
  EXPECT_NEAR(m.azimuthDeg(0), -60.0, 1e-9);
  EXPECT_NEAR(m.azimuthDeg(300), 0.0, 1e-9);
  EXPECT_NEAR(m.azimuthDeg(600), 60.0, 1e-9);
  EXPECT_FLOAT_EQ(m.max_range_m, 200.0f);
}

TEST(LidarModel, Hdl32e) {
  const LidarModel m = LidarModel::hdl32e();
  ASSERT_EQ(m.channels(), 32u);
  EXPECT_NEAR(m.vertical_angles_deg.front(), 10.67, 1e-5);
  EXPECT_NEAR(m.vertical_angles_deg.back(), -30.67, 1e-5);
  for (std::size_t i = 1; i < 32; ++i)
    EXPECT_NEAR(m.vertical_angles_deg[i - 1] - m.vertical_angles_deg[i], 41.34 / 31.0, 1e-4);
  EXPECT_FLOAT_EQ(m.horizontal_resolution_deg, 0.16f);
}

TEST(LidarModel, ByName) {
  EXPECT_EQ(LidarModel::byName("vlp16").channels(), 16u);
  EXPECT_EQ(LidarModel::byName("hdl32e").channels(), 32u);
  EXPECT_EQ(LidarModel::byName("hdl64e").channels(), 64u);
  EXPECT_EQ(LidarModel::byName("carla128").channels(), 128u);
  EXPECT_EQ(LidarModel::byName("robosense_m1").channels(), 126u);
  EXPECT_EQ(LidarModel::byName("robosense_m1").name, "robosense_m1");
  EXPECT_THROW(LidarModel::byName("VLP16"), std::invalid_argument);
  EXPECT_THROW(LidarModel::byName(""), std::invalid_argument);
}

// ---------------------------------------------------------------------------------------------
// Geometry

TEST(RenderScan, OrganizedCloudInTheSensorFrame) {
  const LidarModel m = LidarModel::vlp16();
  Scene scene;
  const Cloud c = render(scene, m, poseAt(0, 0, 1.73f), {}, 1, 2.5);
  EXPECT_EQ(c.width, 1800u);
  EXPECT_EQ(c.height, 16u);
  EXPECT_EQ(c.points.size(), 1800u * 16u);
  EXPECT_FALSE(c.is_dense);
  EXPECT_EQ(c.header.stamp, 2500000u);
}

TEST(RenderScan, GroundRingsAtHeightOverTanElevation) {
  const float h = 1.73f;
  const LidarModel m = LidarModel::vlp16();
  Scene scene;  // flat ground at z = 0, no objects
  const Cloud c = render(scene, m, poseAt(3.0f, -2.0f, h, 0.7f));
  for (std::size_t row = 0; row < m.channels(); ++row) {
    const double e = m.vertical_angles_deg[row];
    for (std::size_t col : {0u, 137u, 450u, 900u, 1333u, 1799u}) {
      const Point& p = at(c, row, col);
      if (e >= 0.0) {
        EXPECT_FALSE(valid(p)) << "channel " << e << " deg sees above the horizon";
        continue;
      }
      ASSERT_TRUE(valid(p)) << "channel " << e << " column " << col;
      const double expected = h / std::tan(-e * kDeg);
      EXPECT_NEAR(std::hypot(p.x, p.y), expected, 1e-3) << "channel " << e;
      EXPECT_NEAR(p.z, -h, 1e-4);
      EXPECT_NEAR(std::atan2(p.y, p.x), m.azimuthDeg(col) * kDeg, 1e-5);
    }
  }
  // Exactly the 8 downward channels return, on every column.
  EXPECT_EQ(countValid(c), 8u * 1800u);
}

TEST(RenderScan, GroundBeyondMaxRangeIsNoReturn) {
  LidarModel m = testModel();
  m.vertical_angles_deg = {-0.5f};  // ground at 1.73 / tan(0.5 deg) = 198 m
  Scene scene;
  EXPECT_EQ(countValid(render(scene, m, poseAt(0, 0, 1.73f))), 0u);
  m.max_range_m = 250.0f;
  EXPECT_EQ(countValid(render(scene, m, poseAt(0, 0, 1.73f))), m.columns());
}

TEST(RenderScan, BoxAheadCentreRayHitsItsNearFace) {
  const LidarModel m = testModel();
  Scene scene;
  scene.objects.push_back(box(1, 10.0f, 0.0f, Eigen::Vector3f(2.0f, 1.6f, 2.0f)));  // l = 2
  const Cloud c = render(scene, m, poseAt(0, 0, 1.0f));
  const Point& p = at(c, kLevelRow, columnAt(m, 0.0));
  ASSERT_TRUE(valid(p));
  EXPECT_NEAR(p.x, 10.0 - 1.0, 1e-4);
  EXPECT_NEAR(p.y, 0.0, 1e-5);
  EXPECT_NEAR(p.z, 0.0, 1e-5);
  // Off-centre ray on the same face: x stays at the face, y = x tan(az).
  const Point& q = at(c, kLevelRow, columnAt(m, 3.0));
  ASSERT_TRUE(valid(q));
  EXPECT_NEAR(q.x, 9.0, 1e-4);
  EXPECT_NEAR(q.y, 9.0 * std::tan(3.0 * kDeg), 1e-4);
  // The face is 1.6 m wide: half-width 0.8 at 9 m is 5.08 deg, so 6 deg misses (and no ground).
  scene.has_ground = false;
  const Cloud c2 = render(scene, m, poseAt(0, 0, 1.0f));
  EXPECT_TRUE(valid(at(c2, kLevelRow, columnAt(m, 5.0))));
  EXPECT_FALSE(valid(at(c2, kLevelRow, columnAt(m, 6.0))));
  EXPECT_FALSE(valid(at(c2, kLevelRow, columnAt(m, 90.0))));
}

TEST(RenderScan, SensorPoseIsApplied) {
  // Sensor yawed +90 deg at (5, 0, 1): a box at world (5, 10) is straight ahead, 10 m away.
  const LidarModel m = testModel();
  Scene scene;
  scene.has_ground = false;
  scene.objects.push_back(box(1, 5.0f, 10.0f, Eigen::Vector3f(1.0f, 1.0f, 2.0f)));
  const Cloud c = render(scene, m, poseAt(5.0f, 0.0f, 1.0f, float(M_PI / 2)));
  const Point& p = at(c, kLevelRow, columnAt(m, 0.0));
  ASSERT_TRUE(valid(p));
  EXPECT_NEAR(p.x, 9.5, 1e-4);
  EXPECT_NEAR(p.y, 0.0, 1e-4);
  for (const Point& q : c.points) {
    if (valid(q)) {
      EXPECT_GT(q.x, 9.0f);  // nothing else in the scene
    }
  }
}

TEST(RenderScan, CylinderSideAndCap) {
  const LidarModel m = testModel();
  Scene scene;
  scene.has_ground = false;
  scene.objects.push_back(cylinder(1, 10.0f, 0.0f, 0.6f, 1.8f));
  const Cloud c = render(scene, m, poseAt(0, 0, 1.0f));
  const Point& p = at(c, kLevelRow, columnAt(m, 0.0));
  ASSERT_TRUE(valid(p));
  EXPECT_NEAR(p.x, 10.0 - 0.3, 1e-4);
  // The side is round: 1 deg off centre the hit is further than the front but on the circle.
  const Point& q = at(c, kLevelRow, columnAt(m, 1.0));
  ASSERT_TRUE(valid(q));
  EXPECT_NEAR(std::hypot(q.x - 10.0, q.y), 0.3, 1e-4);
  EXPECT_GT(q.x, p.x);

  // A flat, wide cylinder (d = 10 m, h = 0.5 m) seen from 1 m up at -2 deg: the ray passes over
  // the near rim (z = 1 - 5 tan 2deg = 0.825 > 0.5) and hits the top cap at z = 0.5.
  Scene flat;
  flat.has_ground = false;
  flat.objects.push_back(cylinder(2, 10.0f, 0.0f, 10.0f, 0.5f));
  const Cloud f = render(flat, m, poseAt(0, 0, 1.0f));
  const Point& cap = at(f, 2, columnAt(m, 0.0));  // row 2 = -2 deg
  ASSERT_TRUE(valid(cap));
  EXPECT_NEAR(cap.z, -0.5, 1e-4);
  EXPECT_NEAR(rangeOf(cap), 0.5 / std::sin(2.0 * kDeg), 1e-3);
}

TEST(RenderScan, OccludedObjectGetsNoHits) {
  const LidarModel m = LidarModel::vlp16();
  Scene scene;
  scene.has_ground = false;
  const SceneObject front = box(1, 10.0f, 0.0f, Eigen::Vector3f(2.0f, 2.0f, 2.0f));
  // Seen from z = 1, the near box covers +-6.3 deg both ways; the far one +-1.5 deg.
  const SceneObject behind = box(2, 20.0f, 0.0f, Eigen::Vector3f(1.0f, 1.0f, 1.5f));
  // Alone, the far box is seen.
  scene.objects = {behind};
  std::size_t far_hits = 0;
  for (const Point& p : render(scene, m, poseAt(0, 0, 1.0f)).points) far_hits += valid(p) && p.x > 19.0f;
  EXPECT_GT(far_hits, 10u);
  // Behind the near box it is not.
  scene.objects = {front, behind};
  const Cloud c = render(scene, m, poseAt(0, 0, 1.0f));
  std::size_t near_hits = 0;
  for (const Point& p : c.points) {
    if (!valid(p)) continue;
    EXPECT_LT(p.x, 11.0f + 1e-4f) << "hit behind the occluder at x = " << p.x;
    ++near_hits;
  }
  EXPECT_GT(near_hits, 100u);
  // Order in the scene list does not matter.
  scene.objects = {behind, front};
  const Cloud c2 = render(scene, m, poseAt(0, 0, 1.0f));
  for (std::size_t i = 0; i < c.points.size(); ++i) {
    ASSERT_EQ(valid(c.points[i]), valid(c2.points[i]));
    if (valid(c.points[i])) {
      EXPECT_FLOAT_EQ(c.points[i].x, c2.points[i].x);
    }
  }
}

TEST(RenderScan, RotatedBoxHitsItsEdgeAndFaces) {
  // A 2 x 2 box yawed 45 deg at (10, 0): its vertical edge points at the sensor at 10 - sqrt(2);
  // the left-near face is the line y - x = sqrt(2) - 10, so at azimuth a the range is
  // (10 - sqrt(2)) / (cos a - sin |a|).
  const LidarModel m = testModel();
  Scene scene;
  scene.has_ground = false;
  scene.objects.push_back(box(1, 10.0f, 0.0f, Eigen::Vector3f(2.0f, 2.0f, 2.0f), float(M_PI / 4)));
  const Cloud c = render(scene, m, poseAt(0, 0, 1.0f));
  const double near = 10.0 - std::sqrt(2.0);
  EXPECT_NEAR(at(c, kLevelRow, columnAt(m, 0.0)).x, near, 1e-4);
  for (double a : {-6.0, -3.0, -1.0, 1.0, 4.0, 7.0}) {
    const Point& p = at(c, kLevelRow, columnAt(m, a));
    ASSERT_TRUE(valid(p)) << a;
    const double ar = a * kDeg;
    EXPECT_NEAR(rangeOf(p), near / (std::cos(ar) - std::sin(std::abs(ar))), 1e-4) << a;
  }
  // Edge-on at 45 deg the box spans +-atan(sqrt(2) / 10) = 8.05 deg: 9 deg misses.
  EXPECT_FALSE(valid(at(c, kLevelRow, columnAt(m, 9.0))));
  EXPECT_TRUE(valid(at(c, kLevelRow, columnAt(m, 8.0))));
}

// Signed distance-like test helpers in the world: inside (<0), on (~0) or outside (>0) a solid.
double surfaceDistance(const SceneObject& o, const Eigen::Vector3d& p_world, double t) {
  const Eigen::Vector3d bottom = o.positionAt(t).cast<double>();
  const Eigen::Vector3d rel = p_world - bottom - Eigen::Vector3d(0, 0, 0.5 * o.size.z());
  const Eigen::Vector3d q =
      Eigen::AngleAxisd(-double(o.yaw), Eigen::Vector3d::UnitZ()).toRotationMatrix() * rel;
  const double dz = std::abs(q.z()) - 0.5 * o.size.z();
  double dxy;
  if (o.shape == Shape::kCylinder) {
    dxy = std::hypot(q.x(), q.y()) - 0.5 * o.size.x();
  } else {
    dxy = std::max(std::abs(q.x()) - 0.5 * o.size.x(), std::abs(q.y()) - 0.5 * o.size.y());
  }
  const double inside = std::max(dxy, dz);
  if (inside <= 0.0) return inside;
  return std::hypot(std::max(dxy, 0.0), std::max(dz, 0.0));
}

TEST(RenderScan, EveryReturnLiesOnAVisibleSurface) {
  // Random boxes and cylinders with random yaw, a rolled / pitched / yawed sensor: each return,
  // taken back to the world, is on the ground or on an object's surface, and the ray before it
  // runs through free space.
  std::mt19937_64 place(99);
  std::uniform_real_distribution<double> xy(-25.0, 25.0), yaw(-M_PI, M_PI), dim(0.4, 5.0);
  Scene scene;
  scene.ground_z = -0.3f;
  for (int k = 0; k < 25; ++k) {
    SceneObject o;
    o.id = k + 1;
    o.shape = k % 3 == 0 ? Shape::kCylinder : Shape::kBox;
    o.size = Eigen::Vector3f(float(dim(place)), float(dim(place)), float(dim(place)));
    o.yaw = float(yaw(place));
    o.position = Eigen::Vector3f(float(xy(place)), float(xy(place)), -0.3f);
    o.velocity = Eigen::Vector3f(float(0.2 * xy(place)), float(0.2 * xy(place)), 0.0f);
    if (o.position.head<2>().norm() > 3.0f) scene.objects.push_back(o);  // not on the sensor
  }
  const double t = 0.7;
  Eigen::Isometry3f pose = Eigen::Isometry3f::Identity();
  pose.translation() = Eigen::Vector3f(0.5f, -1.0f, 1.5f);
  pose.linear() = (Eigen::AngleAxisf(0.4f, Eigen::Vector3f::UnitZ()) *
                   Eigen::AngleAxisf(0.08f, Eigen::Vector3f::UnitY()) *
                   Eigen::AngleAxisf(-0.05f, Eigen::Vector3f::UnitX()))
                      .toRotationMatrix();
  const LidarModel m = LidarModel::vlp16();
  const Cloud c = render(scene, m, pose, {}, 1, t);
  const Eigen::Vector3d origin = pose.translation().cast<double>();
  std::size_t on_ground = 0, on_objects = 0, bad = 0, missing = 0;
  for (std::size_t row = 0; row < c.height; ++row) {
    for (std::size_t col = 0; col < c.width; ++col) {
      if (valid(at(c, row, col))) continue;
      // No return: then the ground must be out of range along this ray (nothing is closer).
      const double e = m.vertical_angles_deg[row] * kDeg, a = m.azimuthDeg(col) * kDeg;
      const Eigen::Vector3d dir = pose.linear().cast<double>() *
                                  Eigen::Vector3d(std::cos(e) * std::cos(a), std::cos(e) * std::sin(a), std::sin(e));
      const double ground = dir.z() < 0.0 ? (scene.ground_z - origin.z()) / dir.z() : 1e9;
      if (ground >= m.min_range_m && ground <= m.max_range_m - 1e-3) ++missing;
    }
  }
  EXPECT_EQ(missing, 0u) << "rays that should have hit at least the ground";
  for (const Point& p : c.points) {
    if (!valid(p)) continue;
    const Eigen::Vector3d w = (pose * p.getVector3fMap()).cast<double>();
    double nearest = std::abs(w.z() - scene.ground_z);
    bool ground = nearest < 2e-3;
    for (const SceneObject& o : scene.objects) nearest = std::min(nearest, std::abs(surfaceDistance(o, w, t)));
    if (nearest > 2e-3) ++bad;
    // Free space before the hit.
    for (double f : {0.25, 0.5, 0.75, 0.98}) {
      const Eigen::Vector3d q = origin + f * (w - origin);
      if (q.z() < scene.ground_z - 1e-6) ++bad;
      for (const SceneObject& o : scene.objects) bad += surfaceDistance(o, q, t) < -1e-6 ? 1 : 0;
    }
    (ground ? on_ground : on_objects)++;
  }
  EXPECT_EQ(bad, 0u);
  EXPECT_GT(on_ground, 3000u);
  EXPECT_GT(on_objects, 1000u);
}

// Distance along the horizontal ray from the origin at azimuth `a` to the closest edge of a
// yawed rectangle (footprint of a box), by segment intersection; +inf when it misses.
double rayToRectangle(double a, double cx, double cy, double l, double w, double yaw) {
  const Eigen::Vector2d d(std::cos(a), std::sin(a));
  const Eigen::Vector2d ax(std::cos(yaw), std::sin(yaw)), ay(-std::sin(yaw), std::cos(yaw));
  const Eigen::Vector2d c(cx, cy);
  const Eigen::Vector2d corners[4] = {c + 0.5 * l * ax + 0.5 * w * ay, c - 0.5 * l * ax + 0.5 * w * ay,
                                      c - 0.5 * l * ax - 0.5 * w * ay, c + 0.5 * l * ax - 0.5 * w * ay};
  double best = std::numeric_limits<double>::infinity();
  for (int i = 0; i < 4; ++i) {
    const Eigen::Vector2d p = corners[i], e = corners[(i + 1) % 4] - corners[i];
    const double den = d.x() * (-e.y()) - d.y() * (-e.x());  // solve s d = p + u e
    if (std::abs(den) < 1e-12) continue;
    const double s = (p.x() * (-e.y()) - p.y() * (-e.x())) / den;
    const double u = (d.x() * p.y() - d.y() * p.x()) / den;
    if (s > 0.0 && u >= 0.0 && u <= 1.0) best = std::min(best, s);
  }
  return best;
}

TEST(RenderScan, LongBoxYawedThirtyDegrees) {
  // A 4 x 1 box yawed +30 deg (counter-clockwise) off the x axis, compared ray by ray with a 2D
  // segment intersection; yawed the other way it would give different ranges.
  const LidarModel m = testModel();
  Scene scene;
  scene.has_ground = false;
  const double yaw = 30.0 * kDeg;
  scene.objects.push_back(box(1, 10.0f, 1.0f, Eigen::Vector3f(4.0f, 1.0f, 2.0f), float(yaw)));
  const Cloud c = render(scene, m, poseAt(0, 0, 1.0f));
  std::size_t hits = 0, asymmetric = 0;
  for (int a = -20; a <= 20; ++a) {
    const double expected = rayToRectangle(a * kDeg, 10.0, 1.0, 4.0, 1.0, yaw);
    const Point& p = at(c, kLevelRow, columnAt(m, a));
    ASSERT_EQ(valid(p), std::isfinite(expected)) << "azimuth " << a;
    if (!valid(p)) continue;
    ++hits;
    EXPECT_NEAR(rangeOf(p), expected, 1e-4) << "azimuth " << a;
    if (std::abs(expected - rayToRectangle(a * kDeg, 10.0, 1.0, 4.0, 1.0, -yaw)) > 0.05) ++asymmetric;
  }
  EXPECT_GE(hits, 10u);
  EXPECT_GE(asymmetric, 3u);  // the test tells the yaw's sign apart
}

TEST(RenderScan, BoxSpansFromItsBottomCentreUp) {
  // Bottom centre at z = 0.5, height 1: the box spans z in [0.5, 1.5]. Seen from z = 0 at
  // elevations up to 2 deg over 10 m (z < 0.37) it is missed; from z = 1 it is hit; from z = 2
  // the -2 deg beam passes over it.
  const LidarModel m = testModel();
  Scene scene;
  scene.has_ground = false;
  SceneObject o = box(1, 10.0f, 0.0f, Eigen::Vector3f(1.0f, 1.0f, 1.0f));
  o.position.z() = 0.5f;
  scene.objects.push_back(o);
  EXPECT_EQ(countValid(render(scene, m, poseAt(0, 0, 0.0f))), 0u);
  EXPECT_GT(countValid(render(scene, m, poseAt(0, 0, 1.0f))), 0u);
  EXPECT_GT(countValid(render(scene, m, poseAt(0, 0, 1.6f))), 0u);  // -2 deg: z 1.27 at 9.5 m
  EXPECT_EQ(countValid(render(scene, m, poseAt(0, 0, 2.0f))), 0u);  // -2 deg: z > 1.63 over it
}

TEST(RenderScan, SensorInsideABoxSeesItsWalls) {
  const LidarModel m = testModel();
  Scene scene;
  scene.has_ground = false;
  scene.objects.push_back(box(1, 0.0f, 0.0f, Eigen::Vector3f(20.0f, 10.0f, 4.0f)));  // a room
  const Cloud c = render(scene, m, poseAt(0, 0, 1.0f));
  EXPECT_EQ(countValid(c), c.points.size());
  EXPECT_NEAR(at(c, kLevelRow, columnAt(m, 0.0)).x, 10.0, 1e-4);
  EXPECT_NEAR(at(c, kLevelRow, columnAt(m, 90.0)).y, 5.0, 1e-4);
}

TEST(RenderScan, MinRangeHidesCloseHits) {
  LidarModel m = testModel();
  m.min_range_m = 2.0f;
  Scene scene;
  scene.has_ground = false;
  scene.objects.push_back(box(1, 2.0f, 0.0f, Eigen::Vector3f(1.0f, 1.0f, 2.0f)));  // face at 1.5 m
  const Cloud c = render(scene, m, poseAt(0, 0, 1.0f));
  EXPECT_FALSE(valid(at(c, kLevelRow, columnAt(m, 0.0))));
  m.min_range_m = 1.0f;
  EXPECT_NEAR(at(render(scene, m, poseAt(0, 0, 1.0f)), kLevelRow, columnAt(m, 0.0)).x, 1.5, 1e-4);
}

TEST(RenderScan, RobosenseM1SeesNothingBehind) {
  const LidarModel m = LidarModel::robosenseM1();
  Scene scene;  // ground plus boxes all around at 8 m
  for (int k = 0; k < 12; ++k) {
    const double a = k * 30.0 * kDeg;
    scene.objects.push_back(box(k + 1, float(8.0 * std::cos(a)), float(8.0 * std::sin(a)),
                                Eigen::Vector3f(1.0f, 1.0f, 3.0f)));
  }
  const Cloud c = render(scene, m, poseAt(0, 0, 1.0f));
  EXPECT_EQ(c.width, 601u);
  std::size_t n = 0, on_boxes = 0;
  for (const Point& p : c.points) {
    if (!valid(p)) continue;
    ++n;
    EXPECT_LE(std::abs(std::atan2(p.y, p.x)), 60.0 * kDeg + 1e-5);
    EXPECT_GT(p.x, 0.0f);
    if (p.z > -0.99f) ++on_boxes;
  }
  EXPECT_GT(n, 10000u);
  EXPECT_GT(on_boxes, 100u);
}

// ---------------------------------------------------------------------------------------------
// Motion and ground truth

TEST(SceneObject, ConstantVelocityBetweenStartAndStop) {
  SceneObject o;
  o.position = Eigen::Vector3f(1.0f, 2.0f, 0.0f);
  o.velocity = Eigen::Vector3f(1.0f, 0.5f, 0.0f);
  o.start_s = 2.0;
  o.stop_s = 5.0;
  EXPECT_TRUE(o.positionAt(0.0).isApprox(Eigen::Vector3f(1.0f, 2.0f, 0.0f)));
  EXPECT_TRUE(o.positionAt(1.9).isApprox(Eigen::Vector3f(1.0f, 2.0f, 0.0f)));
  EXPECT_TRUE(o.positionAt(3.0).isApprox(Eigen::Vector3f(2.0f, 2.5f, 0.0f)));
  EXPECT_TRUE(o.positionAt(5.0).isApprox(Eigen::Vector3f(4.0f, 3.5f, 0.0f)));
  EXPECT_TRUE(o.positionAt(9.0).isApprox(Eigen::Vector3f(4.0f, 3.5f, 0.0f)));
  EXPECT_TRUE(o.velocityAt(1.0).isZero());
  EXPECT_TRUE(o.velocityAt(2.0).isApprox(o.velocity));
  EXPECT_TRUE(o.velocityAt(4.99).isApprox(o.velocity));
  EXPECT_TRUE(o.velocityAt(5.0).isZero());
  EXPECT_TRUE(o.velocityAt(7.0).isZero());
  // Default: moves from t = 0 on, `position` is the position at t = 0.
  SceneObject d;
  d.position = Eigen::Vector3f(0.0f, 0.0f, 0.0f);
  d.velocity = Eigen::Vector3f(-2.0f, 0.0f, 0.0f);
  EXPECT_TRUE(d.positionAt(1.5).isApprox(Eigen::Vector3f(-3.0f, 0.0f, 0.0f)));
  EXPECT_TRUE(d.velocityAt(0.0).isApprox(d.velocity));
}

TEST(RenderScan, MovingObjectIsRenderedWhereItIsAtT) {
  const LidarModel m = testModel();
  Scene scene;
  scene.has_ground = false;
  SceneObject o = box(1, 10.0f, 0.0f, Eigen::Vector3f(1.0f, 1.0f, 2.0f));
  o.velocity = Eigen::Vector3f(-2.0f, 0.0f, 0.0f);  // toward the sensor
  o.stop_s = 2.0;
  scene.objects.push_back(o);
  const std::size_t col = columnAt(m, 0.0);
  EXPECT_NEAR(at(render(scene, m, poseAt(0, 0, 1.0f), {}, 1, 0.0), kLevelRow, col).x, 9.5, 1e-4);
  EXPECT_NEAR(at(render(scene, m, poseAt(0, 0, 1.0f), {}, 1, 1.0), kLevelRow, col).x, 7.5, 1e-4);
  EXPECT_NEAR(at(render(scene, m, poseAt(0, 0, 1.0f), {}, 1, 3.0), kLevelRow, col).x, 5.5, 1e-4);
}

TEST(ObjectTruths, InAFrameRotated90Degrees) {
  Scene scene;
  SceneObject o = box(7, 10.0f, 0.0f, Eigen::Vector3f(4.0f, 2.0f, 1.5f), 0.3f);
  o.type = "car";
  o.velocity = Eigen::Vector3f(1.0f, 0.0f, 0.0f);
  scene.objects.push_back(o);
  // The frame's x axis is the world's +y: world (x, y) -> frame (y, -x), then shifted.
  Eigen::Isometry3f world_to_frame = Eigen::Isometry3f::Identity();
  world_to_frame.linear() = Eigen::AngleAxisf(float(-M_PI / 2), Eigen::Vector3f::UnitZ()).toRotationMatrix();
  world_to_frame.translation() = Eigen::Vector3f(1.0f, 2.0f, -0.5f);
  const std::vector<ObjectTruth> truths = objectTruths(scene, 2.0, world_to_frame);
  ASSERT_EQ(truths.size(), 1u);
  const ObjectTruth& tr = truths[0];
  EXPECT_EQ(tr.id, 7u);
  EXPECT_EQ(tr.type, "car");
  EXPECT_TRUE(tr.size.isApprox(Eigen::Vector3f(4.0f, 2.0f, 1.5f)));
  // Bottom centre at t = 2 is (12, 0, 0); the centre is 0.75 higher.
  EXPECT_NEAR(tr.center.x(), 0.0 + 1.0, 1e-5);
  EXPECT_NEAR(tr.center.y(), -12.0 + 2.0, 1e-5);
  EXPECT_NEAR(tr.center.z(), 0.75 - 0.5, 1e-5);
  EXPECT_NEAR(tr.velocity.x(), 0.0, 1e-6);
  EXPECT_NEAR(tr.velocity.y(), -1.0, 1e-6);  // translation does not touch velocity
  EXPECT_NEAR(tr.velocity.z(), 0.0, 1e-6);
  EXPECT_NEAR(tr.yaw, 0.3 - M_PI / 2, 1e-6);
  // Identity frame: the world values.
  const ObjectTruth w = objectTruths(scene, 0.0, Eigen::Isometry3f::Identity())[0];
  EXPECT_TRUE(w.center.isApprox(Eigen::Vector3f(10.0f, 0.0f, 0.75f)));
  EXPECT_NEAR(w.yaw, 0.3, 1e-6);
}

TEST(ObjectTruths, YawWrapsIntoMinusPiPi) {
  Scene scene;
  scene.objects.push_back(box(1, 0.0f, 0.0f, Eigen::Vector3f(1.0f, 1.0f, 1.0f), float(0.9 * M_PI)));
  Eigen::Isometry3f rot = Eigen::Isometry3f::Identity();
  rot.linear() = Eigen::AngleAxisf(float(0.2 * M_PI), Eigen::Vector3f::UnitZ()).toRotationMatrix();
  EXPECT_NEAR(objectTruths(scene, 0.0, rot)[0].yaw, -0.9 * M_PI, 1e-5);
}

// ---------------------------------------------------------------------------------------------
// Noise and determinism

Scene noiseScene() {
  Scene scene;  // ground plus a ring of walls
  for (int k = 0; k < 8; ++k) {
    const double a = k * 45.0 * kDeg;
    scene.objects.push_back(box(k + 1, float(15.0 * std::cos(a)), float(15.0 * std::sin(a)),
                                Eigen::Vector3f(2.0f, 8.0f, 4.0f), float(a)));
  }
  return scene;
}

TEST(Noise, GaussianRangeNoiseHasTheRequestedStd) {
  const LidarModel m = LidarModel::vlp16();
  const Scene scene = noiseScene();
  const Cloud clean = render(scene, m, poseAt(0, 0, 1.73f));
  NoiseParams noise;
  noise.range_std_m = 0.05f;
  const Cloud noisy = render(scene, m, poseAt(0, 0, 1.73f), noise, 42);
  double sum = 0.0, sum_sq = 0.0;
  std::size_t n = 0;
  for (std::size_t i = 0; i < clean.points.size(); ++i) {
    ASSERT_EQ(valid(clean.points[i]), valid(noisy.points[i]));
    if (!valid(clean.points[i])) continue;
    const double e = rangeOf(noisy.points[i]) - rangeOf(clean.points[i]);
    sum += e;
    sum_sq += e * e;
    ++n;
    // Noise is along the ray: the direction is unchanged.
    const double rn = rangeOf(noisy.points[i]), rc = rangeOf(clean.points[i]);
    EXPECT_NEAR(noisy.points[i].x / rn, clean.points[i].x / rc, 1e-5);
  }
  ASSERT_GT(n, 10000u);
  const double mean = sum / n;
  const double std = std::sqrt(sum_sq / n - mean * mean);
  EXPECT_NEAR(std, 0.05, 0.0025);  // within 5% (sampling error ~0.6% here)
  EXPECT_NEAR(mean, 0.0, 0.002);
}

TEST(Noise, DropoutLosesThatShareOfReturns) {
  const LidarModel m = LidarModel::vlp16();
  const Scene scene = noiseScene();
  const Cloud clean = render(scene, m, poseAt(0, 0, 1.73f));
  NoiseParams noise;
  noise.dropout_prob = 0.3f;
  const Cloud dropped = render(scene, m, poseAt(0, 0, 1.73f), noise, 7);
  const std::size_t before = countValid(clean), after = countValid(dropped);
  ASSERT_GT(before, 10000u);
  EXPECT_NEAR(1.0 - double(after) / before, 0.3, 0.02);
  // The surviving returns are untouched and nothing appears where there was none.
  for (std::size_t i = 0; i < clean.points.size(); ++i) {
    if (!valid(dropped.points[i])) continue;
    ASSERT_TRUE(valid(clean.points[i]));
    EXPECT_EQ(dropped.points[i].x, clean.points[i].x);
  }
}

TEST(Noise, SpuriousReturnsAppearOnEmptyRays) {
  const LidarModel m = LidarModel::vlp16();
  Scene empty;
  empty.has_ground = false;
  EXPECT_EQ(countValid(render(empty, m, poseAt(0, 0, 1.73f))), 0u);
  NoiseParams noise;
  noise.spurious_prob = 0.1f;
  const Cloud c = render(empty, m, poseAt(0, 0, 1.73f), noise, 3);
  const double share = double(countValid(c)) / c.points.size();
  EXPECT_NEAR(share, 0.1, 0.01);
  double sum = 0.0;
  for (const Point& p : c.points) {
    if (!valid(p)) continue;
    const double r = rangeOf(p);
    EXPECT_GE(r, m.min_range_m - 1e-4);
    EXPECT_LE(r, 30.0 + 1e-4);
    sum += r;
  }
  EXPECT_NEAR(sum / countValid(c), 0.5 * (0.5 + 30.0), 1.0);  // uniform in [min, 30]
  // Spurious returns are not subject to dropout.
  NoiseParams with_dropout = noise;
  with_dropout.dropout_prob = 0.5f;
  const Cloud d = render(empty, m, poseAt(0, 0, 1.73f), with_dropout, 3);
  EXPECT_NEAR(double(countValid(d)) / d.points.size(), 0.1, 0.01);
  // Over the ground, rays above the horizon (empty without noise) now return sometimes.
  Scene ground;
  const Cloud g = render(ground, m, poseAt(0, 0, 1.73f), noise, 3);
  std::size_t upper = 0;
  for (std::size_t row = 0; row < 8; ++row) {  // +15 .. +1 deg
    for (std::size_t col = 0; col < g.width; ++col) upper += valid(at(g, row, col)) ? 1 : 0;
  }
  EXPECT_NEAR(double(upper) / (8.0 * g.width), 0.1, 0.015);
}

TEST(Noise, SameSeedSameCloudOtherSeedOtherCloud) {
  const LidarModel m = LidarModel::vlp16();
  const Scene scene = noiseScene();
  NoiseParams noise;
  noise.range_std_m = 0.02f;
  noise.dropout_prob = 0.05f;
  noise.spurious_prob = 0.01f;
  const Cloud a = render(scene, m, poseAt(0, 0, 1.73f), noise, 11);
  const Cloud b = render(scene, m, poseAt(0, 0, 1.73f), noise, 11);
  const Cloud c = render(scene, m, poseAt(0, 0, 1.73f), noise, 12);
  std::size_t differ_ab = 0, differ_ac = 0;
  auto same = [](const Point& p, const Point& q) {
    if (!valid(p) || !valid(q)) return valid(p) == valid(q);
    return p.x == q.x && p.y == q.y && p.z == q.z;
  };
  for (std::size_t i = 0; i < a.points.size(); ++i) {
    differ_ab += same(a.points[i], b.points[i]) ? 0 : 1;
    differ_ac += same(a.points[i], c.points[i]) ? 0 : 1;
  }
  EXPECT_EQ(differ_ab, 0u);
  EXPECT_GT(differ_ac, 1000u);
}

TEST(Noise, RejectsBadParameters) {
  const LidarModel m = testModel();
  Scene scene;
  NoiseParams bad;
  bad.dropout_prob = 1.5f;
  std::mt19937_64 rng(1);
  Cloud c;
  EXPECT_THROW(renderScan(scene, 0.0, poseAt(0, 0, 1), m, bad, rng, c), std::invalid_argument);
  LidarModel none = m;
  none.vertical_angles_deg.clear();
  EXPECT_THROW(renderScan(scene, 0.0, poseAt(0, 0, 1), none, {}, rng, c), std::invalid_argument);
}

// ---------------------------------------------------------------------------------------------
// Performance: one HDL-64E scan with ~20 objects.

TEST(RenderScan, Hdl64eScanIsFast) {
  const LidarModel m = LidarModel::hdl64e();
  Scene scene;
  std::mt19937_64 place(5);
  std::uniform_real_distribution<float> xy(-40.0f, 40.0f), yaw(-3.14f, 3.14f);
  for (int k = 0; k < 20; ++k) {
    if (k % 2) scene.objects.push_back(cylinder(k + 1, xy(place), xy(place), 0.6f, 1.8f));
    else scene.objects.push_back(box(k + 1, xy(place), xy(place), Eigen::Vector3f(4.5f, 1.9f, 1.5f), yaw(place)));
  }
  NoiseParams noise;
  noise.range_std_m = 0.02f;
  std::mt19937_64 rng(1);
  Cloud c;
  renderScan(scene, 0.0, poseAt(0, 0, 1.73f), m, noise, rng, c);  // warm-up
  const int reps = 5;
  const auto t0 = std::chrono::steady_clock::now();
  for (int i = 0; i < reps; ++i) renderScan(scene, 0.1 * i, poseAt(0, 0, 1.73f), m, noise, rng, c);
  const double ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count() / reps;
  std::cout << "[ timing   ] HDL-64E scan (" << c.points.size() << " rays, 20 objects): " << ms
            << " ms\n";
  RecordProperty("hdl64e_scan_ms", std::to_string(ms));
  EXPECT_GT(countValid(c), 50000u);
#if !defined(__SANITIZE_ADDRESS__)
  EXPECT_LT(ms, 250.0) << "far slower than the 50 ms budget";  // loose: shared CI machines
#endif
}

}  // namespace
}  // namespace sim
}  // namespace icanc
