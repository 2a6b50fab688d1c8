// The fast obstacle-detection path (detector.method "fast"), next to the paper's PCL chain:
//
//  1. one pass over the points: drop non-finite / zero / outside the ROI / inside the ego box,
//     then give each point its cell of a bird's-eye-view grid (cell_m). A table computed once
//     per parameter set maps every BEV cell to a polar cell (sector x range bin), so no atan2
//     runs per point; the lowest z of each BEV cell is kept, and reduced to its polar cell after
//     the pass.
//  2. ground that follows slopes: per sector, from the nearest range bin outward, a bin's lowest
//     point is ground when its height step from the previous ground bin is within
//     max_slope_deg (plus ground_step_m), or when it is lower (a drop of more than ground_step_m
//     only when the next bin with returns confirms it, so one return below the floor does not
//     drag the ground down); otherwise the previous ground height carries on. A point is an
//     obstacle when it lies obstacle_height_m .. max_height_m above its cell's ground. Overhangs:
//     points at least overhang_min_height_m up at least overhang_gap_m above the top of what
//     stands lower in their BEV cell are dropped; a cell whose points are all that high is
//     floating: it links only to cells reaching up to within overhang_gap_m of it, and a cluster
//     of floating cells only is no obstacle. A shelter roof then joins the wall that carries it
//     but not the pedestrian under it; a canopy over an empty road is no obstacle.
//  3. obstacles: connected components (cells within link_m) of the occupied BEV cells (union-find
//     over the occupied cells only); a component longer than step_check_min_extent_m (a wall, a
//     hedge, and what stands against it) is linked again only between cells whose highest points
//     differ by at most link_max_step_m (or, with link_step_beams, by the sensor's beam spacing
//     at their range, measured from the returns: where a sparse scan's top beam leaves a wall's
//     top), and the small pieces that gives (at most
//     step_piece_max_m across: a pedestrian, a pole) come apart from the rest; with link_gap_m
//     (the Zebra profile), inside components at most link_gap_max_extent_m across cells link only
//     where the bounds of their points come within link_gap_m (two walkers side by side, 0.3 m
//     apart, fall into touching cells); cluster size
//     limits on points, one box per cluster from its footprint (fitBoxFootprint, shared with the
//     classic chain). Surfaces seen at grazing incidence (a parked car's side): the scan's columns
//     land further apart on them than link_m, a cluster each, at bearings fixed to the sensor; a
//     cluster that is one line of sight is no box when a cluster of its height continues its
//     surface nearly along that line (grazing_reach_m, grazing_angle_deg), so no box stays where a
//     column is while the vehicle drives past.
//  4. optionally (range_split_angle_deg > 0: the KITTI profile; off in the Zebra's and the
//     Model 3's, docs/experiments.md), the
//     range-image split of large components: the angle criterion of Bogoslavskyi & Stachniss
//     between neighbouring returns by azimuth and elevation from the sensor (setSensorOrigin);
//     pedestrian-sized segments in front of what they border on become their own obstacles.
//
// The beam (ring) of a point is never needed, so organized and unorganized clouds, with or
// without a ring field, go through the same code. Every buffer lives in the FastDetector and is
// reused: after the first frames of a given size nothing is allocated per frame.
//
// Code: steps 1-2 in src/core/perception/fast_detector.cpp, 3 in fast_clusters.cpp, 4 (and the
// beam spacing step 3 reads) in range_split.cpp.
#pragma once

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include <opencv2/core/types.hpp>

#include "icanc/core/common/always_inline.hpp"
#include "icanc/core/perception/box.hpp"
#include "icanc/core/perception/cloud_prep.hpp"
#include "icanc/core/common/types.hpp"

