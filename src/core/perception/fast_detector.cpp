#include "icanc/core/perception/fast_detector.hpp"

#include <algorithm>
#include <limits>
#include <numeric>
#include <sstream>
#include <stdexcept>

namespace icanc {

namespace {
constexpr float kInf = std::numeric_limits<float>::infinity();
}  // namespace

std::string validate(const FastDetectorParams& p) {
  std::ostringstream why;
  if (!(p.cell_m >= 0.05f && p.cell_m <= 2.0f)) {
    why << "fast.cell_m must be in [0.05, 2] (got " << p.cell_m << ")";
  } else if (!(p.link_m >= 0.0f && p.link_m <= 8.0f * p.cell_m)) {
    why << "fast.link_m must be in [0, 8 * fast.cell_m] (got " << p.link_m << ")";
  } else if (!(p.link_max_step_m >= 0.0f && p.link_max_step_m <= 5.0f)) {
    why << "fast.link_max_step_m must be in [0, 5] (got " << p.link_max_step_m << ")";
  } else if (!(p.step_piece_max_m >= 0.0f && p.step_piece_max_m <= 100.0f)) {
    why << "fast.step_piece_max_m must be in [0, 100] (got " << p.step_piece_max_m << ")";
  } else if (!(p.step_check_min_extent_m >= 0.0f && p.step_check_min_extent_m <= 1000.0f)) {
    why << "fast.step_check_min_extent_m must be in [0, 1000] (got " << p.step_check_min_extent_m
        << ")";
  } else if (p.sectors < 8 || p.sectors > 3600) {
    why << "fast.sectors must be in [8, 3600] (got " << p.sectors << ")";
  } else if (!(p.range_bin_m >= 0.1f && p.range_bin_m <= 10.0f)) {
    why << "fast.range_bin_m must be in [0.1, 10] (got " << p.range_bin_m << ")";
  } else if (!(p.max_slope_deg >= 0.0f && p.max_slope_deg < 45.0f)) {
    why << "fast.max_slope_deg must be in [0, 45) (got " << p.max_slope_deg << ")";
  } else if (!(p.ground_step_m >= 0.0f && p.ground_step_m <= 2.0f)) {
    why << "fast.ground_step_m must be in [0, 2] (got " << p.ground_step_m << ")";
  } else if (!(p.obstacle_height_m > 0.0f && p.obstacle_height_m < 5.0f)) {
    why << "fast.obstacle_height_m must be in (0, 5) (got " << p.obstacle_height_m << ")";
  } else if (!(p.max_height_m > p.obstacle_height_m && p.max_height_m <= 20.0f)) {
    why << "fast.max_height_m must be in (fast.obstacle_height_m, 20] (got " << p.max_height_m
        << ")";
  } else if (!(p.overhang_gap_m >= 0.0f && p.overhang_gap_m <= 5.0f)) {
    why << "fast.overhang_gap_m must be in [0, 5] (got " << p.overhang_gap_m << ")";
  } else if (!(p.overhang_min_height_m >= p.obstacle_height_m &&
               p.overhang_min_height_m <= p.max_height_m)) {
    why << "fast.overhang_min_height_m must be in [fast.obstacle_height_m, fast.max_height_m] (got "
        << p.overhang_min_height_m << ")";
  } else if (!(p.grazing_reach_m >= 0.0f && p.grazing_reach_m <= 10.0f)) {
    why << "fast.grazing_reach_m must be in [0, 10] (got " << p.grazing_reach_m << ")";
  } else if (!(p.grazing_angle_deg >= 0.0f && p.grazing_angle_deg < 90.0f)) {
    why << "fast.grazing_angle_deg must be in [0, 90) (got " << p.grazing_angle_deg << ")";
  } else if (p.min_points < 1) {
    why << "fast.min_points must be >= 1 (got " << p.min_points << ")";
  } else if (p.max_points < p.min_points) {
    why << "fast.max_points must be >= fast.min_points = " << p.min_points << " (got "
        << p.max_points << ")";
  }
  return why.str();
}

FastDetector::FastDetector(const CloudPrepParams& prep, const FastDetectorParams& params,
                           float footprint_cell_m)
    : prep_(prep), params_(params), footprint_cell_m_(footprint_cell_m) {
  std::string why = validate(prep);
  if (why.empty()) why = validate(params);
  if (why.empty()) {
    const Eigen::Vector3f extent = prep.roi_max - prep.roi_min;
    if (extent.x() / params.cell_m * (extent.y() / params.cell_m) > 64e6f)
      why = "fast.cell_m too small for the ROI (more than 64 million grid cells)";
  }
  if (!why.empty()) throw std::invalid_argument(why);

  inv_cell_ = 1.0f / params.cell_m;
  nx_ = std::max(1, static_cast<int>(std::ceil((prep.roi_max.x() - prep.roi_min.x()) * inv_cell_)));
  ny_ = std::max(1, static_cast<int>(std::ceil((prep.roi_max.y() - prep.roi_min.y()) * inv_cell_)));
  float max_range = 0.0f;
  for (float x : {prep.roi_min.x(), prep.roi_max.x()})
    for (float y : {prep.roi_min.y(), prep.roi_max.y()}) max_range = std::max(max_range, std::hypot(x, y));
  bins_ = static_cast<int>(std::ceil(max_range / params.range_bin_m)) + 1;
  pass_one_.ego = prep.remove_ego;
  for (int i = 0; i < 3; ++i) {
    pass_one_.roi_min[i] = prep.roi_min[i];
    pass_one_.roi_max[i] = prep.roi_max[i];
    pass_one_.ego_min[i] = prep.ego_min[i];
    pass_one_.ego_max[i] = prep.ego_max[i];
    pass_one_.ego = pass_one_.ego && prep.ego_min[i] < prep.ego_max[i];
  }
  pass_one_.inv_cell = inv_cell_;
  pass_one_.nx = nx_;
  pass_one_.ny = ny_;

  // The polar cell of every BEV cell, from the cell's centre: atan2 runs once here, never per
  // point.
  polar_of_cell_.resize(static_cast<std::size_t>(nx_) * ny_);
  for (int cy = 0; cy < ny_; ++cy) {
    for (int cx = 0; cx < nx_; ++cx) {
      const float x = prep.roi_min.x() + (cx + 0.5f) * params.cell_m;
      const float y = prep.roi_min.y() + (cy + 0.5f) * params.cell_m;
      const float a = std::atan2(y, x) + static_cast<float>(M_PI);  // [0, 2 pi]
      int sector = static_cast<int>(a / static_cast<float>(2.0 * M_PI) * params.sectors);
      sector = std::min(std::max(sector, 0), params.sectors - 1);
      const int bin = std::min(bins_ - 1, static_cast<int>(std::hypot(x, y) / params.range_bin_m));
      polar_of_cell_[static_cast<std::size_t>(cy) * nx_ + cx] = sector * bins_ + bin;
    }
  }
  // Forward half of the link window: each pair of linked cells is visited once.
  const float r = params.link_m / params.cell_m;
  const float r2 = std::max(2.0f, r * r) + 1e-3f;
  const int reach = static_cast<int>(std::ceil(std::sqrt(r2)));
  for (int dy = 0; dy <= reach; ++dy)
    for (int dx = -reach; dx <= reach; ++dx)
      if ((dy > 0 || dx > 0) && float(dx * dx + dy * dy) <= r2) forward_.emplace_back(dx, dy);

  polar_min_z_.assign(static_cast<std::size_t>(params.sectors) * bins_, kInf);
  polar_ground_.assign(polar_min_z_.size(), 0.0f);
  cell_min_z_.assign(polar_of_cell_.size(), kInf);
  cells_.resize(polar_of_cell_.size());
  cut_z_.assign(polar_of_cell_.size(), kInf);
}

std::size_t FastDetector::capacityBytes() const {
  return polar_of_cell_.capacity() * sizeof(std::int32_t) + points_.capacity() * sizeof(Kept) +
         (cell_min_z_.capacity() + polar_min_z_.capacity() + polar_ground_.capacity() +
          near_lows_.capacity() + cut_z_.capacity()) * sizeof(float) +
         (cut_cells_.capacity() + high_.capacity() + cluster_of_slot_.capacity() +
          dropped_.capacity()) * sizeof(std::int32_t) +
         cells_.capacity() * sizeof(Cell) +
         (occupied_.capacity() + parent_.capacity() + next_in_cluster_.capacity() +
          cluster_of_root_.capacity()) * sizeof(std::int32_t) +
         clusters_.capacity() * sizeof(Cluster) + footprint_.capacity() * sizeof(cv::Point2f) +
         first_root_.capacity() * sizeof(std::int32_t) + root_box_.capacity() * sizeof(root_box_[0]) +
         long_.capacity() + carved_.capacity() +
         (piece_root_.capacity() + rest_.capacity()) * sizeof(std::int32_t);
}

FastDetector::Kept* FastDetector::growPoints(std::size_t used) {
  kept_ = used;
  points_.resize(std::max<std::size_t>(4096, 2 * points_.size()));
  return points_.data();
}

void FastDetector::beginFrame() {
  kept_ = 0;
}

void FastDetector::detect(const Cloud& cloud, std::vector<Box3D>& boxes, FastStageTimes* times) {
  detectFrom(
      [&cloud](auto&& sink) {
        for (const Point& p : cloud.points) sink(p.x, p.y, p.z);
      },
      boxes, times);
}

void FastDetector::finishFrame(std::vector<Box3D>& boxes, FastStageTimes* times, double prep_ms) {
  const double t1 = fastNowMs();
  estimateGround();
  markObstacles();
  const double t2 = fastNowMs();
  clusterAndFit(boxes);
  const double t3 = fastNowMs();
  if (times) {
    times->prep_ms = prep_ms;
    times->ground_ms = t2 - t1;
    times->cluster_ms = t3 - t2;
  }
}

void FastDetector::estimateGround() {
  // Polar minimum from the BEV cells' minima, which are reset for the next frame on the way.
  std::fill(polar_min_z_.begin(), polar_min_z_.end(), kInf);
  for (std::size_t c = 0; c < cell_min_z_.size(); ++c) {
    float& lowest = polar_min_z_[static_cast<std::size_t>(polar_of_cell_[c])];
    lowest = std::min(lowest, cell_min_z_[c]);
    cell_min_z_[c] = kInf;
  }
  const int sectors = params_.sectors;
  const float bin = params_.range_bin_m;
  // Start height: the median of the lowest points of the bins nearer than 10 m (mostly road
  // around the vehicle); the ROI floor when there are none.
  const int near_bins = std::max(1, std::min(bins_, static_cast<int>(10.0f / bin)));
  near_lows_.clear();
  for (int s = 0; s < sectors; ++s) {
    for (int b = 0; b < near_bins; ++b) {
      const float z = polar_min_z_[static_cast<std::size_t>(s) * bins_ + b];
      if (z < kInf) near_lows_.push_back(z);
    }
  }
  float start = prep_.roi_min.z();
  if (!near_lows_.empty()) {
    auto mid = near_lows_.begin() + near_lows_.size() / 2;
    std::nth_element(near_lows_.begin(), mid, near_lows_.end());
    start = *mid;
  }
  initial_ground_z_ = start;

  const float tan_slope = std::tan(params_.max_slope_deg * static_cast<float>(M_PI / 180.0));
  for (int s = 0; s < sectors; ++s) {
    float ground = start, ground_r = 0.0f;
    const std::size_t base = static_cast<std::size_t>(s) * bins_;
    for (int b = 0; b < bins_; ++b) {
      const float r = (b + 0.5f) * bin;
      const float lowest = polar_min_z_[base + b];
      if (lowest < kInf) {
        const float allowed = tan_slope * (r - ground_r) + params_.ground_step_m;
        bool follow = std::abs(lowest - ground) <= allowed || lowest < ground;
        if (follow && lowest < ground - params_.ground_step_m) {
          // A drop beyond the step is followed (ground never stays above a real return) when
          // the next bin with returns stays nearer the new low than the old ground. One return
          // below the floor (multipath, a spurious range past the surface) is not confirmed:
          // following it made the floor around it an obstacle (pedestrian_far_away through the
          // fast path: boxes 0.01 m high over a ground of -0.3 m).
          for (int n = b + 1; n < bins_; ++n) {
            const float next = polar_min_z_[base + n];
            if (next == kInf) continue;
            follow = std::abs(next - lowest) < std::abs(next - ground);
            break;
          }
        }
        if (follow) {
          ground = lowest;
          ground_r = r;
        }
      }
      polar_ground_[base + b] = ground;
    }
  }
}

void FastDetector::addObstacle(const Kept& p) {
  ++obstacle_points_;
  Cell& c = cells_[p.cell];
  if (c.count == 0) {
    c.slot = static_cast<std::int32_t>(occupied_.size());
    occupied_.push_back(static_cast<std::int32_t>(p.cell));
    c.zmin = c.zmax = p.z;
    c.floor = -kInf;
    c.xmin_x = c.xmax_x = c.ymin_x = c.ymax_x = p.x;
    c.xmin_y = c.xmax_y = c.ymin_y = c.ymax_y = p.y;
  } else {
    c.zmin = std::min(c.zmin, p.z);
    c.zmax = std::max(c.zmax, p.z);
    if (p.x < c.xmin_x) { c.xmin_x = p.x; c.xmin_y = p.y; }
    if (p.x > c.xmax_x) { c.xmax_x = p.x; c.xmax_y = p.y; }
    if (p.y < c.ymin_y) { c.ymin_x = p.x; c.ymin_y = p.y; }
    if (p.y > c.ymax_y) { c.ymax_x = p.x; c.ymax_y = p.y; }
  }
  ++c.count;
}

void FastDetector::markObstacles() {
  occupied_.clear();
  obstacle_points_ = 0;
  for (std::int32_t cell : cut_cells_) cut_z_[static_cast<std::size_t>(cell)] = kInf;
  cut_cells_.clear();
  high_.clear();
  const float lo = params_.obstacle_height_m, hi = params_.max_height_m;
  const float gap = params_.overhang_gap_m;
  const float high = gap > 0.0f ? params_.overhang_min_height_m : kInf;
  for (std::size_t i = 0; i < kept_; ++i) {
    const Kept& p = points_[i];
    const float h = p.z - polar_ground_[static_cast<std::size_t>(polar_of_cell_[p.cell])];
    if (h < lo || h > hi) continue;
    if (h >= high) {
      high_.push_back(static_cast<std::uint32_t>(i));  // decided below, per cell
      continue;
    }
    addObstacle(p);
  }
  if (high_.empty()) return;
  // The high points of a cell that holds something lower are an overhang when the lowest of them
  // is at least `gap` above the top of what stands there (a roof over a pedestrian's head, a
  // canopy over a car); otherwise they are its top (a van, a wall, a tree) and join it. A cell of
  // high points only is kept: it is a floating cell, linked only to cells that reach up to it
  // (linkCells), and a cluster of floating cells only is no obstacle (clusterAndFit). Dropping
  // them here instead lost walls whose lower part a pedestrian hid from a low sensor
  // (indoor_cluttered_course: the wall split into fragments, false danger 7 -> 13).
  for (std::uint32_t i : high_) {
    const Kept& p = points_[i];
    float& cut = cut_z_[p.cell];
    if (cut == kInf) cut_cells_.push_back(static_cast<std::int32_t>(p.cell));
    cut = std::min(cut, p.z);
  }
  for (std::int32_t cell : cut_cells_) {
    const Cell& c = cells_[static_cast<std::size_t>(cell)];
    float& cut = cut_z_[static_cast<std::size_t>(cell)];
    if (c.count == 0 || cut - c.zmax < gap) cut = kInf;
  }
  for (std::uint32_t i : high_) {
    const Kept& p = points_[i];
    if (p.z < cut_z_[p.cell]) addObstacle(p);
  }
  // Floating cells: every point at least overhang_min_height_m up.
  for (std::int32_t cell : cut_cells_) {
    Cell& c = cells_[static_cast<std::size_t>(cell)];
    if (c.count > 0 &&
        c.zmin - polar_ground_[static_cast<std::size_t>(polar_of_cell_[cell])] >= high)
      c.floor = c.zmin;
  }
}

void FastDetector::splitPoints(Cloud& ground, Cloud& obstacles) const {
  ground.clear();
  obstacles.clear();
  const float lo = params_.obstacle_height_m, hi = params_.max_height_m;
  for (std::size_t i = 0; i < kept_; ++i) {
    const Kept& p = points_[i];
    const float h = p.z - polar_ground_[static_cast<std::size_t>(polar_of_cell_[p.cell])];
    if (h < lo)
      ground.push_back(Point(p.x, p.y, p.z));
    else if (h <= hi && p.z < cut_z_[p.cell])  // not an overhang
      obstacles.push_back(Point(p.x, p.y, p.z));
  }
}

std::int32_t FastDetector::find(std::int32_t k) {
  while (parent_[k] != k) {
    parent_[k] = parent_[parent_[k]];  // path halving
    k = parent_[k];
  }
  return k;
}

void FastDetector::linkCells(bool check_steps) {
  const std::int32_t n = static_cast<std::int32_t>(occupied_.size());
  parent_.resize(occupied_.size());
  std::iota(parent_.begin(), parent_.end(), 0);
  const float max_step = params_.link_max_step_m;
  const float gap = params_.overhang_gap_m;
  for (std::int32_t k = 0; k < n; ++k) {
    const int cell = occupied_[k];
    const int cx = cell % nx_, cy = cell / nx_;
    const Cell& here = cells_[cell];
    const bool check = check_steps && long_[first_root_[k]];
    for (const auto& d : forward_) {
      const int x = cx + d.first, y = cy + d.second;
      if (x < 0 || x >= nx_ || y >= ny_) continue;
      const Cell& other = cells_[static_cast<std::size_t>(y) * nx_ + x];
      if (other.count == 0) continue;
      if (check && std::abs(other.zmax - here.zmax) > max_step) continue;
      // A floating cell (floor > -inf) joins only what reaches up to within `gap` of it: a roof
      // does not join the pedestrian under it, a wall's top the wall.
      if (std::max(here.floor, other.floor) - std::min(here.zmax, other.zmax) >= gap) continue;
      const std::int32_t a = find(k), b = find(other.slot);
      if (a != b) parent_[std::max(a, b)] = std::min(a, b);
    }
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
      linkCells(true);
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

  clusters_.clear();
  cluster_of_root_.assign(occupied_.size(), -1);
  next_in_cluster_.resize(occupied_.size());
  cluster_of_slot_.resize(occupied_.size());
  for (std::int32_t k = 0; k < n; ++k) {
    const std::int32_t root = find(k);
    if (cluster_of_root_[root] < 0) {
      cluster_of_root_[root] = static_cast<std::int32_t>(clusters_.size());
      Cluster c;
      c.zmin = c.xmin = c.ymin = kInf;
      c.zmax = c.xmax = c.ymax = -kInf;
      clusters_.push_back(c);
    }
    Cluster& c = clusters_[cluster_of_root_[root]];
    const Cell& cell = cells_[occupied_[k]];
    c.count += cell.count;
    c.grounded = c.grounded || cell.floor == -kInf;
    c.zmin = std::min(c.zmin, cell.zmin);
    c.zmax = std::max(c.zmax, cell.zmax);
    next_in_cluster_[k] = c.first_cell;
    c.first_cell = k;
    ++c.cells;
    cluster_of_slot_[k] = cluster_of_root_[root];
  }
  if (params_.grazing_reach_m > 0.0f) dropGrazingColumns();

  for (const Cluster& c : clusters_) {
    if (c.cells == 0) continue;  // a column of a surface at grazing incidence (dropGrazingColumns)
    if (c.count < params_.min_points || c.count > params_.max_points) continue;
    if (!c.grounded) continue;  // floating cells only: an overhang (a canopy over the road)
    footprint_.clear();
    for (std::int32_t k = c.first_cell; k >= 0; k = next_in_cluster_[k]) {
      const Cell& cell = cells_[occupied_[k]];
      footprint_.emplace_back(cell.xmin_x, cell.xmin_y);
      footprint_.emplace_back(cell.xmax_x, cell.xmax_y);
      footprint_.emplace_back(cell.ymin_x, cell.ymin_y);
      footprint_.emplace_back(cell.ymax_x, cell.ymax_y);
    }
    boxes.push_back(fitBoxFootprint(footprint_, c.zmin, c.zmax, c.count, footprint_cell_m_));
  }
  std::stable_sort(boxes.begin(), boxes.end(),
                   [](const Box3D& a, const Box3D& b) { return a.num_points > b.num_points; });

  for (std::int32_t cell : occupied_) cells_[cell].count = 0;  // ready for the next frame
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
  const float sin_max = std::sin(params_.grazing_angle_deg * static_cast<float>(M_PI / 180.0));
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
      const Cell& cell = cells_[occupied_[k]];
      sx += cell.xmin_x + cell.xmax_x + cell.ymin_x + cell.ymax_x;
      sy += cell.xmin_y + cell.xmax_y + cell.ymin_y + cell.ymax_y;
    }
    const float cx = sx / (4.0f * t.cells), cy = sy / (4.0f * t.cells);
    const float r = std::hypot(cx, cy);
    if (r < params_.cell_m) continue;
    const float ux = cx / r, uy = cy / r;  // line of sight (from the grid's origin)
    float lo = kInf, hi = -kInf;           // its points across the line of sight
    for (std::int32_t k = t.first_cell; k >= 0; k = next_in_cluster_[k]) {
      const Cell& cell = cells_[occupied_[k]];
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
        const Cell& other = cells_[static_cast<std::size_t>(y) * nx_ + x];
        if (other.count == 0 || other.floor != -kInf) continue;
        const std::int32_t oc = cluster_of_slot_[other.slot];
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

float FastDetector::groundAt(float x, float y) const {
  if (!(x >= prep_.roi_min.x() && x <= prep_.roi_max.x() && y >= prep_.roi_min.y() &&
        y <= prep_.roi_max.y()))
    return std::numeric_limits<float>::quiet_NaN();
  const int cx = std::min(nx_ - 1, static_cast<int>((x - prep_.roi_min.x()) * inv_cell_));
  const int cy = std::min(ny_ - 1, static_cast<int>((y - prep_.roi_min.y()) * inv_cell_));
  return polar_ground_[static_cast<std::size_t>(polar_of_cell_[static_cast<std::size_t>(cy) * nx_ + cx])];
}

}  // namespace icanc
