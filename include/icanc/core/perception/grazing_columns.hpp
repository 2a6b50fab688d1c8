// Boxes that are one column of the scan on a surface seen at grazing incidence (the classic
// chain's counterpart of FastDetector's column rule, on boxes instead of grid cells).
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "icanc/core/perception/box.hpp"

namespace icanc {

struct GrazingColumnParams {
  float reach_m = 2.5f;     // a box that is one line of sight is dropped when another box of its
                            // height continues its surface this close (0: off) [m] ...
  float angle_deg = 20.0f;  // ... at most this far off its line of sight [deg] ...
  float max_step_m = 0.3f;  // ... with its top within this of the column's [m]
  float thin_m = 0.1f;      // one line of sight: its points within this across it [m] ...
  float max_length_m = 1.0f;  // ... and within this along it [m]
};

// First problem found, or "" when valid; `prefix` names the section in the message.
std::string validate(const GrazingColumnParams& params, const std::string& prefix);

// A surface seen at grazing incidence (a parked car's side, a façade along the street) is hit by
// the scan's columns r * dtheta / sin(incidence) apart: beyond a clustering tolerance of 0.6 m
// from about 15 m on a 0.72 deg scan (carla128) for a car 3 m to the side. Each column is then a
// box of its own, a vertical line at the column's bearing, which stays there while the vehicle
// drives by: a track moving with the vehicle. Removes from `boxes` every box that is one line of
// sight from `origin` (x, y) when another box with its top within max_step_m has a footprint
// part (Box3D::footprint, else its hull) within reach_m of it and within angle_deg of that line
// of sight, either way along it. A dropped column still holds up its neighbour. Returns how many
// were dropped; reach_m 0 drops none.
std::size_t dropGrazingColumnBoxes(std::vector<Box3D>& boxes, const Eigen::Vector2f& origin,
                                   const GrazingColumnParams& params);

}  // namespace icanc
