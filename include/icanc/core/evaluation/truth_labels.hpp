// Ground-truth danger labels for every object of every frame (docs/design.md, "Ground truth for
// dangerous"), from the objects' true boxes relative to the vehicle. The same functions label the
// simulator's scenarios (trajectories sampled finely from the scripted motion) and recorded data
// such as KITTI (trajectories = the labelled positions of the same track id, nothing between).
#pragma once

#include <cstdint>
#include <limits>
#include <map>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "icanc/core/evaluation/ground_truth.hpp"
#include "icanc/core/evaluation/kitti.hpp"
#include "icanc/core/common/types.hpp"

namespace icanc {

// One object's true box at time t, in the vehicle frame at that time.
struct TruthBox {
  double t = 0.0;                                      // [s]
  std::uint32_t id = 0;                                // true track id, stable over time
  std::string type;                                    // pedestrian, car, Van, ...
  Eigen::Vector3d center = Eigen::Vector3d::Zero();    // box centre (not bottom) [m]
  Eigen::Vector3d size = Eigen::Vector3d::Zero();      // length (along yaw), width, height [m]
  double yaw = 0.0;                                    // about the vehicle's +z [rad]
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();  // relative to the vehicle [m/s]
};

// The ground-truth label of one object in one frame.
struct TruthLabel {
  bool in_corridor = false;        // the footprint overlaps the corridor now
  bool dangerous = false;          // time_to_corridor >= 0
  double time_to_corridor = -1.0;  // [s] until it is first in the corridor within the horizon, else -1
  // Not dangerous as far as the labels go, but they end before the horizon does (a recording's
  // last frames): where it goes next is not known, so its danger is not scored.
  bool horizon_cut = false;
};

// Each id's trajectory (footprints relative to the vehicle), sorted by time.
using Trajectories = std::map<std::uint32_t, std::vector<TruthPose>>;

TruthPose toTruthPose(const TruthBox& box);

// Groups the samples by id and sorts each trajectory by time (stable: equal times keep their order).
Trajectories buildTrajectories(const std::vector<TruthBox>& samples);

// Labels every box from its id's trajectory: time_to_corridor = timeToCorridor(trajectory, box.t,
// corridor), dangerous = time_to_corridor >= 0. A box that is in the corridor itself gets 0
// whether or not its trajectory holds a sample at box.t; a box whose id has no trajectory is
// judged from itself alone. known_until_t is the time of the last labelled frame (a recording's
// end; the simulator's scripted motion has none): a box not dangerous whose horizon runs past it
// is horizon_cut. labels[i] belongs to boxes[i].
std::vector<TruthLabel> labelTruths(const std::vector<TruthBox>& boxes,
                                    const Trajectories& trajectories, const CorridorParams& corridor,
                                    double known_until_t = std::numeric_limits<double>::infinity());

// Recorded data: the trajectories are the boxes themselves (a track whose labels stop is judged
// only from the frames it has: no extrapolation, no interpolation; a track that leaves the
// labelled view is judged not to come back). known_until_t: the recording's last frame.
std::vector<TruthLabel> labelTruths(const std::vector<TruthBox>& boxes, const CorridorParams& corridor,
                                    double known_until_t = std::numeric_limits<double>::infinity());

// Sets each box's velocity from the positions of the same id in the neighbouring frames (frame
// period frame_dt_s): central difference when both neighbours exist, one-sided when only one does,
// zero for a track seen in one frame. A neighbour counts only when it is one frame away
// (|dt - frame_dt_s| < frame_dt_s / 2), so a track that disappears and comes back is not
// differenced across the gap.
void differenceVelocities(std::vector<TruthBox>& boxes, double frame_dt_s);

// Recorded KITTI labels (kitti::toVelodyne: the velodyne frame is the vehicle frame) as truth
// boxes: t = frame * frame_period_s, id = track id, velocity by differenceVelocities. boxes[i]
// belongs to labels[i].
std::vector<TruthBox> truthBoxesFromKitti(const std::vector<kitti::VeloBox>& labels,
                                          double frame_period_s = 0.1);

// True when p (same frame as the box) lies inside the oriented box grown by margin_m on each side.
bool boxContains(const TruthBox& box, const Eigen::Vector3d& p, double margin_m = 0.0);

// Finite points of `cloud` (in the box's frame) inside the box.
std::uint32_t countPointsInside(const TruthBox& box, const Cloud& cloud);

}  // namespace icanc
