#include "icanc/core/perception/ground_removal.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <unordered_map>
#include <vector>

#include <pcl/ModelCoefficients.h>
#include <pcl/PointIndices.h>
#include <pcl/sample_consensus/method_types.h>
#include <pcl/sample_consensus/model_types.h>
#include <pcl/sample_consensus/sac_model_plane.h>
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
  } else if (!std::isfinite(params.expected_height_m)) {
    why << "ground.expected_height_m must be finite (got " << params.expected_height_m << ")";
  } else if (!(params.max_height_error_m > 0.0f) || !std::isfinite(params.max_height_error_m)) {
    why << "ground.max_height_error_m must be > 0 (got " << params.max_height_error_m << ")";
  }
  return why.str();
}

const char* toString(GroundRejection reason) {
  switch (reason) {
    case GroundRejection::kNone: return "none";
    case GroundRejection::kHeight: return "too far from the road's expected height";
    case GroundRejection::kPointsBelow: return "more points under it than on it";
  }
  return "invalid";
}

const char* toString(GroundStatus status) {
  switch (status) {
    case GroundStatus::kSkipped: return "skipped";
    case GroundStatus::kFound: return "found";
    case GroundStatus::kFoundOnRetry: return "found on retry";
    case GroundStatus::kRejected: return "rejected";
    case GroundStatus::kNoPlane: return "no plane";
  }
  return "invalid";
}

namespace {

constexpr float kRetryCellM = 1.0f;  // cells of the retry's lowest points [m]

void copyThrough(const Cloud& in, Cloud& out) {
  out.header = in.header;
  out.points.assign(in.points.begin(), in.points.end());
  out.width = static_cast<std::uint32_t>(in.points.size());
  out.height = 1;
  out.is_dense = in.is_dense;
}

// One RANSAC plane within max_slope_deg of horizontal over `indices` of `input` (all points when
// null): its inliers among those points and the plane, normalised with its normal up.
// A new segmentation object per call: its RANSAC model is seeded with PCL's fixed seed (12345)
// on construction and runs single-threaded, so equal input gives equal output.
bool fitPlane(const Cloud::ConstPtr& input, const pcl::IndicesPtr& indices,
              const GroundParams& params, pcl::PointIndices& inliers, Eigen::Vector4f& plane) {
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
  if (indices) seg.setIndices(indices);

  pcl::ModelCoefficients coefficients;
  seg.segment(inliers, coefficients);
  if (inliers.indices.empty() || coefficients.values.size() != 4) return false;
  plane = Eigen::Vector4f(coefficients.values[0], coefficients.values[1], coefficients.values[2],
                          coefficients.values[3]);
  const float norm = plane.head<3>().norm();
  if (norm > 0.0f && std::isfinite(norm)) plane /= norm;
  if (plane[2] < 0.0f) plane = -plane;  // normal up
  return plane[2] > 0.0f;
}

// Whether `plane`, with `inliers` on it, can be the road: its height at the frame's origin (where
// the vehicle stands on the road) against the expected road height, and the points under it.
struct Verdict {
  GroundRejection rejection = GroundRejection::kNone;
  float height_m = 0.0f;
  std::size_t below = 0;  // points under it, further than the inlier distance
};

Verdict judge(const Cloud& in, const Eigen::Vector4f& plane, const pcl::Indices& inliers,
              const GroundParams& params) {
  Verdict v;
  v.height_m = -plane[3] / plane[2];
  for (const Point& p : in)
    v.below += plane.head<3>().dot(p.getVector3fMap()) + plane[3] < -params.distance_threshold_m;
  if (!(std::abs(v.height_m - params.expected_height_m) <= params.max_height_error_m))
    v.rejection = GroundRejection::kHeight;
  else if (v.below > inliers.size())
    v.rejection = GroundRejection::kPointsBelow;
  return v;
}

// The lowest point of each kRetryCellM cell among those within max_height_error_m of the
// expected road height: the road where it is seen, else an object's underside (RANSAC over all
// of them would take a slab through the road and the lower part of every car alike).
pcl::IndicesPtr lowestNearRoad(const Cloud& in, const GroundParams& params) {
  std::unordered_map<std::uint64_t, pcl::index_t> lowest;  // cell -> its lowest point
  constexpr float kMaxCoordM = 1.0e6f;  // cell indices fit 32 bits (and NaN is left out)
  for (std::size_t i = 0; i < in.size(); ++i) {
    const Point& p = in.points[i];
    if (!(std::abs(p.z - params.expected_height_m) <= params.max_height_error_m)) continue;
    if (!(std::abs(p.x) < kMaxCoordM && std::abs(p.y) < kMaxCoordM)) continue;
    const auto cx = static_cast<std::int32_t>(std::floor(p.x / kRetryCellM));
    const auto cy = static_cast<std::int32_t>(std::floor(p.y / kRetryCellM));
    const std::uint64_t key = (std::uint64_t{static_cast<std::uint32_t>(cx)} << 32) | static_cast<std::uint32_t>(cy);
    const auto cell = lowest.emplace(key, static_cast<pcl::index_t>(i));
    if (!cell.second && p.z < in.points[cell.first->second].z)
      cell.first->second = static_cast<pcl::index_t>(i);
  }
  pcl::IndicesPtr indices(new pcl::Indices);
  for (const auto& cell : lowest) indices->push_back(cell.second);
  std::sort(indices->begin(), indices->end());  // independent of the hash map's order
  return indices;
}

}  // namespace

