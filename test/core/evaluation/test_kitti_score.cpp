// kitti::scoreFrame: which labels count (type, range, points inside), when a label is found,
// which detections count toward precision, and which counted labels lie outside the detector's ROI.
#include "icanc/core/evaluation/kitti_score.hpp"

#include <gtest/gtest.h>

namespace icanc {
namespace kitti {
namespace {

VeloBox label(const std::string& type, const Eigen::Vector3d& center, const Eigen::Vector3d& size) {
  VeloBox b;
  b.type = type;
  b.center = center;
  b.size = size;
  return b;
}

Box3D detection(float x, float y, float z) {
  Box3D b;
  b.center = Eigen::Vector3f(x, y, z);
  return b;
}

void addPoints(Cloud& cloud, const Eigen::Vector3d& at, int n) {
  for (int i = 0; i < n; ++i) cloud.push_back(Point(at.x() + 0.01 * i, at.y(), at.z()));
}

TEST(KittiScore, RecallAndPrecisionFollowTheRule) {
  const std::vector<VeloBox> labels = {
      label("Car", {10, 0, -1}, {4, 2, 1.5}),         // 30 points: counts, found
      label("Pedestrian", {8, -3, -1}, {0.6, 0.6, 1.7}),  // 25 points: counts, missed
      label("Cyclist", {15, 3, -1}, {1.8, 0.6, 1.7}),    // 19 points: does not count
      label("Car", {45, 0, -1}, {4, 2, 1.5}),          // beyond 40 m: does not count
      label("Misc", {20, -5, -1}, {1, 1, 1}),           // other type: never counted, but a hit
  };
  Cloud cloud;
  addPoints(cloud, {10, 0, -1}, 30);
  addPoints(cloud, {8, -3, -1}, 25);
  addPoints(cloud, {15, 3, -1}, 19);
  addPoints(cloud, {45, 0, -1}, 50);
  const std::vector<Box3D> detections = {
      detection(12.4f, 0.5f, -1.0f),   // inside the car grown by 0.5 m (12.5 edge)
      detection(20.0f, -5.0f, -1.0f),  // the Misc box: correct
      detection(25.0f, 8.0f, -1.0f),   // nothing there: a false positive
      detection(-10.0f, 0.0f, -1.0f),  // behind: outside the labelled field of view
      detection(5.0f, 20.0f, -1.0f),   // 76 deg to the left: outside too
  };
  const DetectionScore s = scoreFrame(labels, cloud, detections);
  EXPECT_EQ(s.labelledTotal(), 2);
  EXPECT_EQ(s.labelled.at("Car"), 1);
  EXPECT_EQ(s.labelled.at("Pedestrian"), 1);
  EXPECT_EQ(s.foundTotal(), 1);
  EXPECT_EQ(s.found.at("Car"), 1);
  EXPECT_DOUBLE_EQ(s.recall(), 0.5);
  EXPECT_EQ(s.detections, 3);
  EXPECT_EQ(s.correct, 2);
  EXPECT_DOUBLE_EQ(s.precision(), 2.0 / 3.0);

  DetectionScore total;
  total.add(s);
  total.add(s);
  EXPECT_EQ(total.labelledTotal(), 4);
  EXPECT_EQ(total.correct, 4);
  EXPECT_DOUBLE_EQ(total.recall(), 0.5);

  // With the detector's ROI: the counted pedestrian (x 8, y -3) lies outside x 9..60, the car inside.
  const Eigen::AlignedBox2d roi(Eigen::Vector2d(9.0, -20.0), Eigen::Vector2d(60.0, 20.0));
  const DetectionScore cropped = scoreFrame(labels, cloud, detections, &roi);
  EXPECT_EQ(cropped.outsideRoiTotal(), 1);
  EXPECT_EQ(cropped.outside_roi.at("Pedestrian"), 1);
  EXPECT_EQ(cropped.outside_roi.count("Car"), 0u);
  EXPECT_EQ(cropped.labelledTotal(), s.labelledTotal());  // the rule for what counts is unchanged
  EXPECT_EQ(s.outsideRoiTotal(), 0);                       // no ROI given: none counted
  total.add(cropped);
  EXPECT_EQ(total.outsideRoiTotal(), 1);

  const DetectionScore none = scoreFrame({}, Cloud(), {});
  EXPECT_DOUBLE_EQ(none.recall(), 1.0);
  EXPECT_DOUBLE_EQ(none.precision(), 1.0);
}

}  // namespace
}  // namespace kitti
}  // namespace icanc
