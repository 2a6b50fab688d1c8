// Ground removal: one RANSAC plane, as in the paper's obstacle detector (PCL SACSegmentation),
// checked against where the road must be: a horizontal plane through car roofs or a wall's top
// is rejected, the search retried near the expected road height, and a frame without a
// plausible road keeps every point (an obstacle is never deleted) and says so.
#pragma once

#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "icanc/core/common/types.hpp"

namespace icanc {

struct GroundParams {
  bool enabled = true;
  int max_iterations = 30;            // RANSAC iterations
  float distance_threshold_m = 0.3f;  // inlier distance to the plane [m]
  float max_slope_deg = 15.0f;        // plane normal within this angle of +z (rejects walls)
  // Where the road is: its height at the origin of the cloud's frame (the vehicle frame, origin
  // on the road: 0; a cloud in a roof sensor's own frame: minus the mount height) [m], and how
  // far a plane's height there may be from it [m]. A plane further off is not the road.
  float expected_height_m = 0.0f;
  float max_height_error_m = 0.5f;
};

std::string validate(const GroundParams& params);

// Why a plane RANSAC found was not taken for the road.
enum class GroundRejection : std::uint8_t {
  kNone,
  kHeight,       // its height at the frame's origin is off expected_height_m by > max_height_error_m
  kPointsBelow,  // more points lie under it, beyond distance_threshold_m, than on it
};
const char* toString(GroundRejection reason);

enum class GroundStatus : std::uint8_t {
  kSkipped,       // disabled, or fewer than 3 points: nothing removed
  kFound,         // the first plane is the road
  kFoundOnRetry,  // the first plane was rejected; the retry near the expected height found the road
  kRejected,      // every plane found was rejected: nothing removed
  kNoPlane,       // no plane within max_slope_deg of horizontal (e.g. only walls): nothing removed
};
const char* toString(GroundStatus status);

struct GroundResult {
  GroundStatus status = GroundStatus::kSkipped;
  bool found() const { return status == GroundStatus::kFound || status == GroundStatus::kFoundOnRetry; }
  Eigen::Vector4f plane = Eigen::Vector4f::Zero();  // a x + b y + c z + d = 0, normal up (c > 0)
  std::size_t inliers = 0;
  float height_m = std::numeric_limits<float>::quiet_NaN();  // the plane's z at x = y = 0
  // The first plane rejected this frame, if any (kFoundOnRetry, kRejected).
  GroundRejection rejection = GroundRejection::kNone;
  float rejected_height_m = std::numeric_limits<float>::quiet_NaN();  // its z at x = y = 0
  std::size_t rejected_inliers = 0;
  std::size_t rejected_points_below = 0;  // points under it beyond distance_threshold_m
  // kRejected: why the retry's plane was rejected too (kNone: no plane near the expected height).
  GroundRejection retry_rejection = GroundRejection::kNone;
};

// The paper's detector alone: one RANSAC plane within max_slope_deg of horizontal over all of
// `in` (normal up, unit length) and its inliers, unchecked; false when there is none.
// removeGround's first step.
bool ransacGroundPlane(const Cloud& in, const GroundParams& params, Eigen::Vector4f& plane,
                       std::vector<int>& inliers);

// Splits `in` into ground (dropped) and the rest (`nonground`, cleared first; must not alias
// `in`). RANSAC runs over the whole cloud first (the paper's detector); a plane whose height at
// the frame's origin is off `expected_height_m` by more than `max_height_error_m`, or with more
// points under it (further than `distance_threshold_m`) than on it, is rejected, and RANSAC runs
// again on the lowest point of each 1 m cell within `max_height_error_m` of the expected height;
// the plane it finds there (checked the same way) removes its inliers from the whole cloud. When
// no plane is accepted, or ground removal is disabled, `nonground` is a copy of `in`.
// Deterministic: PCL's RANSAC runs single-threaded from a fixed seed on every call.
GroundResult removeGround(const Cloud& in, const GroundParams& params, Cloud& nonground);

}  // namespace icanc
