// FastDetector, the range split (Bogoslavskyi & Stachniss): a cluster's returns as a range image,
// neighbours one surface unless the angle at the farther one says otherwise; the beam spacing it
// measures also sets the height check's step (beamStepTangent).
#include "icanc/core/perception/fast_detector.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

namespace icanc {

namespace {
constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr float kDeg = static_cast<float>(M_PI / 180.0);

// atan2 to about 1e-5 rad (a minimax polynomial for atan on [0, 1]): the range split needs an
// azimuth and an elevation per obstacle point of the clusters it looks at, and std::atan2 cost
// about as much as the rest of the split.
inline float fastAtan2(float y, float x) {
  const float ax = std::abs(x), ay = std::abs(y);
  const float hi = std::max(ax, ay), lo = std::min(ax, ay);
  if (hi == 0.0f) return 0.0f;
  const float t = lo / hi, t2 = t * t;
  float a = t * (0.99997726f +
                 t2 * (-0.33262347f +
                       t2 * (0.19354346f + t2 * (-0.11643287f + t2 * (0.05265332f + t2 * -0.01172120f)))));
  if (ay > ax) a = static_cast<float>(M_PI / 2.0) - a;
  if (x < 0.0f) a = static_cast<float>(M_PI) - a;
  return y < 0.0f ? -a : a;
}

// The median of v (reordered); 0 when empty.
float median(std::vector<float>& v) {
  if (v.empty()) return 0.0f;
  auto mid = v.begin() + v.size() / 2;
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}
}  // namespace

FastDetector::Ray FastDetector::rayOf(std::uint32_t i) const {
  const Kept& p = points_[i];
  Ray r;
  r.x = p.x - sensor_origin_.x();
  r.y = p.y - sensor_origin_.y();
  r.z = p.z - sensor_origin_.z();
  const float xy2 = r.x * r.x + r.y * r.y;
  r.range2 = xy2 + r.z * r.z;
  r.az = fastAtan2(r.y, r.x);
  r.el = fastAtan2(r.z, std::sqrt(xy2));
  r.point = i;
  return r;
}

float FastDetector::beamStepTangent() {
  if (!stepsDue()) return std::tan(params_.link_step_beams * range_row_deg_ * kDeg);
  // The component with the most obstacle points (a wall, a car: many beams over one surface).
  std::vector<std::int32_t>& points_of = pixel_parent_;  // scratch (the range split reuses it)
  points_of.assign(occupied_.size(), 0);
  std::int32_t widest = -1;
  for (std::size_t k = 0; k < occupied_.size(); ++k) {
    const std::int32_t root = first_root_[k];
    points_of[root] += cells_[static_cast<std::size_t>(k)].count;
    if (widest < 0 || points_of[root] > points_of[widest]) widest = root;
  }
  if (widest < 0) return 0.0f;
  // Its rays (the first 1500: the estimate sorts them), from the sensor.
  rays_.clear();
  for (std::uint32_t i : obstacle_index_) {
    if (first_root_[cell_slot_[points_[i].cell]] != widest) continue;
    rays_.push_back(rayOf(i));
    if (rays_.size() == 1500) break;
  }
  if (!estimateRangeSteps(0, rays_.size())) return 0.0f;
  return std::tan(params_.link_step_beams * range_row_deg_ * kDeg);
}

void FastDetector::rangeSplit(std::vector<Box3D>& boxes) {
  // Clusters to look at: boxed ones (grounded, within the point limits) at least
  // range_split_min_extent_m across; one pedestrian alone is never split.
  const std::size_t nc = clusters_.size();
  ray_begin_.assign(nc + 1, -1);
  bool any = false;
  for (std::size_t i = 0; i < nc; ++i) {
    const Cluster& c = clusters_[i];
    if (c.cells == 0 || !c.grounded || c.count < 2 * params_.min_points ||
        c.count > params_.max_points)
      continue;  // (cells 0: a column dropGrazingColumns dropped)
    float xmin = kInf, xmax = -kInf, ymin = kInf, ymax = -kInf;
    for (std::int32_t k = c.first_cell; k >= 0; k = next_in_cluster_[k]) {
      const Cell& cell = cells_[static_cast<std::size_t>(k)];
      xmin = std::min(xmin, cell.xmin_x);
      xmax = std::max(xmax, cell.xmax_x);
      ymin = std::min(ymin, cell.ymin_y);
      ymax = std::max(ymax, cell.ymax_y);
    }
    if (std::max(xmax - xmin, ymax - ymin) < params_.range_split_min_extent_m) continue;
    ray_begin_[i] = 0;
    any = true;
  }
  if (!any) return;
  // The rays of those clusters, grouped by cluster (counting sort over the obstacle points).
  std::vector<std::int32_t>& count = pixel_parent_;  // scratch until splitCluster
  count.assign(nc, 0);
  for (std::uint32_t i : obstacle_index_) {
    const std::int32_t cl = cluster_of_slot_[cell_slot_[points_[i].cell]];
    if (ray_begin_[cl] >= 0) ++count[cl];
  }
  std::int32_t total = 0;
  std::size_t widest = nc;  // the cluster the angular steps are estimated from: the most rays
  for (std::size_t i = 0; i < nc; ++i) {
    if (ray_begin_[i] < 0) continue;
    if (widest == nc || count[i] > count[widest]) widest = i;
    ray_begin_[i] = total;
    total += count[i];
  }
  ray_begin_[nc] = total;
  rays_.resize(static_cast<std::size_t>(total));
  std::vector<std::int32_t>& fill = pixel_parent_;  // scratch: next free ray per cluster
  fill.assign(ray_begin_.begin(), ray_begin_.end());
  for (std::uint32_t i : obstacle_index_) {
    const Kept& p = points_[i];
    const std::int32_t cl = cluster_of_slot_[cell_slot_[p.cell]];
    if (ray_begin_[cl] < 0) continue;
    rays_[static_cast<std::size_t>(fill[cl]++)] = rayOf(i);
  }
  // Cluster ends: the start of the next cluster that has rays.
  const auto endOf = [&](std::size_t i) {
    for (std::size_t j = i + 1; j < nc; ++j)
      if (ray_begin_[j] >= 0) return static_cast<std::size_t>(ray_begin_[j]);
    return static_cast<std::size_t>(total);
  };
  // (its first 1500 rays at most: the estimate sorts them)
  const std::size_t first = static_cast<std::size_t>(ray_begin_[widest]);
  if (stepsDue() && !estimateRangeSteps(first, std::min(endOf(widest), first + 1500))) return;
  for (std::size_t i = 0; i < nc; ++i)
    if (ray_begin_[i] >= 0) splitCluster(i, static_cast<std::size_t>(ray_begin_[i]), endOf(i), boxes);
}

bool FastDetector::estimateRangeSteps(std::size_t begin, std::size_t end) {
  // The sensor's azimuth step: the median gap between returns next to each other in azimuth
  // among those at the same elevation (one beam); its beam spacing: the median gap between
  // returns next to each other in elevation within one azimuth step. Measured on the rays, so
  // the same profile serves a 16-, 32-, 64- or 128-beam unit.
  const auto sortedGaps = [&](float lo, float hi) {
    std::sort(steps_.begin(), steps_.end());
    diffs_.clear();
    for (std::size_t i = 1; i < steps_.size(); ++i) {
      if (steps_[i][0] != steps_[i - 1][0]) continue;
      const float d = steps_[i][1] - steps_[i - 1][1];
      if (d > lo && d < hi) diffs_.push_back(d);
    }
    return diffs_.size() >= 20 ? median(diffs_) : 0.0f;
  };
  steps_.clear();
  for (std::size_t j = begin; j < end; ++j)
    steps_.push_back({std::round(rays_[j].el / (0.02f * kDeg)), rays_[j].az});
  // Too few returns side by side to measure (a frame of small clusters only): the last frame's
  // steps, if any.
  const bool known = stepsKnown();
  const float col = sortedGaps(0.01f * kDeg, 3.0f * kDeg);
  if (!(col > 0.0f)) return known;
  steps_.clear();
  for (std::size_t j = begin; j < end; ++j)
    steps_.push_back({std::round(rays_[j].az / col), rays_[j].el});
  const float row = sortedGaps(0.05f * kDeg, 6.0f * kDeg);
  if (!(row > 0.0f)) return known;
  range_col_deg_ = col / kDeg;
  range_row_deg_ = row / kDeg;
  steps_age_ = 0;
  return true;
}

void FastDetector::splitCluster(std::size_t cluster, std::size_t begin, std::size_t end,
                                std::vector<Box3D>& boxes) {
  const std::int32_t n = static_cast<std::int32_t>(end - begin);
  if (n < 2 * params_.min_points) return;
  Ray* const ray = rays_.data() + begin;
  // Pixels: azimuth steps from the first ray's (wrapped, so a cluster behind the sensor across
  // +-pi is one block) and beam spacings from its elevation, rounded: a beam's returns fall on
  // pixel centres. (+ 65536: rounding by truncation of a positive number, no libm call.)
  const float inv_col = 1.0f / (range_col_deg_ * kDeg), inv_row = 1.0f / (range_row_deg_ * kDeg);
  const float az0 = ray[0].az, el0 = ray[0].el;
  const float pi = static_cast<float>(M_PI), two_pi = static_cast<float>(2.0 * M_PI);
  int cmin = 0, cmax = 0, rmin = 0, rmax = 0;
  for (std::int32_t j = 0; j < n; ++j) {
    Ray& r = ray[j];
    float daz = r.az - az0;
    daz += daz > pi ? -two_pi : (daz < -pi ? two_pi : 0.0f);
    r.col = static_cast<int>(daz * inv_col + 65536.5f) - 65536;
    r.row = static_cast<int>((r.el - el0) * inv_row + 65536.5f) - 65536;
    cmin = std::min(cmin, r.col);
    cmax = std::max(cmax, r.col);
    rmin = std::min(rmin, r.row);
    rmax = std::max(rmax, r.row);
  }
  const std::int64_t width = cmax - cmin + 1, height = rmax - rmin + 1;
  if (width * height > (std::int64_t(1) << 22)) return;  // not a sensor's image: leave it whole
  pixel_ray_.assign(static_cast<std::size_t>(width * height), -1);
  std::int32_t* const pixel = pixel_ray_.data();
  for (std::int32_t j = 0; j < n; ++j) {
    Ray& r = ray[j];
    r.pixel = static_cast<std::int32_t>((r.row - rmin) * width + (r.col - cmin));
    std::int32_t& best = pixel[r.pixel];
    if (best < 0 || r.range2 < ray[best].range2) best = j;
  }
  // Union-find over the rays that hold their pixel; neighbours to the right, up (or two up:
  // beams unevenly spaced) and diagonally; the angle criterion between each pair.
  pixel_parent_.resize(static_cast<std::size_t>(n));
  std::int32_t* const parent = pixel_parent_.data();
  std::iota(parent, parent + n, 0);
  const auto root = [parent](std::int32_t k) {
    while (parent[k] != k) {
      parent[k] = parent[parent[k]];
      k = parent[k];
    }
    return k;
  };
  broken_.clear();
  const float cos2_split = cos_split_ * cos_split_;
  const float cos2_vertical = cos_split_vertical_ * cos_split_vertical_;
  const std::int32_t w_px = static_cast<std::int32_t>(width), h_px = static_cast<std::int32_t>(height);
  for (std::int32_t j = 0; j < n; ++j) {
    const Ray& a = ray[j];
    if (pixel[a.pixel] != j) continue;
    const std::int32_t c = a.pixel % w_px, w = a.pixel / w_px;
    const bool right = c + 1 < w_px;
    std::int32_t next[4] = {right ? pixel[a.pixel + 1] : -1, -1,
                            right && w + 1 < h_px ? pixel[a.pixel + w_px + 1] : -1,
                            right && w > 0 ? pixel[a.pixel - w_px + 1] : -1};
    if (w + 1 < h_px) next[1] = pixel[a.pixel + w_px];
    if (next[1] < 0 && w + 2 < h_px) next[1] = pixel[a.pixel + 2 * w_px];
    for (int t = 0; t < 4; ++t) {
      const std::int32_t k = next[t];
      if (k < 0) continue;
      const Ray& b = ray[k];
      const bool a_far = a.range2 >= b.range2;
      const Ray& f = a_far ? a : b;
      const Ray& q = a_far ? b : a;
      // beta, at the farther return, between its beam (towards the sensor) and the line to the
      // nearer: one surface when beta > the threshold, i.e. cos(beta) < cos(threshold).
      const float dx = q.x - f.x, dy = q.y - f.y, dz = q.z - f.z;
      const float dot = -(f.x * dx + f.y * dy + f.z * dz);
      const float cos2 = t == 0 ? cos2_split : cos2_vertical;
      if (dot <= 0.0f || dot * dot < cos2 * f.range2 * (dx * dx + dy * dy + dz * dz)) {
        const std::int32_t ra = root(j), rb = root(k);
        if (ra != rb) parent[std::max(ra, rb)] = std::min(ra, rb);
      } else if (t == 0) {  // apart side by side (in azimuth): who stands in front
        broken_.push_back(a_far ? std::array<std::int32_t, 2>{k, j} : std::array<std::int32_t, 2>{j, k});
      }
    }
  }
  // Pieces: every ray in its pixel's segment (Ray::pixel becomes its piece, a root).
  if (pieces_.size() < static_cast<std::size_t>(n)) pieces_.resize(static_cast<std::size_t>(n));
  Piece* const piece = pieces_.data();
  for (std::int32_t j = 0; j < n; ++j) {
    if (parent[j] != j) continue;
    Piece& p = piece[j];
    p = Piece();
    p.xmin = p.ymin = p.zmin = p.colmin = kInf;
    p.xmax = p.ymax = p.zmax = p.colmax = -kInf;
    p.range2 = kInf;
  }
  for (std::int32_t j = 0; j < n; ++j) {
    Ray& r = ray[j];
    r.pixel = root(pixel[r.pixel]);
    const Kept& p = points_[r.point];
    Piece& s = piece[r.pixel];
    ++s.count;
    s.xmin = std::min(s.xmin, p.x);
    s.xmax = std::max(s.xmax, p.x);
    s.ymin = std::min(s.ymin, p.y);
    s.ymax = std::max(s.ymax, p.y);
    s.zmin = std::min(s.zmin, p.z);
    s.zmax = std::max(s.zmax, p.z);
    s.colmin = std::min(s.colmin, static_cast<float>(r.col));
    s.colmax = std::max(s.colmax, static_cast<float>(r.col));
    s.range2 = std::min(s.range2, r.range2);
  }
  for (const auto& pair : broken_) {
    const std::int32_t near = root(pair[0]), far = root(pair[1]);
    if (near == far) continue;
    ++piece[near].nearer;
    ++piece[far].farther;
  }
  std::int32_t carved_points = 0, carved_pieces = 0;
  const float col_rad = range_col_deg_ * kDeg;
  for (std::int32_t j = 0; j < n; ++j) {
    if (parent[j] != j) continue;
    Piece& p = piece[j];
    const std::int32_t borders = p.nearer + p.farther;
    // Width across the line of sight: its columns at its nearest range.
    const float across = (p.colmax - p.colmin + 1.0f) * col_rad * std::sqrt(p.range2);
    p.carved = p.count >= params_.min_points &&
               std::max(p.xmax - p.xmin, p.ymax - p.ymin) <= params_.range_piece_max_m &&
               across <= params_.range_piece_max_width_m &&
               p.zmax - p.zmin >= params_.range_piece_min_height_m &&
               (borders == 0 || p.nearer >= params_.range_piece_foreground * borders);
    if (p.carved) {
      p.box = carved_pieces++;
      carved_points += p.count;
    }
  }
  if (carved_pieces == 0 || (carved_pieces == 1 && carved_points == n))
    return;  // nothing comes apart: boxed whole as every cluster

  Cluster& c = clusters_[cluster];
  c.split = true;
  // The carved pieces, each from its own points: the rays ordered by piece (counting sort into
  // pixel_ray_, no longer needed), then one box per run.
  std::vector<std::int32_t>& order = pixel_ray_;
  order.assign(static_cast<std::size_t>(carved_pieces) + 1 + static_cast<std::size_t>(carved_points), 0);
  std::int32_t* const start = order.data();
  std::int32_t* const sorted = start + carved_pieces + 1;
  for (std::int32_t j = 0; j < n; ++j)
    if (piece[ray[j].pixel].carved) ++start[piece[ray[j].pixel].box + 1];
  for (std::int32_t b = 0; b < carved_pieces; ++b) start[b + 1] += start[b];
  for (std::int32_t j = 0; j < n; ++j) {
    const Piece& p = piece[ray[j].pixel];
    if (p.carved) sorted[start[p.box]++] = j;
  }
  for (std::int32_t b = 0, from = 0; b < carved_pieces; from = start[b++]) {
    footprint_.clear();
    for (std::int32_t i = from; i < start[b]; ++i) {
      const Kept& p = points_[ray[sorted[i]].point];
      footprint_.emplace_back(p.x, p.y);
    }
    const Piece& p = piece[ray[sorted[from]].pixel];
    boxes.push_back(fitBoxFootprint(footprint_, p.zmin, p.zmax, p.count, footprint_cell_m_));
  }
  // The rest: the extreme points of its cells that hold nothing carved, and the points of
  // those that do.
  cell_carved_.resize(occupied_.size());
  for (std::int32_t k = c.first_cell; k >= 0; k = next_in_cluster_[k]) cell_carved_[k] = 0;
  for (std::int32_t j = 0; j < n; ++j)
    if (piece[ray[j].pixel].carved) cell_carved_[cell_slot_[points_[ray[j].point].cell]] = 1;
  footprint_.clear();
  float zmin = kInf, zmax = -kInf;
  for (std::int32_t k = c.first_cell; k >= 0; k = next_in_cluster_[k]) {
    if (cell_carved_[k]) continue;
    const Cell& cell = cells_[static_cast<std::size_t>(k)];
    appendExtremes(cell, footprint_);
    zmin = std::min(zmin, cell.zmin);
    zmax = std::max(zmax, cell.zmax);
  }
  for (std::int32_t j = 0; j < n; ++j) {
    const Kept& p = points_[ray[j].point];
    if (piece[ray[j].pixel].carved || !cell_carved_[cell_slot_[p.cell]]) continue;
    footprint_.emplace_back(p.x, p.y);
    zmin = std::min(zmin, p.z);
    zmax = std::max(zmax, p.z);
  }
  const std::int32_t rest = c.count - carved_points;
  if (rest >= params_.min_points && !footprint_.empty())
    boxes.push_back(fitBoxFootprint(footprint_, zmin, zmax, rest, footprint_cell_m_));
}

}  // namespace icanc
