// Ground truth (core TruthBox + TruthLabel) as icanc/GroundTruthArray, for the bag writers
// (icanc_sim_bag, icanc_kitti2bag). Header-only.
#pragma once

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include <ros/time.h>

#include "icanc/GroundTruthArray.h"
#include "icanc/core/evaluation/ground_truth.hpp"
#include "icanc/core/evaluation/truth_labels.hpp"

namespace icanc {

inline GroundTruthObject toGroundTruthObject(const TruthBox& box, const TruthLabel& label,
                                             std::uint32_t num_points) {
  GroundTruthObject o;
  o.id = box.id;
  o.type = box.type;
  o.pose.position.x = box.center.x();
  o.pose.position.y = box.center.y();
  o.pose.position.z = box.center.z();
  o.pose.orientation.z = std::sin(0.5 * box.yaw);
  o.pose.orientation.w = std::cos(0.5 * box.yaw);
  o.dimensions.x = box.size.x();
  o.dimensions.y = box.size.y();
  o.dimensions.z = box.size.z();
  o.velocity.x = box.velocity.x();
  o.velocity.y = box.velocity.y();
  o.velocity.z = box.velocity.z();
  o.num_points = num_points;
  o.in_corridor = label.in_corridor;
  o.dangerous = label.dangerous;
  o.time_to_corridor = static_cast<float>(label.time_to_corridor);
  o.horizon_cut = label.horizon_cut;
  return o;
}

// boxes, labels and num_points are parallel (num_points may be empty: zeros).
inline GroundTruthArray toGroundTruthArray(const std::vector<TruthBox>& boxes,
                                           const std::vector<TruthLabel>& labels,
                                           const std::vector<std::uint32_t>& num_points,
                                           const CorridorParams& corridor, const ros::Time& stamp,
                                           const std::string& frame_id) {
  GroundTruthArray a;
  a.header.stamp = stamp;
  a.header.frame_id = frame_id;
  a.horizon_s = static_cast<float>(corridor.horizon_s);
  a.corridor_half_width_m = static_cast<float>(corridor.halfWidth());
  a.corridor_length_m = static_cast<float>(corridor.length());
  a.objects.reserve(boxes.size());
  for (std::size_t i = 0; i < boxes.size(); ++i)
    a.objects.push_back(toGroundTruthObject(boxes[i], labels.at(i),
                                            i < num_points.size() ? num_points[i] : 0u));
  return a;
}

}  // namespace icanc
