#include "icanc/core/evaluation/truth_labels.hpp"

#include <algorithm>
#include <cmath>

#include "icanc/core/perception/box.hpp"

namespace icanc {

TruthPose toTruthPose(const TruthBox& box) {
  TruthPose p;
  p.t = box.t;
  p.center = box.center.head<2>();
  p.size = box.size.head<2>();
  p.yaw = box.yaw;
  return p;
}

Trajectories buildTrajectories(const std::vector<TruthBox>& samples) {
  Trajectories trajectories;
  for (const TruthBox& b : samples) trajectories[b.id].push_back(toTruthPose(b));
  for (auto& entry : trajectories) {
    std::stable_sort(entry.second.begin(), entry.second.end(),
                     [](const TruthPose& a, const TruthPose& b) { return a.t < b.t; });
  }
  return trajectories;
}

std::vector<TruthLabel> labelTruths(const std::vector<TruthBox>& boxes,
                                    const Trajectories& trajectories, const CorridorParams& corridor,
                                    double known_until_t) {
  std::vector<TruthLabel> labels(boxes.size());
  for (std::size_t i = 0; i < boxes.size(); ++i) {
    const TruthBox& box = boxes[i];
    TruthLabel& label = labels[i];
    const TruthPose now = toTruthPose(box);
    label.in_corridor = inCorridor(now, corridor);
    if (label.in_corridor) {
      label.time_to_corridor = 0.0;
    } else {
      const auto it = trajectories.find(box.id);
      label.time_to_corridor = it == trajectories.end()
                                   ? timeToCorridor({now}, box.t, corridor)
                                   : timeToCorridor(it->second, box.t, corridor);
    }
    label.dangerous = label.time_to_corridor >= 0.0;
    // (a microsecond's tolerance: frame times are sums of periods)
    label.horizon_cut = !label.dangerous && box.t + corridor.horizon_s > known_until_t + 1e-6;
  }
  return labels;
}

std::vector<TruthLabel> labelTruths(const std::vector<TruthBox>& boxes, const CorridorParams& corridor,
                                    double known_until_t) {
  return labelTruths(boxes, buildTrajectories(boxes), corridor, known_until_t);
}

void differenceVelocities(std::vector<TruthBox>& boxes, double frame_dt_s) {
  std::map<std::uint32_t, std::vector<std::size_t>> tracks;
  for (std::size_t i = 0; i < boxes.size(); ++i) tracks[boxes[i].id].push_back(i);
  const auto oneFrameApart = [frame_dt_s](double dt) {
    return std::abs(dt - frame_dt_s) < 0.5 * frame_dt_s;
  };
  for (auto& entry : tracks) {
    std::vector<std::size_t>& idx = entry.second;
    std::stable_sort(idx.begin(), idx.end(),
                     [&boxes](std::size_t a, std::size_t b) { return boxes[a].t < boxes[b].t; });
    // Copy the centres first: velocities are written in place.
    std::vector<Eigen::Vector3d> c(idx.size());
    std::vector<double> t(idx.size());
    for (std::size_t k = 0; k < idx.size(); ++k) {
      c[k] = boxes[idx[k]].center;
      t[k] = boxes[idx[k]].t;
    }
    for (std::size_t k = 0; k < idx.size(); ++k) {
      const bool prev = k > 0 && oneFrameApart(t[k] - t[k - 1]);
      const bool next = k + 1 < idx.size() && oneFrameApart(t[k + 1] - t[k]);
      Eigen::Vector3d v = Eigen::Vector3d::Zero();
      if (prev && next) v = (c[k + 1] - c[k - 1]) / (t[k + 1] - t[k - 1]);
      else if (next) v = (c[k + 1] - c[k]) / (t[k + 1] - t[k]);
      else if (prev) v = (c[k] - c[k - 1]) / (t[k] - t[k - 1]);
      boxes[idx[k]].velocity = v;
    }
  }
}

std::vector<TruthBox> truthBoxesFromKitti(const std::vector<kitti::VeloBox>& labels,
                                          double frame_period_s) {
  std::vector<TruthBox> boxes;
  boxes.reserve(labels.size());
  for (const kitti::VeloBox& v : labels) {
    TruthBox b;
    b.t = frame_period_s * v.frame;
    b.id = static_cast<std::uint32_t>(v.track_id);
    b.type = v.type;
    b.center = v.center;
    b.size = v.size;
    b.yaw = v.yaw;
    boxes.push_back(std::move(b));
  }
  differenceVelocities(boxes, frame_period_s);
  return boxes;
}

bool boxContains(const TruthBox& box, const Eigen::Vector3d& p, double margin_m) {
  return orientedBoxContains(box.center, box.size, box.yaw, p, margin_m);
}

std::uint32_t countPointsInside(const TruthBox& box, const Cloud& cloud) {
  std::uint32_t n = 0;
  for (const Point& q : cloud.points) {
    if (!std::isfinite(q.x) || !std::isfinite(q.y) || !std::isfinite(q.z)) continue;
    if (boxContains(box, Eigen::Vector3d(q.x, q.y, q.z))) ++n;
  }
  return n;
}

}  // namespace icanc
