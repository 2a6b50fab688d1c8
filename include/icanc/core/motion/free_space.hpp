// Motion read from free space: a return that lies where an earlier ray of the sensor passed
// through is on something that moved; a return on a surface an earlier ray ended on is on
// something that stands (the occlusion test of M-detector, Wu et al. 2024, and the "ever free"
// space of Dynablox, Schmid et al. 2023, on range images as Yoon et al. 2019).
//
// Each frame's returns are laid into a range image around the sensor (azimuth x elevation pixels
// of the sensor's own angular steps, the nearest return per pixel). The last images are kept with
// the vehicle's motion since each, so a point of this frame can be looked at from where the sensor
// was then. For a point at range d from that past sensor, over the past pixels around its
// direction (one pixel up and down, two to each side: the pose's and the sampling's error):
//   - free:  every past return there lies farther than d + tolerance: the rays passed through
//            where the point is now, so what it lies on has moved in;
//   - seen:  a past return lies within the tolerance of d: the same surface was there;
//   - else:  the point was hidden then (behind what the rays ended on) or out of view: no evidence.
// An object that moves away from the sensor along its rays, or along its own surface, occludes
// nothing new and gives no free points: the tracker's own history covers it.
// Tolerance: tolerance_m plus the width of a pixel at the point's range.
//
// No ROS here; time is the caller's (frame stamps).
#pragma once

#include <cmath>
#include <cstdint>
#include <deque>
#include <limits>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "icanc/core/motion/motion_state.hpp"
#include "icanc/core/perception/box.hpp"
#include "icanc/core/common/types.hpp"

namespace icanc {

struct FreeSpaceParams {
  float azimuth_step_deg = 0.2f;    // the sensor's horizontal resolution (one image column) [deg]
  float elevation_step_deg = 0.4f;  // its vertical beam spacing (one image row) [deg]
  float tolerance_m = 0.3f;         // range noise and pose error a surface may show [m]
};

std::string validate(const FreeSpaceParams& params);

class FreeSpaceMotion {
 public:
  explicit FreeSpaceMotion(const FreeSpaceParams& params = FreeSpaceParams());
  void setParams(const FreeSpaceParams& params);
  const FreeSpaceParams& params() const { return params_; }

  // Starts a frame: `motion` maps the previous frame's vehicle frame into this one (p_now =
  // motion * p_prev; identity: the vehicle stood still), `sensor` is where the sensor is in this
  // frame's vehicle frame. Images older than the horizon are dropped.
  void beginFrame(double stamp_s, const Eigen::Isometry3d& motion, const Eigen::Vector3f& sensor);
  // Every return of the frame, in the vehicle frame (ground too: a ray that ended on the road far
  // away passed through everything before it). Returns inside the ego box are skipped.
  void addPoint(float x, float y, float z) {
    if (!std::isfinite(x + y + z)) return;
    if (x >= ego_min_.x() && x <= ego_max_.x() && y >= ego_min_.y() && y <= ego_max_.y() &&
        z >= ego_min_.z() && z <= ego_max_.z())
      return;
    if (count_ == xs_.size()) grow();
    xs_[count_] = x;
    ys_[count_] = y;
    zs_[count_] = z;
    ++count_;
  }
  // The frame's image from the added points; then each box's points (the returns of this frame
  // inside its footprint and height) tested against the past images into box.motion.
  void evaluate(std::vector<Box3D>& boxes);
  // Keeps this frame's image for the frames to come.
  void endFrame();

  // The vehicle's own body, whose returns are not the world (CloudPrepParams' ego box) [m].
  void setEgoBox(const Eigen::Vector3f& min, const Eigen::Vector3f& max) {
    ego_min_ = min;
    ego_max_ = max;
  }
  // Keep the points found free in the last evaluate() (a debug cloud), in the vehicle frame.
  void setCollectFree(bool collect) { collect_free_ = collect; }
  const Cloud& freePoints() const { return free_points_; }
  void reset();

  // How far back the images go, and the youngest age tested: a walker moves 0.2-0.7 m in that
  // time, more than the tolerance [s].
  static constexpr double kMaxAgeS = 0.55;
  static constexpr double kMinAgeS = 0.18;
  // At most this many points of one box are tested (evenly spread over its pixels).
  static constexpr int kMaxTestedPerBox = 96;

 private:
  struct Image {
    // Per pixel, +inf: no return; and one spare pixel past the rows (never read).
    std::vector<float> range;
    // The pixels with a return lie in written_lo..written_hi (to clear them).
    std::int32_t written_lo = std::numeric_limits<std::int32_t>::max(), written_hi = -1;
    Eigen::Isometry3f to_image = Eigen::Isometry3f::Identity();  // current vehicle frame -> its
    Eigen::Vector3f sensor = Eigen::Vector3f::Zero();             // its sensor in its frame
    double stamp_s = 0.0;
  };
  enum class PointResult : std::uint8_t { kNone, kSeen, kFree };
  // A row's elevations (grown by a margin): their sines, and the bounds of their cosines.
  struct RowBand {
    double sin_lo = 0.0, sin_hi = 0.0, cos_min = 1.0, cos_max = 1.0;
  };
  // A box's footprint cells by a coarse grid over its bounds: the cells near a point.
  struct FootprintGrid {
    float x0 = 0.0f, y0 = 0.0f, inv_x = 0.0f, inv_y = 0.0f;
    int nx = 0, ny = 0;
    std::vector<std::int32_t> start;  // per grid cell, into parts (nx * ny + 1)
    std::vector<std::int32_t> parts;  // indices into the footprint
  };

  void layout();
  void grow();  // room for more returns
  Image& takeImage();
  void buildCurrent();
  // The pixel of each of n directions from `origin` (-1 outside the rows) and its range; four or
  // eight at a time where the CPU has SIMD, with the same float operations as one at a time.
  void pixelsOf(const float* x, const float* y, const float* z, const Eigen::Vector3f& origin,
                std::size_t n, std::int32_t* pixel, float* range) const;
  PointResult test(const Image& past, std::int32_t pixel, float d) const;
  void buildFootprintGrid(const Box3D& box, float edge);
  void evaluateBox(Box3D& box);

  FreeSpaceParams params_;
  int cols_ = 0, rows_ = 0;
  float inv_az_ = 0.0f, inv_el_ = 0.0f, el_min_ = 0.0f, pixel_rad_ = 0.0f;
  std::vector<RowBand> row_bands_;
  Eigen::Vector3f ego_min_ = Eigen::Vector3f::Constant(1.0f);  // empty box
  Eigen::Vector3f ego_max_ = Eigen::Vector3f::Constant(-1.0f);
  std::vector<float> xs_, ys_, zs_;      // this frame's returns: the first count_
  std::size_t count_ = 0;
  // Current image: nearest point per pixel, valid where its range is finite (never cleared).
  std::vector<std::int32_t> point_of_;
  Image current_;
  std::deque<Image> past_;               // oldest first
  std::vector<Image> spare_;             // recycled buffers
  std::vector<const Image*> tested_;     // this frame's images to test against
  std::vector<std::int32_t> candidates_;  // scratch: one box's points
  FootprintGrid grid_;                    // scratch: one box's footprint
  // Scratch: one box's tested points seen from each tested image.
  std::vector<float> qx_, qy_, qz_, qd_;
  std::vector<std::int32_t> qpixel_;
  double stamp_s_ = 0.0;
  bool built_ = false;  // current_ holds this frame's returns
  bool collect_free_ = false;
  Cloud free_points_;
};

}  // namespace icanc