namespace icanc {

struct FastDetectorParams {
  float cell_m = 0.25f;             // BEV grid cell [m]
  float link_m = 0.5f;              // occupied cells whose centres are this close (and always
                                    // the 8 neighbours) belong to one obstacle [m]; inside a
                                    // component longer than step_check_min_extent_m only ...
  float link_max_step_m = 0.3f;     // ... when their highest points differ by at most this: a
                                    // pedestrian (1.7 m) against a hedge or wall (2.3 m) stays
                                    // apart; 0: no height check [m]
  float step_check_min_extent_m = 30.0f;  // shorter components are not checked: 12 m found more
                                    // pedestrians but raised false danger (docs/performance.md) [m]
  float step_piece_max_m = 1.0f;    // of the pieces the check makes, those at most this across
                                    // come apart; the rest of the component stays one [m]
  float link_step_beams = 1.25f;    // > 0: the check lets the tops of neighbouring cells at range
                                    // r from the sensor differ by r * tan(this many of the sensor's
                                    // vertical beam spacings) when that is more than
                                    // link_max_step_m. On a sparse scan the top beam on a long
                                    // surface leaves its top edge (or the ROI's top) at fixed
                                    // ranges, where the seen top drops by one spacing (0.35 m at
                                    // 10 m on a 16-beam unit): the check cut a wall there into
                                    // pieces that stay with the vehicle. The spacing is measured
                                    // from the returns as the range split does; 0: off
  int sectors = 180;                // polar ground grid: angular sectors over 360 deg
  float range_bin_m = 1.0f;         // polar ground grid: radial bin [m]
  float max_slope_deg = 10.0f;      // ground may rise or fall this steeply between bins
  float ground_step_m = 0.15f;      // plus this step (kerbs, noise) [m]
  float obstacle_height_m = 0.3f;   // a point this far above its ground is an obstacle [m]
  float max_height_m = 3.0f;        // ... up to this height (branches, bridges above) [m]
  float overhang_gap_m = 0.3f;      // points at least overhang_min_height_m above their ground
                                    // this far above what stands lower in their cell are an
                                    // overhang (a shelter roof, a canopy), dropped; cells of such
                                    // points only join cells reaching up to within this, and
                                    // alone are no obstacle; 0: off [m]
  float overhang_min_height_m = 2.3f;  // overhangs start this high: below, a gap between rows of
                                    // a sparse scan on a pedestrian never counts [m]
  float grazing_reach_m = 2.5f;     // a cluster that is one line of sight (its points within
                                    // cell_m / 2 across it: one column of the scan, e.g. on a car's
                                    // side seen at grazing incidence) is no box when a cluster this
                                    // close nearly along that line of sight (grazing_angle_deg),
                                    // its top within link_max_step_m of its own, continues its
                                    // surface; 0: off [m]
  float grazing_angle_deg = 20.0f;  // ... at most this far off the line of sight [deg]
  // Point-gap link: > 0: inside components at most link_gap_max_extent_m
  // across (a pedestrian, a pair of them, a pole and its walker), neighbouring cells link only
  // when the bounds of their points come within this: two walkers 0.3 m apart whose points fall
  // into touching cells come apart. 0: off [m].
  float link_gap_m = 0.0f;
  float link_gap_max_extent_m = 2.0f;  // larger components keep their links: on every component
                                       // the gap cut KITTI's cars at their glass [m]
  int min_points = 10;              // points per obstacle (raw cloud, no voxel grid)
  int max_points = 20000;
  // Range-image split (Bogoslavskyi & Stachniss's angle criterion): the points
  // of a component at least range_split_min_extent_m across are laid out by azimuth (column) and
  // elevation (row) as seen from the sensor; two neighbouring returns belong to one surface when
  // the angle at the farther one between its beam and the line to the nearer exceeds
  // range_split_angle_deg. Of the segments that gives, those no more than range_piece_max_m
  // across (from above) and range_piece_max_width_m wide across the line of sight (a car's
  // rear, 1.8 m, stays with its roof and sides), range_piece_min_height_m tall or more, and in
  // front of what they border on side by side (nearer on at least range_piece_foreground of the
  // pairs of neighbours in azimuth that are apart, or none: a gap) become their own obstacles;
  // the rest of the component stays one. 0: off.
  float range_split_angle_deg = 0.0f;
  // ... between returns of neighbouring beams (rows, and diagonal neighbours) this angle: beams
  // 1-2 deg apart see a pedestrian's head and the wall 0.9 m behind it at 18-25 deg, which
  // range_split_angle_deg would call one surface; a vertical surface is 65-90 deg [deg].
  float range_split_vertical_angle_deg = 45.0f;
  float range_split_min_extent_m = 1.0f;  // [m]
  float range_piece_max_m = 2.0f;         // [m]
  float range_piece_max_width_m = 1.2f;   // [m]
  float range_piece_min_height_m = 0.8f;  // [m]
  float range_piece_foreground = 0.8f;    // [0, 1]
};

std::string validate(const FastDetectorParams& params);

struct FastStageTimes {
  double prep_ms = 0.0;     // pass 1: filter, BEV cell, polar minimum
  double ground_ms = 0.0;   // ground per polar cell + obstacle points into the BEV grid
  double cluster_ms = 0.0;  // connected components + boxes
};

class FastDetector {
 public:
  // `prep` gives the ROI and ego box (its voxel grid is not used: the BEV grid replaces it).
  // Throws std::invalid_argument when either parameter set is invalid.
  // footprint_cell_m > 0: each box carries its footprint cells (Box3D::footprint).
  FastDetector(const CloudPrepParams& prep, const FastDetectorParams& params,
               float footprint_cell_m = 0.0f);

