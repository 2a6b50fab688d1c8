// The camera overlay: tracked boxes drawn into the camera image, dangerous ones in red with their
// id and speed, so the operator sees what the LiDAR flagged from the camera detector's point of
// view. Geometry and drawing only: the projection (a calibrated pinhole model) is a callback,
// supplied by the CameraOverlay nodelet from image_geometry::PinholeCameraModel.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <utility>
#include <vector>

#include <Eigen/Geometry>
#include <opencv2/core.hpp>

namespace icanc {

// One tracked object to draw, in the vehicle frame (REP-103).
struct OverlayObject {
  std::uint32_t id = 0;
  Eigen::Vector3d center = Eigen::Vector3d::Zero();  // box centre [m]
  Eigen::Vector3d size = Eigen::Vector3d::Zero();    // length (along yaw), width, height [m]
  double yaw = 0.0;                                  // about +z [rad]
  double speed_mps = 0.0;
  bool dangerous = false;
};

struct OverlayStyle {
  double near_m = 0.1;       // edges are clipped to z >= near_m in the camera optical frame
  bool draw_safe = true;     // draw non-dangerous boxes too (thin, green)
  int danger_thickness_px = 2;
};

// A point in the camera optical frame (z forward, x right, y down) [m] -> pixel (u, v).
using Projector = std::function<cv::Point2d(const cv::Point3d&)>;
using Segment2d = std::pair<cv::Point2d, cv::Point2d>;

// The 8 corners of the oriented box: bottom face (z - h/2) first, counter-clockwise from
// (+l/2, +w/2) seen from above, then the top face in the same order.
std::array<Eigen::Vector3d, 8> boxCorners(const OverlayObject& object);

// The 12 edges of a box whose corners are given in the camera optical frame, each clipped to the
// half-space z >= near_m (the part behind the camera is cut off; an edge wholly behind is
// dropped) and projected. The result may still lie outside the image (cv::line clips it).
std::vector<Segment2d> projectBoxEdges(const std::array<Eigen::Vector3d, 8>& corners_camera,
                                       const Projector& project, double near_m);

// Draws every object into `image` (CV_8UC3, BGR): boxes transformed by camera_from_vehicle
// (the camera optical frame's pose inverse, from tf2), projected, dangerous in red with
// "#id speed m/s", the others (if style.draw_safe) in green. Returns the number of objects
// drawn (at least one edge in front of the camera and inside the image).
int drawOverlay(cv::Mat& image, const std::vector<OverlayObject>& objects,
                const Eigen::Isometry3d& camera_from_vehicle, const Projector& project,
                const OverlayStyle& style = OverlayStyle());

// Colours (BGR) of the overlay, for tests and figures.
const cv::Scalar& overlayDangerColour();
const cv::Scalar& overlaySafeColour();

}  // namespace icanc
