// Reading the KITTI tracking layout: velodyne scans (.bin or .bin.xz), label_02 and calib.
#pragma once

#include <map>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "icanc/core/common/types.hpp"

namespace icanc {
namespace kitti {

// Reads a KITTI velodyne scan: little-endian float32 x y z intensity per point. `path` may end
// in .xz (decompressed with liblzma). Throws std::runtime_error naming the file on any failure
// (missing, not a multiple of 16 bytes, corrupt xz stream).
void readVelodyne(const std::string& path, Cloud& out);

// The scan of `frame` in a sequence directory: DIR/velodyne/NNNNNN.bin, or .bin.xz when the .bin
// is not there (the name to report when neither is).
std::string velodynePath(const std::string& dir, int frame);

struct Calib {
  Eigen::Matrix3d r0_rect = Eigen::Matrix3d::Identity();
  Eigen::Matrix<double, 3, 4> tr_velo_to_cam = Eigen::Matrix<double, 3, 4>::Zero();
  // p_cam_rect = R0_rect * Tr_velo_to_cam * p_velo, as a rigid transform, and its inverse. The
  // rotation part is projected onto the nearest rotation (the published matrices are orthonormal
  // only to ~1e-4), so the inverse is exact.
  Eigen::Isometry3d veloToCamRect() const;
  Eigen::Isometry3d camRectToVelo() const;
};
// Parses calib/NNNN.txt (keys "R0_rect:"/"R_rect" and "Tr_velo_cam:"/"Tr_velo_to_cam:", with or
// without the colon; other keys are ignored). Throws std::runtime_error naming the file when
// either entry is missing or has the wrong count of numbers.
Calib readCalib(const std::string& path);

struct Label {
  int frame = 0;
  int track_id = -1;
  std::string type;          // Car, Van, Pedestrian, Cyclist, ..., DontCare
  int truncated = 0;
  int occluded = 0;
  double h = 0, w = 0, l = 0;           // box height, width, length [m]
  Eigen::Vector3d bottom_center_cam;    // (x, y, z) in the rectified camera frame
  double rotation_y = 0;                // yaw about camera y [rad]
};
// Parses label_02/NNNN.txt; throws std::runtime_error with the line number on a malformed line.
std::vector<Label> readLabels(const std::string& path);

// A labelled box expressed in the velodyne frame.
struct VeloBox {
  int frame = 0;
  int track_id = -1;
  std::string type;
  Eigen::Vector3d center;   // box centre (not bottom) [m]
  Eigen::Vector3d size;     // length (along yaw), width, height [m]
  double yaw = 0;           // about velodyne +z [rad]
};
// Converts every non-DontCare label to the velodyne frame.
std::vector<VeloBox> toVelodyne(const std::vector<Label>& labels, const Calib& calib);

// True when (x, y, z) in the velodyne frame lies inside the box (oriented).
bool contains(const VeloBox& box, const Eigen::Vector3d& p, double margin_m = 0.0);

}  // namespace kitti
}  // namespace icanc
