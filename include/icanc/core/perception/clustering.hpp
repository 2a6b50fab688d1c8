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
  int max_points = 5000;
  // A box that is one column of the scan on a surface seen at grazing incidence is dropped when
  // another box of its height continues that surface (dropGrazingColumnBoxes; keys
  // cluster/grazing_reach_m, grazing_angle_deg, grazing_max_step_m; its thin_m is set from the
  // voxel grid by the ObstacleDetector).
  GrazingColumnParams grazing;
};

std::string validate(const ClusterParams& params);

// Clusters `cloud` and returns one fitted box per cluster, largest cluster first, with its
// footprint cells when footprint_cell_m > 0 (fitBox).
std::vector<Box3D> clusterBoxes(const Cloud& cloud, const ClusterParams& params,
                                float footprint_cell_m = 0.0f);

}  // namespace icanc
