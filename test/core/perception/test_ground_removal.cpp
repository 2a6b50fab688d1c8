// removeGround: a noisy road with an obstacle standing on it, a tilted road, a wall that must not
// be taken for ground, a horizontal plane above the road (car roofs) that plain RANSAC takes for
// it, a cloud without a road, the pass-through cases and run-to-run determinism.
#include "icanc/core/perception/ground_removal.hpp"

#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "icanc/core/perception/cloud_prep.hpp"
#include "icanc/sim/lidar_sim.hpp"

namespace icanc {
namespace {

constexpr float kGroundZ = -1.7f;  // road 1.7 m below the sensor
constexpr float kNoise = 0.02f;    // sigma of the road's height noise [m]

// Obstacle: 0.5 x 0.5 x 1.7 m box standing on the road, footprint centred at (10, 2).
constexpr float kBoxX0 = 9.75f, kBoxX1 = 10.25f, kBoxY0 = 1.75f, kBoxY1 = 2.25f;
constexpr float kBoxTop = kGroundZ + 1.7f;

// The defaults with the road where these clouds have it (the sensor's frame, 1.7 m above it).
GroundParams roadBelowSensor() {
  GroundParams params;
  params.expected_height_m = kGroundZ;
  return params;
}

bool inBoxFootprint(const Point& p, float margin = 0.05f) {
  return p.x >= kBoxX0 - margin && p.x <= kBoxX1 + margin && p.y >= kBoxY0 - margin &&
         p.y <= kBoxY1 + margin;
}

// Road on a 0.25 m grid over x in [-20, 40), y in [-15, 15), height z = ground(x) + noise,
// skipping the obstacle's footprint (the obstacle hides it from the sensor).
template <typename Height>
void addRoad(Cloud& cloud, Height ground, std::mt19937& rng) {
  std::normal_distribution<float> noise(0.0f, kNoise);
  for (float x = -20.0f; x < 40.0f; x += 0.25f) {
    for (float y = -15.0f; y < 15.0f; y += 0.25f) {
      Point p(x, y, 0.0f);
      if (inBoxFootprint(p)) continue;
      p.z = ground(x) + noise(rng);
      cloud.push_back(p);
    }
  }
}

// Surface of the box: its four sides and its top on a 5 cm grid.
void addBox(Cloud& cloud) {
  const float step = 0.05f;
  for (float z = kGroundZ; z <= kBoxTop + 1e-4f; z += step) {
    for (float t = 0.0f; t <= 0.5f + 1e-4f; t += step) {
      cloud.push_back(Point(kBoxX0 + t, kBoxY0, z));
      cloud.push_back(Point(kBoxX0 + t, kBoxY1, z));
      cloud.push_back(Point(kBoxX0, kBoxY0 + t, z));
      cloud.push_back(Point(kBoxX1, kBoxY0 + t, z));
    }
  }
  for (float u = kBoxX0; u <= kBoxX1 + 1e-4f; u += step) {
    for (float v = kBoxY0; v <= kBoxY1 + 1e-4f; v += step) cloud.push_back(Point(u, v, kBoxTop));
  }
}

// Vertical wall x = 8, y in [-10, 10], z from the road up to 3 m above it, on a 0.1 m grid.
void addWall(Cloud& cloud) {
  for (float y = -10.0f; y <= 10.0f; y += 0.1f) {
    for (float z = kGroundZ; z <= kGroundZ + 3.0f; z += 0.1f) cloud.push_back(Point(8.0f, y, z));
  }
}

Cloud roadWithBox(unsigned seed = 7) {
  std::mt19937 rng(seed);
  Cloud cloud;
  addRoad(cloud, [](float) { return kGroundZ; }, rng);
  addBox(cloud);
  return cloud;
}

// Clearance above the plane beyond which a box point must survive: the distance threshold plus
// a margin for the fitted plane's small error. Lower box points are ground by definition.
float survivalHeight(const GroundParams& params) {
  return kGroundZ + params.distance_threshold_m + 0.05f;
}

TEST(GroundRemoval, FlatRoadRemovedObstacleKept) {
  const Cloud in = roadWithBox();
  const GroundParams params = roadBelowSensor();  // defaults: 30 iterations, 0.3 m, 15 deg
  std::size_t road = 0, box_high = 0;
  for (const Point& p : in) {
    if (!inBoxFootprint(p)) ++road;
    else if (p.z > survivalHeight(params)) ++box_high;
  }
  ASSERT_GT(road, 20000u);
  ASSERT_GT(box_high, 500u);

  Cloud out;
  const GroundResult r = removeGround(in, params, out);
  ASSERT_TRUE(r.found());
  EXPECT_NEAR(r.plane[0], 0.0f, 0.01f);
  EXPECT_NEAR(r.plane[1], 0.0f, 0.01f);
  EXPECT_NEAR(r.plane[2], 1.0f, 1e-3f);
  EXPECT_NEAR(r.plane[3], 1.7f, 0.02f);
  EXPECT_NEAR(r.plane.head<3>().norm(), 1.0f, 1e-5f);
  EXPECT_EQ(r.inliers + out.size(), in.size());

  std::size_t road_left = 0, box_high_left = 0;
  for (const Point& p : out) {
    if (!inBoxFootprint(p)) ++road_left;
    else if (p.z > survivalHeight(params)) ++box_high_left;
  }
  EXPECT_EQ(box_high_left, box_high);  // every box point clear of the road survives
  EXPECT_LE(road_left, road / 100);    // >= 99 % of the road removed
  EXPECT_EQ(out.width, out.size());
  EXPECT_EQ(out.height, 1u);
}

TEST(GroundRemoval, TiltedRoadRemoved) {
  // A 5 deg climb along x: z = -1.7 + tan(5 deg) x, within max_slope_deg = 15.
  const float slope = std::tan(5.0f * static_cast<float>(M_PI) / 180.0f);
  std::mt19937 rng(11);
  Cloud in;
  addRoad(in, [slope](float x) { return kGroundZ + slope * x; }, rng);
  Cloud out;
  const GroundResult r = removeGround(in, roadBelowSensor(), out);
  ASSERT_TRUE(r.found());
  EXPECT_LE(out.size(), in.size() / 100);
  const float tilt_deg = std::acos(r.plane[2]) * 180.0f / static_cast<float>(M_PI);
  EXPECT_NEAR(tilt_deg, 5.0f, 0.3f);
  EXPECT_LT(r.plane[0], 0.0f);  // normal leans back against the climb: (-sin 5, 0, cos 5)

  // The same road with max_slope_deg below its tilt is not ground.
  GroundParams strict = roadBelowSensor();
  strict.max_slope_deg = 2.0f;
  const GroundResult none = removeGround(in, strict, out);
  EXPECT_FALSE(none.found());
  EXPECT_EQ(none.status, GroundStatus::kNoPlane);
  EXPECT_EQ(out.size(), in.size());
}

TEST(GroundRemoval, WallAloneIsNotGround) {
  Cloud in;
  addWall(in);
  Cloud out;
  const GroundResult r = removeGround(in, roadBelowSensor(), out);
  EXPECT_FALSE(r.found());
  EXPECT_EQ(r.status, GroundStatus::kNoPlane);
  EXPECT_EQ(r.inliers, 0u);
  ASSERT_EQ(out.size(), in.size());  // copied through
  for (std::size_t i = 0; i < in.size(); ++i) EXPECT_EQ(out[i].y, in[i].y);
}

TEST(GroundRemoval, WallBesideRoadSurvives) {
  std::mt19937 rng(3);
  Cloud in;
  addRoad(in, [](float) { return kGroundZ; }, rng);
  addWall(in);
  const GroundParams params = roadBelowSensor();
  Cloud out;
  const GroundResult r = removeGround(in, params, out);
  ASSERT_TRUE(r.found());
  EXPECT_GT(r.plane[2], 0.999f);  // the road, not the wall
  std::size_t wall_high = 0, wall_high_left = 0;
  for (const Point& p : in) wall_high += (p.x == 8.0f && p.z > survivalHeight(params));
  for (const Point& p : out) wall_high_left += (p.x == 8.0f && p.z > survivalHeight(params));
  ASSERT_GT(wall_high, 1000u);
  EXPECT_EQ(wall_high_left, wall_high);
}

TEST(GroundRemoval, DisabledCopiesThrough) {
  const Cloud in = roadWithBox();
  GroundParams params = roadBelowSensor();
  params.enabled = false;
  Cloud out;
  const GroundResult r = removeGround(in, params, out);
  EXPECT_FALSE(r.found());
  EXPECT_EQ(r.status, GroundStatus::kSkipped);
  EXPECT_EQ(r.inliers, 0u);
  ASSERT_EQ(out.size(), in.size());
  EXPECT_EQ(out.width, in.size());
  for (std::size_t i = 0; i < in.size(); i += 97) EXPECT_EQ(out[i].z, in[i].z);
}

TEST(GroundRemoval, FewerThanThreePointsCopiedThrough) {
  Cloud in;
  in.push_back(Point(1, 0, -1.7f));
  in.push_back(Point(2, 0, -1.7f));
  Cloud out;
  out.push_back(Point(9, 9, 9));  // cleared first
  const GroundResult r = removeGround(in, roadBelowSensor(), out);
  EXPECT_FALSE(r.found());
  ASSERT_EQ(out.size(), 2u);
  EXPECT_EQ(out[1].x, 2.0f);
  EXPECT_FALSE(removeGround(Cloud(), roadBelowSensor(), out).found());
  EXPECT_TRUE(out.empty());
}

TEST(GroundRemoval, DeterministicAcrossRuns) {
  const Cloud in = roadWithBox(5);
  GroundParams params = roadBelowSensor();
  params.max_iterations = 10;  // few iterations: any randomness would show
  Cloud a, b;
  const GroundResult ra = removeGround(in, params, a);
  const GroundResult rb = removeGround(in, params, b);
  ASSERT_TRUE(ra.found());
  EXPECT_EQ(ra.plane, rb.plane);
  EXPECT_EQ(ra.inliers, rb.inliers);
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    ASSERT_EQ(a[i].x, b[i].x);
    ASSERT_EQ(a[i].y, b[i].y);
    ASSERT_EQ(a[i].z, b[i].z);
  }
}

// Bodies standing on the road of the vehicle frame (road at z = 0): each a box from z_lo (its
// underside, e.g. a car's clearance) to z_hi, its sides and top on a 0.1 m grid.
struct Body {
  float x0, x1, y0, y1, z_lo, z_hi;
  bool contains(const Point& p, float margin = 0.05f) const {
    return p.x >= x0 - margin && p.x <= x1 + margin && p.y >= y0 - margin && p.y <= y1 + margin;
  }
};

void addBody(Cloud& cloud, const Body& b) {
  const float step = 0.1f;
  for (float z = b.z_lo; z <= b.z_hi + 1e-4f; z += step) {
    for (float x = b.x0; x <= b.x1 + 1e-4f; x += step) {
      cloud.push_back(Point(x, b.y0, z));
      cloud.push_back(Point(x, b.y1, z));
    }
    for (float y = b.y0 + step; y < b.y1 - 1e-4f; y += step) {
      cloud.push_back(Point(b.x0, y, z));
      cloud.push_back(Point(b.x1, y, z));
    }
  }
  for (float x = b.x0 + 0.1f; x < b.x1 - 1e-4f; x += step)
    for (float y = b.y0 + 0.1f; y < b.y1 - 1e-4f; y += step) cloud.push_back(Point(x, y, b.z_hi));
}

// A car park as a roof unit sees it after the voxel grid: four parked cars (4.5 x 1.8 x 1.5 m,
// body from 0.3 m up) and the road around them thinned to a `road_step` grid (none: 0), road at 0.
const Body kCars[] = {{6.0f, 10.5f, 3.0f, 4.8f, 0.3f, 1.5f},
                      {12.0f, 16.5f, 3.0f, 4.8f, 0.3f, 1.5f},
                      {6.0f, 10.5f, -4.8f, -3.0f, 0.3f, 1.5f},
                      {12.0f, 16.5f, -4.8f, -3.0f, 0.3f, 1.5f}};

bool onACar(const Point& p) {
  for (const Body& car : kCars)
    if (car.contains(p)) return true;
  return false;
}

Cloud carPark(float road_step) {
  Cloud cloud;
  for (const Body& car : kCars) addBody(cloud, car);
  if (road_step <= 0.0f) return cloud;
  std::mt19937 rng(13);
  std::normal_distribution<float> noise(0.0f, kNoise);
  for (float x = -20.0f; x < 40.0f; x += road_step) {
    for (float y = -15.0f; y < 15.0f; y += road_step) {
      Point p(x, y, noise(rng));
      if (!onACar(p)) cloud.push_back(p);
    }
  }
  return cloud;
}

// A roof unit's sparse road and the cars' flat roofs: RANSAC's best horizontal plane
// is the roofs, 1.5 m above the road, and the paper's detector deleted the car bodies. Now that
// plane is rejected (the road is at 0 in the vehicle frame) and the retry near 0 finds the road.
TEST(GroundRemoval, RoofPlaneThatPlainRansacTakesIsRejectedAndTheRoadFound) {
  const Cloud in = carPark(1.0f);
  const GroundParams params;  // expected at 0 +- 0.5 m
  const float clear = params.distance_threshold_m + 0.05f;  // car points above this must survive
  std::size_t car_high = 0, road = 0;
  for (const Point& p : in) {
    if (!onACar(p)) ++road;
    else if (p.z > clear) ++car_high;
  }
  Eigen::Vector4f roofs;
  std::vector<int> on_roofs;
  ASSERT_TRUE(ransacGroundPlane(in, params, roofs, on_roofs));  // the paper's detector
  EXPECT_NEAR(-roofs[3] / roofs[2], 1.5f, 0.1f);  // took the roofs for the road ...
  std::size_t car_high_deleted = 0;
  for (const int i : on_roofs) car_high_deleted += onACar(in[i]) && in[i].z > clear;
  EXPECT_GT(car_high_deleted, car_high / 4);  // ... and deleted them and the sides' top 0.3 m

  Cloud out;
  const GroundResult r = removeGround(in, params, out);
  ASSERT_EQ(r.status, GroundStatus::kFoundOnRetry);
  EXPECT_TRUE(r.found());
  EXPECT_EQ(r.rejection, GroundRejection::kHeight);
  EXPECT_NEAR(r.rejected_height_m, 1.5f, 0.1f);
  EXPECT_EQ(r.rejected_inliers, on_roofs.size());
  EXPECT_NEAR(r.height_m, 0.0f, 0.05f);
  EXPECT_GT(r.plane[2], 0.999f);
  EXPECT_EQ(r.inliers + out.size(), in.size());
  std::size_t car_high_left = 0;
  for (const Point& p : out) car_high_left += onACar(p) && p.z > clear;
  EXPECT_EQ(car_high_left, car_high);  // every car point clear of the road survives
  std::size_t road_left = 0;
  for (const Point& p : out) road_left += !onACar(p);
  EXPECT_LE(road_left, road / 100);
}

// Nothing near the expected road height (a trailer's box from 1.2 to 4 m, the road out of
// view): the trailer's roof is rejected, the retry has no points, every point is kept.
TEST(GroundRemoval, NoRoadKeepsEveryPointAndSaysSo) {
  Cloud in;
  addBody(in, {8.0f, 20.0f, -1.25f, 1.25f, 1.2f, 4.0f});
  addBody(in, {8.0f, 20.0f, 3.0f, 5.5f, 1.2f, 4.0f});
  Cloud out;
  const GroundResult r = removeGround(in, GroundParams(), out);
  EXPECT_EQ(r.status, GroundStatus::kRejected);
  EXPECT_FALSE(r.found());
  EXPECT_EQ(r.rejection, GroundRejection::kHeight);
  EXPECT_EQ(r.retry_rejection, GroundRejection::kNone);  // nothing near the road's height
  EXPECT_NEAR(r.rejected_height_m, 4.0f, 0.1f);
  EXPECT_GT(r.rejected_inliers, 1000u);
  EXPECT_EQ(r.inliers, 0u);
  ASSERT_EQ(out.size(), in.size());
  for (std::size_t i = 0; i < in.size(); i += 7) EXPECT_EQ(out[i].z, in[i].z);
}

// The lowest returns: the car park given in the sensor's own frame (1.9 m above the road, e.g.
// no transform to base_link) to a profile that expects the road at 0. The roofs, 0.4 m below
// the origin, are within max_height_error_m of it, but the road and most of each car lie under
// them beyond the inlier distance: not the ground. Every point is kept.
TEST(GroundRemoval, PlaneWithMorePointsUnderItThanOnItIsRejected) {
  Cloud in = carPark(0.5f);
  for (Point& p : in) p.z -= 1.9f;
  Cloud out;
  const GroundResult r = removeGround(in, GroundParams(), out);
  EXPECT_EQ(r.status, GroundStatus::kRejected);
  EXPECT_EQ(r.retry_rejection, GroundRejection::kPointsBelow);
  ASSERT_EQ(out.size(), in.size());

  // The same roofs with nothing far below them are a plane that may be the ground.
  GroundParams roofs;
  roofs.expected_height_m = -0.4f;
  roofs.max_height_error_m = 0.3f;
  const Cloud roofs_only = [&] {
    Cloud c;
    for (const Point& p : in) if (p.z > -0.7f) c.push_back(p);
    return c;
  }();
  const GroundResult alone = removeGround(roofs_only, roofs, out);
  EXPECT_EQ(alone.status, GroundStatus::kFound);
  EXPECT_NEAR(alone.height_m, -0.4f, 0.05f);
  const GroundResult with_road = removeGround(in, roofs, out);
  EXPECT_EQ(with_road.status, GroundStatus::kRejected);
  EXPECT_EQ(with_road.retry_rejection, GroundRejection::kPointsBelow);
}

// The case, rendered: a 64-beam unit 2.0 m above the road (LidarModel::hdl64e) in a
// street lined with parked cars `side` m either side (and a bus beside the lane), house fronts
// behind the cars; base_link frame, the classic chain's ROI, ego box and 0.2 m voxel grid.
sim::SceneObject block(const char* type, float length, float width, float height, float x, float y) {
  sim::SceneObject o;
  o.type = type;
  o.size = {length, width, height};
  o.position = {x, y, 0.0f};
  return o;
}

Cloud parkedStreet(float side, bool bus, int seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<float> jitter(-0.5f, 0.5f);
  sim::Scene scene;
  for (float x = -8.0f; x < 55.0f; x += 5.5f) {
    scene.objects.push_back(block("car", 4.5f, 1.8f, 1.5f, x + jitter(rng), side + 0.2f * jitter(rng)));
    scene.objects.push_back(block("car", 4.5f, 1.8f, 1.5f, x + 2.0f + jitter(rng), -side + 0.2f * jitter(rng)));
  }
  if (bus) scene.objects.push_back(block("bus", 12.0f, 2.5f, 3.0f, 8.0f, 2.6f));
  scene.objects.push_back(block("wall", 80.0f, 0.3f, 8.0f, 20.0f, side + 3.0f));
  scene.objects.push_back(block("wall", 80.0f, 0.3f, 8.0f, 20.0f, -side - 3.0f));
  Eigen::Isometry3f sensor = Eigen::Isometry3f::Identity();
  sensor.translation().z() = 2.0f;
  Cloud scan, base_link, prepared;
  sim::renderScan(scene, 0.0, sensor, sim::LidarModel::hdl64e(), sim::NoiseParams(), rng, scan);
  for (Point p : scan) {
    if (!std::isfinite(p.x)) continue;
    p.z += 2.0f;
    base_link.push_back(p);
  }
  CloudPrepParams prep;  // carla_model3's
  prep.roi_min = {-10.0f, -20.0f, -0.5f};
  prep.roi_max = {60.0f, 20.0f, 3.0f};
  prep.ego_min = {-2.5f, -1.05f, -0.5f};
  prep.ego_max = {2.5f, 1.05f, 1.6f};
  prep.voxel_leaf_m = 0.2f;
  prepareCloud(base_link, prep, prepared);
  return prepared;
}

// Cars 3, 4 and 5 m either side, with and without the bus, ten scans each. Every plane of the
// paper's RANSAC further than max_height_error_m from the road (or with more points under it than
// on it) is rejected, the road found on retry and every point clear of it kept; a plane kept is
// the paper's. With the cars 3 m away and the bus (the tightest street) the paper's plane is wrong
// in every scan (measured 10 of 10, 0.84-1.54 m up; rejected in 26 of the 60 scans in all,
// 0.46-1.54 m up). Left as they were: slabs 0.23-0.39 m up through the road and the cars' lower
// edges, within both checks (4 of 60).
TEST(GroundRemoval, RoofUnitInAParkedStreetFindsTheRoad) {
  const GroundParams params;  // road at base_link's origin
  const float clear = params.distance_threshold_m + 0.05f;
  int plain_wrong = 0, tightest_wrong = 0, slabs = 0;
  for (const float side : {3.0f, 4.0f, 5.0f}) {
    for (const bool bus : {false, true}) {
      for (int seed = 1; seed <= 10; ++seed) {
        SCOPED_TRACE(::testing::Message() << "side " << side << " bus " << bus << " seed " << seed);
        const Cloud in = parkedStreet(side, bus, seed);
        Eigen::Vector4f plain;
        std::vector<int> plain_inliers;
        ASSERT_TRUE(ransacGroundPlane(in, params, plain, plain_inliers));
        const float plain_height = -plain[3] / plain[2];
        Cloud out;
        const GroundResult r = removeGround(in, params, out);
        if (r.status == GroundStatus::kFound) {  // the paper's plane, kept as it was
          EXPECT_LE(plain_height, params.max_height_error_m);
          EXPECT_EQ(r.inliers, plain_inliers.size());
          slabs += plain_height > 0.1f;
          continue;
        }
        ++plain_wrong;
        tightest_wrong += side == 3.0f && bus;
        EXPECT_EQ(r.rejection, plain_height > params.max_height_error_m
                                   ? GroundRejection::kHeight : GroundRejection::kPointsBelow);
        EXPECT_NEAR(r.rejected_height_m, plain_height, 1e-4f);
        ASSERT_EQ(r.status, GroundStatus::kFoundOnRetry);
        EXPECT_NEAR(r.height_m, 0.0f, 0.05f);
        std::size_t high = 0, high_left = 0;  // car, bus and wall points clear of the road
        for (const Point& p : in) high += p.z > clear;
        for (const Point& p : out) high_left += p.z > clear;
        EXPECT_EQ(high_left, high);
      }
    }
  }
  std::printf("the paper's plane rejected in %d of 60 scans (%d of 10 in the tightest street), "
              "slabs above the road kept: %d\n", plain_wrong, tightest_wrong, slabs);
  EXPECT_GE(tightest_wrong, 8);  // measured 10
  EXPECT_GE(plain_wrong, 20);    // measured 26
  EXPECT_LE(slabs, 6);           // measured 4
}

TEST(GroundRemoval, ValidateMessages) {
  EXPECT_EQ(validate(GroundParams()), "");
  GroundParams p;
  p.max_iterations = 0;
  EXPECT_EQ(validate(p), "ground.max_iterations must be >= 1 (got 0)");
  p = GroundParams();
  p.distance_threshold_m = -0.3f;
  EXPECT_EQ(validate(p), "ground.distance_threshold_m must be > 0 (got -0.3)");
  p = GroundParams();
  p.max_slope_deg = 90.0f;
  EXPECT_EQ(validate(p), "ground.max_slope_deg must be in [0, 90) (got 90)");
  p = GroundParams();
  p.expected_height_m = std::numeric_limits<float>::quiet_NaN();
  EXPECT_EQ(validate(p), "ground.expected_height_m must be finite (got nan)");
  p = GroundParams();
  p.max_height_error_m = 0.0f;
  EXPECT_EQ(validate(p), "ground.max_height_error_m must be > 0 (got 0)");
}

}  // namespace
}  // namespace icanc
