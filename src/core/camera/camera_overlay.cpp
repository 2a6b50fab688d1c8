#include "icanc/core/camera/camera_overlay.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <opencv2/imgproc.hpp>

namespace icanc {
namespace {

// Edges of boxCorners(): bottom ring, top ring, verticals.
constexpr int kEdges[12][2] = {{0, 1}, {1, 2}, {2, 3}, {3, 0}, {4, 5}, {5, 6},
                               {6, 7}, {7, 4}, {0, 4}, {1, 5}, {2, 6}, {3, 7}};

cv::Point3d toCv(const Eigen::Vector3d& p) { return cv::Point3d(p.x(), p.y(), p.z()); }

}  // namespace

const cv::Scalar& overlayDangerColour() {
  static const cv::Scalar red(0, 0, 255);
  return red;
}

const cv::Scalar& overlaySafeColour() {
  static const cv::Scalar green(0, 200, 0);
  return green;
}

std::array<Eigen::Vector3d, 8> boxCorners(const OverlayObject& o) {
  const double c = std::cos(o.yaw), s = std::sin(o.yaw);
  const double hl = 0.5 * o.size.x(), hw = 0.5 * o.size.y(), hh = 0.5 * o.size.z();
  const double xs[4] = {hl, -hl, -hl, hl};
  const double ys[4] = {hw, hw, -hw, -hw};
  std::array<Eigen::Vector3d, 8> corners;
  for (int k = 0; k < 8; ++k) {
    const double x = xs[k % 4], y = ys[k % 4], z = k < 4 ? -hh : hh;
    corners[k] = o.center + Eigen::Vector3d(c * x - s * y, s * x + c * y, z);
  }
  return corners;
}

std::vector<Segment2d> projectBoxEdges(const std::array<Eigen::Vector3d, 8>& corners,
                                       const Projector& project, double near_m) {
  std::vector<Segment2d> out;
  for (const auto& e : kEdges) {
    Eigen::Vector3d a = corners[e[0]], b = corners[e[1]];
    if (a.z() < near_m && b.z() < near_m) continue;  // wholly behind the near plane
    // Cut the part behind the near plane at z = near_m.
    if (a.z() < near_m) a = a + (b - a) * ((near_m - a.z()) / (b.z() - a.z()));
    if (b.z() < near_m) b = b + (a - b) * ((near_m - b.z()) / (a.z() - b.z()));
    out.emplace_back(project(toCv(a)), project(toCv(b)));
  }
  return out;
}

int drawOverlay(cv::Mat& image, const std::vector<OverlayObject>& objects,
                const Eigen::Isometry3d& camera_from_vehicle, const Projector& project,
                const OverlayStyle& style) {
  const cv::Rect frame(0, 0, image.cols, image.rows);
  int drawn = 0;
  // Safe boxes first so red is drawn on top.
  std::vector<const OverlayObject*> order;
  for (const OverlayObject& o : objects)
    if (o.dangerous || style.draw_safe) order.push_back(&o);
  std::stable_sort(order.begin(), order.end(),
                   [](const OverlayObject* a, const OverlayObject* b) { return !a->dangerous && b->dangerous; });
  for (const OverlayObject* o : order) {
    std::array<Eigen::Vector3d, 8> corners = boxCorners(*o);
    for (Eigen::Vector3d& c : corners) c = camera_from_vehicle * c;
    const std::vector<Segment2d> edges = projectBoxEdges(corners, project, style.near_m);
    const cv::Scalar& colour = o->dangerous ? overlayDangerColour() : overlaySafeColour();
    const int thickness = o->dangerous ? style.danger_thickness_px : 1;
    bool visible = false;
    cv::Point label(image.cols, image.rows);  // top-left-most visible end point
    for (const Segment2d& s : edges) {
      // Pixel coordinates far outside the image overflow cv::Point; clip in doubles first.
      cv::Point a(cvRound(std::clamp(s.first.x, -1e6, 1e6)), cvRound(std::clamp(s.first.y, -1e6, 1e6)));
      cv::Point b(cvRound(std::clamp(s.second.x, -1e6, 1e6)), cvRound(std::clamp(s.second.y, -1e6, 1e6)));
      if (!cv::clipLine(frame, a, b)) continue;
      visible = true;
      cv::line(image, a, b, colour, thickness, cv::LINE_AA);
      for (const cv::Point& p : {a, b})
        if (p.y < label.y || (p.y == label.y && p.x < label.x)) label = p;
    }
    if (!visible) continue;
    ++drawn;
    if (!o->dangerous) continue;
    char text[64];
    std::snprintf(text, sizeof(text), "#%u %.1f m/s", o->id, o->speed_mps);
    const cv::Point at(std::max(0, label.x), std::max(14, label.y - 4));
    cv::putText(image, text, at, cv::FONT_HERSHEY_SIMPLEX, 0.5, colour, 1, cv::LINE_AA);
  }
  return drawn;
}

}  // namespace icanc
