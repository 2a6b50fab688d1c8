// FastDetector, the grid's clusters: occupied cells linked into components (union-find), the
// height check inside long ones, grazing columns dropped, a box fitted to each cluster.
#include "icanc/core/perception/fast_detector.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

namespace icanc {

namespace {
constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr float kDeg = static_cast<float>(M_PI / 180.0);
}  // namespace

std::int32_t FastDetector::find(std::int32_t k) {
  while (parent_[k] != k) {
    parent_[k] = parent_[parent_[k]];  // path halving
    k = parent_[k];
  }
  return k;
}

namespace {

// A floating cell (floor > -inf) joins only what reaches up to within `gap` of it: a roof does
// not join the pedestrian under it, a wall's top the wall.
template <class C>
bool floatsApart(const C& a, const C& b, float gap) {
  return std::max(a.floor, b.floor) - std::min(a.zmax, b.zmax) >= gap;
}

// Squared distance between the bounds of two cells' points (0 when they overlap).
template <class C>
float pointGap2(const C& a, const C& b) {
  const float dx = std::max(0.0f, std::max(a.xmin_x - b.xmax_x, b.xmin_x - a.xmax_x));
  const float dy = std::max(0.0f, std::max(a.ymin_y - b.ymax_y, b.ymin_y - a.ymax_y));
  return dx * dx + dy * dy;
}

}  // namespace

template <class Links>
void FastDetector::linkForward(std::int32_t k, const Links& links) {
  const int cx = occupied_[k] % nx_, cy = occupied_[k] / nx_;
  for (const auto& d : forward_) {
    const int x = cx + d.first, y = cy + d.second;
    if (x < 0 || x >= nx_ || y >= ny_) continue;
    const std::int32_t slot = cell_slot_[static_cast<std::size_t>(y) * nx_ + x];
    if (slot < 0 || !links(slot)) continue;
    const std::int32_t a = find(k), b = find(slot);
    if (a != b) parent_[std::max(a, b)] = std::min(a, b);
  }
}

void FastDetector::linkCells(bool check_steps, float step_tan) {
  const std::int32_t n = static_cast<std::int32_t>(occupied_.size());
  parent_.resize(occupied_.size());
  std::iota(parent_.begin(), parent_.end(), 0);
  const float gap = params_.overhang_gap_m;
  for (std::int32_t k = 0; k < n; ++k) {
    const Cell& here = cells_[static_cast<std::size_t>(k)];
    const bool check = check_steps && long_[first_root_[k]];
    float max_step = params_.link_max_step_m;
    if (check && step_tan > 0.0f) {  // one beam spacing at this cell's range from the sensor
      const int cx = occupied_[k] % nx_, cy = occupied_[k] / nx_;
      const float range = std::hypot(prep_.roi_min.x() + (cx + 0.5f) * params_.cell_m - sensor_origin_.x(),
                                     prep_.roi_min.y() + (cy + 0.5f) * params_.cell_m - sensor_origin_.y());
      max_step = std::max(max_step, range * step_tan);
    }
    linkForward(k, [&](std::int32_t slot) {
      const Cell& other = cells_[static_cast<std::size_t>(slot)];
      if (check && std::abs(other.zmax - here.zmax) > max_step) return false;
      return !floatsApart(here, other, gap);
    });
  }
}

void FastDetector::splitByGaps() {
  const std::int32_t n = static_cast<std::int32_t>(occupied_.size());
  boundComponents(gap_root_);
  const int max_cells = static_cast<int>(params_.link_gap_max_extent_m * inv_cell_ + 1e-3f);
  gap_small_.resize(occupied_.size());
  bool any = false;
  for (std::int32_t k = 0; k < n; ++k) {
    const auto& b = root_box_[gap_root_[k]];
    gap_small_[k] = std::max(b[2] - b[0], b[3] - b[1]) + 1 <= max_cells;
    any = any || gap_small_[k];
  }
  if (!any) return;
  for (std::int32_t k = 0; k < n; ++k) parent_[k] = gap_small_[k] ? k : gap_root_[k];
  const float gap2 = params_.link_gap_m * params_.link_gap_m;
  for (std::int32_t k = 0; k < n; ++k) {
    if (!gap_small_[k]) continue;
    const Cell& here = cells_[static_cast<std::size_t>(k)];
    linkForward(k, [&](std::int32_t slot) {
      const Cell& other = cells_[static_cast<std::size_t>(slot)];
      return gap_root_[slot] == gap_root_[k] && !floatsApart(here, other, params_.overhang_gap_m) &&
             pointGap2(here, other) <= gap2;
    });
  }
}

void FastDetector::boundComponents(std::vector<std::int32_t>& root_of) {
  root_of.resize(occupied_.size());
  root_box_.assign(occupied_.size(), {nx_, ny_, -1, -1});
  for (std::size_t k = 0; k < occupied_.size(); ++k) {
    const std::int32_t root = find(static_cast<std::int32_t>(k));
    root_of[k] = root;
    const int cx = occupied_[k] % nx_, cy = occupied_[k] / nx_;
    auto& b = root_box_[root];
    b[0] = std::min(b[0], cx);
    b[1] = std::min(b[1], cy);
    b[2] = std::max(b[2], cx);
    b[3] = std::max(b[3], cy);
  }
}

void FastDetector::clusterAndFit(std::vector<Box3D>& boxes) {
  boxes.clear();
  const std::int32_t n = static_cast<std::int32_t>(occupied_.size());
  linkCells(false);
  if (params_.link_max_step_m > 0.0f) {
    // Components longer than step_check_min_extent_m (walls, hedges, parked rows and whatever
    // stands against them) are linked again, now only between cells whose tops differ by at most
    // link_max_step_m: a pedestrian against a hedge comes apart, a car on its own stays whole.
    boundComponents(first_root_);
    const int min_cells = static_cast<int>(params_.step_check_min_extent_m * inv_cell_);
    long_.assign(occupied_.size(), 0);
    bool any = false;
    for (std::int32_t k = 0; k < n; ++k) {
      const auto& b = root_box_[k];
      long_[k] = b[2] >= 0 && std::max(b[2] - b[0], b[3] - b[1]) + 1 >= min_cells;
      any = any || long_[k];
    }
    if (any) {
      linkCells(true, params_.link_step_beams > 0.0f ? beamStepTangent() : 0.0f);
      // Of the pieces a long component fell into, only the small ones (a pedestrian, a pole: at
      // most step_piece_max_m across) come apart; the rest of it stays one obstacle, so a hedge
      // or a wall whose top varies does not break into fragments.
      const int max_piece = static_cast<int>(params_.step_piece_max_m * inv_cell_ + 1e-3f);
      boundComponents(piece_root_);
      rest_.assign(occupied_.size(), -1);
      carved_.resize(occupied_.size());
      for (std::int32_t k = 0; k < n; ++k) {
        const auto& b = root_box_[piece_root_[k]];
        carved_[k] = long_[first_root_[k]] && std::max(b[2] - b[0], b[3] - b[1]) + 1 <= max_piece;
        if (!carved_[k] && rest_[first_root_[k]] < 0) rest_[first_root_[k]] = k;
      }
      for (std::int32_t k = 0; k < n; ++k)
        parent_[k] = carved_[k] ? piece_root_[k] : rest_[first_root_[k]];
    }
  }
  if (params_.link_gap_m > 0.0f) splitByGaps();

  clusters_.clear();
  cluster_of_root_.assign(occupied_.size(), -1);
  next_in_cluster_.resize(occupied_.size());
  cluster_of_slot_.resize(occupied_.size());
  for (std::int32_t k = 0; k < n; ++k) {
    const std::int32_t root = find(k);
    if (cluster_of_root_[root] < 0) {
      cluster_of_root_[root] = static_cast<std::int32_t>(clusters_.size());
      Cluster c;
      c.zmin = kInf;
      c.zmax = -kInf;
      clusters_.push_back(c);
    }
    cluster_of_slot_[k] = cluster_of_root_[root];
    Cluster& c = clusters_[cluster_of_root_[root]];
    const Cell& cell = cells_[static_cast<std::size_t>(k)];
    c.count += cell.count;
    c.grounded = c.grounded || cell.floor == -kInf;
    c.zmin = std::min(c.zmin, cell.zmin);
    c.zmax = std::max(c.zmax, cell.zmax);
    next_in_cluster_[k] = c.first_cell;
    c.first_cell = k;
    ++c.cells;
  }
  if (params_.grazing_reach_m > 0.0f) dropGrazingColumns();

  if (params_.range_split_angle_deg > 0.0f) rangeSplit(boxes);
  for (const Cluster& c : clusters_) {
    if (c.cells == 0) continue;  // a column of a surface at grazing incidence (dropGrazingColumns)
    if (c.count < params_.min_points || c.count > params_.max_points) continue;
    if (!c.grounded) continue;  // floating cells only: an overhang (a canopy over the road)
    if (c.split) continue;      // boxed by rangeSplit
    footprint_.clear();
    for (std::int32_t k = c.first_cell; k >= 0; k = next_in_cluster_[k])
      appendExtremes(cells_[static_cast<std::size_t>(k)], footprint_);
    boxes.push_back(fitBoxFootprint(footprint_, c.zmin, c.zmax, c.count, footprint_cell_m_));
  }
  std::stable_sort(boxes.begin(), boxes.end(),
                   [](const Box3D& a, const Box3D& b) { return a.num_points > b.num_points; });

}

void FastDetector::appendExtremes(const Cell& cell, std::vector<cv::Point2f>& out) {
  const cv::Point2f a(cell.xmin_x, cell.xmin_y), b(cell.xmax_x, cell.xmax_y);
  const cv::Point2f c(cell.ymin_x, cell.ymin_y), d(cell.ymax_x, cell.ymax_y);
  out.push_back(a);
  if (b != a) out.push_back(b);
  if (c != a && c != b) out.push_back(c);
  if (d != a && d != b && d != c) out.push_back(d);
}

void FastDetector::dropGrazingColumns() {
  // A surface seen at grazing incidence (a parked car's side from the lane beside it) is hit by
  // the scan's columns r * dtheta / sin(incidence) apart: beyond link_m from about 11 m on a
  // 0.72 deg scan (carla128) for a car 3 m to the side, 1.6 m apart at 20 m. Each column is then
  // a cluster of its own, one line of sight (its points within cell_m / 2 across it) with enough
  // returns (10-16 on a car's side) to be boxed, and it stays at its column's bearing while the
  // car goes by: a track moving with the vehicle (night_parked_cars: parked cars' speed over
  // ground p90 11.6 m/s). Such a column is no box when a cluster of its height (tops within
  // link_max_step_m) continues its surface: within grazing_reach_m, at most grazing_angle_deg off
  // its line of sight; the car stays boxed from its other columns and its face towards the
  // sensor. Joining the columns to that cluster instead bridged the gaps between parked cars
  // (KITTI 0000: 660 -> 652 of 670 found, docs/performance.md). A pole or a distant pedestrian
  // (one column too) stays unless something of its height stands right behind or in front of it.
  const std::int32_t nc = static_cast<std::int32_t>(clusters_.size());
  const float thin = 0.5f * params_.cell_m;
  const float reach_m = params_.grazing_reach_m;
  const float sin_max = std::sin(params_.grazing_angle_deg * kDeg);
  const float max_step = params_.link_max_step_m;
  const int reach = static_cast<int>(std::ceil(reach_m * inv_cell_));
  dropped_.clear();
  for (std::int32_t c = 0; c < nc; ++c) {
    const Cluster& t = clusters_[c];
    // One column covers a few cells at most; with fewer than min_points returns it is no box
    // anyway, nor does it hold up another column (a spurious return lies on the line of sight
    // of whatever stands behind it).
    if (!t.grounded || t.cells > 4 || t.count < params_.min_points) continue;
    float sx = 0.0f, sy = 0.0f;
    for (std::int32_t k = t.first_cell; k >= 0; k = next_in_cluster_[k]) {
      const Cell& cell = cells_[static_cast<std::size_t>(k)];
      sx += cell.xmin_x + cell.xmax_x + cell.ymin_x + cell.ymax_x;
      sy += cell.xmin_y + cell.xmax_y + cell.ymin_y + cell.ymax_y;
    }
    const float cx = sx / (4.0f * t.cells), cy = sy / (4.0f * t.cells);
    const float r = std::hypot(cx, cy);
    if (r < params_.cell_m) continue;
    const float ux = cx / r, uy = cy / r;  // line of sight (from the grid's origin)
    float lo = kInf, hi = -kInf;           // its points across the line of sight
    for (std::int32_t k = t.first_cell; k >= 0; k = next_in_cluster_[k]) {
      const Cell& cell = cells_[static_cast<std::size_t>(k)];
      for (const auto& q : {std::make_pair(cell.xmin_x, cell.xmin_y),
                            std::make_pair(cell.xmax_x, cell.xmax_y),
                            std::make_pair(cell.ymin_x, cell.ymin_y),
                            std::make_pair(cell.ymax_x, cell.ymax_y)}) {
        const float across = ux * q.second - uy * q.first;
        lo = std::min(lo, across);
        hi = std::max(hi, across);
      }
    }
    if (hi - lo > thin) continue;
    const int gx = static_cast<int>((cx - prep_.roi_min.x()) * inv_cell_);
    const int gy = static_cast<int>((cy - prep_.roi_min.y()) * inv_cell_);
    bool continued = false;
    for (int y = std::max(0, gy - reach); y <= std::min(ny_ - 1, gy + reach) && !continued; ++y) {
      for (int x = std::max(0, gx - reach); x <= std::min(nx_ - 1, gx + reach); ++x) {
        const std::int32_t slot = cell_slot_[static_cast<std::size_t>(y) * nx_ + x];
        if (slot < 0) continue;
        const Cell& other = cells_[static_cast<std::size_t>(slot)];
        if (other.floor != -kInf) continue;
        const std::int32_t oc = cluster_of_slot_[slot];
        if (oc == c || clusters_[oc].count < params_.min_points) continue;
        if (max_step > 0.0f && std::abs(other.zmax - t.zmax) > max_step) continue;
        // From the column to the middle of the cell's points.
        const float dx = 0.5f * (other.xmin_x + other.xmax_x) - cx;
        const float dy = 0.5f * (other.ymin_y + other.ymax_y) - cy;
        const float d = std::hypot(dx, dy);
        if (d > reach_m || std::abs(ux * dy - uy * dx) > sin_max * d) continue;
        continued = true;
        break;
      }
    }
    if (continued) dropped_.push_back(c);
  }
  // Marked after the search: a dropped column still continues the surface of the next one.
  for (std::int32_t c : dropped_) clusters_[c].cells = 0;
}

}  // namespace icanc
