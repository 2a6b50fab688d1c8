#include "icanc/core/perception/box.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include <opencv2/imgproc.hpp>

namespace icanc {

namespace {
bool finite(const cv::Point2f& p) { return std::isfinite(p.x) && std::isfinite(p.y); }
}  // namespace

Box3D fitBox(const Cloud& cloud, const std::vector<int>* indices, float footprint_cell_m) {
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
  return fitBoxFootprint(xy, zmin, zmax, static_cast<int>(n), footprint_cell_m);
}

std::vector<FootprintCell> footprintCells(const std::vector<cv::Point2f>& xy, float cell_m) {
  std::vector<FootprintCell> cells;
  if (xy.empty() || !(cell_m > 0.0f)) return cells;
  const float inv = 1.0f / cell_m;
  // A dense grid over the points' own cells when it is small against the points (every cluster a
  // detector makes): linear, no sort. Cells come out ordered by x cell, then y cell, as below.
  // Non-finite points are skipped.
  const float inf = std::numeric_limits<float>::infinity();
  float xmin = inf, xmax = -inf, ymin = inf, ymax = -inf;
  std::size_t n = 0;
  for (const cv::Point2f& p : xy) {
    if (!finite(p)) continue;
    ++n;
    xmin = std::min(xmin, p.x);
    xmax = std::max(xmax, p.x);
    ymin = std::min(ymin, p.y);
    ymax = std::max(ymax, p.y);
  }
  if (n == 0) return cells;
  const double kx0 = std::floor(xmin * inv), ky0 = std::floor(ymin * inv);
  const double nx = std::floor(xmax * inv) - kx0 + 1.0, ny = std::floor(ymax * inv) - ky0 + 1.0;
  if (nx * ny <= 4.0 * static_cast<double>(n) + 64.0) {
    const int w = static_cast<int>(nx), h = static_cast<int>(ny);
    std::vector<FootprintCell> grid(static_cast<std::size_t>(w) * h);
    std::vector<char> used(grid.size(), 0);
    for (const cv::Point2f& p : xy) {
      if (!finite(p)) continue;
      const int ix = std::min(w - 1, std::max(0, static_cast<int>(std::floor(p.x * inv) - kx0)));
      const int iy = std::min(h - 1, std::max(0, static_cast<int>(std::floor(p.y * inv) - ky0)));
      const std::size_t k = static_cast<std::size_t>(ix) * h + iy;
      const Eigen::Vector2f q(p.x, p.y);
      if (!used[k]) {
        grid[k] = {q, q};
        used[k] = 1;
      } else {
        grid[k].min = grid[k].min.cwiseMin(q);
        grid[k].max = grid[k].max.cwiseMax(q);
      }
    }
    for (std::size_t k = 0; k < grid.size(); ++k)
      if (used[k]) cells.push_back(grid[k]);
    return cells;
  }
  struct Keyed {
    std::int64_t key;
    cv::Point2f p;
  };
  std::vector<Keyed> keyed;
  keyed.reserve(n);
  for (const cv::Point2f& p : xy) {
    if (!finite(p)) continue;
    const auto kx = static_cast<std::int64_t>(std::floor(p.x * inv));
    const auto ky = static_cast<std::int64_t>(std::floor(p.y * inv));
    // Ordered by x cell, then y cell (offset to be non-negative in the low 32 bits).
    keyed.push_back({kx * (std::int64_t(1) << 32) + (ky + (std::int64_t(1) << 31)), p});
  }
  std::sort(keyed.begin(), keyed.end(),
            [](const Keyed& a, const Keyed& b) { return a.key < b.key; });
  for (std::size_t i = 0; i < keyed.size(); ++i) {
    const Eigen::Vector2f p(keyed[i].p.x, keyed[i].p.y);
    if (i == 0 || keyed[i].key != keyed[i - 1].key) {
      cells.push_back({p, p});
    } else {
      cells.back().min = cells.back().min.cwiseMin(p);
      cells.back().max = cells.back().max.cwiseMax(p);
    }
  }
  return cells;
}

void hullCandidates(const std::vector<cv::Point2f>& xy, std::vector<cv::Point2f>& out) {
  out.clear();
  if (xy.empty()) return;
  // The extreme point along each of eight directions, counter-clockwise from -x: -x, -(x + y),
  // -y, x - y, x, x + y, y, -(x - y). (The first of equals. A NaN never wins, and is kept below
  // as cv::convexHull was given it before; an infinite coordinate may win, and then every point
  // is kept.)
  std::size_t first = 0;
  while (first < xy.size() && !finite(xy[first])) ++first;
  if (first == xy.size()) {
    out = xy;
    return;
  }
  cv::Point2f ext[8];
  std::fill(ext, ext + 8, xy[first]);
  for (std::size_t i = first + 1; i < xy.size(); ++i) {
    const cv::Point2f& p = xy[i];
    if (p.x < ext[0].x) ext[0] = p;
    if (p.x + p.y < ext[1].x + ext[1].y) ext[1] = p;
    if (p.y < ext[2].y) ext[2] = p;
    if (p.x - p.y > ext[3].x - ext[3].y) ext[3] = p;
    if (p.x > ext[4].x) ext[4] = p;
    if (p.x + p.y > ext[5].x + ext[5].y) ext[5] = p;
    if (p.y > ext[6].y) ext[6] = p;
    if (p.x - p.y < ext[7].x - ext[7].y) ext[7] = p;
  }
  // The octagon's edges, in coordinates from its first corner (repeated corners give none: an edge
  // of zero length that every point passes). A point is strictly inside when it lies to the left
  // of every edge by more than the rounding of the cross product could make up: 1e-5 of the edge
  // times the octagon's span, against a few 1e-7 of it.
  for (const cv::Point2f& e : ext)
    if (!finite(e)) {  // an infinite coordinate: keep everything
      out = xy;
      return;
    }
  const cv::Point2f o = ext[0];
  const float span = (ext[4].x - ext[0].x) + (ext[6].y - ext[2].y);
  float ex[8], ey[8], c[8];
  int edges = 0;
  for (int k = 0; k < 8; ++k) {
    const cv::Point2f a = ext[k] - o, b = ext[(k + 1) % 8] - o;
    ex[k] = b.x - a.x;
    ey[k] = b.y - a.y;
    const bool degenerate = ex[k] == 0.0f && ey[k] == 0.0f;
    edges += !degenerate;
    // cross((b - a), (q - a)) = ex * qy - ey * qx - (ex * ay - ey * ax), less the margin.
    c[k] = degenerate ? -1.0f : ex[k] * a.y - ey[k] * a.x + 1e-5f * (std::abs(ex[k]) + std::abs(ey[k])) * span;
  }
  if (edges < 3) {
    out = xy;
    return;
  }
  out.reserve(64);
  for (const cv::Point2f& p : xy) {
    const float qx = p.x - o.x, qy = p.y - o.y;
    bool inside = true;
    for (int k = 0; k < 8; ++k) inside &= ex[k] * qy - ey[k] * qx - c[k] > 0.0f;
    if (!inside) out.push_back(p);  // (a NaN fails every test: kept)
  }
}

Box3D fitBoxFootprint(const std::vector<cv::Point2f>& xy, float zmin, float zmax, int num_points,
                      float footprint_cell_m) {
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

  // Oriented box: OpenCV's minimum-area rectangle of the footprint, found on its convex hull
  // (minAreaRect takes the hull first; done once here, the hull is kept). The hull is taken of
  // the points that may lie on it: sorting a wall's thousands of points was a sixth of the fast
  // detector's time on KITTI.
  std::vector<cv::Point2f> candidates, hull;
  hullCandidates(xy, candidates);
  cv::convexHull(candidates, hull, /*clockwise=*/false);
  box.hull.reserve(hull.size());
  for (const cv::Point2f& p : hull) box.hull.emplace_back(p.x, p.y);
  const cv::RotatedRect rect = cv::minAreaRect(hull);
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
  box.footprint = footprintCells(xy, footprint_cell_m);
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
