#include "icanc/core/perception/fast_detector.hpp"

#include <algorithm>
#include <cstddef>
#include <cstring>
#include <limits>
#include <numeric>
#include <sstream>
#include <stdexcept>

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
  } else if (!(p.link_step_beams >= 0.0f && p.link_step_beams <= 5.0f)) {
    why << "fast.link_step_beams must be in [0, 5] (got " << p.link_step_beams << ")";
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
  } else if (!(p.range_split_angle_deg >= 0.0f && p.range_split_angle_deg < 90.0f)) {
    why << "fast.range_split_angle_deg must be in [0, 90) (got " << p.range_split_angle_deg << ")";
  } else if (!(p.range_split_vertical_angle_deg >= 0.0f && p.range_split_vertical_angle_deg < 90.0f)) {
    why << "fast.range_split_vertical_angle_deg must be in [0, 90) (got "
        << p.range_split_vertical_angle_deg << ")";
  } else if (!(p.range_split_min_extent_m >= 0.0f && p.range_split_min_extent_m <= 1000.0f)) {
    why << "fast.range_split_min_extent_m must be in [0, 1000] (got "
        << p.range_split_min_extent_m << ")";
  } else if (!(p.range_piece_max_m > 0.0f && p.range_piece_max_m <= 100.0f)) {
    why << "fast.range_piece_max_m must be in (0, 100] (got " << p.range_piece_max_m << ")";
  } else if (!(p.range_piece_max_width_m > 0.0f && p.range_piece_max_width_m <= 100.0f)) {
    why << "fast.range_piece_max_width_m must be in (0, 100] (got " << p.range_piece_max_width_m
        << ")";
  } else if (!(p.range_piece_min_height_m >= 0.0f && p.range_piece_min_height_m <= 5.0f)) {
    why << "fast.range_piece_min_height_m must be in [0, 5] (got " << p.range_piece_min_height_m
        << ")";
  } else if (!(p.range_piece_foreground >= 0.0f && p.range_piece_foreground <= 1.0f)) {
    why << "fast.range_piece_foreground must be in [0, 1] (got " << p.range_piece_foreground
        << ")";
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
  bool ego = prep.remove_ego;
  for (int i = 0; i < 3; ++i) ego = ego && prep.ego_min[i] < prep.ego_max[i];
  for (int i = 0; i < 4; ++i) {
    const int axis = std::min(i, 2);  // the fourth lane repeats z
    pass_one_.roi_min[i] = prep.roi_min[axis];
    pass_one_.roi_max[i] = prep.roi_max[axis];
    pass_one_.ego_min[i] = ego ? prep.ego_min[axis] : kInf;  // no ego box: nothing is inside
    pass_one_.ego_max[i] = ego ? prep.ego_max[axis] : -kInf;
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
  cell_slot_.assign(polar_of_cell_.size(), -1);
  cut_z_.assign(polar_of_cell_.size(), kInf);
  cos_split_ = std::cos(params.range_split_angle_deg * kDeg);
  cos_split_vertical_ = std::cos(params.range_split_vertical_angle_deg * kDeg);
}

std::size_t FastDetector::capacityBytes() const {
  return polar_of_cell_.capacity() * sizeof(std::int32_t) + points_.capacity() * sizeof(Kept) +
         (cell_min_z_.capacity() + polar_min_z_.capacity() + polar_ground_.capacity() +
          near_lows_.capacity() + cut_z_.capacity()) * sizeof(float) +
         (cut_cells_.capacity() + high_.capacity() + cluster_of_slot_.capacity() +
          dropped_.capacity()) * sizeof(std::int32_t) +
         cells_.capacity() * sizeof(Cell) + cell_slot_.capacity() * sizeof(std::int32_t) +
         (occupied_.capacity() + parent_.capacity() + next_in_cluster_.capacity() +
          cluster_of_root_.capacity()) * sizeof(std::int32_t) +
         clusters_.capacity() * sizeof(Cluster) + footprint_.capacity() * sizeof(cv::Point2f) +
         first_root_.capacity() * sizeof(std::int32_t) + root_box_.capacity() * sizeof(root_box_[0]) +
         long_.capacity() + carved_.capacity() +
         (piece_root_.capacity() + rest_.capacity()) * sizeof(std::int32_t) +
         obstacle_index_.capacity() * sizeof(std::uint32_t) +
         (ray_begin_.capacity() + pixel_ray_.capacity() +
          pixel_parent_.capacity()) * sizeof(std::int32_t) +
         rays_.capacity() * sizeof(Ray) + broken_.capacity() * sizeof(broken_[0]) +
         steps_.capacity() * sizeof(steps_[0]) + diffs_.capacity() * sizeof(float) +
         pieces_.capacity() * sizeof(Piece) + cell_carved_.capacity();
}

FastDetector::Kept* FastDetector::growPoints(std::size_t used) {
  kept_ = used;
  points_.resize(std::max<std::size_t>(4096, 2 * points_.size()));
  return points_.data();
}

void FastDetector::beginFrame() {
  kept_ = 0;
  if (steps_age_ < kStepsEveryFrames) ++steps_age_;  // saturates: only "due or not" is read
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
  std::int32_t& slot = cell_slot_[p.cell];
  if (slot < 0) {
    slot = static_cast<std::int32_t>(occupied_.size());
    occupied_.push_back(static_cast<std::int32_t>(p.cell));
    cells_.emplace_back();
    Cell& c = cells_.back();
    c.count = 1;
    c.zmin = c.zmax = p.z;
    c.floor = -kInf;
    c.xmin_x = c.xmax_x = c.ymin_x = c.ymax_x = p.x;
    c.xmin_y = c.xmax_y = c.ymin_y = c.ymax_y = p.y;
    return;
  }
  Cell& c = cells_[static_cast<std::size_t>(slot)];
  c.zmin = std::min(c.zmin, p.z);
  c.zmax = std::max(c.zmax, p.z);
  // Each extreme point as one 8-byte (x, y) word, taken or kept by a conditional move: which
  // point of a cell is the extreme one follows no pattern a branch predictor learns.
  static_assert(offsetof(Kept, y) == offsetof(Kept, x) + sizeof(float) &&
                    offsetof(Cell, xmin_y) == offsetof(Cell, xmin_x) + sizeof(float) &&
                    offsetof(Cell, xmax_y) == offsetof(Cell, xmax_x) + sizeof(float) &&
                    offsetof(Cell, ymin_y) == offsetof(Cell, ymin_x) + sizeof(float) &&
                    offsetof(Cell, ymax_y) == offsetof(Cell, ymax_x) + sizeof(float),
                "an extreme point's x and y are one 8-byte word");
  std::uint64_t xy;
  std::memcpy(&xy, &p.x, sizeof xy);
  const auto take = [xy](float* pair, bool better) ICANC_ALWAYS_INLINE {
    std::uint64_t old;
    std::memcpy(&old, pair, sizeof old);
    const std::uint64_t now = better ? xy : old;
    std::memcpy(pair, &now, sizeof now);
  };
  take(&c.xmin_x, p.x < c.xmin_x);
  take(&c.xmax_x, p.x > c.xmax_x);
  take(&c.ymin_x, p.y < c.ymin_y);
  take(&c.ymax_x, p.y > c.ymax_y);
  ++c.count;
}

void FastDetector::markObstacles() {
  for (std::int32_t cell : occupied_) cell_slot_[static_cast<std::size_t>(cell)] = -1;
  occupied_.clear();
  cells_.clear();
  obstacle_points_ = 0;
  obstacle_index_.clear();
  const bool record = params_.range_split_angle_deg > 0.0f || params_.link_step_beams > 0.0f;
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
    if (record) obstacle_index_.push_back(static_cast<std::uint32_t>(i));
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
    const std::int32_t slot = cell_slot_[static_cast<std::size_t>(cell)];
    float& cut = cut_z_[static_cast<std::size_t>(cell)];
    if (slot < 0 || cut - cells_[static_cast<std::size_t>(slot)].zmax < gap) cut = kInf;
  }
  for (std::uint32_t i : high_) {
    const Kept& p = points_[i];
    if (p.z < cut_z_[p.cell]) {
      addObstacle(p);
      if (record) obstacle_index_.push_back(i);
    }
  }
  // Floating cells: every point at least overhang_min_height_m up.
  for (std::int32_t cell : cut_cells_) {
    const std::int32_t slot = cell_slot_[static_cast<std::size_t>(cell)];
    if (slot < 0) continue;
    Cell& c = cells_[static_cast<std::size_t>(slot)];
    if (c.zmin - polar_ground_[static_cast<std::size_t>(polar_of_cell_[cell])] >= high)
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

void FastDetector::linkCells(bool check_steps, float step_tan) {
  const std::int32_t n = static_cast<std::int32_t>(occupied_.size());
  parent_.resize(occupied_.size());
  std::iota(parent_.begin(), parent_.end(), 0);
  const float gap = params_.overhang_gap_m;
  for (std::int32_t k = 0; k < n; ++k) {
    const int cell = occupied_[k];
    const int cx = cell % nx_, cy = cell / nx_;
    const Cell& here = cells_[static_cast<std::size_t>(k)];
    const bool check = check_steps && long_[first_root_[k]];
    float max_step = params_.link_max_step_m;
    if (check && step_tan > 0.0f) {  // one beam spacing at this cell's range from the sensor
      const float range = std::hypot(prep_.roi_min.x() + (cx + 0.5f) * params_.cell_m - sensor_origin_.x(),
                                     prep_.roi_min.y() + (cy + 0.5f) * params_.cell_m - sensor_origin_.y());
      max_step = std::max(max_step, range * step_tan);
    }
    for (const auto& d : forward_) {
      const int x = cx + d.first, y = cy + d.second;
      if (x < 0 || x >= nx_ || y >= ny_) continue;
      const std::int32_t slot = cell_slot_[static_cast<std::size_t>(y) * nx_ + x];
      if (slot < 0) continue;
      const Cell& other = cells_[static_cast<std::size_t>(slot)];
      if (check && std::abs(other.zmax - here.zmax) > max_step) continue;
      // A floating cell (floor > -inf) joins only what reaches up to within `gap` of it: a roof
      // does not join the pedestrian under it, a wall's top the wall.
      if (std::max(here.floor, other.floor) - std::min(here.zmax, other.zmax) >= gap) continue;
      const std::int32_t a = find(k), b = find(slot);
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

float FastDetector::groundAt(float x, float y) const {
  if (!(x >= prep_.roi_min.x() && x <= prep_.roi_max.x() && y >= prep_.roi_min.y() &&
        y <= prep_.roi_max.y()))
    return std::numeric_limits<float>::quiet_NaN();
  const int cx = std::min(nx_ - 1, static_cast<int>((x - prep_.roi_min.x()) * inv_cell_));
  const int cy = std::min(ny_ - 1, static_cast<int>((y - prep_.roi_min.y()) * inv_cell_));
  return polar_ground_[static_cast<std::size_t>(polar_of_cell_[static_cast<std::size_t>(cy) * nx_ + cx])];
}

}  // namespace icanc
