// clusterBoxes: separation by the tolerance, cluster size limits, order, and the boxes fitted to
// the clusters (axis-aligned bounds and the oriented box of a car-sized footprint).
#include "icanc/core/perception/clustering.hpp"

#include <algorithm>
#include <cmath>

#include <gtest/gtest.h>

namespace icanc {
namespace {

// Solid block of points on a `step` grid from `lo` to `hi` (both included).
void addBlock(Cloud& cloud, const Eigen::Vector3f& lo, const Eigen::Vector3f& hi, float step) {
  const int nx = static_cast<int>(std::round((hi.x() - lo.x()) / step));
  const int ny = static_cast<int>(std::round((hi.y() - lo.y()) / step));
  const int nz = static_cast<int>(std::round((hi.z() - lo.z()) / step));
  for (int i = 0; i <= nx; ++i) {
    for (int j = 0; j <= ny; ++j) {
      for (int k = 0; k <= nz; ++k) {
        cloud.push_back(Point(lo.x() + i * step, lo.y() + j * step, lo.z() + k * step));
      }
    }
  }
}

// A line of n points 0.1 m apart along x starting at `start`.
void addLine(Cloud& cloud, const Eigen::Vector3f& start, int n) {
  for (int i = 0; i < n; ++i) cloud.push_back(Point(start.x() + 0.1f * i, start.y(), start.z()));
}

void expectVecNear(const Eigen::Vector3f& a, const Eigen::Vector3f& b, float tol) {
  EXPECT_NEAR(a.x(), b.x(), tol);
  EXPECT_NEAR(a.y(), b.y(), tol);
  EXPECT_NEAR(a.z(), b.z(), tol);
}

TEST(Clustering, TwoBoxesThreeMetresApart) {
  Cloud cloud;
  // 1 x 1 x 1 m block (6^3 = 216 points) and a 1 x 2 x 1 m block (6 x 11 x 6 = 396 points) with a
  // 3 m gap in x.
  addBlock(cloud, {5, -1, -1.5f}, {6, 0, -0.5f}, 0.2f);
  addBlock(cloud, {9, 1, -1.5f}, {10, 3, -0.5f}, 0.2f);
  ASSERT_EQ(cloud.size(), 216u + 396u);
  ClusterParams params;  // 0.6 m, 10..5000
  const std::vector<Box3D> boxes = clusterBoxes(cloud, params);
  ASSERT_EQ(boxes.size(), 2u);
  // Largest first.
  EXPECT_EQ(boxes[0].num_points, 396);
  EXPECT_EQ(boxes[1].num_points, 216);
  expectVecNear(boxes[0].min, {9, 1, -1.5f}, 1e-4f);
  expectVecNear(boxes[0].max, {10, 3, -0.5f}, 1e-4f);
  expectVecNear(boxes[1].min, {5, -1, -1.5f}, 1e-4f);
  expectVecNear(boxes[1].max, {6, 0, -0.5f}, 1e-4f);
  expectVecNear(boxes[0].center, {9.5f, 2, -1}, 1e-3f);
  EXPECT_NEAR(boxes[0].size.x(), 2.0f, 1e-3f);  // length is the longer side
  EXPECT_NEAR(boxes[0].size.y(), 1.0f, 1e-3f);
  EXPECT_NEAR(boxes[0].size.z(), 1.0f, 1e-4f);
}

TEST(Clustering, BoxesCloserThanToleranceMerge) {
  Cloud cloud;
  addBlock(cloud, {5, 0, 0}, {6, 1, 1}, 0.2f);
  addBlock(cloud, {6.3f, 0, 0}, {7.3f, 1, 1}, 0.2f);  // 0.3 m gap
  ClusterParams params;
  params.tolerance_m = 0.6f;
  std::vector<Box3D> boxes = clusterBoxes(cloud, params);
  ASSERT_EQ(boxes.size(), 1u);
  EXPECT_EQ(boxes[0].num_points, static_cast<int>(cloud.size()));
  expectVecNear(boxes[0].min, {5, 0, 0}, 1e-4f);
  expectVecNear(boxes[0].max, {7.3f, 1, 1}, 1e-4f);

  params.tolerance_m = 0.25f;  // tighter than the gap (and above the 0.2 m grid): split again
  boxes = clusterBoxes(cloud, params);
  EXPECT_EQ(boxes.size(), 2u);
}

TEST(Clustering, MinAndMaxClusterSizeRespected) {
  Cloud cloud;
  addLine(cloud, {0, 0, 0}, 9);     // below min_points: dropped
  addLine(cloud, {0, 5, 0}, 10);    // exactly min_points: kept
  addLine(cloud, {0, 10, 0}, 40);   // exactly max_points: kept
  addLine(cloud, {0, 15, 0}, 41);   // above max_points: dropped, not split
  addLine(cloud, {0, 20, 0}, 25);
  ClusterParams params;
  params.tolerance_m = 0.15f;
  params.min_points = 10;
  params.max_points = 40;
  const std::vector<Box3D> boxes = clusterBoxes(cloud, params);
  ASSERT_EQ(boxes.size(), 3u);
  EXPECT_EQ(boxes[0].num_points, 40);  // sorted by size, largest first
  EXPECT_EQ(boxes[1].num_points, 25);
  EXPECT_EQ(boxes[2].num_points, 10);
  EXPECT_NEAR(boxes[0].min.y(), 10.0f, 1e-5f);
  EXPECT_NEAR(boxes[1].min.y(), 20.0f, 1e-5f);
  EXPECT_NEAR(boxes[2].min.y(), 5.0f, 1e-5f);
}

TEST(Clustering, MinPointsFallWithRangeBeyondMinPointsRange) {
  ClusterParams params;  // min_points 10
  EXPECT_EQ(minClusterPoints(params, 40.0f), 10);  // off by default: the paper's chain
  params.min_points_range_m = 20.0f;
  params.min_points_far = 7;
  EXPECT_EQ(minClusterPoints(params, 5.0f), 10);
  EXPECT_EQ(minClusterPoints(params, 20.0f), 10);
  EXPECT_EQ(minClusterPoints(params, 25.0f), 8);  // ceil(10 * 20 / 25)
  EXPECT_EQ(minClusterPoints(params, 40.0f), 7);  // 5, held at min_points_far
  params.min_points_far = 12;                     // never more than min_points
  EXPECT_EQ(minClusterPoints(params, 40.0f), 10);
}

TEST(Clustering, AFarSparseClusterIsKeptANearOneOfTheSameSizeDropped) {
  Cloud cloud;
  addLine(cloud, {5, 0, 0}, 8);    // 5 m: needs 10
  addLine(cloud, {30, 0, 0}, 8);   // 30 m: needs ceil(10 * 20 / 30) = 7
  addLine(cloud, {40, 5, 0}, 6);   // 40 m: needs 7 (min_points_far)
  ClusterParams params;
  params.tolerance_m = 0.15f;
  EXPECT_TRUE(clusterBoxes(cloud, params).empty());  // min_points 10 everywhere
  params.min_points_range_m = 20.0f;
  params.min_points_far = 7;
  const std::vector<Box3D> boxes = clusterBoxes(cloud, params);
  ASSERT_EQ(boxes.size(), 1u);
  EXPECT_EQ(boxes[0].num_points, 8);
  EXPECT_NEAR(boxes[0].min.x(), 30.0f, 1e-4f);
}

TEST(Clustering, OrientedBoxOfRotatedCar) {
  // A 4 x 1.8 m footprint, rotated 30 deg about z and centred at (15, -4), filled on a 0.1 m grid
  // at four heights 0.5 m apart (within the 0.6 m tolerance), 1.5 m tall in all.
  const float yaw = 30.0f * static_cast<float>(M_PI) / 180.0f;
  const float c = std::cos(yaw), s = std::sin(yaw);
  Cloud cloud;
  for (int i = 0; i <= 40; ++i) {
    for (int j = 0; j <= 18; ++j) {
      const float u = -2.0f + 0.1f * i, v = -0.9f + 0.1f * j;
      for (const float z : {-1.2f, -0.7f, -0.2f, 0.3f}) {
        cloud.push_back(Point(15 + c * u - s * v, -4 + s * u + c * v, z));
      }
    }
  }
  const std::vector<Box3D> boxes = clusterBoxes(cloud, ClusterParams());
  ASSERT_EQ(boxes.size(), 1u);
  const Box3D& b = boxes[0];
  const float longer = std::max(b.size.x(), b.size.y()), shorter = std::min(b.size.x(), b.size.y());
  EXPECT_NEAR(longer, 4.0f, 0.02f);
  EXPECT_NEAR(shorter, 1.8f, 0.02f);
  EXPECT_NEAR(b.size.z(), 1.5f, 1e-4f);
  EXPECT_NEAR(b.center.x(), 15.0f, 0.02f);
  EXPECT_NEAR(b.center.y(), -4.0f, 0.02f);
  // Yaw about 30 deg modulo 90 deg (a rectangle's sides are interchangeable).
  const float yaw_deg = b.yaw * 180.0f / static_cast<float>(M_PI);
  float off = std::fmod(yaw_deg - 30.0f, 90.0f);
  if (off < -45.0f) off += 90.0f;
  if (off > 45.0f) off -= 90.0f;
  EXPECT_NEAR(off, 0.0f, 1.0f) << "yaw " << yaw_deg << " deg";
  // The axis-aligned bounds hold every point and are wider than the footprint's sides.
  EXPECT_GT(b.max.x() - b.min.x(), 4.0f * c);
}

TEST(Clustering, EmptyCloudGivesNoBoxes) {
  EXPECT_TRUE(clusterBoxes(Cloud(), ClusterParams()).empty());
}

TEST(Clustering, ValidateMessages) {
  EXPECT_EQ(validate(ClusterParams()), "");
  ClusterParams p;
  p.tolerance_m = 0.0f;
  EXPECT_EQ(validate(p), "cluster.tolerance_m must be > 0 (got 0)");
  p = ClusterParams();
  p.min_points = 0;
  EXPECT_EQ(validate(p), "cluster.min_points must be >= 1 (got 0)");
  p = ClusterParams();
  p.min_points_range_m = -1.0f;
  EXPECT_EQ(validate(p), "cluster.min_points_range_m must be >= 0 (got -1)");
  p = ClusterParams();
  p.min_points_far = 0;
  EXPECT_EQ(validate(p), "cluster.min_points_far must be >= 1 (got 0)");
  p = ClusterParams();
  p.max_points = 5;
  EXPECT_EQ(validate(p), "cluster.max_points must be >= cluster.min_points = 10 (got 5)");
}

}  // namespace
}  // namespace icanc