  // One frame, already in the vehicle frame. Boxes are largest cluster first.
  void detect(const Cloud& cloud, std::vector<Box3D>& boxes, FastStageTimes* times = nullptr);

  // Same, reading points through a callable `source(sink)` that calls sink(x, y, z) for every
  // point: lets a decoder feed pass 1 directly, without an intermediate cloud.
  template <class Source>
  void detectFrom(Source&& source, std::vector<Box3D>& boxes, FastStageTimes* times = nullptr);

  // Where the sensor is in the frame the points are given in (range split only: rows and columns
  // are elevation and azimuth from here; the sensor's own tilt is not corrected). Default: origin.
  void setSensorOrigin(const Eigen::Vector3f& origin) { sensor_origin_ = origin; }
  // Angular steps [deg] the range split measured (on the last frame that could tell; 0: none).
  // They are the sensor's: once known, measured again only every kStepsEveryFrames frames (1 s
  // at 10 Hz; the estimate sorts the rays twice, a cost not worth paying every frame).
  static constexpr int kStepsEveryFrames = 10;
  float rangeColumnDeg() const { return range_col_deg_; }
  float rangeRowDeg() const { return range_row_deg_; }

  // Ground height [m] the last frame estimated under (x, y); NaN outside the grid.
  float groundAt(float x, float y) const;
  std::size_t keptPoints() const { return kept_; }
  std::size_t obstaclePoints() const { return obstacle_points_; }
  // The last frame's kept points split by their height above the ground under them: `ground`
  // below obstacle_height_m, `obstacles` obstacle_height_m .. max_height_m (what the clusters are
  // made of); points higher up, and overhangs, are in neither. Both are cleared first. Built only
  // when called (debug clouds): detect() does none of this work.
  void splitPoints(Cloud& ground, Cloud& obstacles) const;

  // Bytes held by the reusable buffers (capacities): stable in steady state.
  std::size_t capacityBytes() const;

 private:
  struct Kept {
    float x, y, z;
    std::uint32_t cell;
  };
  struct Cell {  // accumulator of an occupied BEV cell (cells_[slot], occupied_[slot] its cell)
    std::int32_t count = 0;
    float zmin, zmax;
    float floor;             // zmin when every point is overhang_min_height_m up, else -inf
    float xmin_x, xmin_y, xmax_x, xmax_y, ymin_x, ymin_y, ymax_x, ymax_y;  // extreme points
  };
  struct Cluster {
    std::int32_t count = 0;
    std::int32_t cells = 0;  // 0: dropped (dropGrazingColumns)
    bool grounded = false;  // holds a cell that is not floating
    float zmin, zmax;
    std::int32_t first_cell = -1;  // linked list of its cells through next_in_cluster_
    bool split = false;            // boxed by rangeSplit
  };
  struct Ray {  // an obstacle point of a cluster the range split looks at
    float x, y, z;      // from the sensor [m]
    float range2;       // squared range
    float az, el;       // [rad]; az relative to the cluster's first ray
    std::uint32_t point;  // index into points_
    std::int32_t col, row;  // in the cluster's range image
    std::int32_t pixel;     // its pixel; after linking, its piece (a ray index)
  };

