// Ray-cast model of a spinning multi-beam LiDAR against a scene of a ground plane and
// boxes / vertical cylinders moving at constant velocity or along a path of straights and arcs.
// ROS-free, deterministic from a seed.
// Used to make the project's own test and demo data (no recorded data needed).
#pragma once

#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "icanc/core/common/types.hpp"
#include "icanc/sim/path.hpp"

namespace icanc {
namespace sim {

struct LidarModel {
  std::string name;
  std::vector<float> vertical_angles_deg;  // one per channel, elevation (+ up)
  float horizontal_resolution_deg = 0.2f;
  float h_fov_min_deg = -180.0f;            // azimuth range, 0 = +x, +90 = +y
  float h_fov_max_deg = 180.0f;
  float rate_hz = 10.0f;
  float min_range_m = 0.5f;
  float max_range_m = 100.0f;

  std::size_t channels() const { return vertical_angles_deg.size(); }
  // Azimuth steps per scan. A full circle (max - min >= 360 deg) has round(360 / resolution)
  // columns spaced 360 / columns apart from h_fov_min_deg; a partial field of view has one column
  // at each end and resolution-spaced columns between (e.g. -60..+60 at 0.2 deg: 601).
  std::size_t columns() const;
  double azimuthStepDeg() const;                 // spacing of the columns actually cast [deg]
  double azimuthDeg(std::size_t column) const;   // h_fov_min_deg + column * azimuthStepDeg()
  double pointsPerSecond() const { return double(channels()) * double(columns()) * rate_hz; }

  static LidarModel vlp16();        // Velodyne VLP-16: 16 ch, -15..+15 deg, 0.2 deg, 100 m
  static LidarModel hdl32e();       // Velodyne HDL-32E: 32 ch, +10.67..-30.67 deg, 0.16 deg, 100 m
  static LidarModel hdl64e();       // Velodyne HDL-64E: 64 ch, +2..-24.9 deg, 0.17 deg, 120 m
  static LidarModel carla128();     // paper's CARLA sensor: 128 ch, 640k points/s at 10 Hz
  static LidarModel robosenseM1();  // forward solid-state like the Zebra's M1: 120 x 25 deg, 200 m
  // "vlp16" | "hdl32e" | "hdl64e" | "carla128" | "robosense_m1"; throws std::invalid_argument
  // otherwise.
  static LidarModel byName(const std::string& name);
};

enum class Shape { kBox, kCylinder };

struct SceneObject {
  std::uint32_t id = 0;
  std::string type;                              // "pedestrian", "car", "wall", ...
  Shape shape = Shape::kBox;
  Eigen::Vector3f size{0.5f, 0.5f, 1.7f};        // box: length (along yaw), width, height;
                                                 // cylinder: diameter, diameter, height [m]
  float yaw = 0.0f;                              // [rad] about the world z axis at t = 0
  Eigen::Vector3f position{0.0f, 0.0f, 0.0f};    // world position of the bottom centre at t = 0
  Eigen::Vector3f velocity{0.0f, 0.0f, 0.0f};    // world velocity [m/s] (without a path)
  double start_s = 0.0;                          // moves only between start_s and stop_s
  double stop_s = 1e9;
  // When not empty, the object follows this path (a car along a bend) instead of `velocity`:
  // from `position` with heading `yaw`, its speed along its heading and its yaw turning with it.
  std::vector<PathSegment> path;

  // Bottom centre in the world at time t (holds still before start_s and after stop_s).
  Eigen::Vector3f positionAt(double t) const;
  // Velocity in the world at time t (zero outside [start_s, stop_s)).
  Eigen::Vector3f velocityAt(double t) const;
  // Yaw about the world z axis at time t: `yaw`, plus the path's turn so far.
  float yawAt(double t) const;
};

struct Scene {
  bool has_ground = true;
  float ground_z = 0.0f;                 // world height of the ground plane [m]
  std::vector<SceneObject> objects;
};

struct NoiseParams {
  float range_std_m = 0.0f;      // Gaussian range noise [m]
  float dropout_prob = 0.0f;     // probability a return is lost
  float spurious_prob = 0.0f;    // probability a ray returns a random point in range instead
};

// Casts one full scan at time t from a sensor at `sensor_pose` (sensor frame -> world) and
// returns the returns in the sensor frame, channel-major is NOT guaranteed: the cloud is
// organized as height = channels, width = columns, with NaN points for rays with no return
// (is_dense = false), like a driver's organized output.
// Row r is channel vertical_angles_deg[r] (the presets list them from the top beam down), column
// c is azimuth model.azimuthDeg(c). Every ray is cast at the same time t (no motion skew). The
// closest hit among the ground and the objects counts; outside [min_range_m, max_range_m] it is
// no return. A sensor inside a box or cylinder sees its inner walls. Noise per ray, in this
// order: spurious (replaces the ray's result by a uniform range in
// [min_range_m, min(max_range_m, 30 m)]), else for a real return dropout, else range noise.
// out.header.stamp is set to t in microseconds (PCL convention); frame_id is left to the caller.
// Throws std::invalid_argument for a model without channels or columns, or bad noise values.
void renderScan(const Scene& scene, double t, const Eigen::Isometry3f& sensor_pose,
                const LidarModel& model, const NoiseParams& noise, std::mt19937_64& rng,
                Cloud& out);

// Ground-truth of one object at time t expressed in the frame given by `world_to_frame`.
struct ObjectTruth {
  std::uint32_t id = 0;
  std::string type;
  Eigen::Vector3f center;     // box centre (not bottom) [m]
  Eigen::Vector3f size;
  float yaw = 0.0f;
  Eigen::Vector3f velocity;   // in that frame's axes [m/s] (world velocity rotated)
};
std::vector<ObjectTruth> objectTruths(const Scene& scene, double t,
                                      const Eigen::Isometry3f& world_to_frame);

}  // namespace sim
}  // namespace icanc
