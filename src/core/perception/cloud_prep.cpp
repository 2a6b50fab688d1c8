#include "icanc/core/perception/cloud_prep.hpp"

#include <cmath>
#include <limits>
#include <sstream>

#include <pcl/filters/voxel_grid.h>

namespace icanc {

namespace {

const char* const kAxis[3] = {"x", "y", "z"};

bool allFinite(const Eigen::Vector3f& v) { return v.allFinite(); }

bool egoBoxEnabled(const CloudPrepParams& params) {
  if (!params.remove_ego) return false;
  for (int i = 0; i < 3; ++i) {
    if (!(params.ego_min[i] < params.ego_max[i])) return false;  // empty box: nothing to drop
  }
  return true;
}

// pcl::VoxelGrid indexes voxels with 32-bit ints: floor(coordinate / leaf) must fit, and so must
// the number of voxels in the bounding box (PCL itself warns and copies the input through when
// the latter does not, and silently overflows when only the former does not). This check runs in
// double with a factor-2 margin for PCL's float arithmetic.
bool voxelGridFits(const Eigen::Vector3f& lo, const Eigen::Vector3f& hi, float leaf) {
  const double inv = 1.0 / static_cast<double>(leaf);
  const double limit = static_cast<double>(std::numeric_limits<std::int32_t>::max()) / 2.0;
  double voxels = 1.0;
  for (int i = 0; i < 3; ++i) {
    const double bmin = std::floor(static_cast<double>(lo[i]) * inv);
    const double bmax = std::floor(static_cast<double>(hi[i]) * inv);
    if (!std::isfinite(bmin) || !std::isfinite(bmax)) return false;
    if (std::fabs(bmin) > limit || std::fabs(bmax) > limit) return false;
    voxels *= (bmax - bmin + 2.0);  // +1 for the inclusive range, +1 for PCL's own rounding
  }
  return voxels <= limit;
}

}  // namespace

std::string validate(const CloudPrepParams& params) {
  std::ostringstream why;
  if (!allFinite(params.roi_min) || !allFinite(params.roi_max)) {
    why << "prep.roi_min and prep.roi_max must be finite (got [" << params.roi_min.transpose()
        << "] and [" << params.roi_max.transpose() << "])";
    return why.str();
  }
  for (int i = 0; i < 3; ++i) {
    if (!(params.roi_min[i] < params.roi_max[i])) {
      why << "prep.roi_min." << kAxis[i] << " must be < prep.roi_max." << kAxis[i] << " (got "
          << params.roi_min[i] << " >= " << params.roi_max[i] << ")";
      return why.str();
    }
  }
  if (!allFinite(params.ego_min) || !allFinite(params.ego_max)) {
    why << "prep.ego_min and prep.ego_max must be finite (got [" << params.ego_min.transpose()
        << "] and [" << params.ego_max.transpose() << "])";
    return why.str();
  }
  if (!(params.voxel_leaf_m >= 0.0f) || !std::isfinite(params.voxel_leaf_m)) {
    why << "prep.voxel_leaf_m must be >= 0 (got " << params.voxel_leaf_m << ")";
    return why.str();
  }
  return "";
}

void prepareCloud(const Cloud& in, const CloudPrepParams& params, Cloud& out) {
  // When the voxel grid runs, the crop goes to a scratch cloud first (the grid cannot write in
  // place); thread_local keeps its capacity across frames without changing the API.
  const bool voxel = params.voxel_leaf_m > 0.0f && std::isfinite(params.voxel_leaf_m);
  thread_local Cloud scratch;
  Cloud& cropped = voxel ? scratch : out;

  out.clear();
  cropped.clear();
  out.header = in.header;
  cropped.header = in.header;
  const bool ego = egoBoxEnabled(params);
  const Eigen::Vector3f& rmin = params.roi_min;
  const Eigen::Vector3f& rmax = params.roi_max;
  const Eigen::Vector3f& emin = params.ego_min;
  const Eigen::Vector3f& emax = params.ego_max;
  const float inf = std::numeric_limits<float>::infinity();
  Eigen::Vector3f lo(inf, inf, inf), hi(-inf, -inf, -inf);

  cropped.points.reserve(in.size());
  for (const Point& p : in.points) {
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) continue;
    if (p.x == 0.0f && p.y == 0.0f && p.z == 0.0f) continue;
    // ROI and ego box are both closed: a point on the ROI boundary is kept, one on the ego
    // boundary is dropped.
    if (p.x < rmin.x() || p.x > rmax.x() || p.y < rmin.y() || p.y > rmax.y() || p.z < rmin.z() ||
        p.z > rmax.z()) {
      continue;
    }
    if (ego && p.x >= emin.x() && p.x <= emax.x() && p.y >= emin.y() && p.y <= emax.y() &&
        p.z >= emin.z() && p.z <= emax.z()) {
      continue;
    }
    cropped.points.push_back(p);
    lo = lo.cwiseMin(p.getVector3fMap());
    hi = hi.cwiseMax(p.getVector3fMap());
  }
  cropped.width = static_cast<std::uint32_t>(cropped.points.size());
  cropped.height = 1;
  cropped.is_dense = true;
  if (!voxel) return;

  // A leaf too small for the extent (see voxelGridFits) falls back to no downsampling: the
  // cropped cloud is correct, only larger, where PCL would overflow or warn every frame.
  if (cropped.empty() || !voxelGridFits(lo, hi, params.voxel_leaf_m)) {
    out.points.assign(cropped.points.begin(), cropped.points.end());
    out.width = cropped.width;
    out.height = 1;
    out.is_dense = true;
    return;
  }

  // Non-owning pointer: pcl::VoxelGrid wants a shared_ptr; the scratch cloud outlives the call.
  const Cloud::ConstPtr input(&cropped, [](const Cloud*) {});
  pcl::VoxelGrid<Point> grid;
  grid.setInputCloud(input);
  grid.setLeafSize(params.voxel_leaf_m, params.voxel_leaf_m, params.voxel_leaf_m);
  grid.filter(out);
  out.is_dense = true;
}

}  // namespace icanc