  // What pass 1 reads per point, copied into a local of detectFrom: the stores into points_ then
  // cannot alias it, so the compiler keeps the bounds in registers instead of reloading them
  // after every point.
  // Each box as four lanes (x, y, z, z again); without an ego box, an empty one (+inf .. -inf).
  struct PassOne {
    alignas(16) float roi_min[4];
    alignas(16) float roi_max[4];
    alignas(16) float ego_min[4];
    alignas(16) float ego_max[4];
    float inv_cell;
    int nx, ny;
  };
  Kept* growPoints(std::size_t used);  // cold path of pass 1: doubles points_, returns its data
  void beginFrame();
  void finishFrame(std::vector<Box3D>& boxes, FastStageTimes* times, double prep_ms);
  void estimateGround();
  void markObstacles();
  inline void addObstacle(const Kept& p);  // into its BEV cell's accumulator
  // Union-find over occupied_ into parent_; with check_steps, tops may differ by
  // max(link_max_step_m, range * step_tan) inside long components.
  void linkCells(bool check_steps, float step_tan = 0.0f);
  // Unites slot k with each occupied neighbour of the forward half window for which
  // links(neighbour slot) holds (the one neighbour walk of linkCells and splitByGaps).
  template <class Links>
  void linkForward(std::int32_t k, const Links& links);
  // Each slot's root into root_of, each root's cell bounds into root_box_.
  void boundComponents(std::vector<std::int32_t>& root_of);
  // Relinks the cells of the components at most link_gap_max_extent_m across by the gap between
  // their points' bounds (link_gap_m): parent_ in, parent_ out.
  void splitByGaps();
  void clusterAndFit(std::vector<Box3D>& boxes);
  // A cell's extreme points into a footprint, each distinct one once (a cell of one return gives
  // one point, not four: the same hull and footprint cells, less to sort and bin).
  static void appendExtremes(const Cell& cell, std::vector<cv::Point2f>& out);
  // Drops clusters that are one line of sight on a surface another cluster continues (grazing).
  void dropGrazingColumns();
  std::int32_t find(std::int32_t k);
  // Range split of the clusters at least range_split_min_extent_m across: boxes of the split
  // ones into `boxes`, each split cluster's `split` flag set (clusterAndFit boxes the others).
  void rangeSplit(std::vector<Box3D>& boxes);
  Ray rayOf(std::uint32_t point) const;  // points_[point] seen from the sensor origin
  // From one cluster's rays; false when neither this frame nor an earlier one could tell.
  bool estimateRangeSteps(std::size_t begin, std::size_t end);
  // tan(link_step_beams beam spacings) from the rays of the component with the most points of the
  // first linking (first_root_); 0 when the spacing is unknown.
  float beamStepTangent();
  void splitCluster(std::size_t cluster, std::size_t begin, std::size_t end,
                    std::vector<Box3D>& boxes);

  CloudPrepParams prep_;
  FastDetectorParams params_;
  float footprint_cell_m_ = 0.0f;
  PassOne pass_one_{};
  int nx_ = 0, ny_ = 0, bins_ = 0;
  float inv_cell_ = 0.0f;
  float initial_ground_z_ = 0.0f;

