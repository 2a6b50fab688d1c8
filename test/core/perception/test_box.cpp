// Pins the box fitting's footprint cells (Box3D::footprint): tight bounds of the points in each
// occupied cell of a grid anchored at the origin, their union's bounds the axis-aligned box; and
// its convex hull (Box3D::hull).
#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include <opencv2/imgproc.hpp>

#include <gtest/gtest.h>

#include "icanc/core/perception/box.hpp"

namespace icanc {
namespace {

Cloud uShape() {  // side walls x in [2, 6] at y = +-2, an end wall at x = 6, points 0.1 m apart
  Cloud cloud;
  for (int i = 20; i <= 60; ++i) {
    cloud.push_back(Point(i / 10.0f, 2.0f, 0.5f));
    cloud.push_back(Point(i / 10.0f, -2.0f, 1.5f));
  }
  for (int i = -19; i <= 19; ++i) cloud.push_back(Point(6.0f, i / 10.0f, 1.0f));
  return cloud;
}

TEST(BoxFootprint, CellsAreTightAndCoverOnlyThePoints) {
  const Cloud cloud = uShape();
  const Box3D box = fitBox(cloud, nullptr, 1.0f);
  EXPECT_NEAR(box.min.x(), 2.0f, 1e-4f);
  EXPECT_NEAR(box.max.y(), 2.0f, 1e-4f);
  ASSERT_FALSE(box.footprint.empty());
  Eigen::Vector2f lo = box.footprint[0].min, hi = box.footprint[0].max;
  for (const FootprintCell& c : box.footprint) {
    lo = lo.cwiseMin(c.min);
    hi = hi.cwiseMax(c.max);
    // Inside one grid cell, and tight: a corner of it is a point's coordinate.
    EXPECT_LE(c.max.x() - c.min.x(), 1.0f);
    EXPECT_LE(c.max.y() - c.min.y(), 1.0f);
    // The U's inside (|y| < 1.9, x < 5.9) holds no part.
    EXPECT_FALSE(c.min.x() < 5.9f && c.min.y() > -1.9f && c.max.y() < 1.9f) << c.min.transpose();
  }
  EXPECT_TRUE(lo.isApprox(box.min.head<2>(), 1e-5f));
  EXPECT_TRUE(hi.isApprox(box.max.head<2>(), 1e-5f));
  // Every point lies in a part.
  for (const Point& p : cloud) {
    bool inside = false;
    for (const FootprintCell& c : box.footprint)
      inside |= p.x >= c.min.x() && p.x <= c.max.x() && p.y >= c.min.y() && p.y <= c.max.y();
    EXPECT_TRUE(inside) << p;
  }
  // Side walls: x cells 2..6 at y cells 2 and -2; the end wall: y cells -2..1 at x cell 6, of
  // which (6, -2) also holds the right wall's last point.
  EXPECT_EQ(box.footprint.size(), 5u + 5u + 4u - 1u);
}

TEST(BoxFootprint, CellsFollowTheGridNotThePointsAndNoneWhenOff) {
  // Points on both sides of x = 1.0 fall into two cells split at the grid line; negative
  // coordinates floor (-0.2 is cell -1).
  const std::vector<cv::Point2f> xy{{0.8f, 0.1f}, {0.95f, 0.3f}, {1.05f, 0.2f}, {-0.2f, 0.5f}};
  const std::vector<FootprintCell> cells = footprintCells(xy, 1.0f);
  ASSERT_EQ(cells.size(), 3u);  // ordered by cell: x cell -1, 0, 1
  EXPECT_FLOAT_EQ(cells[0].min.x(), -0.2f);
  EXPECT_FLOAT_EQ(cells[1].min.x(), 0.8f);
  EXPECT_FLOAT_EQ(cells[1].max.x(), 0.95f);
  EXPECT_FLOAT_EQ(cells[1].min.y(), 0.1f);
  EXPECT_FLOAT_EQ(cells[1].max.y(), 0.3f);
  EXPECT_FLOAT_EQ(cells[2].min.x(), 1.05f);
  EXPECT_TRUE(footprintCells(xy, 0.0f).empty());
  // Non-finite points are skipped, by both paths (dense here; sorted with a far point).
  std::vector<cv::Point2f> bad = xy;
  bad.emplace_back(std::numeric_limits<float>::quiet_NaN(), 0.5f);
  bad.emplace_back(0.5f, std::numeric_limits<float>::infinity());
  EXPECT_EQ(footprintCells(bad, 1.0f).size(), 3u);
  bad.emplace_back(500.0f, 500.0f);
  EXPECT_EQ(footprintCells(bad, 1.0f).size(), 4u);
  EXPECT_TRUE(footprintCells({{std::numeric_limits<float>::quiet_NaN(), 1.0f}}, 1.0f).empty());
  EXPECT_TRUE(fitBoxFootprint(xy, 0.0f, 1.0f, 4).footprint.empty());
  EXPECT_EQ(fitBoxFootprint(xy, 0.0f, 1.0f, 4, 0.5f).footprint.size(), 3u);
  EXPECT_EQ(fitBoxFootprint(xy, 0.0f, 1.0f, 4, 0.1f).footprint.size(), 4u);  // 0.8 | 0.95 split
}

// Points spread far apart (a grid over their cells would be mostly empty) take a sorted path: the
// same cells, in the same order, as the dense grid gives for the compact part.
TEST(BoxFootprint, SparsePointsGiveTheSameCellsAsTheDenseGrid) {
  std::vector<cv::Point2f> xy;
  for (const Point& p : uShape()) xy.emplace_back(p.x, p.y);
  const std::vector<FootprintCell> dense = footprintCells(xy, 1.0f);
  xy.emplace_back(-150.5f, 300.25f);  // one far point: 157 x 303 cells for 123 points
  const std::vector<FootprintCell> sparse = footprintCells(xy, 1.0f);
  ASSERT_EQ(sparse.size(), dense.size() + 1);
  EXPECT_FLOAT_EQ(sparse[0].min.x(), -150.5f);  // its x cell comes first
  EXPECT_FLOAT_EQ(sparse[0].max.y(), 300.25f);
  for (std::size_t i = 0; i < dense.size(); ++i) {
    EXPECT_EQ(sparse[i + 1].min, dense[i].min) << i;
    EXPECT_EQ(sparse[i + 1].max, dense[i].max) << i;
  }
}

// Box3D::hull: the convex hull of the footprint, whose bounds along any axes are the points'. The
// U's hull is its outer rectangle (its inside is not a corner of it); turned by 30 deg, the hull's
// extreme along x is the points' extreme.
TEST(BoxHull, HoldsTheExtremePointsAlongAnyAxes) {
  const Cloud cloud = uShape();
  const Box3D box = fitBox(cloud);
  ASSERT_GE(box.hull.size(), 4u);
  Eigen::Vector2f lo = box.hull[0], hi = box.hull[0];
  for (const Eigen::Vector2f& p : box.hull) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
    EXPECT_TRUE(p.x() < 2.05f || p.x() > 5.95f || std::abs(std::abs(p.y()) - 2.0f) < 1e-4f)
        << p.transpose();  // on the outline, never inside the U
  }
  EXPECT_TRUE(lo.isApprox(box.min.head<2>(), 1e-5f));
  EXPECT_TRUE(hi.isApprox(box.max.head<2>(), 1e-5f));
  const Eigen::Vector2f dir(std::cos(0.5236f), std::sin(0.5236f));
  float points_max = -std::numeric_limits<float>::infinity(), hull_max = points_max;
  for (const Point& p : cloud)
    points_max = std::max(points_max, dir.dot(Eigen::Vector2f(p.x, p.y)));
  for (const Eigen::Vector2f& p : box.hull) hull_max = std::max(hull_max, dir.dot(p));
  EXPECT_NEAR(hull_max, points_max, 1e-5f);
}

// hullCandidates leaves out only points that cannot be on the hull: OpenCV's hull of what it keeps
// is the hull of all the points, vertex for vertex, on clouds with ties along every direction it
// tests (lattices, duplicates, axis-parallel and diagonal edges), lines, a few points, and
// non-finite values; on a dense cloud it keeps few.
TEST(BoxHull, CandidatesGiveTheSameHullAsAllThePoints) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> uni(-20.0f, 20.0f);
  std::normal_distribution<float> gauss(0.0f, 0.3f);
  std::uniform_int_distribution<int> lattice(-6, 6), count(0, 300), shape(0, 5);
  std::vector<cv::Point2f> xy, candidates, all_hull, hull;
  std::size_t kept = 0, offered = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    xy.clear();
    const int n = count(rng), kind = shape(rng);
    const float cx = uni(rng), cy = uni(rng);
    for (int i = 0; i < n; ++i) {
      switch (kind) {
        case 0: xy.emplace_back(cx + gauss(rng), cy + gauss(rng)); break;
        case 1: xy.emplace_back(cx + 0.1f * lattice(rng), cy + 0.1f * lattice(rng)); break;
        case 2: {  // a diamond's lattice: edges along x + y and x - y
          const int a = lattice(rng), b = lattice(rng);
          xy.emplace_back(cx + 0.25f * (a + b), cy + 0.25f * (a - b));
          break;
        }
        case 3: {  // a line, as a wall seen end on
          const float t = uni(rng);
          xy.emplace_back(cx + t, cy + 0.5f * t);
          break;
        }
        case 4: xy.emplace_back(std::round(uni(rng)), std::round(uni(rng) * 0.1f)); break;
        default: xy.emplace_back(uni(rng), uni(rng)); break;
      }
      if (i > 0 && trial % 7 == 0 && i % 5 == 0) xy.push_back(xy[static_cast<std::size_t>(i - 1)]);
    }
    hullCandidates(xy, candidates);
    for (const cv::Point2f& p : candidates)  // a subset of the points
      ASSERT_NE(std::find(xy.begin(), xy.end(), p), xy.end()) << "trial " << trial;
    if (xy.empty()) {
      EXPECT_TRUE(candidates.empty());
      continue;
    }
    cv::convexHull(xy, all_hull, false);
    cv::convexHull(candidates, hull, false);
    ASSERT_EQ(hull, all_hull) << "trial " << trial << ", kind " << kind << ", " << n << " points";
    if (n >= 200 && (kind == 0 || kind == 5)) {
      kept += candidates.size();
      offered += xy.size();
    }
  }
  ASSERT_GT(offered, 0u);
  EXPECT_LT(kept * 4, offered);  // a dense cloud keeps less than a quarter of its points

  // Collinear points have no inside: all are kept. A NaN is kept (cv::convexHull decides).
  xy = {{0, 0}, {1, 1}, {2, 2}, {3, 3}};
  hullCandidates(xy, candidates);
  EXPECT_EQ(candidates.size(), 4u);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  xy = {{0, 0}, {4, 0}, {4, 4}, {0, 4}, {2, 2}, {nan, 1}};
  hullCandidates(xy, candidates);
  EXPECT_EQ(candidates.size(), 5u);  // the square's corners and the NaN, not its middle
}

}  // namespace
}  // namespace icanc
