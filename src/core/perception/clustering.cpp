#include "icanc/core/perception/clustering.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include <pcl/PointIndices.h>
#include <pcl/common/centroid.h>
#include <pcl/search/kdtree.h>
#include <pcl/segmentation/extract_clusters.h>

namespace icanc {

std::string validate(const ClusterParams& params) {
  std::ostringstream why;
  if (!(params.tolerance_m > 0.0f) || !std::isfinite(params.tolerance_m)) {
    why << "cluster.tolerance_m must be > 0 (got " << params.tolerance_m << ")";
  } else if (params.min_points < 1) {
    why << "cluster.min_points must be >= 1 (got " << params.min_points << ")";
  } else if (!(params.min_points_range_m >= 0.0f) || !std::isfinite(params.min_points_range_m)) {
    why << "cluster.min_points_range_m must be >= 0 (got " << params.min_points_range_m << ")";
  } else if (params.min_points_far < 1) {
    why << "cluster.min_points_far must be >= 1 (got " << params.min_points_far << ")";
  } else if (params.max_points < params.min_points) {
    why << "cluster.max_points must be >= cluster.min_points = " << params.min_points << " (got "
        << params.max_points << ")";
  } else {
    why << validate(params.grazing, "cluster.");
  }
  return why.str();
}

int minClusterPoints(const ClusterParams& params, float range_m) {
  if (!(params.min_points_range_m > 0.0f) || !(range_m > params.min_points_range_m))
    return params.min_points;
  const int scaled = static_cast<int>(
      std::ceil(static_cast<float>(params.min_points) * params.min_points_range_m / range_m));
  return std::min(params.min_points, std::max(params.min_points_far, scaled));
}

std::vector<Box3D> clusterBoxes(const Cloud& cloud, const ClusterParams& params,
                                float footprint_cell_m) {
  std::vector<Box3D> boxes;
  if (cloud.empty()) return boxes;

  // Non-owning pointer: PCL wants a shared_ptr; `cloud` outlives the call.
  const Cloud::ConstPtr input(&cloud, [](const Cloud*) {});
  pcl::search::KdTree<Point>::Ptr tree(new pcl::search::KdTree<Point>);
  tree->setInputCloud(input);

  pcl::EuclideanClusterExtraction<Point> extraction;
  extraction.setClusterTolerance(params.tolerance_m);
  const bool by_range = params.min_points_range_m > 0.0f;
  extraction.setMinClusterSize(by_range ? std::min(params.min_points, params.min_points_far)
                                        : params.min_points);
  extraction.setMaxClusterSize(params.max_points);
  extraction.setSearchMethod(tree);
  extraction.setInputCloud(input);
  std::vector<pcl::PointIndices> clusters;
  extraction.extract(clusters);

  boxes.reserve(clusters.size());
  for (const pcl::PointIndices& cluster : clusters) {
    const int n = static_cast<int>(cluster.indices.size());
    if (n < params.min_points) {  // only by_range: the cluster's mean position gives its range
      Eigen::Vector4f mean;
      pcl::compute3DCentroid(cloud, cluster.indices, mean);
      if (n < minClusterPoints(params, std::hypot(mean.x(), mean.y()))) continue;
    }
    boxes.push_back(fitBox(cloud, &cluster.indices, footprint_cell_m));
  }
  // PCL already returns clusters largest first; a stable sort makes that a guarantee here
  // while keeping PCL's order among equal sizes.
  std::stable_sort(boxes.begin(), boxes.end(),
                   [](const Box3D& a, const Box3D& b) { return a.num_points > b.num_points; });
  return boxes;
}

}  // namespace icanc