  std::vector<std::int32_t> polar_of_cell_;  // BEV cell -> polar cell (sector * bins_ + bin)
  // Storage of pass 1: the first kept_ entries are this frame's points. Pass 1 writes each field
  // in place through a pointer; push_back of a temporary stalled store forwarding (a 16-byte
  // load right after four 4-byte stores), and at -O2 emplace_back stayed a call per point.
  std::vector<Kept> points_;
  std::size_t kept_ = 0;
  std::vector<float> cell_min_z_;             // lowest z per BEV cell, +inf when empty
  std::vector<float> polar_min_z_;
  std::vector<float> polar_ground_;
  std::vector<float> near_lows_;             // scratch: lowest z of the bins near the vehicle
  // Per BEV cell: its slot in occupied_ and cells_ this frame, -1 when empty (reset through
  // occupied_ at the next frame's start). The accumulators live only per occupied cell: a dense
  // grid of them (56 bytes a cell, 2.5 MB on the KITTI profile's grid) made every obstacle point a
  // cache miss in markObstacles.
  std::vector<std::int32_t> cell_slot_;
  std::vector<Cell> cells_;  // per slot
  // Per BEV cell: points at or above this z are an overhang (+inf: none). Set for the cells in
  // cut_cells_, which the next frame resets; read again by splitPoints.
  std::vector<float> cut_z_;
  std::vector<std::int32_t> cut_cells_;
  std::vector<std::uint32_t> high_;          // scratch: points overhang_min_height_m up or more
  std::vector<std::int32_t> occupied_;       // occupied BEV cells this frame
  std::vector<std::int32_t> parent_;         // union-find over occupied_ slots
  std::vector<std::int32_t> next_in_cluster_;
  std::vector<std::int32_t> cluster_of_root_;
  std::vector<Cluster> clusters_;
  std::vector<std::int32_t> cluster_of_slot_;  // cluster of each occupied slot
  std::vector<std::int32_t> dropped_;          // scratch: clusters dropGrazingColumns drops
  std::vector<std::int32_t> first_root_;     // root of each slot after linking without steps
  std::vector<std::array<int, 4>> root_box_;  // per root: cell bounds x0 y0 x1 y1
  std::vector<std::uint8_t> long_;           // per root: longer than step_check_min_extent_m
  std::vector<std::int32_t> piece_root_;     // root of each slot after linking with steps
  std::vector<std::int32_t> rest_;           // per first root: a slot of what is not carved out
  std::vector<std::uint8_t> carved_;         // per slot: in a small piece of a long component
  std::vector<std::int32_t> gap_root_;       // root of each slot before splitByGaps
  std::vector<std::uint8_t> gap_small_;      // per slot: in a component splitByGaps relinks
  std::vector<cv::Point2f> footprint_;
  std::vector<std::pair<int, int>> forward_;  // neighbour offsets linked "forward" (half window)
  std::size_t obstacle_points_ = 0;
  // Range split (off: none of these is touched).
  Eigen::Vector3f sensor_origin_ = Eigen::Vector3f::Zero();
  float cos_split_ = 1.0f, cos_split_vertical_ = 1.0f;
  float range_col_deg_ = 0.0f, range_row_deg_ = 0.0f;
  int steps_age_ = 0;  // frames since the steps were last measured, counted up to kStepsEveryFrames
  bool stepsKnown() const { return range_col_deg_ > 0.0f && range_row_deg_ > 0.0f; }
  bool stepsDue() const { return !stepsKnown() || steps_age_ >= kStepsEveryFrames; }
  std::vector<std::uint32_t> obstacle_index_;   // this frame's obstacle points (into points_)
  std::vector<std::int32_t> ray_begin_;         // per cluster: its rays in rays_ (counting sort)
  std::vector<Ray> rays_;
  std::vector<std::int32_t> pixel_ray_;         // range image: nearest ray per pixel, -1 empty
  std::vector<std::int32_t> pixel_parent_;      // union-find over the pixels
  std::vector<std::array<std::int32_t, 2>> broken_;  // neighbour pixels apart: {nearer, farther}
  std::vector<std::array<float, 2>> steps_;     // scratch: (key, value) to estimate the steps
  std::vector<float> diffs_;
  struct Piece {
    std::int32_t count = 0, nearer = 0, farther = 0;
    float xmin, xmax, ymin, ymax, zmin, zmax;
    float colmin, colmax, range2;  // its columns, its nearest squared range
    bool carved = false;
    std::int32_t box = -1;         // carved: its number among the carved pieces
  };
  std::vector<Piece> pieces_;                   // per pixel root
  std::vector<std::uint8_t> cell_carved_;       // per slot: holds a carved point
};

inline double fastNowMs() {
  return std::chrono::duration<double, std::milli>(
             std::chrono::steady_clock::now().time_since_epoch()).count();
}

template <class Source>
void FastDetector::detectFrom(Source&& source, std::vector<Box3D>& boxes, FastStageTimes* times) {
  const auto t0 = fastNowMs();
  beginFrame();
  const PassOne p = pass_one_;
  float* const cell_min_z = cell_min_z_.data();
  Kept* out = points_.data();
  std::size_t n = 0, capacity = points_.size();
#if defined(__SSE2__)
  const __m128 roi_lo = _mm_load_ps(p.roi_min), roi_hi = _mm_load_ps(p.roi_max);
  const __m128 ego_lo = _mm_load_ps(p.ego_min), ego_hi = _mm_load_ps(p.ego_max);
#endif
  source([&](float x, float y, float z) ICANC_ALWAYS_INLINE {
    // ROI closed, ego box closed (as prepareCloud). Written as "inside" tests so that NaN (every
    // comparison false) and +-Inf (beyond the finite ROI) fall out without isfinite calls, and
    // combined into one branch: the && chains were a branch per comparison. With SSE2 (every
    // x86-64) each box is two packed comparisons of (x, y, z, z), not six scalar ones.
#if defined(__SSE2__)
    const __m128 v = _mm_setr_ps(x, y, z, z);
    const int in_roi = _mm_movemask_ps(_mm_and_ps(_mm_cmpge_ps(v, roi_lo), _mm_cmple_ps(v, roi_hi)));
    const int in_ego = _mm_movemask_ps(_mm_and_ps(_mm_cmpge_ps(v, ego_lo), _mm_cmple_ps(v, ego_hi)));
    const int zero = _mm_movemask_ps(_mm_cmpeq_ps(v, _mm_setzero_ps()));
    if ((in_roi != 0xF) | (zero == 0xF) | (in_ego == 0xF)) return;
#else
    const bool in_roi = (x >= p.roi_min[0]) & (x <= p.roi_max[0]) & (y >= p.roi_min[1]) &
                        (y <= p.roi_max[1]) & (z >= p.roi_min[2]) & (z <= p.roi_max[2]);
    const bool zero = (x == 0.0f) & (y == 0.0f) & (z == 0.0f);
    const bool in_ego = (x >= p.ego_min[0]) & (x <= p.ego_max[0]) & (y >= p.ego_min[1]) &
                        (y <= p.ego_max[1]) & (z >= p.ego_min[2]) & (z <= p.ego_max[2]);
    if (!in_roi | zero | in_ego) return;
#endif
    int cx = static_cast<int>((x - p.roi_min[0]) * p.inv_cell);
    int cy = static_cast<int>((y - p.roi_min[1]) * p.inv_cell);
    if (cx >= p.nx) cx = p.nx - 1;  // a point on the upper ROI boundary
    if (cy >= p.ny) cy = p.ny - 1;
    const std::uint32_t cell = static_cast<std::uint32_t>(cy * p.nx + cx);
    if (n == capacity) {
      out = growPoints(n);
      capacity = points_.size();
    }
    Kept& k = out[n++];
    k.x = x;
    k.y = y;
    k.z = z;
    k.cell = cell;
    // Lowest z per BEV cell (one access; the polar minimum is reduced from it per cell, not per
    // point, in estimateGround). std::min compiles to minss: no branch to mispredict.
    cell_min_z[cell] = std::min(cell_min_z[cell], z);
  });
  kept_ = n;
  finishFrame(boxes, times, fastNowMs() - t0);
}

}  // namespace icanc