bool ransacGroundPlane(const Cloud& in, const GroundParams& params, Eigen::Vector4f& plane,
                       std::vector<int>& inliers) {
  inliers.clear();
  if (in.size() < 3) return false;
  const Cloud::ConstPtr input(&in, [](const Cloud*) {});  // non-owning: `in` outlives the call
  pcl::PointIndices found;
  if (!fitPlane(input, nullptr, params, found, plane)) return false;
  inliers.swap(found.indices);
  return true;
}

GroundResult removeGround(const Cloud& in, const GroundParams& params, Cloud& nonground) {
  GroundResult result;
  nonground.clear();
  if (!params.enabled || in.size() < 3) {
    copyThrough(in, nonground);
    return result;
  }

  // Non-owning pointer: PCL wants a shared_ptr; `in` outlives the call.
  const Cloud::ConstPtr input(&in, [](const Cloud*) {});

  pcl::PointIndices inliers;
  Eigen::Vector4f plane;
  if (!ransacGroundPlane(in, params, plane, inliers.indices)) {
    result.status = GroundStatus::kNoPlane;  // e.g. only walls
    copyThrough(in, nonground);
    return result;
  }
  Verdict verdict = judge(in, plane, inliers.indices, params);
  result.rejection = verdict.rejection;
  result.status = GroundStatus::kFound;
  if (result.rejection != GroundRejection::kNone) {
    result.rejected_height_m = verdict.height_m;
    result.rejected_inliers = inliers.indices.size();
    result.rejected_points_below = verdict.below;
    // Retry where the road must be; that plane then takes its inliers from every point.
    const pcl::IndicesPtr band = lowestNearRoad(in, params);
    result.status = GroundStatus::kRejected;
    if (band->size() >= 3 && fitPlane(input, band, params, inliers, plane)) {
      pcl::SampleConsensusModelPlane<Point> model(input);
      model.selectWithinDistance(Eigen::VectorXf(plane), params.distance_threshold_m, inliers.indices);
      verdict = judge(in, plane, inliers.indices, params);
      result.retry_rejection = verdict.rejection;
      if (result.retry_rejection == GroundRejection::kNone)
        result.status = GroundStatus::kFoundOnRetry;
    }
    if (result.status == GroundStatus::kRejected) {
      copyThrough(in, nonground);  // no plausible road: an obstacle is never deleted
      return result;
    }
  }
  result.plane = plane;
  result.inliers = inliers.indices.size();
  result.height_m = verdict.height_m;

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
