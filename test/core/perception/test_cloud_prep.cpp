// prepareCloud and validate(CloudPrepParams): ROI and ego box boundaries, invalid points, voxel
// grid on a known lattice, the small-leaf fallback, and the validation messages.
#include "icanc/core/perception/cloud_prep.hpp"

#include <cmath>
#include <limits>
#include <map>
#include <tuple>

#include <gtest/gtest.h>

namespace icanc {
namespace {

Cloud cloudOf(const std::vector<Eigen::Vector3f>& pts) {
  Cloud c;
  for (const auto& p : pts) c.push_back(Point(p.x(), p.y(), p.z()));
  return c;
}

bool contains(const Cloud& c, float x, float y, float z) {
  for (const Point& p : c) {
    if (p.x == x && p.y == y && p.z == z) return true;
  }
  return false;
}

CloudPrepParams noEgoNoVoxel() {
  CloudPrepParams p;
  p.remove_ego = false;
  p.voxel_leaf_m = 0.0f;
  return p;
}

TEST(CloudPrep, RoiBoundariesAreInclusive) {
  CloudPrepParams params = noEgoNoVoxel();
  params.roi_min = Eigen::Vector3f(-20, -10, -3);
  params.roi_max = Eigen::Vector3f(60, 10, 3);
  const float below = std::nextafter(-20.0f, -100.0f);
  const float above = std::nextafter(60.0f, 100.0f);
  const Cloud in = cloudOf({{-20, 0, 0.5f},     // on roi_min.x: kept
                            {60, 0, 0.5f},      // on roi_max.x: kept
                            {below, 0, 0.5f},   // one ulp outside: dropped
                            {above, 0, 0.5f},   // dropped
                            {5, -10, 0.5f},     // on roi_min.y: kept
                            {5, 10.01f, 0.5f},  // dropped
                            {5, 0, -3},         // on roi_min.z: kept
                            {5, 0, 3.001f},     // dropped
                            {5, 0, -3.001f}});  // dropped
  Cloud out;
  prepareCloud(in, params, out);
  EXPECT_EQ(out.size(), 4u);
  EXPECT_EQ(out.width, 4u);
  EXPECT_EQ(out.height, 1u);
  EXPECT_TRUE(contains(out, -20, 0, 0.5f));
  EXPECT_TRUE(contains(out, 60, 0, 0.5f));
  EXPECT_TRUE(contains(out, 5, -10, 0.5f));
  EXPECT_TRUE(contains(out, 5, 0, -3));
}

TEST(CloudPrep, DropsNonFiniteAndZeroPoints) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  Cloud in = cloudOf({{1, 1, 1}, {nan, 1, 1}, {1, inf, 1}, {0, 0, 0}, {0, 0, 0.5f}});
  in.is_dense = false;
  Cloud out;
  prepareCloud(in, noEgoNoVoxel(), out);
  ASSERT_EQ(out.size(), 2u);
  EXPECT_TRUE(contains(out, 1, 1, 1));
  EXPECT_TRUE(contains(out, 0, 0, 0.5f));
  EXPECT_TRUE(out.is_dense);
}

TEST(CloudPrep, EgoBoxRemoved) {
  CloudPrepParams params = noEgoNoVoxel();
  params.remove_ego = true;
  params.ego_min = Eigen::Vector3f(-1, -1, -2);
  params.ego_max = Eigen::Vector3f(2, 1, 1);
  const Cloud in = cloudOf({{0.5f, 0.2f, 0},   // inside: dropped
                            {2, 1, 1},         // on the corner: dropped (closed box)
                            {-1, 0, -2},       // on a face: dropped
                            {2.01f, 0, 0},     // just ahead: kept
                            {0, 1.01f, 0},     // just left: kept
                            {0, 0, 1.01f},     // just above: kept
                            {10, 0, 0}});      // far: kept
  Cloud out;
  prepareCloud(in, params, out);
  EXPECT_EQ(out.size(), 4u);
  EXPECT_FALSE(contains(out, 0.5f, 0.2f, 0));
  EXPECT_TRUE(contains(out, 2.01f, 0, 0));
  EXPECT_TRUE(contains(out, 0, 1.01f, 0));
  EXPECT_TRUE(contains(out, 0, 0, 1.01f));

  params.remove_ego = false;  // switched off: everything kept
  prepareCloud(in, params, out);
  EXPECT_EQ(out.size(), 7u);

  params.remove_ego = true;  // empty box (min >= max on z): disabled
  params.ego_max.z() = params.ego_min.z();
  prepareCloud(in, params, out);
  EXPECT_EQ(out.size(), 7u);
}

// Lattice 20 x 20 x 2 with spacing 0.5 starting at (10.25, -4.75, 0.25): with a 1 m leaf every
// voxel [10+i, 11+i) x [-5+j, -4+j) x [0, 1) holds 2 x 2 x 2 points, so 10 x 10 x 1 = 100
// voxels with centroids at the voxel centres' x/y and z = 0.5.
Cloud lattice() {
  Cloud c;
  for (int i = 0; i < 20; ++i) {
    for (int j = 0; j < 20; ++j) {
      for (int k = 0; k < 2; ++k) {
        c.push_back(Point(10.25f + 0.5f * i, -4.75f + 0.5f * j, 0.25f + 0.5f * k));
      }
    }
  }
  return c;
}

TEST(CloudPrep, VoxelGridCountOnKnownLattice) {
  CloudPrepParams params;  // default ROI and ego box: the lattice lies inside / outside them
  params.voxel_leaf_m = 1.0f;
  const Cloud in = lattice();
  ASSERT_EQ(in.size(), 800u);
  Cloud out;
  prepareCloud(in, params, out);
  ASSERT_EQ(out.size(), 100u);
  EXPECT_EQ(out.width, 100u);
  EXPECT_EQ(out.height, 1u);
  std::map<std::pair<int, int>, int> seen;
  for (const Point& p : out) {
    EXPECT_NEAR(p.z, 0.5f, 1e-5f);
    const float fx = p.x - std::floor(p.x), fy = p.y - std::floor(p.y);
    EXPECT_NEAR(fx, 0.5f, 1e-4f);  // centroid of 10.25 / 10.75 is 10.5
    EXPECT_NEAR(fy, 0.5f, 1e-4f);
    ++seen[{static_cast<int>(std::floor(p.x)), static_cast<int>(std::floor(p.y))}];
  }
  EXPECT_EQ(seen.size(), 100u);

  params.voxel_leaf_m = 0.5f;  // one point per voxel: nothing merged
  prepareCloud(in, params, out);
  EXPECT_EQ(out.size(), 800u);
  params.voxel_leaf_m = 0.0f;  // disabled
  prepareCloud(in, params, out);
  EXPECT_EQ(out.size(), 800u);
}

TEST(CloudPrep, VoxelGridAfterCrop) {
  // The crop runs first: points outside the ROI never reach the grid.
  CloudPrepParams params = noEgoNoVoxel();
  params.voxel_leaf_m = 1.0f;
  params.roi_max.x() = 15.0f;  // keeps lattice columns with x < 15: 5 of 10 voxel columns
  Cloud out;
  prepareCloud(lattice(), params, out);
  EXPECT_EQ(out.size(), 50u);
  for (const Point& p : out) EXPECT_LT(p.x, 15.0f);
}

TEST(CloudPrep, LeafTooSmallForExtentFallsBackToNoDownsampling) {
  // 80 m x 40 m at a 1e-4 m leaf is ~3e17 voxels: pcl::VoxelGrid's int indices would overflow.
  CloudPrepParams params = noEgoNoVoxel();
  params.voxel_leaf_m = 1e-4f;
  const Cloud in = cloudOf({{-19, -19, -2}, {59, 19, 2}, {10, 0, 0}, {10, 0, 0}});
  Cloud out;
  prepareCloud(in, params, out);
  EXPECT_EQ(out.size(), 4u);  // copied through, duplicates included
  EXPECT_TRUE(contains(out, -19, -19, -2));
  EXPECT_TRUE(contains(out, 59, 19, 2));

  // Two far points 1 mm apart with a 1e-9 m leaf: the voxel count (1e6) fits PCL's check, but
  // x / leaf = 5e10 overflows its int voxel bounds, which would merge them into one voxel.
  params.voxel_leaf_m = 1e-9f;
  const Cloud far = cloudOf({{50, 0, 0}, {50.001f, 0, 0}});
  prepareCloud(far, params, out);
  ASSERT_EQ(out.size(), 2u);
  EXPECT_TRUE(contains(out, 50, 0, 0));
  EXPECT_TRUE(contains(out, 50.001f, 0, 0));
}

TEST(CloudPrep, OutputClearedFirst) {
  Cloud out = cloudOf({{1, 2, 3}, {4, 5, 6}});
  prepareCloud(Cloud(), CloudPrepParams(), out);
  EXPECT_TRUE(out.empty());
  EXPECT_EQ(out.width, 0u);
  CloudPrepParams voxel;
  voxel.voxel_leaf_m = 0.2f;
  out = cloudOf({{1, 2, 3}});
  prepareCloud(Cloud(), voxel, out);
  EXPECT_TRUE(out.empty());
}

TEST(CloudPrep, ValidateDefaultsAreValid) { EXPECT_EQ(validate(CloudPrepParams()), ""); }

TEST(CloudPrep, ValidateMessagesNameParameterAndValue) {
  CloudPrepParams p;
  p.voxel_leaf_m = -0.1f;
  EXPECT_EQ(validate(p), "prep.voxel_leaf_m must be >= 0 (got -0.1)");
  p.voxel_leaf_m = std::numeric_limits<float>::quiet_NaN();
  EXPECT_NE(validate(p).find("prep.voxel_leaf_m"), std::string::npos);

  p = CloudPrepParams();
  p.roi_min.y() = 5.0f;
  p.roi_max.y() = 5.0f;
  EXPECT_EQ(validate(p), "prep.roi_min.y must be < prep.roi_max.y (got 5 >= 5)");
  p = CloudPrepParams();
  p.roi_min.z() = 4.0f;
  EXPECT_EQ(validate(p), "prep.roi_min.z must be < prep.roi_max.z (got 4 >= 3)");
  p = CloudPrepParams();
  p.roi_max.x() = std::numeric_limits<float>::infinity();
  EXPECT_NE(validate(p).find("prep.roi_min and prep.roi_max must be finite"), std::string::npos);

  p = CloudPrepParams();
  p.ego_min.x() = 3.0f;  // empty ego box: valid, it only disables ego removal
  EXPECT_EQ(validate(p), "");
  p.ego_min.x() = std::numeric_limits<float>::quiet_NaN();
  EXPECT_NE(validate(p).find("prep.ego_min"), std::string::npos);
}

}  // namespace
}  // namespace icanc
