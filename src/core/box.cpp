#include "icanc/core/box.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <opencv2/imgproc.hpp>

namespace icanc {

Box3D fitBox(const Cloud& cloud, const std::vector<int>* indices) {
  const std::size_t n = indices ? indices->size() : cloud.size();
  if (n == 0) return Box3D();
  const float inf = std::numeric_limits<float>::infinity();
  float zmin = inf, zmax = -inf;
  std::vector<cv::Point2f> xy;
  xy.reserve(n);
  for (std::size_t k = 0; k < n; ++k) {
    const Point& p = cloud[indices ? static_cast<std::size_t>((*indices)[k]) : k];
    zmin = std::min(zmin, p.z);
    zmax = std::max(zmax, p.z);
    xy.emplace_back(p.x, p.y);
  }
  return fitBoxFootprint(xy, zmin, zmax, static_cast<int>(n));
}

Box3D fitBoxFootprint(const std::vector<cv::Point2f>& xy, float zmin, float zmax, int num_points) {
  Box3D box;
  if (xy.empty()) return box;
  const float inf = std::numeric_limits<float>::infinity();
  float xmin = inf, ymin = inf, xmax = -inf, ymax = -inf;
  for (const cv::Point2f& p : xy) {
    xmin = std::min(xmin, p.x);
    xmax = std::max(xmax, p.x);
    ymin = std::min(ymin, p.y);
    ymax = std::max(ymax, p.y);
  }
  box.min = Eigen::Vector3f(xmin, ymin, zmin);
  box.max = Eigen::Vector3f(xmax, ymax, zmax);
  box.num_points = num_points;

  // Oriented box: OpenCV's minimum-area rectangle of the footprint.
  const cv::RotatedRect rect = cv::minAreaRect(xy);
  float length = rect.size.width, width = rect.size.height;
  float yaw = rect.angle * static_cast<float>(M_PI / 180.0);
  if (width > length) {  // length is the longer side; yaw follows it
    std::swap(length, width);
    yaw += static_cast<float>(M_PI / 2.0);
  }
  // Normalise to (-pi/2, pi/2]: a box is symmetric under a half turn.
  while (yaw > static_cast<float>(M_PI / 2.0)) yaw -= static_cast<float>(M_PI);
  while (yaw <= -static_cast<float>(M_PI / 2.0)) yaw += static_cast<float>(M_PI);

  box.center = Eigen::Vector3f(rect.center.x, rect.center.y, 0.5f * (zmin + zmax));
  box.size = Eigen::Vector3f(length, width, zmax - zmin);
  box.yaw = yaw;
  return box;
}

float bevIoU(const Box3D& a, const Box3D& b) {
  const float ix = std::min(a.max.x(), b.max.x()) - std::max(a.min.x(), b.min.x());
  const float iy = std::min(a.max.y(), b.max.y()) - std::max(a.min.y(), b.min.y());
  if (ix <= 0.0f || iy <= 0.0f) return 0.0f;
  const float inter = ix * iy;
  const float area_a = (a.max.x() - a.min.x()) * (a.max.y() - a.min.y());
  const float area_b = (b.max.x() - b.min.x()) * (b.max.y() - b.min.y());
  const float uni = area_a + area_b - inter;
  return uni > 0.0f ? inter / uni : 0.0f;
}

bool orientedBoxContains(const Eigen::Vector3d& center, const Eigen::Vector3d& size, double yaw,
                         const Eigen::Vector3d& p, double margin_m) {
  const Eigen::Vector3d d = p - center;
  const double c = std::cos(yaw), s = std::sin(yaw);
  const double along = c * d.x() + s * d.y();
  const double across = -s * d.x() + c * d.y();
  return std::abs(along) <= 0.5 * size.x() + margin_m &&
         std::abs(across) <= 0.5 * size.y() + margin_m &&
         std::abs(d.z()) <= 0.5 * size.z() + margin_m;
}

}  // namespace icanc
