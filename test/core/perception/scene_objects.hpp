// Simulated scene objects for the perception gtests: a box or an upright cylinder standing on
// the road at its bottom centre.
#pragma once

#include <string>

#include <Eigen/Core>

#include "icanc/sim/lidar_sim.hpp"

namespace icanc {
namespace test_scene {

inline sim::SceneObject block(const std::string& type, const Eigen::Vector3f& size,
                              const Eigen::Vector3f& bottom_centre) {
  sim::SceneObject o;
  o.type = type;
  o.size = size;
  o.position = bottom_centre;
  return o;
}

inline sim::SceneObject cylinder(const std::string& type, float diameter, float height,
                                 const Eigen::Vector3f& bottom_centre) {
  sim::SceneObject o = block(type, {diameter, diameter, height}, bottom_centre);
  o.shape = sim::Shape::kCylinder;
  return o;
}

}  // namespace test_scene
}  // namespace icanc
