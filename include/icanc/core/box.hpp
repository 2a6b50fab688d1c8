// 3D boxes fitted to clusters, and the overlap measure the tracker gates on.
#pragma once

#include <vector>

#include <Eigen/Core>
#include <opencv2/core/types.hpp>

#include "icanc/core/types.hpp"

namespace icanc {

struct Box3D {
  Eigen::Vector3f center = Eigen::Vector3f::Zero();  // centre of the oriented box [m]
  Eigen::Vector3f size = Eigen::Vector3f::Zero();    // length (along yaw), width, height [m]
  float yaw = 0.0f;                                  // oriented box yaw about +z [rad], in (-pi/2, pi/2]
  Eigen::Vector3f min = Eigen::Vector3f::Zero();     // axis-aligned bounds [m]
  Eigen::Vector3f max = Eigen::Vector3f::Zero();
  int num_points = 0;
};

// Fits both boxes to the given points (indices into cloud; all points when indices is null):
// axis-aligned bounds from min/max, oriented box from OpenCV's minimum-area rectangle of the
// points' x/y with z from min/max. An empty point set gives a zero box with num_points = 0.
Box3D fitBox(const Cloud& cloud, const std::vector<int>* indices = nullptr);

// The same boxes from a footprint only: x/y points (the cluster's points, or any subset holding
// its extreme points), the cluster's z range and its point count. Shared by fitBox and the fast
// path (which passes each grid cell's extreme points). An empty footprint gives a zero box.
Box3D fitBoxFootprint(const std::vector<cv::Point2f>& xy, float zmin, float zmax, int num_points);

// Intersection over union of the axis-aligned boxes seen from above (x/y only), in [0, 1].
float bevIoU(const Box3D& a, const Box3D& b);

// True when p lies inside the box with this centre, size (length along yaw, width, height) and
// yaw about +z, grown by margin_m on every side.
bool orientedBoxContains(const Eigen::Vector3d& center, const Eigen::Vector3d& size, double yaw,
                         const Eigen::Vector3d& p, double margin_m = 0.0);

}  // namespace icanc
