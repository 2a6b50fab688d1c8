// dropGrazingColumnBoxes: the classic chain's boxes that are one column of the scan on a surface
// seen at grazing incidence.
#include "icanc/core/perception/grazing_columns.hpp"

#include <algorithm>
#include <cmath>
#include <random>
#include <string>

#include <gtest/gtest.h>

#include "icanc/core/common/yaml_params.hpp"
#include "icanc/core/perception/obstacle_detector.hpp"
#include "icanc/sim/lidar_sim.hpp"
#include "scene_objects.hpp"

namespace icanc {
namespace {

std::string configDir() {
  const std::string here = __FILE__;
  return here.substr(0, here.rfind("/test/core/")) + "/config/";
}

// A vertical line at (x, y), top at `top` (a column of the scan).
Box3D column(float x, float y, float top) {
  Box3D b;
  b.center = {x, y, 0.5f * top};
  b.min = {x, y, 0.3f};
  b.max = {x, y, top};
  b.size = {0.0f, 0.0f, top - 0.3f};
  b.hull = {{x, y}};
  b.num_points = 12;
  return b;
}

// An axis-aligned block seen from above, its top at `top`.
Box3D block(float x0, float y0, float x1, float y1, float top) {
  Box3D b;
  b.min = {x0, y0, 0.3f};
  b.max = {x1, y1, top};
  b.center = 0.5f * (b.min + b.max);
  b.size = b.max - b.min;
  b.hull = {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}};
  b.num_points = 200;
  return b;
}

TEST(GrazingColumns, ColumnContinuedAlongItsLineOfSightIsDropped) {
  const Eigen::Vector2f origin = Eigen::Vector2f::Zero();
  GrazingColumnParams params;
  // The car's side on y = -3.05, its rear at x 12: a column of the side at 15 m (line of sight
  // 11.5 deg off the side) and the rest of the side from 15.6 m on.
  std::vector<Box3D> boxes = {column(15.0f, -3.05f, 1.45f), block(15.6f, -4.9f, 17.0f, -3.05f, 1.5f)};
  EXPECT_EQ(dropGrazingColumnBoxes(boxes, origin, params), 1u);
  ASSERT_EQ(boxes.size(), 1u);
  EXPECT_EQ(boxes[0].num_points, 200);

  // Behind it along the line of sight counts the same way (the rest of the side nearer).
  boxes = {column(15.0f, -3.05f, 1.45f), block(13.0f, -4.9f, 14.4f, -2.6f, 1.5f)};
  EXPECT_EQ(dropGrazingColumnBoxes(boxes, origin, params), 1u);

  // A neighbouring column, itself dropped, still holds the first one up: both go.
  boxes = {column(15.0f, -3.05f, 1.45f), column(16.0f, -3.05f, 1.4f)};
  EXPECT_EQ(dropGrazingColumnBoxes(boxes, origin, params), 2u);
  EXPECT_TRUE(boxes.empty());
}

TEST(GrazingColumns, OthersStay) {
  const Eigen::Vector2f origin = Eigen::Vector2f::Zero();
  GrazingColumnParams params;
  const Box3D side = block(15.6f, -4.9f, 17.0f, -3.05f, 1.5f);
  // A pole (3 m) in line with the car's side: its top is not the car's.
  std::vector<Box3D> boxes = {column(15.0f, -3.05f, 3.0f), side};
  EXPECT_EQ(dropGrazingColumnBoxes(boxes, origin, params), 0u);
  // A pedestrian beside the car, across the line of sight (1 m to its left): not along it.
  boxes = {column(16.3f, -2.0f, 1.45f), side};
  EXPECT_EQ(dropGrazingColumnBoxes(boxes, origin, params), 0u);
  // Further than reach_m along the line of sight.
  boxes = {column(12.0f, -2.45f, 1.45f), side};
  EXPECT_EQ(dropGrazingColumnBoxes(boxes, origin, params), 0u);
  // Alone.
  boxes = {column(15.0f, -3.05f, 1.45f)};
  EXPECT_EQ(dropGrazingColumnBoxes(boxes, origin, params), 0u);
  // Not one line of sight: 0.3 m across it.
  Box3D wide = column(15.0f, -3.05f, 1.45f);
  wide.hull = {{15.0f, -3.2f}, {15.0f, -2.9f}};
  boxes = {wide, side};
  EXPECT_EQ(dropGrazingColumnBoxes(boxes, origin, params), 0u);
  // The rule off.
  params.reach_m = 0.0f;
  boxes = {column(15.0f, -3.05f, 1.45f), side};
  EXPECT_EQ(dropGrazingColumnBoxes(boxes, origin, params), 0u);
  EXPECT_EQ(boxes.size(), 2u);
}

TEST(GrazingColumns, ParametersAreValidated) {
  GrazingColumnParams p;
  EXPECT_EQ(validate(p, "cluster."), "");
  p.reach_m = -1.0f;
  EXPECT_EQ(validate(p, "cluster."), "cluster.grazing_reach_m must be in [0, 10] (got -1)");
  p = GrazingColumnParams();
  p.angle_deg = 90.0f;
  EXPECT_EQ(validate(p, "cluster."), "cluster.grazing_angle_deg must be in [0, 90) (got 90)");
  p = GrazingColumnParams();
  p.max_step_m = NAN;
  EXPECT_NE(validate(p, "cluster."), "");
  ClusterParams cluster;
  cluster.grazing.angle_deg = -5.0f;
  EXPECT_EQ(validate(cluster), "cluster.grazing_angle_deg must be in [0, 90) (got -5)");
}

// The shipped CARLA profile's classic chain (voxel grid 0.2 m, clusters at 0.6 m) along a
// façade 6 m to the side with the paper's 128-beam unit (500 columns, 0.72 deg): from about 17 m
// on, its columns land further apart than 0.6 m, and each (2.7 m tall up to the region's top,
// about 13 voxels) was a box of its own at its column's bearing, which travels with the vehicle
// (night_town_street: buildings' speed over ground p90 4-13 m/s). Now no box on the façade within
// 30 m is one line of sight, no other box is lost, and a pedestrian standing in front of it keeps
// the box it had: its top is not the façade's.
TEST(GrazingColumns, ClassicChainGivesNoColumnBoxesOnAFacade) {
  const Profile profile = loadProfile(configDir() + "carla_model3.yaml");
  ObstacleDetectorParams on = profile.detector, off = profile.detector;
  on.method = off.method = DetectorMethod::kClassic;
  off.cluster.grazing.reach_m = 0.0f;
  ObstacleDetector with_rule(on), without_rule(off);
  sim::Scene scene;
  // The façade's face on y = -6, x 0..40; the pedestrian 0.45 m in front of it.
  scene.objects = {test_scene::block("building", {40.0f, 10.0f, 9.0f}, {20.0f, -11.0f, 0.0f}),
                   test_scene::cylinder("pedestrian", 0.5f, 1.75f, {22.0f, -5.3f, 0.0f})};
  sim::NoiseParams noise;
  noise.range_std_m = 0.02f;  // the scenarios'
  const auto onFacade = [](const Box3D& b) { return b.max.y() < -5.8f; };
  const auto oneLineOfSight = [](const Box3D& b) {  // within 0.1 m across it, 1 m along it
    const Eigen::Vector2f u = b.center.head<2>().normalized();
    float lo = 1e9f, hi = -1e9f, near = 1e9f, far = -1e9f;
    for (const Eigen::Vector2f& v : b.hull) {
      lo = std::min(lo, u.x() * v.y() - u.y() * v.x());
      hi = std::max(hi, u.x() * v.y() - u.y() * v.x());
      near = std::min(near, u.dot(v));
      far = std::max(far, u.dot(v));
    }
    return hi - lo <= 0.1f && far - near <= 1.0f;
  };
  int columns_before = 0, walkers = 0;
  for (float sensor_x = 0.0f; sensor_x <= 8.0f; sensor_x += 0.5f) {
    std::mt19937_64 rng(13);
    Cloud scan, cloud;
    Eigen::Isometry3f pose = Eigen::Isometry3f::Identity();
    pose.translation() = Eigen::Vector3f(sensor_x, 0.0f, 1.8f);
    sim::renderScan(scene, 0.0, pose, sim::LidarModel::carla128(), noise, rng, scan);
    for (const Point& p : scan)  // base_link: the road at z = 0
      if (std::isfinite(p.x)) cloud.push_back(Point(p.x, p.y, p.z + 1.8f));
    without_rule.process(sensor_x, cloud);
    for (const Box3D& b : without_rule.detections())
      columns_before += onFacade(b) && oneLineOfSight(b) && b.center.x() <= 30.0f;
    with_rule.process(sensor_x, cloud);
    for (const Box3D& b : with_rule.detections()) {
      // Within 30 m: further on, the columns on a face 6 m aside land more than reach_m (2.5 m)
      // apart (2.7 m at 36 m), and stay.
      if (!onFacade(b) || b.center.x() > 30.0f) continue;
      EXPECT_FALSE(oneLineOfSight(b)) << "sensor at " << sensor_x << ": a column at "
                                      << b.center.transpose() << ", " << b.num_points << " points";
    }
    // Nothing but columns went: every other box is still there.
    for (const Box3D& b : without_rule.detections()) {
      if (oneLineOfSight(b)) continue;
      bool kept = false;
      for (const Box3D& a : with_rule.detections())
        kept = kept || (a.num_points == b.num_points && (a.center - b.center).norm() < 1e-4f);
      EXPECT_TRUE(kept) << "sensor at " << sensor_x << ": lost the box at " << b.center.transpose();
    }
    const float walker_x = 22.0f - sensor_x;
    for (const Box3D& b : without_rule.detections()) {
      if (std::hypot(b.center.x() - walker_x, b.center.y() + 5.3f) > 0.4f) continue;
      ++walkers;
      bool kept = false;
      for (const Box3D& a : with_rule.detections())
        kept = kept || (a.num_points == b.num_points && (a.center - b.center).norm() < 1e-4f);
      EXPECT_TRUE(kept) << "pedestrian " << walker_x << " m ahead";
    }
  }
  EXPECT_GT(columns_before, 20);  // without the rule the façade's far part fell apart into columns
  EXPECT_GT(walkers, 10);
}

}  // namespace
}  // namespace icanc
