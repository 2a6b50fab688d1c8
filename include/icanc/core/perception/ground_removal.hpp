// Ground removal: one RANSAC plane, as in the paper's obstacle detector (PCL SACSegmentation).
#pragma once

#include <string>

#include <Eigen/Core>

#include "icanc/core/common/types.hpp"

namespace icanc {

struct GroundParams {
  bool enabled = true;
  int max_iterations = 30;            // RANSAC iterations
  float distance_threshold_m = 0.3f;  // inlier distance to the plane [m]
  float max_slope_deg = 15.0f;        // plane normal within this angle of +z (rejects walls)
};

std::string validate(const GroundParams& params);

struct GroundResult {
  bool found = false;
  Eigen::Vector4f plane = Eigen::Vector4f::Zero();  // a x + b y + c z + d = 0, normal up (c > 0)
  std::size_t inliers = 0;
};

// Splits `in` into ground (dropped) and the rest (`nonground`, cleared first; must not alias
// `in`). When no plane is found, or ground removal is disabled, `nonground` is a copy of `in`.
// Deterministic: PCL's RANSAC runs single-threaded from a fixed seed on every call.
GroundResult removeGround(const Cloud& in, const GroundParams& params, Cloud& nonground);

}  // namespace icanc
