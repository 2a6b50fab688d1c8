// Euclidean clustering (PCL EuclideanClusterExtraction with a k-d tree) and box fitting.
#pragma once

#include <string>
#include <vector>

#include "icanc/core/perception/box.hpp"
#include "icanc/core/perception/grazing_columns.hpp"
#include "icanc/core/common/types.hpp"

namespace icanc {

struct ClusterParams {
  float tolerance_m = 0.6f;  // neighbour distance [m]
  int min_points = 10;
  // > 0: beyond this planar range from the frame's origin a cluster needs only
  // min_points * min_points_range_m / range points, and at least min_points_far: a far object's
  // returns thin out with range, a near clump of a few returns stays clutter; 0: min_points
  // everywhere (the paper's chain) [m]
  float min_points_range_m = 0.0f;
  int min_points_far = 3;
  int max_points = 5000;
  // A box that is one column of the scan on a surface seen at grazing incidence is dropped when
  // another box of its height continues that surface (dropGrazingColumnBoxes; keys
  // cluster/grazing_reach_m, grazing_angle_deg, grazing_max_step_m; its thin_m is set from the
  // voxel grid by the ObstacleDetector).
  GrazingColumnParams grazing;
};

// The points a cluster needs whose points' mean lies `range_m` (planar) from the origin.
int minClusterPoints(const ClusterParams& params, float range_m);

std::string validate(const ClusterParams& params);

// Clusters `cloud` and returns one fitted box per cluster, largest cluster first, with its
// footprint cells when footprint_cell_m > 0 (fitBox).
std::vector<Box3D> clusterBoxes(const Cloud& cloud, const ClusterParams& params,
                                float footprint_cell_m = 0.0f);

}  // namespace icanc
