// FastDetector (detector.method "fast"): ground removed on flat roads and followed up slopes,
// objects found on a slope, objects separated by the grid, organized and unorganized clouds alike,
// no buffer growth in steady state, empty / NaN input, parameter checks, and its wiring into
// ObstacleDetector and the YAML profile.
#include "icanc/core/perception/fast_detector.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <random>

#include <gtest/gtest.h>
#include <unistd.h>

#include "icanc/core/perception/cloud_decode.hpp"
#include "icanc/core/perception/obstacle_detector.hpp"
#include "icanc/core/common/yaml_params.hpp"
#include "icanc/sim/lidar_sim.hpp"
#include "scene_objects.hpp"

namespace icanc {
namespace {

CloudPrepParams roiAndEgo(const Eigen::Vector3f& roi_min, const Eigen::Vector3f& roi_max,
                          const Eigen::Vector3f& ego_min, const Eigen::Vector3f& ego_max) {
  CloudPrepParams prep;
  prep.roi_min = roi_min;
  prep.roi_max = roi_max;
  prep.ego_min = ego_min;
  prep.ego_max = ego_max;
  prep.voxel_leaf_m = 0.0f;  // the classic chain's voxel grid: the fast detector reads every point
  return prep;
}

CloudPrepParams wideRoi() {
  return roiAndEgo({-20.0f, -20.0f, -5.0f}, {60.0f, 20.0f, 12.0f}, {-1.0f, -1.0f, -3.0f},
                   {1.0f, 1.0f, 3.0f});
}

// Road surface z = height(x, y) sampled on a 0.2 m grid within `radius` of the origin.
template <class Height>
void addGround(Cloud& cloud, float radius, Height height) {
  for (float x = -radius; x <= radius; x += 0.2f)
    for (float y = -radius; y <= radius; y += 0.2f)
      if (std::hypot(x, y) <= radius) cloud.push_back(Point(x, y, height(x, y)));
}

// Solid block of points from `lo` to `hi` on a `step` grid.
void addBlock(Cloud& cloud, const Eigen::Vector3f& lo, const Eigen::Vector3f& hi, float step) {
  for (float x = lo.x(); x <= hi.x() + 1e-4f; x += step)
    for (float y = lo.y(); y <= hi.y() + 1e-4f; y += step)
      for (float z = lo.z(); z <= hi.z() + 1e-4f; z += step) cloud.push_back(Point(x, y, z));
}

const float kFlat = -1.7f;
float slope(float x) {  // flat to 10 m, then up at 8 degrees (a steep street)
  return x < 10.0f ? kFlat : kFlat + (x - 10.0f) * std::tan(8.0f * static_cast<float>(M_PI) / 180.0f);
}

TEST(FastDetector, FlatGroundIsRemoved) {
  Cloud cloud;
  addGround(cloud, 40.0f, [](float, float) { return kFlat; });
  FastDetector detector(wideRoi(), FastDetectorParams());
  std::vector<Box3D> boxes;
  detector.detect(cloud, boxes);
  EXPECT_GT(detector.keptPoints(), 50000u);
  EXPECT_EQ(detector.obstaclePoints(), 0u);
  EXPECT_TRUE(boxes.empty());
  EXPECT_NEAR(detector.groundAt(20.0f, 5.0f), kFlat, 1e-4f);
}

// A return below the floor (multipath, or a spurious range past the surface: the simulator's
// spurious_prob) used to drag its polar cell's ground down, so the floor around it, 0.3 m above
// that false ground, became a flat "obstacle" (pedestrian_far_away through the fast path: boxes
// 0.01 m high over a ground of -0.4 m, 9 false danger frames).
TEST(FastDetector, OneReturnBelowTheFloorDoesNotTurnTheFloorIntoAnObstacle) {
  Cloud cloud;
  addGround(cloud, 40.0f, [](float, float) { return kFlat; });
  const std::vector<Eigen::Vector2f> holes = {{8.0f, -3.0f}, {15.0f, 6.0f}, {25.0f, 0.5f}};
  for (const auto& at : holes) cloud.push_back(Point(at.x(), at.y(), kFlat - 0.45f));
  FastDetector detector(wideRoi(), FastDetectorParams());
  std::vector<Box3D> boxes;
  detector.detect(cloud, boxes);
  EXPECT_TRUE(boxes.empty());
  EXPECT_EQ(detector.obstaclePoints(), 0u);
  for (const auto& at : holes) EXPECT_NEAR(detector.groundAt(at.x(), at.y()), kFlat, 1e-4f);

  // A real dip (a whole polar cell lower) is still followed.
  Cloud dip;
  addGround(dip, 40.0f, [](float x, float y) {
    return std::hypot(x - 20.0f, y) < 2.0f ? kFlat - 0.25f : kFlat;
  });
  detector.detect(dip, boxes);
  EXPECT_TRUE(boxes.empty());
  EXPECT_NEAR(detector.groundAt(20.0f, 0.0f), kFlat - 0.25f, 1e-4f);
}

TEST(FastDetector, GroundFollowsASlopeThatOnePlaneCannotFit) {
  Cloud cloud;
  addGround(cloud, 40.0f, [](float x, float) { return slope(x); });
  FastDetector detector(wideRoi(), FastDetectorParams());
  std::vector<Box3D> boxes;
  detector.detect(cloud, boxes);
  EXPECT_EQ(detector.obstaclePoints(), 0u);  // 30 m up the slope the road is 2.8 m higher
  EXPECT_TRUE(boxes.empty());
  EXPECT_NEAR(detector.groundAt(35.0f, 0.0f), slope(35.0f), 0.3f);

  // The same road seen by the classic chain's single RANSAC plane leaves the far slope as
  // obstacles: this is the case the polar ground is for.
  ObstacleDetectorParams classic;
  classic.prep = wideRoi();
  classic.ground.expected_height_m = kFlat;  // the sensor's frame
  classic.cluster.max_points = 1000000;
  ObstacleDetector reference(classic);
  reference.process(0.0, cloud);
  EXPECT_FALSE(reference.detections().empty());
}

TEST(FastDetector, PedestrianOnTheSlopeIsFound) {
  Cloud cloud;
  addGround(cloud, 40.0f, [](float x, float) { return slope(x); });
  const float base = slope(30.0f);
  addBlock(cloud, {29.8f, 4.8f, base + 0.1f}, {30.2f, 5.2f, base + 1.7f}, 0.1f);
  FastDetector detector(wideRoi(), FastDetectorParams());
  std::vector<Box3D> boxes;
  detector.detect(cloud, boxes);
  ASSERT_EQ(boxes.size(), 1u);
  EXPECT_NEAR(boxes[0].center.x(), 30.0f, 0.1f);
  EXPECT_NEAR(boxes[0].center.y(), 5.0f, 0.1f);
  EXPECT_NEAR(boxes[0].max.z(), base + 1.7f, 1e-3f);
  // Points below obstacle_height_m above the ground belong to the road.
  EXPECT_GE(boxes[0].min.z(), base + 0.3f - 0.15f);
}

TEST(FastDetector, ObjectsApartAreSeparateAndTouchingOnesJoin) {
  const float z0 = kFlat + 0.4f, z1 = kFlat + 1.5f;
  Cloud apart;
  addGround(apart, 30.0f, [](float, float) { return kFlat; });
  addBlock(apart, {10.0f, 0.0f, z0}, {11.0f, 1.0f, z1}, 0.1f);
  addBlock(apart, {12.0f, 0.0f, z0}, {14.0f, 2.0f, z1}, 0.1f);  // 1 m gap
  FastDetector detector(wideRoi(), FastDetectorParams());
  std::vector<Box3D> boxes;
  detector.detect(apart, boxes);
  ASSERT_EQ(boxes.size(), 2u);
  EXPECT_GT(boxes[0].num_points, boxes[1].num_points);  // largest first
  EXPECT_NEAR(boxes[0].center.x(), 13.0f, 0.05f);
  EXPECT_NEAR(boxes[0].size.x(), 2.0f, 0.05f);
  EXPECT_NEAR(boxes[1].center.x(), 10.5f, 0.05f);

  Cloud touching;
  addGround(touching, 30.0f, [](float, float) { return kFlat; });
  addBlock(touching, {10.0f, 0.0f, z0}, {11.0f, 1.0f, z1}, 0.1f);
  addBlock(touching, {11.4f, 0.0f, z0}, {13.0f, 1.0f, z1}, 0.1f);  // 0.4 m gap < link_m
  detector.detect(touching, boxes);
  ASSERT_EQ(boxes.size(), 1u);
  EXPECT_NEAR(boxes[0].size.x(), 3.0f, 0.05f);

  FastDetectorParams tight;  // linking only the 8 neighbours: 0.4 m is then a gap
  tight.link_m = 0.0f;
  tight.cell_m = 0.2f;
  FastDetector split(wideRoi(), tight);
  split.detect(touching, boxes);
  EXPECT_EQ(boxes.size(), 2u);
}

// A pedestrian (top 1.7 m above the road) against a 32 m hedge or wall (2.4 m),
// no gap between them, is its own obstacle; with link_max_step_m 0 (no height check) the two join,
// as KITTI 0000's pedestrian 12 joined the 22-37 m hedge beside it in 11 of 16 frames.
TEST(FastDetector, PedestrianAgainstATallerWallStaysApart) {
  Cloud cloud;
  addGround(cloud, 30.0f, [](float, float) { return kFlat; });
  addBlock(cloud, {2.0f, -6.5f, kFlat + 0.4f}, {34.0f, -6.1f, kFlat + 2.4f}, 0.2f);  // wall
  addBlock(cloud, {11.0f, -5.9f, kFlat + 0.4f}, {11.4f, -5.5f, kFlat + 1.7f}, 0.1f);  // walker
  std::vector<Box3D> boxes;
  FastDetector detector(wideRoi(), FastDetectorParams());
  detector.detect(cloud, boxes);
  ASSERT_EQ(boxes.size(), 2u);
  EXPECT_NEAR(boxes[1].center.x(), 11.2f, 0.1f);
  EXPECT_NEAR(boxes[1].center.y(), -5.7f, 0.1f);
  EXPECT_NEAR(boxes[0].size.x(), 32.0f, 0.1f);  // the wall whole

  // A car (hood 0.9 m, roof 1.5 m), shorter than step_check_min_extent_m, is not checked: whole.
  Cloud car;
  addGround(car, 30.0f, [](float, float) { return kFlat; });
  addBlock(car, {10.0f, 2.0f, kFlat + 0.4f}, {11.0f, 3.8f, kFlat + 0.9f}, 0.1f);   // hood
  addBlock(car, {11.1f, 2.0f, kFlat + 0.4f}, {14.5f, 3.8f, kFlat + 1.5f}, 0.1f);   // cabin
  detector.detect(car, boxes);
  ASSERT_EQ(boxes.size(), 1u);
  EXPECT_NEAR(boxes[0].size.x(), 4.5f, 0.1f);

  FastDetectorParams no_check;
  no_check.link_max_step_m = 0.0f;
  FastDetector joined(wideRoi(), no_check);
  joined.detect(cloud, boxes);
  EXPECT_EQ(boxes.size(), 1u);
}

// Two walkers side by side 0.3 m apart (mount_robot16_clutter's pair) fall
// into touching cells of the 0.25 m grid, so link_m makes them one box; with link_gap_m the
// cells link only where their points come within 0.25 m: two boxes. A car whose hood and cabin
// are 0.3 m apart (glass without returns) is larger than link_gap_max_extent_m and stays whole;
// without that limit it falls apart too.
TEST(FastDetector, PointGapPartsWalkersSideBySideButNotACar) {
  Cloud cloud;
  addGround(cloud, 30.0f, [](float, float) { return kFlat; });
  addBlock(cloud, {8.0f, 0.0f, kFlat + 0.4f}, {8.4f, 0.4f, kFlat + 1.7f}, 0.05f);  // walker
  addBlock(cloud, {8.0f, 0.7f, kFlat + 0.4f}, {8.4f, 1.1f, kFlat + 1.65f}, 0.05f);  // walker
  addBlock(cloud, {10.0f, 3.0f, kFlat + 0.4f}, {11.0f, 4.8f, kFlat + 0.9f}, 0.1f);  // hood
  addBlock(cloud, {11.3f, 3.0f, kFlat + 0.4f}, {14.5f, 4.8f, kFlat + 1.5f}, 0.1f);  // cabin
  const auto walkersAndCars = [](const std::vector<Box3D>& boxes, int& walkers, int& cars) {
    walkers = cars = 0;
    for (const Box3D& b : boxes) {
      if (b.center.x() < 9.0f) ++walkers;
      else ++cars;
    }
  };
  std::vector<Box3D> boxes;
  int walkers = 0, cars = 0;
  FastDetector shipped(wideRoi(), FastDetectorParams());
  shipped.detect(cloud, boxes);
  walkersAndCars(boxes, walkers, cars);
  EXPECT_EQ(walkers, 1);  // one box for the pair
  EXPECT_EQ(cars, 1);

  FastDetectorParams gap;
  gap.link_gap_m = 0.25f;
  FastDetector parted(wideRoi(), gap);
  parted.detect(cloud, boxes);
  walkersAndCars(boxes, walkers, cars);
  EXPECT_EQ(walkers, 2);
  EXPECT_EQ(cars, 1);
  for (const Box3D& b : boxes) {
    if (b.center.x() > 9.0f) EXPECT_NEAR(b.size.x(), 4.5f, 0.1f);  // the car whole
    else EXPECT_LT(b.size.y(), 0.5f);                              // each walker alone
  }

  gap.link_gap_max_extent_m = 100.0f;  // every component
  FastDetector every(wideRoi(), gap);
  every.detect(cloud, boxes);
  walkersAndCars(boxes, walkers, cars);
  EXPECT_EQ(walkers, 2);
  EXPECT_EQ(cars, 2);  // hood and cabin
}

TEST(FastDetector, ClusterSizeLimitsApply) {
  Cloud cloud;
  addGround(cloud, 30.0f, [](float, float) { return kFlat; });
  addBlock(cloud, {10.0f, 0.0f, kFlat + 0.5f}, {10.2f, 0.2f, kFlat + 0.7f}, 0.1f);  // 27 points
  FastDetectorParams params;
  params.min_points = 28;
  FastDetector small(wideRoi(), params);
  std::vector<Box3D> boxes;
  small.detect(cloud, boxes);
  EXPECT_TRUE(boxes.empty());
  params.min_points = 27;
  FastDetector enough(wideRoi(), params);
  enough.detect(cloud, boxes);
  ASSERT_EQ(boxes.size(), 1u);
  EXPECT_EQ(boxes[0].num_points, 27);
  params.min_points = 1;
  params.max_points = 26;
  FastDetector large(wideRoi(), params);
  large.detect(cloud, boxes);
  EXPECT_TRUE(boxes.empty());
}

sim::Scene street() {
  sim::Scene scene;
  scene.ground_z = 0.0f;
  sim::SceneObject car;
  car.type = "car";
  car.size = {4.5f, 1.8f, 1.5f};
  car.position = {15.0f, 3.0f, 0.0f};
  car.yaw = -0.3f;  // the long side faces the sensor (at grazing angles it breaks up)
  sim::SceneObject walker;
  walker.type = "pedestrian";
  walker.shape = sim::Shape::kCylinder;
  walker.size = {0.5f, 0.5f, 1.7f};
  walker.position = {8.0f, -4.0f, 0.0f};
  scene.objects = {car, walker};
  return scene;
}

Cloud renderStreet() {
  std::mt19937_64 rng(7);
  Cloud organized;
  Eigen::Isometry3f pose = Eigen::Isometry3f::Identity();
  pose.translation() = Eigen::Vector3f(0.0f, 0.0f, 1.73f);  // roof sensor; cloud in sensor frame
  sim::renderScan(street(), 0.0, pose, sim::LidarModel::hdl64e(), sim::NoiseParams(), rng,
                  organized);
  return organized;
}

// A scan from `height` above the road at (sensor_x, 0), in base_link (the road at z = 0).
Cloud renderMounted(const sim::Scene& scene, const sim::LidarModel& model, float sensor_x,
                    float height, unsigned seed) {
  std::mt19937_64 rng(seed);
  Cloud scan, cloud;
  Eigen::Isometry3f pose = Eigen::Isometry3f::Identity();
  pose.translation() = Eigen::Vector3f(sensor_x, 0.0f, height);
  sim::renderScan(scene, 0.0, pose, model, sim::NoiseParams(), rng, scan);
  for (const Point& p : scan)
    if (std::isfinite(p.x)) cloud.push_back(Point(p.x, p.y, p.z + height));
  return cloud;
}

// A 32-beam unit 1.9 m up (mount_roof32_clutter), with the carla_model3
// profile's ROI.
Cloud renderRoof32(const sim::Scene& scene, float sensor_x) {
  return renderMounted(scene, sim::LidarModel::hdl32e(), sensor_x, 1.9f, 11);
}

CloudPrepParams roofRoi() {  // carla_model3's
  return roiAndEgo({-10.0f, -20.0f, -0.5f}, {60.0f, 20.0f, 3.0f}, {-2.5f, -1.05f, -0.5f},
                   {2.5f, 1.05f, 1.6f});
}

using test_scene::block;
using test_scene::cylinder;

// The box whose centre is nearest (x, y), if within `tolerance`.
const Box3D* boxAt(const std::vector<Box3D>& boxes, float x, float y, float tolerance) {
  const Box3D* nearest = nullptr;
  for (const Box3D& b : boxes) {
    const float d = std::hypot(b.center.x() - x, b.center.y() - y);
    if (d <= tolerance) {
      nearest = &b;
      tolerance = d;
    }
  }
  return nearest;
}

// The bus shelter of mount_roof32_clutter: roof 2.4 m up over the pavement, back wall behind, a
// pedestrian (1.7 m) under it. In bird's-eye view the roof covers the walker's cells and reaches
// the back wall's, so the grid made one obstacle of roof, wall and walker, boxed as the shelter
// (found 5 of 42 frames). Points above a vertical gap from what stands below belong to the
// overhang: the walker is its own obstacle, its top its head, at every range the scenario scores.
TEST(FastDetector, PedestrianUnderAShelterRoofIsFound) {
  sim::Scene scene;
  scene.objects = {cylinder("pedestrian", 0.5f, 1.7f, {42.0f, 4.6f, 0.0f}), block("shelter_roof", {3.0f, 1.8f, 0.1f}, {42.0f, 4.9f, 2.4f}),
                   block("shelter_wall", {3.0f, 0.1f, 2.4f}, {42.0f, 5.8f, 0.0f})};
  // From 4 m behind (beside the vehicle) to 25 m ahead (further, fewer than 10 returns: the
  // evaluation does not score it). The walker's own box: centred on it, no wider than a person.
  const std::vector<float> distances = {-4.0f, -2.0f, 0.0f, 2.0f, 4.0f, 6.0f, 8.0f, 12.0f,
                                        16.0f, 20.0f, 25.0f};
  auto walkerAt = [](const std::vector<Box3D>& boxes, float x) {
    const Box3D* b = boxAt(boxes, x, 4.6f, 0.35f);
    return b && std::max(b->size.x(), b->size.y()) < 0.9f ? b : nullptr;
  };
  FastDetector detector(roofRoi(), FastDetectorParams());
  std::vector<Box3D> boxes;
  for (float distance : distances) {
    detector.detect(renderRoof32(scene, 42.0f - distance), boxes);
    const Box3D* found = walkerAt(boxes, distance);
    ASSERT_NE(found, nullptr) << "walker " << distance << " m ahead, " << boxes.size() << " boxes";
    EXPECT_LT(found->max.z(), 1.8f) << distance;  // its head, not the roof
    EXPECT_GE(found->num_points, 10) << distance;
  }

  // With the overhang check off (overhang_gap_m 0: the grid without it) the roof
  // joins the walker to the shelter up to 12 m ahead: one box of roof, wall and walker.
  FastDetectorParams off;
  off.overhang_gap_m = 0.0f;
  FastDetector unchecked(roofRoi(), off);
  for (float distance : distances) {
    if (distance > 12.0f) continue;
    unchecked.detect(renderRoof32(scene, 42.0f - distance), boxes);
    EXPECT_EQ(walkerAt(boxes, distance), nullptr) << distance;
  }
}

// A genuine overhang over an empty road (a tree canopy, 2.7-3.4 m up over the whole carriageway)
// is no obstacle; a car and a cyclist under it are found, without the canopy. (In the shadow of
// the car and the cyclist the ground estimate rises 0.15-0.35 m onto their lowest returns: a
// canopy at 2.5 m is then less than overhang_min_height_m = 2.3 m above it there, and boxed.)
TEST(FastDetector, CanopyOverTheRoadIsNoObstacleAndWhatStandsUnderItIsFound) {
  sim::Scene empty;
  empty.objects = {block("canopy", {8.0f, 10.0f, 0.7f}, {22.0f, 0.0f, 2.7f})};
  FastDetector detector(roofRoi(), FastDetectorParams());
  std::vector<Box3D> boxes;
  for (float sensor_x : {0.0f, 5.0f, 10.0f}) {
    detector.detect(renderRoof32(empty, sensor_x), boxes);
    for (const Box3D& b : boxes)
      ADD_FAILURE() << "sensor at x " << sensor_x << ": a box at " << b.center.transpose()
                    << " size " << b.size.transpose();
  }

  // A car and a cyclist under it: every box lies on one of them (the 32 beams see the car's rear
  // and a row across its roof 3.5 m further: two boxes at some ranges), none reaches the canopy,
  // and each is found (the car's rear face whole across).
  sim::Scene under = empty;
  under.objects.push_back(block("car", {4.5f, 1.8f, 1.5f}, {21.0f, -1.5f, 0.0f}));
  under.objects.push_back(block("cyclist", {1.8f, 0.6f, 1.7f}, {23.0f, 2.5f, 0.0f}));
  for (float sensor_x : {0.0f, 5.0f, 10.0f}) {
    detector.detect(renderRoof32(under, sensor_x), boxes);
    // Box centres within the footprints grown by 0.3 m.
    auto onCar = [&](const Box3D& b) {
      return std::abs(b.center.x() + sensor_x - 21.0f) <= 2.55f && std::abs(b.center.y() + 1.5f) <= 1.2f;
    };
    auto onCyclist = [&](const Box3D& b) {
      return std::abs(b.center.x() + sensor_x - 23.0f) <= 1.2f && std::abs(b.center.y() - 2.5f) <= 0.6f;
    };
    bool car = false, cyclist = false;
    for (const Box3D& b : boxes) {
      EXPECT_TRUE(onCar(b) || onCyclist(b)) << "sensor at x " << sensor_x << ": a box at "
                                            << b.center.transpose() << " size " << b.size.transpose();
      EXPECT_LT(b.max.z(), 1.8f) << "sensor at x " << sensor_x;
      car = car || (onCar(b) && std::max(b.size.x(), b.size.y()) > 1.6f);
      cyclist = cyclist || onCyclist(b);
    }
    EXPECT_TRUE(car) << "sensor at x " << sensor_x;
    EXPECT_TRUE(cyclist) << "sensor at x " << sensor_x;
  }

  // With the overhang check off (overhang_gap_m 0) the canopy is an obstacle, as before.
  FastDetectorParams off;
  off.overhang_gap_m = 0.0f;
  FastDetector unchecked(roofRoi(), off);
  unchecked.detect(renderRoof32(empty, 0.0f), boxes);
  EXPECT_FALSE(boxes.empty());
}

// The parked cars of night_parked_cars (carla128, 0.72 deg columns, 1.8 m up),
// rendered into base_link (the road at z = 0) with the carla_model3 profile's ROI.
Cloud renderCarla128(const sim::Scene& scene, float sensor_x) {
  return renderMounted(scene, sim::LidarModel::carla128(), sensor_x, 1.8f, 13);
}

// A parked car's side seen from the lane beside it: the columns land 0.9 m apart on it at 15 m,
// 1.6 m at 20 m, beyond link_m. Each was a box of its own, a line of sight 0.01-0.06 m across
// with 10-16 returns, at its column's bearing whatever the car's position: tracks that moved
// with the vehicle (night_parked_cars: static objects' speed p90 11.6 m/s). Now no box on the car
// is one line of sight, and the car is still found (its rear and the columns that link). A pole
// (3 m) 3 m in front of the car at the kerb, in line with its side, is one column too and stays
// the box it was: its top is not the car's.
TEST(FastDetector, ParkedCarSideAtGrazingIncidenceGivesNoColumnBoxes) {
  sim::Scene scene;
  scene.objects = {block("car", {4.7f, 1.9f, 1.5f}, {5.35f, -4.0f, 0.0f}),
                   cylinder("pole", 0.15f, 3.0f, {0.0f, -3.0f, 0.0f})};
  auto onCar = [](const Box3D& b, float car_x) {  // centre within the footprint grown by 0.5 m
    return std::abs(b.center.x() - car_x) <= 2.85f && std::abs(b.center.y() + 4.0f) <= 1.45f;
  };
  auto oneLineOfSight = [](const Box3D& b) {
    return std::max(b.max.x() - b.min.x(), b.max.y() - b.min.y()) < 0.1f;
  };
  FastDetector detector(roofRoi(), FastDetectorParams());
  FastDetectorParams off;
  off.grazing_reach_m = 0.0f;
  FastDetector unjoined(roofRoi(), off);
  std::vector<Box3D> boxes, before;
  int columns_before = 0, poles = 0;
  // From 12 m (columns further apart than link_m) to 22 m (further, its rear corner's column can
  // stand alone at some ranges).
  for (float car_x = 12.0f; car_x <= 22.0f; car_x += 0.5f) {
    const Cloud cloud = renderCarla128(scene, 5.35f - car_x);
    unjoined.detect(cloud, before);
    for (const Box3D& b : before) columns_before += onCar(b, car_x) && oneLineOfSight(b);
    detector.detect(cloud, boxes);
    bool car = false;
    for (const Box3D& b : boxes) {
      if (!onCar(b, car_x)) continue;
      EXPECT_FALSE(oneLineOfSight(b)) << "car " << car_x << " m ahead: a column at "
                                      << b.center.transpose() << ", " << b.num_points << " points";
      car = car || b.num_points >= 50;
    }
    EXPECT_TRUE(car) << "car " << car_x << " m ahead";
    // The pole (some ranges fall between two columns: no box either way) is the same box.
    const float pole_x = car_x - 5.35f;
    const Box3D* pole_before = boxAt(before, pole_x, -3.0f, 0.3f);
    if (!pole_before) continue;
    ++poles;
    const Box3D* pole_now = boxAt(boxes, pole_x, -3.0f, 0.3f);
    ASSERT_NE(pole_now, nullptr) << "pole " << pole_x << " m ahead";
    EXPECT_EQ(pole_now->num_points, pole_before->num_points) << "pole " << pole_x << " m ahead";
    EXPECT_GT(pole_now->max.z(), 2.5f);
  }
  EXPECT_GT(poles, 15);
  EXPECT_GT(columns_before, 10);  // before: the side fell apart into columns
}

// mount_robot16_clutter: a 16-beam unit (2 deg between beams) 0.5 m above the floor, driving
// past a wall 3 m tall 2.85 m to the side, with the Zebra's ROI (top 2.5 m) and its step check on
// every component. The wall's seen top is its highest beam below 2.5 m, which drops by one beam
// spacing (0.35 m at 10 m) wherever a beam leaves the top as the range grows: the check cut the
// wall there, at ranges fixed to the sensor, into pieces whose ends moved with the vehicle (a wall
// tracked at the robot's 1.5 m/s: static objects' speed p90 1.50 m/s). With link_step_beams the
// wall ahead is one box, its spacing measured from the returns; a pedestrian walking along it
// 0.15 m off its face 8 m ahead stays a box of its own.
TEST(FastDetector, SparseBeamsLeavingAWallsTopDoNotCutIt) {
  sim::Scene scene;
  scene.objects = {block("wall", {40.0f, 0.3f, 3.0f}, {15.0f, -3.0f, 0.0f})};
  const CloudPrepParams zebra = roiAndEgo({-2.0f, -10.0f, -0.5f}, {30.0f, 10.0f, 2.5f},
                                          {-0.6f, -0.45f, -0.5f}, {0.6f, 0.45f, 1.5f});
  FastDetectorParams cut;
  cut.step_check_min_extent_m = 0.0f;
  cut.step_piece_max_m = 100.0f;
  cut.link_step_beams = 0.0f;
  FastDetectorParams whole = cut;
  whole.link_step_beams = 1.25f;
  FastDetector before(zebra, cut), detector(zebra, whole);
  before.setSensorOrigin({0.0f, 0.0f, 0.5f});
  detector.setSensorOrigin({0.0f, 0.0f, 0.5f});
  auto onWall = [](const Box3D& b) { return b.max.y() < -2.7f && b.max.x() > 10.0f; };
  std::vector<Box3D> boxes;
  int pieces_before = 0, frames = 0;
  for (float sx = 0.0f; sx <= 6.0f; sx += 0.5f, ++frames) {
    sim::Scene here = scene;  // the pedestrian keeps 8 m ahead
    here.objects.push_back(cylinder("pedestrian", 0.5f, 1.75f, {sx + 8.0f, -2.45f, 0.0f}));
    const Cloud cloud = renderMounted(here, sim::LidarModel::vlp16(), sx, 0.5f, 3);
    before.detect(cloud, boxes);
    for (const Box3D& b : boxes) pieces_before += onWall(b);
    detector.detect(cloud, boxes);
    int pieces = 0;
    for (const Box3D& b : boxes) pieces += onWall(b);
    EXPECT_EQ(pieces, 1) << "sensor at " << sx;
    const Box3D* walker = boxAt(boxes, 8.0f, -2.45f, 0.4f);
    ASSERT_NE(walker, nullptr) << "sensor at " << sx;
    EXPECT_LT(walker->max.z(), 1.8f);
    EXPECT_GT(walker->min.y(), -2.75f);
  }
  EXPECT_NEAR(detector.rangeRowDeg(), 2.0f, 0.1f);  // measured
  EXPECT_GT(pieces_before, 2 * frames);             // before: three pieces or more a frame
}

TEST(FastDetector, OrganizedAndUnorganizedCloudsGiveTheSameObjects) {
  const Cloud organized = renderStreet();
  ASSERT_EQ(organized.height, 64u);
  Cloud unorganized;  // no NaNs, no rows, shuffled: no beam order to rely on
  for (const Point& p : organized)
    if (std::isfinite(p.x)) unorganized.push_back(p);
  std::shuffle(unorganized.points.begin(), unorganized.points.end(), std::mt19937(3));

  CloudPrepParams prep = wideRoi();
  prep.roi_min.z() = -2.5f;
  prep.roi_max.z() = 2.0f;
  FastDetector a(prep, FastDetectorParams()), b(prep, FastDetectorParams());
  std::vector<Box3D> from_organized, from_unorganized;
  a.detect(organized, from_organized);
  b.detect(unorganized, from_unorganized);
  ASSERT_EQ(from_organized.size(), 2u);
  ASSERT_EQ(from_unorganized.size(), 2u);
  for (std::size_t i = 0; i < 2; ++i) {
    EXPECT_EQ(from_organized[i].num_points, from_unorganized[i].num_points);
    EXPECT_TRUE(from_organized[i].center.isApprox(from_unorganized[i].center, 1e-4f));
  }
  // Sensor frame: the ground is 1.73 m below; the car (largest; only its near sides are seen,
  // so its box centre sits toward the sensor) and the pedestrian.
  EXPECT_NEAR(a.groundAt(12.0f, 0.0f), -1.73f, 0.05f);
  EXPECT_NEAR(from_organized[0].center.x(), 15.0f, 0.6f);
  EXPECT_NEAR(from_organized[0].center.y(), 3.0f, 0.8f);
  EXPECT_NEAR(from_organized[1].center.x(), 8.0f, 0.4f);
  EXPECT_NEAR(from_organized[1].center.y(), -4.0f, 0.4f);
}

TEST(FastDetector, NoBufferGrowsInSteadyState) {
  const Cloud cloud = renderStreet();
  FastDetector detector(wideRoi(), FastDetectorParams());
  std::vector<Box3D> boxes;
  detector.detect(cloud, boxes);
  const std::size_t bytes = detector.capacityBytes();
  const Box3D* data = boxes.data();
  for (int i = 0; i < 20; ++i) detector.detect(cloud, boxes);
  EXPECT_EQ(detector.capacityBytes(), bytes);
  EXPECT_EQ(boxes.data(), data);  // the caller's box vector is reused too
  EXPECT_EQ(boxes.size(), 2u);
}

TEST(FastDetector, EmptyAndNonFiniteInputGiveNoObjects) {
  FastDetector detector(wideRoi(), FastDetectorParams());
  std::vector<Box3D> boxes(3);
  detector.detect(Cloud(), boxes);
  EXPECT_TRUE(boxes.empty());
  Cloud bad;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  for (int i = 0; i < 100; ++i) {
    bad.push_back(Point(nan, 1.0f, 0.0f));
    bad.push_back(Point(10.0f, inf, 0.0f));
    bad.push_back(Point(0.0f, 0.0f, 0.0f));
    bad.push_back(Point(1e30f, 0.0f, 0.0f));  // outside the ROI
  }
  detector.detect(bad, boxes);
  EXPECT_EQ(detector.keptPoints(), 0u);
  EXPECT_TRUE(boxes.empty());
}

// Pass 1 keeps exactly what prepareCloud keeps (voxel grid off): both boxes closed, the ROI's
// boundary kept and the ego box's dropped, NaN, +-inf and all-zero points out, the ego box off when
// remove_ego is false or it is empty on an axis. Pass 1 tests each box with packed comparisons
// where SSE2 exists, so the boundaries are pinned here point by point.
TEST(FastDetector, PassOneKeepsWhatPrepareCloudKeeps) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  CloudPrepParams with_ego = roiAndEgo({-10.0f, -20.0f, -2.5f}, {60.0f, 20.0f, 1.5f},
                                       {-2.0f, -1.0f, -2.0f}, {3.0f, 1.0f, 0.5f});
  CloudPrepParams no_ego = with_ego;
  no_ego.remove_ego = false;
  CloudPrepParams empty_ego = with_ego;
  empty_ego.ego_max.z() = empty_ego.ego_min.z();  // empty on z: nothing dropped
  CloudPrepParams zero_outside_ego = roiAndEgo({-10.0f, -20.0f, -2.5f}, {60.0f, 20.0f, 1.5f},
                                               {2.0f, 2.0f, -2.0f}, {3.0f, 3.0f, 0.5f});
  Cloud cloud;
  const std::vector<float> xs = {-10.0f, std::nextafter(-10.0f, -inf), -2.0f, 0.0f, 3.0f,
                                 std::nextafter(3.0f, inf), 60.0f, std::nextafter(60.0f, inf),
                                 -0.0f, nan, inf, -inf};
  const std::vector<float> ys = {-20.0f, std::nextafter(-20.0f, -inf), -1.0f, 0.0f, 1.0f,
                                 std::nextafter(1.0f, inf), 20.0f, std::nextafter(20.0f, inf), nan};
  const std::vector<float> zs = {-2.5f, std::nextafter(-2.5f, -inf), -2.0f, 0.0f, 0.5f,
                                 std::nextafter(0.5f, inf), 1.5f, std::nextafter(1.5f, inf), nan, -inf};
  for (float x : xs)
    for (float y : ys)
      for (float z : zs) cloud.push_back(Point(x, y, z));
  for (const CloudPrepParams& prep : {with_ego, no_ego, empty_ego, zero_outside_ego}) {
    Cloud prepared;
    prepareCloud(cloud, prep, prepared);
    FastDetector detector(prep, FastDetectorParams());
    std::vector<Box3D> boxes;
    detector.detect(cloud, boxes);
    Cloud ground, obstacles;
    detector.splitPoints(ground, obstacles);
    EXPECT_EQ(detector.keptPoints(), prepared.size());
    // Point by point: every point of the split (ground and obstacles) is one prepareCloud kept.
    EXPECT_GT(prepared.size(), 100u);
    for (const Cloud* part : {&ground, &obstacles})
      for (const Point& p : part->points)
        ASSERT_TRUE(std::any_of(prepared.points.begin(), prepared.points.end(), [&p](const Point& q) {
          return q.x == p.x && q.y == p.y && q.z == p.z;
        })) << p.x << " " << p.y << " " << p.z;
  }
}

TEST(FastDetector, InvalidParametersAreNamed) {
  EXPECT_EQ(validate(FastDetectorParams()), "");
  FastDetectorParams p;
  p.cell_m = 0.0f;
  EXPECT_NE(validate(p).find("fast.cell_m"), std::string::npos);
  p = FastDetectorParams();
  p.sectors = 2;
  EXPECT_NE(validate(p).find("fast.sectors"), std::string::npos);
  p = FastDetectorParams();
  p.max_slope_deg = std::numeric_limits<float>::quiet_NaN();
  EXPECT_NE(validate(p).find("fast.max_slope_deg"), std::string::npos);
  p = FastDetectorParams();
  p.link_max_step_m = -0.1f;
  EXPECT_NE(validate(p).find("fast.link_max_step_m"), std::string::npos);
  p = FastDetectorParams();
  p.step_check_min_extent_m = -1.0f;
  EXPECT_NE(validate(p).find("fast.step_check_min_extent_m"), std::string::npos);
  p = FastDetectorParams();
  p.link_step_beams = 6.0f;
  EXPECT_NE(validate(p).find("fast.link_step_beams"), std::string::npos);
  p = FastDetectorParams();
  p.max_height_m = 0.1f;
  EXPECT_NE(validate(p).find("fast.max_height_m"), std::string::npos);
  p = FastDetectorParams();
  p.overhang_gap_m = -0.1f;
  EXPECT_NE(validate(p).find("fast.overhang_gap_m"), std::string::npos);
  p = FastDetectorParams();
  p.overhang_min_height_m = p.max_height_m + 0.5f;
  EXPECT_NE(validate(p).find("fast.overhang_min_height_m"), std::string::npos);
  p = FastDetectorParams();
  p.grazing_reach_m = -1.0f;
  EXPECT_NE(validate(p).find("fast.grazing_reach_m"), std::string::npos);
  p = FastDetectorParams();
  p.grazing_angle_deg = 90.0f;
  EXPECT_NE(validate(p).find("fast.grazing_angle_deg"), std::string::npos);
  p = FastDetectorParams();
  p.link_gap_m = -0.1f;
  EXPECT_NE(validate(p).find("fast.link_gap_m"), std::string::npos);
  p = FastDetectorParams();
  p.link_gap_max_extent_m = 0.0f;
  EXPECT_NE(validate(p).find("fast.link_gap_max_extent_m"), std::string::npos);
  p = FastDetectorParams();
  p.max_points = 5;
  EXPECT_NE(validate(p).find("fast.max_points"), std::string::npos);
  EXPECT_THROW(FastDetector(wideRoi(), p), std::invalid_argument);

  ObstacleDetectorParams d;
  d.method = parseDetectorMethod("fastest");
  EXPECT_NE(validate(d).find("method"), std::string::npos);
  d.method = parseDetectorMethod("fast");
  EXPECT_EQ(validate(d), "");
  d.footprint_cell_m = -1.0f;
  EXPECT_NE(validate(d).find("footprint_cell_m"), std::string::npos);
  d.footprint_cell_m = 0.0f;  // off
  EXPECT_EQ(validate(d), "");
  d.fast.cell_m = 0.05f;
  d.prep.roi_min = {-5000.0f, -5000.0f, -3.0f};
  d.prep.roi_max = {5000.0f, 5000.0f, 3.0f};
  EXPECT_NE(validate(d).find("fast.cell_m"), std::string::npos);
}

TEST(FastDetector, ObstacleDetectorRunsEitherMethodAndTracks) {
  const Cloud cloud = renderStreet();
  ObstacleDetectorParams params;
  params.prep = wideRoi();
  params.method = DetectorMethod::kFast;
  ObstacleDetector fast(params);
  ASSERT_NE(fast.fast(), nullptr);
  for (int i = 0; i < 3; ++i) fast.process(0.1 * i, cloud);
  EXPECT_EQ(fast.detections().size(), 2u);
  int confirmed = 0;
  for (const Track& t : fast.tracks()) confirmed += t.confirmed;
  EXPECT_EQ(confirmed, 2);

  // processFrom (points straight from a decoder) gives the same boxes as process.
  ObstacleDetector streamed(params);
  streamed.processFrom(0.0, [&cloud](auto&& sink) {
    for (const Point& p : cloud) sink(p.x, p.y, p.z);
  });
  ASSERT_EQ(streamed.detections().size(), 2u);
  EXPECT_TRUE(streamed.detections()[0].center.isApprox(fast.detections()[0].center, 1e-5f));

  params.method = DetectorMethod::kClassic;
  fast.setParams(params);
  EXPECT_EQ(fast.fast(), nullptr);
}

// The debug clouds (~ground_points, ~obstacle_points): each method's split accounts for the points
// it kept, the obstacle side holds every clustered point and the ground side the road.
TEST(FastDetector, SplitPointsOfEitherMethodMatchWhatTheFrameKept) {
  const Cloud cloud = renderStreet();
  for (const DetectorMethod method : {DetectorMethod::kFast, DetectorMethod::kClassic}) {
    ObstacleDetectorParams params;
    params.prep = wideRoi();
    params.method = method;
    params.ground.expected_height_m = -1.73f;  // the cloud is in the roof sensor's frame
    ObstacleDetector detector(params);
    detector.process(0.0, cloud);
    Cloud ground, obstacles;
    detector.splitPoints(ground, obstacles);
    std::size_t clustered = 0;
    for (const Box3D& b : detector.detections()) clustered += b.num_points;
    ASSERT_GE(detector.detections().size(), 2u) << toString(method);
    EXPECT_GE(obstacles.size(), clustered) << toString(method);
    EXPECT_GT(ground.size(), 1000u) << toString(method);
    EXPECT_LE(ground.size() + obstacles.size(), cloud.size()) << toString(method);
    // The road lies 1.73 m under the sensor: ground points up to obstacle_height_m (+ noise) above it.
    for (const Point& p : ground.points) ASSERT_LT(p.z, -1.73f + 0.4f) << toString(method);
    if (method == DetectorMethod::kFast) {
      EXPECT_EQ(obstacles.size(), detector.fast()->obstaclePoints());
      EXPECT_LE(ground.size() + obstacles.size(), detector.fast()->keptPoints());
    }
  }
}

// The nodelet's fused path: the fast detector reading a PointCloud2-shaped buffer in its first
// pass gives what decoding into a cloud and then detecting gives.
TEST(FastDetector, DetectingStraightFromTheMessageMatchesDecodingFirst) {
  const Cloud organized = renderStreet();  // 64 rows with NaN returns, x y z + padding
  RawCloud raw;
  raw.width = organized.width;
  raw.height = organized.height;
  raw.point_step = sizeof(Point);
  raw.row_step = raw.width * raw.point_step;
  raw.fields = {{"x", 0, 7, 1}, {"y", 4, 7, 1}, {"z", 8, 7, 1}};
  raw.data = reinterpret_cast<const std::uint8_t*>(organized.points.data());
  raw.data_size = organized.size() * sizeof(Point);
  Eigen::Affine3f to_base = Eigen::Affine3f::Identity();
  to_base.translation() = Eigen::Vector3f(1.0f, 0.0f, 1.73f);  // sensor -> base_link

  ObstacleDetectorParams params;
  params.prep = wideRoi();
  params.method = DetectorMethod::kFast;
  ObstacleDetector decoded_first(params), fused(params);
  Cloud cloud;
  DecodeStats decode_stats, fused_stats;
  ASSERT_EQ(decodeXYZ(raw, to_base, 1000000, cloud, &decode_stats), DecodeError::kNone);
  decoded_first.process(0.0, cloud);
  DecodePlan plan;
  ASSERT_EQ(planDecode(raw, 1000000, plan), DecodeError::kNone);
  fused.processFrom(0.0, [&](auto&& sink) { fused_stats = forEachXYZ(raw, plan, to_base, sink); });

  EXPECT_EQ(fused_stats.kept, decode_stats.kept);
  EXPECT_EQ(fused_stats.dropped_nonfinite, decode_stats.dropped_nonfinite);
  EXPECT_GT(fused_stats.dropped_nonfinite, 0u);  // the sky
  ASSERT_EQ(fused.detections().size(), 2u);
  ASSERT_EQ(decoded_first.detections().size(), 2u);
  for (std::size_t i = 0; i < 2; ++i) {
    EXPECT_EQ(fused.detections()[i].num_points, decoded_first.detections()[i].num_points);
    EXPECT_TRUE(fused.detections()[i].center.isApprox(decoded_first.detections()[i].center, 1e-6f));
  }
  EXPECT_NEAR(fused.detections()[0].center.x(), 15.0f + 1.0f, 0.6f);  // in base_link
}

TEST(FastDetector, ProfileSelectsTheMethod) {
  const std::string path = ::testing::TempDir() + "icanc_fast_profile_" + std::to_string(::getpid()) + ".yaml";
  {
    std::ofstream out(path);
    out << "obstacle_detector:\n  method: fast\n  fast:\n    cell_m: 0.5\n    sectors: 90\n";
  }
  const Profile profile = loadProfile(path);
  EXPECT_EQ(profile.detector.method, DetectorMethod::kFast);
  EXPECT_FLOAT_EQ(profile.detector.fast.cell_m, 0.5f);
  EXPECT_EQ(profile.detector.fast.sectors, 90);
  {
    std::ofstream out(path);
    out << "obstacle_detector:\n  method: quick\n";
  }
  EXPECT_THROW(loadProfile(path), std::runtime_error);
  std::remove(path.c_str());
}

}  // namespace
}  // namespace icanc
