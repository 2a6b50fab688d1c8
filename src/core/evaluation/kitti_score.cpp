#include "icanc/core/evaluation/kitti_score.hpp"

#include <cmath>

namespace icanc {
namespace kitti {

namespace {
constexpr double kMaxRangeM = 40.0;
constexpr int kMinPoints = 20;
constexpr double kMarginM = 0.5;
constexpr double kHalfFovRad = 45.0 * M_PI / 180.0;

bool counted(const std::string& type) {
  return type == "Car" || type == "Van" || type == "Cyclist" || type == "Pedestrian";
}
}  // namespace

int DetectionScore::labelledTotal() const {
  int n = 0;
  for (const auto& kv : labelled) n += kv.second;
  return n;
}

int DetectionScore::foundTotal() const {
  int n = 0;
  for (const auto& kv : found) n += kv.second;
  return n;
}

int DetectionScore::outsideRoiTotal() const {
  int n = 0;
  for (const auto& kv : outside_roi) n += kv.second;
  return n;
}

double DetectionScore::recall() const {
  const int n = labelledTotal();
  return n ? double(foundTotal()) / n : 1.0;
}

double DetectionScore::precision() const { return detections ? double(correct) / detections : 1.0; }

void DetectionScore::add(const DetectionScore& other) {
  for (const auto& kv : other.labelled) labelled[kv.first] += kv.second;
  for (const auto& kv : other.found) found[kv.first] += kv.second;
  for (const auto& kv : other.outside_roi) outside_roi[kv.first] += kv.second;
  detections += other.detections;
  correct += other.correct;
}

DetectionScore scoreFrame(const std::vector<VeloBox>& labels, const Cloud& cloud,
                          const std::vector<Box3D>& detections, const Eigen::AlignedBox2d* roi) {
  DetectionScore score;
  for (const VeloBox& label : labels) {
    if (!counted(label.type) || label.center.head<2>().norm() > kMaxRangeM) continue;
    int inside = 0;
    for (const Point& p : cloud) {
      if (contains(label, Eigen::Vector3d(p.x, p.y, p.z)) && ++inside >= kMinPoints) break;
    }
    if (inside < kMinPoints) continue;
    ++score.labelled[label.type];
    if (roi && !roi->contains(label.center.head<2>())) ++score.outside_roi[label.type];
    for (const Box3D& d : detections) {
      if (contains(label, d.center.cast<double>(), kMarginM)) {
        ++score.found[label.type];
        break;
      }
    }
  }
  for (const Box3D& d : detections) {
    const Eigen::Vector3d c = d.center.cast<double>();
    if (c.x() <= 0.0 || c.head<2>().norm() > kMaxRangeM ||
        std::abs(std::atan2(c.y(), c.x())) > kHalfFovRad)
      continue;
    ++score.detections;
    for (const VeloBox& label : labels) {
      if (contains(label, c, kMarginM)) {
        ++score.correct;
        break;
      }
    }
  }
  return score;
}

}  // namespace kitti
}  // namespace icanc
