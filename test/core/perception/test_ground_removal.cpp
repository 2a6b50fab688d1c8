// removeGround: a noisy road with an obstacle standing on it, a tilted road, a wall that must not
// be taken for ground, the pass-through cases and run-to-run determinism.
#include "icanc/core/perception/ground_removal.hpp"

#include <cmath>
#include <random>

#include <gtest/gtest.h>

namespace icanc {
namespace {

constexpr float kGroundZ = -1.7f;  // road 1.7 m below the sensor
constexpr float kNoise = 0.02f;    // sigma of the road's height noise [m]

// Obstacle: 0.5 x 0.5 x 1.7 m box standing on the road, footprint centred at (10, 2).
constexpr float kBoxX0 = 9.75f, kBoxX1 = 10.25f, kBoxY0 = 1.75f, kBoxY1 = 2.25f;
constexpr float kBoxTop = kGroundZ + 1.7f;

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
  const GroundParams params;  // defaults: 30 iterations, 0.3 m, 15 deg
  std::size_t road = 0, box_high = 0;
  for (const Point& p : in) {
    if (!inBoxFootprint(p)) ++road;
    else if (p.z > survivalHeight(params)) ++box_high;
  }
  ASSERT_GT(road, 20000u);
  ASSERT_GT(box_high, 500u);

  Cloud out;
  const GroundResult r = removeGround(in, params, out);
  ASSERT_TRUE(r.found);
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
  const GroundResult r = removeGround(in, GroundParams(), out);
  ASSERT_TRUE(r.found);
  EXPECT_LE(out.size(), in.size() / 100);
  const float tilt_deg = std::acos(r.plane[2]) * 180.0f / static_cast<float>(M_PI);
  EXPECT_NEAR(tilt_deg, 5.0f, 0.3f);
  EXPECT_LT(r.plane[0], 0.0f);  // normal leans back against the climb: (-sin 5, 0, cos 5)

  // The same road with max_slope_deg below its tilt is not ground.
  GroundParams strict;
  strict.max_slope_deg = 2.0f;
  const GroundResult none = removeGround(in, strict, out);
  EXPECT_FALSE(none.found);
  EXPECT_EQ(out.size(), in.size());
}

TEST(GroundRemoval, WallAloneIsNotGround) {
  Cloud in;
  addWall(in);
  Cloud out;
  const GroundResult r = removeGround(in, GroundParams(), out);
  EXPECT_FALSE(r.found);
  EXPECT_EQ(r.inliers, 0u);
  ASSERT_EQ(out.size(), in.size());  // copied through
  for (std::size_t i = 0; i < in.size(); ++i) EXPECT_EQ(out[i].y, in[i].y);
}

TEST(GroundRemoval, WallBesideRoadSurvives) {
  std::mt19937 rng(3);
  Cloud in;
  addRoad(in, [](float) { return kGroundZ; }, rng);
  addWall(in);
  const GroundParams params;
  Cloud out;
  const GroundResult r = removeGround(in, params, out);
  ASSERT_TRUE(r.found);
  EXPECT_GT(r.plane[2], 0.999f);  // the road, not the wall
  std::size_t wall_high = 0, wall_high_left = 0;
  for (const Point& p : in) wall_high += (p.x == 8.0f && p.z > survivalHeight(params));
  for (const Point& p : out) wall_high_left += (p.x == 8.0f && p.z > survivalHeight(params));
  ASSERT_GT(wall_high, 1000u);
  EXPECT_EQ(wall_high_left, wall_high);
}

TEST(GroundRemoval, DisabledCopiesThrough) {
  const Cloud in = roadWithBox();
  GroundParams params;
  params.enabled = false;
  Cloud out;
  const GroundResult r = removeGround(in, params, out);
  EXPECT_FALSE(r.found);
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
  const GroundResult r = removeGround(in, GroundParams(), out);
  EXPECT_FALSE(r.found);
  ASSERT_EQ(out.size(), 2u);
  EXPECT_EQ(out[1].x, 2.0f);
  EXPECT_FALSE(removeGround(Cloud(), GroundParams(), out).found);
  EXPECT_TRUE(out.empty());
}

TEST(GroundRemoval, DeterministicAcrossRuns) {
  const Cloud in = roadWithBox(5);
  GroundParams params;
  params.max_iterations = 10;  // few iterations: any randomness would show
  Cloud a, b;
  const GroundResult ra = removeGround(in, params, a);
  const GroundResult rb = removeGround(in, params, b);
  ASSERT_TRUE(ra.found);
  EXPECT_EQ(ra.plane, rb.plane);
  EXPECT_EQ(ra.inliers, rb.inliers);
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    ASSERT_EQ(a[i].x, b[i].x);
    ASSERT_EQ(a[i].y, b[i].y);
    ASSERT_EQ(a[i].z, b[i].z);
  }
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
}

}  // namespace
}  // namespace icanc
