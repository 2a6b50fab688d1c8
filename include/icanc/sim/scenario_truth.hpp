// Ground truth of a scenario's frames (docs/design.md, "Ground truth for dangerous"): every scene
// object's true box relative to the vehicle, its velocity relative to the vehicle, the LiDAR
// returns inside it and its danger label, with each object's trajectory sampled finely from the
// scripted motion (not only at frame times). ROS-free; icanc_sim_bag writes it as /ground_truth.
#pragma once

#include <cstdint>
#include <vector>

#include "icanc/core/evaluation/ground_truth.hpp"
#include "icanc/core/evaluation/truth_labels.hpp"
#include "icanc/core/common/types.hpp"
#include "icanc/sim/scenario.hpp"

namespace icanc {
namespace sim {

// Every scene object's true box at time t in the vehicle frame at t (scene order, the vehicle at
// scenario.vehiclePose(t), turning or not); velocity = object world velocity minus the vehicle's
// world velocity at t, rotated into the vehicle frame.
std::vector<TruthBox> truthBoxes(const Scenario& scenario, double t);

struct FrameTruth {
  double t = 0.0;
  std::vector<TruthBox> boxes;            // one per scene object, scene order
  std::vector<TruthLabel> labels;         // labels[i] belongs to boxes[i]
  std::vector<std::uint32_t> num_points;  // returns inside boxes[i]; zeros without a scan
};

class ScenarioTruth {
 public:
  // Samples every object relative to the vehicle at k * sample_dt_s over
  // [0, duration_s + horizon_s] (the scripted motion continues past the last frame, so the last
  // frames are labelled from it too) and at every frame time.
  // Throws std::invalid_argument for sample_dt_s <= 0 or an invalid corridor.
  ScenarioTruth(const Scenario& scenario, const CorridorParams& corridor, double sample_dt_s = 0.02);

  // The truth at time t. `scan` (optional) is the frame's cloud in the sensor frame, as
  // renderScan returns it; its points are moved into the vehicle frame with the sensor mount
  // and counted per box.
  FrameTruth frame(double t, const Cloud* scan = nullptr) const;

  const Trajectories& trajectories() const { return trajectories_; }
  const CorridorParams& corridor() const { return corridor_; }

 private:
  Scenario scenario_;  // a copy: the truth outlives the caller's scenario
  CorridorParams corridor_;
  Trajectories trajectories_;
};

}  // namespace sim
}  // namespace icanc
