// Scene motion, the scan renderer and the ground truth of the LiDAR simulator.
// The ray-object intersection maths lives in raycast.hpp.
#include "icanc/sim/lidar_sim.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "raycast.hpp"

namespace icanc {
namespace sim {

namespace {

// Moving time between start_s and stop_s up to t.
double clampTime(double t, const SceneObject& o) { return std::min(std::max(t, o.start_s), o.stop_s); }

constexpr double kDegToRad = M_PI / 180.0;
constexpr double kSpuriousMaxRange = 30.0;

// One object prepared for a scan: its pose relative to the sensor and its bounding sphere.
struct PreparedObject {
  Eigen::Matrix3d sensor_to_local;  // rotation of sensor-frame directions into the object frame
  Eigen::Vector3d origin_local;     // sensor origin in the object frame (centred on the object)
  Eigen::Vector3d center_sensor;    // object centre in the sensor frame
  double center_sq = 0.0;           // |center_sensor|^2
  double radius = 0.0;              // bounding sphere
  Eigen::Vector3d half;             // box half extents; cylinder: (radius, radius, half height)
  bool cylinder = false;
};

}  // namespace

Eigen::Vector3f SceneObject::positionAt(double t) const {
  // `position` is where the object is at t = 0; it moves only inside [start_s, stop_s].
  const double moved = clampTime(t, *this) - clampTime(0.0, *this);
  if (path.empty()) return position + velocity * static_cast<float>(moved);
  const PlanarPose p = poseAlong(path, moved);  // path from its start, heading +x ...
  const double c = std::cos(double(yaw)), s = std::sin(double(yaw));  // ... turned to `yaw`
  return position + Eigen::Vector3f(float(c * p.x - s * p.y), float(s * p.x + c * p.y), 0.0f);
}

Eigen::Vector3f SceneObject::velocityAt(double t) const {
  if (!(t >= start_s && t < stop_s)) return Eigen::Vector3f::Zero();
  if (path.empty()) return velocity;
  const double heading = double(yawAt(t));
  const double speed = speedAlong(path, t - clampTime(0.0, *this));
  return Eigen::Vector3f(float(speed * std::cos(heading)), float(speed * std::sin(heading)), 0.0f);
}

float SceneObject::yawAt(double t) const {
  if (path.empty()) return yaw;
  const double moved = clampTime(t, *this) - clampTime(0.0, *this);
  return static_cast<float>(double(yaw) + poseAlong(path, moved).theta);
}

void renderScan(const Scene& scene, double t, const Eigen::Isometry3f& sensor_pose,
                const LidarModel& model, const NoiseParams& noise, std::mt19937_64& rng,
                Cloud& out) {
  const std::size_t rows = model.channels();
  const std::size_t cols = model.columns();
  if (rows == 0 || cols == 0) {
    throw std::invalid_argument("renderScan: lidar model '" + model.name +
                                "' has no channels or no columns");
  }
  auto isProb = [](float p) { return p >= 0.0f && p <= 1.0f; };
  if (!(noise.range_std_m >= 0.0f) || !isProb(noise.dropout_prob) ||
      !isProb(noise.spurious_prob)) {
    throw std::invalid_argument(
        "renderScan: noise needs range_std_m >= 0 and probabilities in [0, 1]");
  }
  const double min_range = model.min_range_m;
  const double max_range = model.max_range_m;

  out.header.stamp = t > 0.0 ? static_cast<std::uint64_t>(std::llround(t * 1e6)) : 0;
  out.width = static_cast<std::uint32_t>(cols);
  out.height = static_cast<std::uint32_t>(rows);
  out.is_dense = false;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  Point nan_point;
  nan_point.x = nan_point.y = nan_point.z = nan;
  out.points.assign(rows * cols, nan_point);

  // Work in the sensor frame: rays start at its origin.
  const Eigen::Isometry3d pose = sensor_pose.cast<double>();
  const Eigen::Matrix3d world_from_sensor = pose.linear();
  const Eigen::Matrix3d sensor_from_world = world_from_sensor.transpose();
  const Eigen::Vector3d sensor_in_world = pose.translation();

  // Ground z = ground_z in the world is the plane n . x = k in the sensor frame.
  const Eigen::Vector3d ground_n = world_from_sensor.row(2).transpose();
  const double ground_k = double(scene.ground_z) - sensor_in_world.z();

  std::vector<PreparedObject> objects;
  objects.reserve(scene.objects.size());
  for (const SceneObject& o : scene.objects) {
    const Eigen::Vector3d size = o.size.cast<double>();
    if (!(size.x() > 0.0 && size.y() > 0.0 && size.z() > 0.0)) continue;
    PreparedObject p;
    p.cylinder = o.shape == Shape::kCylinder;
    p.half = p.cylinder ? Eigen::Vector3d(0.5 * size.x(), 0.5 * size.x(), 0.5 * size.z())
                        : Eigen::Vector3d(0.5 * size);
    p.radius = p.cylinder ? std::hypot(p.half.x(), p.half.z()) : p.half.norm();
    const Eigen::Vector3d center_world =
        o.positionAt(t).cast<double>() + Eigen::Vector3d(0.0, 0.0, p.half.z());
    p.center_sensor = sensor_from_world * (center_world - sensor_in_world);
    p.center_sq = p.center_sensor.squaredNorm();
    if (std::sqrt(p.center_sq) - p.radius > max_range) continue;  // cannot be seen
    const Eigen::Matrix3d world_from_local =
        Eigen::AngleAxisd(double(o.yawAt(t)), Eigen::Vector3d::UnitZ()).toRotationMatrix();
    p.sensor_to_local = world_from_local.transpose() * world_from_sensor;
    p.origin_local = -(p.sensor_to_local * p.center_sensor);
    objects.push_back(p);
  }

  // Ray directions: elevation per row, azimuth per column (REP-103).
  std::vector<double> sin_el(rows), cos_el(rows);
  for (std::size_t r = 0; r < rows; ++r) {
    const double el = double(model.vertical_angles_deg[r]) * kDegToRad;
    sin_el[r] = std::sin(el);
    cos_el[r] = std::cos(el);
  }

  std::vector<double> sin_az(cols), cos_az(cols);
  for (std::size_t c = 0; c < cols; ++c) {
    const double az = model.azimuthDeg(c) * kDegToRad;
    sin_az[c] = std::sin(az);
    cos_az[c] = std::cos(az);
  }

  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  std::normal_distribution<double> gaussian(0.0, 1.0);
  const double spurious_hi = std::max(min_range, std::min(max_range, kSpuriousMaxRange));
  const bool any_noise =
      noise.spurious_prob > 0.0f || noise.dropout_prob > 0.0f || noise.range_std_m > 0.0f;

  // Results are computed column by column (objects culled per column), then noise is drawn in
  // row-major order so that the random stream does not depend on the culling.
  std::vector<double> ranges(rows * cols, std::numeric_limits<double>::infinity());
  std::vector<const PreparedObject*> candidates;
  candidates.reserve(objects.size());
  for (std::size_t c = 0; c < cols; ++c) {
    const double ca = cos_az[c], sa = sin_az[c];
    // Every ray of this column lies in the half-plane spanned by (ca, sa, 0) and +z.
    candidates.clear();
    for (const PreparedObject& p : objects) {
      const Eigen::Vector3d& q = p.center_sensor;
      const double across = -sa * q.x() + ca * q.y();
      const double along = ca * q.x() + sa * q.y();
      if (std::abs(across) <= p.radius && along >= -p.radius) candidates.push_back(&p);
    }
    for (std::size_t r = 0; r < rows; ++r) {
      const Eigen::Vector3d d(cos_el[r] * ca, cos_el[r] * sa, sin_el[r]);
      double best = std::numeric_limits<double>::infinity();
      if (scene.has_ground) {
        const double denom = ground_n.dot(d);
        if (denom != 0.0) {
          const double hit = ground_k / denom;
          if (hit > 0.0) best = hit;
        }
      }
      for (const PreparedObject* p : candidates) {
        const double tc = p->center_sensor.dot(d);            // closest approach along the ray
        const double miss_sq = p->center_sq - tc * tc;          // squared distance ray-centre
        const double r_sq = p->radius * p->radius;
        if (miss_sq > r_sq || tc + p->radius < 0.0) continue;   // misses the bounding sphere
        if (tc - std::sqrt(r_sq - std::max(0.0, miss_sq)) >= best) continue;  // cannot be closer
        const Eigen::Vector3d dl = p->sensor_to_local * d;
        const double hit = p->cylinder
                               ? raycast::cylinder(p->origin_local, dl, p->half.x(), p->half.z())
                               : raycast::box(p->origin_local, dl, p->half);
        if (hit < best) best = hit;
      }
      ranges[r * cols + c] = best;
    }
  }

  for (std::size_t r = 0; r < rows; ++r) {
    const double cos_e = cos_el[r], sin_e = sin_el[r];
    for (std::size_t c = 0; c < cols; ++c) {
      const std::size_t i = r * cols + c;
      double range = ranges[i];
      bool valid = range >= min_range && range <= max_range;
      if (any_noise) {
        if (noise.spurious_prob > 0.0f && uniform(rng) < double(noise.spurious_prob)) {
          range = min_range + (spurious_hi - min_range) * uniform(rng);
          valid = true;
        } else if (valid) {
          if (noise.dropout_prob > 0.0f && uniform(rng) < double(noise.dropout_prob)) {
            valid = false;
          } else if (noise.range_std_m > 0.0f) {
            range += double(noise.range_std_m) * gaussian(rng);
            valid = range > 0.0;
          }
        }
      }
      if (!valid) continue;
      Point& pt = out.points[i];
      pt.x = static_cast<float>(range * cos_e * cos_az[c]);
      pt.y = static_cast<float>(range * cos_e * sin_az[c]);
      pt.z = static_cast<float>(range * sin_e);
    }
  }
}

std::vector<ObjectTruth> objectTruths(const Scene& scene, double t,
                                      const Eigen::Isometry3f& world_to_frame) {
  const Eigen::Matrix3f rot = world_to_frame.linear();
  std::vector<ObjectTruth> truths;
  truths.reserve(scene.objects.size());
  for (const SceneObject& o : scene.objects) {
    ObjectTruth truth;
    truth.id = o.id;
    truth.type = o.type;
    truth.size = o.size;
    truth.center = world_to_frame * (o.positionAt(t) + Eigen::Vector3f(0.0f, 0.0f, 0.5f * o.size.z()));
    const float yaw = o.yawAt(t);
    const Eigen::Vector3f heading = rot * Eigen::Vector3f(std::cos(yaw), std::sin(yaw), 0.0f);
    truth.yaw = std::atan2(heading.y(), heading.x());
    truth.velocity = rot * o.velocityAt(t);
    truths.push_back(truth);
  }
  return truths;
}

}  // namespace sim
}  // namespace icanc
