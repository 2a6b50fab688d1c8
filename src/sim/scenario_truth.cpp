#include "icanc/sim/scenario_truth.hpp"

#include <cmath>
#include <stdexcept>

namespace icanc {
namespace sim {

std::vector<TruthBox> truthBoxes(const Scenario& scenario, double t) {
  const Eigen::Isometry3f world_to_vehicle = scenario.vehiclePose(t).inverse();
  // Velocity relative to the vehicle, as its LiDAR sees it: the world velocities' difference in the
  // vehicle's axes at t, minus yaw_rate x r (the frame turns with the vehicle), as icanc/Obstacle's
  // velocity (relativeVelocity).
  const Eigen::Vector3f ego_velocity = world_to_vehicle.linear() * scenario.vehicleVelocity(t);
  const float yaw_rate = scenario.vehicleTwist(t).yaw_rate;
  std::vector<TruthBox> boxes;
  boxes.reserve(scenario.scene.objects.size());
  for (const ObjectTruth& truth : objectTruths(scenario.scene, t, world_to_vehicle)) {
    TruthBox b;
    b.t = t;
    b.id = truth.id;
    b.type = truth.type;
    b.center = truth.center.cast<double>();
    b.size = truth.size.cast<double>();
    b.yaw = truth.yaw;
    const Eigen::Vector3f frame_velocity(-yaw_rate * truth.center.y(), yaw_rate * truth.center.x(), 0.0f);
    b.velocity = (truth.velocity - ego_velocity - frame_velocity).cast<double>();
    boxes.push_back(std::move(b));
  }
  return boxes;
}

ScenarioTruth::ScenarioTruth(const Scenario& scenario, const CorridorParams& corridor,
                             double sample_dt_s)
    : scenario_(scenario), corridor_(corridor) {
  if (!(sample_dt_s > 0.0)) throw std::invalid_argument("ScenarioTruth: sample_dt_s must be > 0");
  const std::string why = validate(corridor);
  if (!why.empty()) throw std::invalid_argument("ScenarioTruth: " + why);
  std::vector<TruthBox> samples;
  const double end = scenario.duration_s + corridor.horizon_s;
  const long steps = static_cast<long>(std::ceil(end / sample_dt_s - 1e-9));
  for (long k = 0; k <= steps; ++k) {
    for (TruthBox& b : truthBoxes(scenario, static_cast<double>(k) * sample_dt_s))
      samples.push_back(std::move(b));
  }
  for (std::size_t k = 0; k < scenario.frames(); ++k) {
    for (TruthBox& b : truthBoxes(scenario, static_cast<double>(k) / scenario.rate_hz))
      samples.push_back(std::move(b));
  }
  trajectories_ = buildTrajectories(samples);
}

FrameTruth ScenarioTruth::frame(double t, const Cloud* scan) const {
  FrameTruth f;
  f.t = t;
  f.boxes = truthBoxes(scenario_, t);
  f.labels = labelTruths(f.boxes, trajectories_, corridor_);
  f.num_points.assign(f.boxes.size(), 0u);
  if (scan != nullptr) {
    Cloud in_vehicle;
    in_vehicle.points.reserve(scan->points.size());
    const Eigen::Isometry3f& mount = scenario_.sensor_mount;
    for (const Point& q : scan->points) {
      if (!std::isfinite(q.x) || !std::isfinite(q.y) || !std::isfinite(q.z)) continue;
      const Eigen::Vector3f p = mount * Eigen::Vector3f(q.x, q.y, q.z);
      in_vehicle.points.emplace_back(p.x(), p.y(), p.z());
    }
    for (std::size_t i = 0; i < f.boxes.size(); ++i)
      f.num_points[i] = countPointsInside(f.boxes[i], in_vehicle);
  }
  return f;
}

}  // namespace sim
}  // namespace icanc
