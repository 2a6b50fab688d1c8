#include "icanc/core/perception/fast_detector.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace icanc {

namespace {
constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr float kDeg = static_cast<float>(M_PI / 180.0);
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
  } else if (!(p.link_gap_m >= 0.0f && p.link_gap_m <= 10.0f)) {
    why << "fast.link_gap_m must be in [0, 10] (got " << p.link_gap_m << ")";
  } else if (!(p.link_gap_max_extent_m > 0.0f && p.link_gap_max_extent_m <= 1000.0f)) {
    why << "fast.link_gap_max_extent_m must be in (0, 1000] (got " << p.link_gap_max_extent_m
        << ")";
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
         long_.capacity() + carved_.capacity() + gap_small_.capacity() +
         (piece_root_.capacity() + rest_.capacity() + gap_root_.capacity()) * sizeof(std::int32_t) +
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

float FastDetector::groundAt(float x, float y) const {
  if (!(x >= prep_.roi_min.x() && x <= prep_.roi_max.x() && y >= prep_.roi_min.y() &&
        y <= prep_.roi_max.y()))
    return std::numeric_limits<float>::quiet_NaN();
  const int cx = std::min(nx_ - 1, static_cast<int>((x - prep_.roi_min.x()) * inv_cell_));
  const int cy = std::min(ny_ - 1, static_cast<int>((y - prep_.roi_min.y()) * inv_cell_));
  return polar_ground_[static_cast<std::size_t>(polar_of_cell_[static_cast<std::size_t>(cy) * nx_ + cx])];
}

}  // namespace icanc
