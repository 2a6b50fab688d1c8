// What the tracker tests feed the tracker and look up in it: an axis-aligned box standing on the
// ground, a track by its id.
#pragma once

#include <cstdint>

#include "icanc/core/tracking/tracker.hpp"

namespace icanc {
namespace test {

inline Box3D box(double x, double y, double length = 0.8, double width = 0.8,
                 double height = 1.7) {
  Box3D b;
  b.center = Eigen::Vector3f(x, y, height / 2);
  b.size = Eigen::Vector3f(length, width, height);
  b.min = b.center - b.size / 2;
  b.max = b.center + b.size / 2;
  b.num_points = 50;
  return b;
}

inline const Track* findId(const MultiObjectTracker& t, std::uint32_t id) {
  for (const Track& track : t.tracks()) {
    if (track.id == id) return &track;
  }
  return nullptr;
}

}  // namespace test
}  // namespace icanc
