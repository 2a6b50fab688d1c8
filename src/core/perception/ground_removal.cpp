#include "icanc/core/perception/ground_removal.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <vector>

#include <pcl/ModelCoefficients.h>
#include <pcl/PointIndices.h>
#include <pcl/sample_consensus/method_types.h>
#include <pcl/sample_consensus/model_types.h>
#include <pcl/segmentation/sac_segmentation.h>

namespace icanc {

std::string validate(const GroundParams& params) {
  std::ostringstream why;
  if (params.max_iterations < 1) {
    why << "ground.max_iterations must be >= 1 (got " << params.max_iterations << ")";
  } else if (!(params.distance_threshold_m > 0.0f) || !std::isfinite(params.distance_threshold_m)) {
    why << "ground.distance_threshold_m must be > 0 (got " << params.distance_threshold_m << ")";
  } else if (!(params.max_slope_deg >= 0.0f && params.max_slope_deg < 90.0f)) {
    why << "ground.max_slope_deg must be in [0, 90) (got " << params.max_slope_deg << ")";
  }
  return why.str();
}

namespace {

void copyThrough(const Cloud& in, Cloud& out) {
  out.header = in.header;
  out.points.assign(in.points.begin(), in.points.end());
  out.width = static_cast<std::uint32_t>(in.points.size());
  out.height = 1;
  out.is_dense = in.is_dense;
}

}  // namespace

GroundResult removeGround(const Cloud& in, const GroundParams& params, Cloud& nonground) {
  GroundResult result;
  nonground.clear();
  if (!params.enabled || in.size() < 3) {
    copyThrough(in, nonground);
    return result;
  }

  // Non-owning pointer: PCL wants a shared_ptr; `in` outlives the call.
  const Cloud::ConstPtr input(&in, [](const Cloud*) {});

  // A new segmentation object per call: its RANSAC model is seeded with PCL's fixed seed
  // (12345) on construction and runs single-threaded, so equal input gives equal output.
  pcl::SACSegmentation<Point> seg;
  seg.setOptimizeCoefficients(true);
  seg.setModelType(pcl::SACMODEL_PERPENDICULAR_PLANE);
  seg.setMethodType(pcl::SAC_RANSAC);
  seg.setAxis(Eigen::Vector3f::UnitZ());
  seg.setEpsAngle(static_cast<double>(params.max_slope_deg) * M_PI / 180.0);
  seg.setMaxIterations(params.max_iterations);
  seg.setDistanceThreshold(params.distance_threshold_m);
  seg.setNumberOfThreads(-1);
  seg.setInputCloud(input);

  pcl::PointIndices inliers;
  pcl::ModelCoefficients coefficients;
  seg.segment(inliers, coefficients);
  if (inliers.indices.empty() || coefficients.values.size() != 4) {
    copyThrough(in, nonground);  // no plane within max_slope_deg of horizontal (e.g. only walls)
    return result;
  }

  Eigen::Vector4f plane(coefficients.values[0], coefficients.values[1], coefficients.values[2],
                        coefficients.values[3]);
  const float norm = plane.head<3>().norm();
  if (norm > 0.0f && std::isfinite(norm)) plane /= norm;
  if (plane[2] < 0.0f) plane = -plane;  // normal up
  result.found = true;
  result.plane = plane;
  result.inliers = inliers.indices.size();

  // Keep every point not listed as an inlier.
  std::vector<std::uint8_t> is_ground(in.size(), 0);
  for (const int i : inliers.indices) {
    if (i >= 0 && static_cast<std::size_t>(i) < is_ground.size()) is_ground[i] = 1;
  }
  nonground.header = in.header;
  nonground.points.reserve(in.size() - std::min(in.size(), result.inliers));
  for (std::size_t i = 0; i < in.size(); ++i) {
    if (!is_ground[i]) nonground.points.push_back(in.points[i]);
  }
  nonground.width = static_cast<std::uint32_t>(nonground.points.size());
  nonground.height = 1;
  nonground.is_dense = in.is_dense;
  return result;
}

}  // namespace icanc
