// Pins the camera overlay geometry: box corners, clipping behind the camera, projection through a
// known pinhole model to known pixels, and the drawing (red for dangerous, green otherwise).
#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "icanc/core/camera/camera_overlay.hpp"

namespace icanc {
namespace {

// A 640x480 pinhole camera, fx = fy = 500 px, principal point at the centre.
constexpr double kF = 500.0, kCx = 320.0, kCy = 240.0;
cv::Point2d pinhole(const cv::Point3d& p) { return {kCx + kF * p.x / p.z, kCy + kF * p.y / p.z}; }

// Camera optical frame at the vehicle origin looking along +x (REP-103 -> optical: z = x,
// x = -y, y = -z).
Eigen::Isometry3d cameraFromVehicle() {
  Eigen::Matrix3d r;
  r << 0, -1, 0,
       0, 0, -1,
       1, 0, 0;
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() = r;
  return t;
}

OverlayObject cubeAhead(double x, bool dangerous) {
  OverlayObject o;
  o.id = 7;
  o.center = Eigen::Vector3d(x, 0.0, 0.0);
  o.size = Eigen::Vector3d(1.0, 1.0, 1.0);
  o.speed_mps = 1.8;
  o.dangerous = dangerous;
  return o;
}

int countColour(const cv::Mat& image, const cv::Scalar& colour, cv::Rect roi = cv::Rect()) {
  if (roi.area() == 0) roi = cv::Rect(0, 0, image.cols, image.rows);
  cv::Mat mask;
  cv::inRange(image(roi), colour - cv::Scalar::all(40), colour + cv::Scalar::all(40), mask);
  return cv::countNonZero(mask);
}

TEST(CameraOverlay, BoxCornersFollowYaw) {
  OverlayObject o;
  o.center = Eigen::Vector3d(10, 2, 1);
  o.size = Eigen::Vector3d(4, 2, 1.5);
  o.yaw = M_PI / 2;
  const auto c = boxCorners(o);
  // Corner 0 is (+l/2, +w/2, -h/2) rotated by 90 deg: (-w/2, +l/2).
  EXPECT_NEAR(c[0].x(), 10 - 1, 1e-9);
  EXPECT_NEAR(c[0].y(), 2 + 2, 1e-9);
  EXPECT_NEAR(c[0].z(), 1 - 0.75, 1e-9);
  EXPECT_NEAR(c[4].z(), 1 + 0.75, 1e-9);
}

TEST(CameraOverlay, ABoxStraightAheadProjectsToKnownPixels) {
  const OverlayObject o = cubeAhead(10.0, true);
  auto corners = boxCorners(o);
  for (auto& c : corners) c = cameraFromVehicle() * c;
  // The near face is at 9.5 m: its corners at +-0.5 m project to 320 +- 500 * 0.5 / 9.5.
  const double d_near = kF * 0.5 / 9.5, d_far = kF * 0.5 / 10.5;
  const std::vector<Segment2d> edges = projectBoxEdges(corners, pinhole, 0.1);
  ASSERT_EQ(edges.size(), 12u);
  double umin = 1e9, umax = -1e9, vmin = 1e9, vmax = -1e9;
  for (const Segment2d& e : edges)
    for (const cv::Point2d& p : {e.first, e.second}) {
      umin = std::min(umin, p.x); umax = std::max(umax, p.x);
      vmin = std::min(vmin, p.y); vmax = std::max(vmax, p.y);
      // Every end point is a projected corner of the near or the far face.
      const double du = std::abs(p.x - kCx), dv = std::abs(p.y - kCy);
      EXPECT_TRUE((std::abs(du - d_near) < 1e-9 && std::abs(dv - d_near) < 1e-9) ||
                  (std::abs(du - d_far) < 1e-9 && std::abs(dv - d_far) < 1e-9)) << p;
    }
  EXPECT_NEAR(umin, kCx - d_near, 1e-9);  // 293.68 px
  EXPECT_NEAR(umax, kCx + d_near, 1e-9);
  EXPECT_NEAR(vmin, kCy - d_near, 1e-9);
  EXPECT_NEAR(vmax, kCy + d_near, 1e-9);
  // Left in the vehicle (+y) is left in the image (small u); up (+z) is up (small v).
  EXPECT_LT(pinhole({corners[0].x(), corners[0].y(), corners[0].z()}).x, kCx);  // y = +0.5
  EXPECT_GT(pinhole({corners[0].x(), corners[0].y(), corners[0].z()}).y, kCy);  // z = -0.5
}

TEST(CameraOverlay, BehindTheCameraIsNotDrawnAndStraddlingBoxesAreClipped) {
  auto behind = boxCorners(cubeAhead(-10.0, true));
  for (auto& c : behind) c = cameraFromVehicle() * c;
  EXPECT_TRUE(projectBoxEdges(behind, pinhole, 0.1).empty());

  // A long box from 5 m behind to 5 m ahead: the 4 edges along x are cut at z = near, the
  // 4 edges of the rear face are dropped.
  OverlayObject straddle = cubeAhead(0.0, true);
  straddle.size.x() = 10.0;
  auto corners = boxCorners(straddle);
  for (auto& c : corners) c = cameraFromVehicle() * c;
  const std::vector<Segment2d> edges = projectBoxEdges(corners, pinhole, 0.5);
  EXPECT_EQ(edges.size(), 8u);
  for (const Segment2d& e : edges)
    for (const cv::Point2d& p : {e.first, e.second}) {
      EXPECT_TRUE(std::isfinite(p.x) && std::isfinite(p.y));
      // Nothing projected from behind the near plane: |u - cx| <= f * 0.5 / 0.5.
      EXPECT_LE(std::abs(p.x - kCx), kF + 1e-6);
    }

  cv::Mat image(480, 640, CV_8UC3, cv::Scalar::all(0));
  EXPECT_EQ(drawOverlay(image, {cubeAhead(-10.0, true)}, cameraFromVehicle(), pinhole), 0);
  EXPECT_EQ(cv::countNonZero(image.reshape(1)), 0);
}

TEST(CameraOverlay, DangerousInRedWithLabelSafeInGreen) {
  cv::Mat image(480, 640, CV_8UC3, cv::Scalar::all(10));
  OverlayObject safe = cubeAhead(10.0, false);
  safe.center.y() = 3.0;  // left of the path: u = 320 - 500 * 3 / 10 ~ 170
  const int drawn = drawOverlay(image, {cubeAhead(10.0, true), safe}, cameraFromVehicle(), pinhole);
  EXPECT_EQ(drawn, 2);
  // Red on the near face's left edge (u = 293.7, v in [213.7, 266.3]); none far from the boxes.
  const cv::Rect left_edge(291, 220, 6, 40);
  EXPECT_GT(countColour(image, overlayDangerColour(), left_edge), 40);
  EXPECT_EQ(countColour(image, overlayDangerColour(), cv::Rect(0, 300, 640, 180)), 0);
  // Green around the safe box, no red there.
  const cv::Rect safe_box(130, 200, 80, 80);
  EXPECT_GT(countColour(image, overlaySafeColour(), safe_box), 40);
  EXPECT_EQ(countColour(image, overlayDangerColour(), safe_box), 0);
  // The label "#7 1.8 m/s" sits above the dangerous box.
  EXPECT_GT(countColour(image, overlayDangerColour(), cv::Rect(280, 190, 100, 22)), 20);

  cv::Mat only_danger(480, 640, CV_8UC3, cv::Scalar::all(10));
  OverlayStyle style;
  style.draw_safe = false;
  EXPECT_EQ(drawOverlay(only_danger, {safe}, cameraFromVehicle(), pinhole, style), 0);
  EXPECT_EQ(countColour(only_danger, overlaySafeColour()), 0);
}

TEST(CameraOverlay, BoxOutsideTheFieldOfViewIsNotCounted) {
  cv::Mat image(480, 640, CV_8UC3, cv::Scalar::all(0));
  OverlayObject side = cubeAhead(2.0, true);
  side.center.y() = 30.0;  // far to the left, in front of the camera plane but out of view
  EXPECT_EQ(drawOverlay(image, {side}, cameraFromVehicle(), pinhole), 0);
}

}  // namespace
}  // namespace icanc
