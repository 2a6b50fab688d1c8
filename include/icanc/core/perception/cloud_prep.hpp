// Cloud preparation before ground removal: region of interest, ego-vehicle box, voxel grid.
#pragma once

#include <string>

#include <Eigen/Core>

#include "icanc/core/common/types.hpp"

namespace icanc {

struct CloudPrepParams {
  // Region of interest in the vehicle frame [m]; points outside are dropped.
  Eigen::Vector3f roi_min{-20.0f, -20.0f, -3.0f};
  Eigen::Vector3f roi_max{60.0f, 20.0f, 3.0f};
  // The vehicle's own body [m]; points inside are dropped (disabled when min >= max on any axis).
  Eigen::Vector3f ego_min{-1.0f, -1.0f, -3.0f};
  Eigen::Vector3f ego_max{1.0f, 1.0f, 3.0f};
  bool remove_ego = true;
  // Voxel grid leaf size [m] (pcl::VoxelGrid, centroid per voxel); 0 disables downsampling.
  // A leaf so small that PCL's 32-bit voxel indices would overflow for the cropped cloud's
  // extent falls back to no downsampling (the ROI bounds that extent).
  float voxel_leaf_m = 0.2f;
};

// Returns an empty string when the parameters are valid, else a sentence naming the problem.
std::string validate(const CloudPrepParams& params);

// Drops non-finite and all-zero points, points outside the ROI and inside the ego box, then
// downsamples with a voxel grid when enabled. `out` is cleared first and must not alias `in`.
// Both boxes are closed: a point on the ROI boundary is kept, one on the ego boundary dropped.
void prepareCloud(const Cloud& in, const CloudPrepParams& params, Cloud& out);

}  // namespace icanc
