// 3D boxes fitted to clusters, and the overlap measure the tracker gates on.
#pragma once

#include <vector>

#include <Eigen/Core>
#include <opencv2/core/types.hpp>

#include "icanc/core/common/types.hpp"
#include "icanc/core/motion/motion_state.hpp"

namespace icanc {

// A tight axis-aligned part of a footprint seen from above (x/y) [m].
struct FootprintCell {
  Eigen::Vector2f min = Eigen::Vector2f::Zero();
  Eigen::Vector2f max = Eigen::Vector2f::Zero();
};

struct Box3D {
  Eigen::Vector3f center = Eigen::Vector3f::Zero();  // centre of the oriented box [m]
  Eigen::Vector3f size = Eigen::Vector3f::Zero();    // length (along yaw), width, height [m]
  float yaw = 0.0f;                                  // oriented box yaw about +z [rad], in (-pi/2, pi/2]
  Eigen::Vector3f min = Eigen::Vector3f::Zero();     // axis-aligned bounds [m]
  Eigen::Vector3f max = Eigen::Vector3f::Zero();
  int num_points = 0;
  // Where the points are, seen from above: one tight box per occupied cell of a grid of
  // footprint_cell_m, so a concave cluster (walls meeting at a corner, a curving hedge) covers
  // only its points, not its whole axis-aligned box. Their union's bounds are min/max (x, y).
  // Empty: the axis-aligned box is the footprint.
  std::vector<FootprintCell> footprint;
  // The convex hull of the footprint's points (x, y) [m], counter-clockwise: the extreme points
  // along any direction, so the box's bounds in any axes (the tracker measures a track's faces in
  // axes fixed to the ground while the vehicle turns). Empty: the axis-aligned box's corners.
  std::vector<Eigen::Vector2f> hull;
  // What free space says of its points this frame (FreeSpaceMotion::evaluate; none: unknown).
  MotionEvidence motion;
};

// Fits both boxes to the given points (indices into cloud; all points when indices is null):
// axis-aligned bounds from min/max, oriented box from OpenCV's minimum-area rectangle of the
// points' x/y with z from min/max, their convex hull, and the footprint cells when
// footprint_cell_m > 0. An empty
// point set gives a zero box with num_points = 0.
Box3D fitBox(const Cloud& cloud, const std::vector<int>* indices = nullptr,
             float footprint_cell_m = 0.0f);

// The same boxes from a footprint only: x/y points (the cluster's points, or any subset holding
// its extreme points), the cluster's z range and its point count. Shared by fitBox and the fast
// path (which passes each grid cell's extreme points). An empty footprint gives a zero box.
Box3D fitBoxFootprint(const std::vector<cv::Point2f>& xy, float zmin, float zmax, int num_points,
                      float footprint_cell_m = 0.0f);

// Box3D::footprint of the x/y points: the tight bounds of the points in each occupied cell of a
// grid of cell_m (cells anchored at the frame's origin), ordered by cell.
std::vector<FootprintCell> footprintCells(const std::vector<cv::Point2f>& xy, float cell_m);

// The points of xy that may lie on its convex hull, appended to out (cleared first): all but
// those strictly inside the octagon of its extreme points along x, y, x + y and x - y
// (Akl-Toussaint). The hull of what is left is the hull of xy, found without sorting the points
// the octagon already rules out (most of a cluster's). Points on or near the octagon's edges are
// kept; so is everything when the octagon has no inside (collinear points, fewer than three).
void hullCandidates(const std::vector<cv::Point2f>& xy, std::vector<cv::Point2f>& out);

// Intersection over union of the axis-aligned boxes seen from above (x/y only), in [0, 1].
float bevIoU(const Box3D& a, const Box3D& b);

// True when p lies inside the box with this centre, size (length along yaw, width, height) and
// yaw about +z, grown by margin_m on every side.
bool orientedBoxContains(const Eigen::Vector3d& center, const Eigen::Vector3d& size, double yaw,
                         const Eigen::Vector3d& p, double margin_m = 0.0);

}  // namespace icanc
