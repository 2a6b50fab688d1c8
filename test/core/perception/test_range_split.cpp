// The fast path's range-image split (FastDetectorParams::range_split_*): a
// road user beside what it stands against — a wall behind a walker, a second cyclist, a parked
// car — comes apart from it where the grid joins them, and a car seen from its corner stays one
// box. Simulated scans (the sensor presets the scenarios use) in base_link, sensor origin set.
#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "icanc/core/perception/fast_detector.hpp"
#include "icanc/core/perception/obstacle_detector.hpp"
#include "icanc/sim/lidar_sim.hpp"

namespace icanc {
namespace {

CloudPrepParams carlaRoi() {  // carla_model3's ROI and ego box
  CloudPrepParams prep;
  prep.roi_min = {-10.0f, -20.0f, -0.5f};
  prep.roi_max = {60.0f, 20.0f, 3.0f};
  prep.ego_min = {-2.5f, -1.05f, -0.5f};
  prep.ego_max = {2.5f, 1.05f, 1.6f};
  return prep;
}

FastDetectorParams withSplit(bool on) {
  FastDetectorParams p;  // the profiles' other fast keys are the defaults
  p.range_split_angle_deg = on ? 10.0f : 0.0f;
  return p;
}

sim::SceneObject object(const std::string& type, sim::Shape shape, const Eigen::Vector3f& size,
                        const Eigen::Vector3f& bottom_centre, float yaw = 0.0f) {
  sim::SceneObject o;
  o.type = type;
  o.shape = shape;
  o.size = size;
  o.position = bottom_centre;
  o.yaw = yaw;
  return o;
}

sim::SceneObject walker(float x, float y) {
  return object("pedestrian", sim::Shape::kCylinder, {0.5f, 0.5f, 1.75f}, {x, y, 0.0f});
}

// One scan from a sensor `height` up at the origin, in base_link (road at z = 0), with the
// scenarios' noise (2 cm range noise, 2 % dropouts).
Cloud render(const sim::Scene& scene, const sim::LidarModel& model, float height) {
  std::mt19937_64 rng(22);
  sim::NoiseParams noise;
  noise.range_std_m = 0.02f;
  noise.dropout_prob = 0.02f;
  Eigen::Isometry3f pose = Eigen::Isometry3f::Identity();
  pose.translation() = Eigen::Vector3f(0.0f, 0.0f, height);
  Cloud scan, cloud;
  sim::renderScan(scene, 0.0, pose, model, noise, rng, scan);
  for (const Point& p : scan)
    if (std::isfinite(p.x)) cloud.push_back(Point(p.x, p.y, p.z + height));
  return cloud;
}

std::vector<Box3D> detect(const Cloud& cloud, float height, bool split) {
  FastDetector detector(carlaRoi(), withSplit(split));
  detector.setSensorOrigin({0.0f, 0.0f, height});
  std::vector<Box3D> boxes;
  detector.detect(cloud, boxes);
  return boxes;
}

// A box of a road user: centre within `tolerance` of (x, y), no longer than `max_length`.
bool found(const std::vector<Box3D>& boxes, float x, float y, float tolerance, float max_length) {
  return std::any_of(boxes.begin(), boxes.end(), [&](const Box3D& b) {
    return std::hypot(b.center.x() - x, b.center.y() - y) <= tolerance &&
           std::max(b.size.x(), b.size.y()) <= max_length && b.num_points >= 10;
  });
}

// A walker 0.3 m in front of a 20 m wall (too short for the height check of link_max_step_m),
// as mount_roof64_clutter's, at several distances: its own box with the split, inside the
// wall's without it; the wall stays one box either way.
TEST(RangeSplit, WalkerInFrontOfAWallComesApart) {
  for (const char* model : {"hdl64e", "hdl32e"}) {
    for (float x : {8.0f, 12.0f, 18.0f}) {
      sim::Scene scene;
      scene.objects = {object("wall", sim::Shape::kBox, {20.0f, 0.3f, 2.5f}, {15.0f, -6.0f, 0.0f}),
                       walker(x, -5.3f)};  // its edge 0.3 m from the wall's face
      const Cloud cloud = render(scene, sim::LidarModel::byName(model), 2.0f);
      const auto on = detect(cloud, 2.0f, true), off = detect(cloud, 2.0f, false);
      EXPECT_TRUE(found(on, x, -5.3f, 0.35f, 0.9f)) << model << " x " << x;
      EXPECT_FALSE(found(off, x, -5.3f, 0.35f, 0.9f)) << model << " x " << x;
      EXPECT_TRUE(found(on, 15.0f, -6.0f, 1.5f, 21.0f)) << model << " x " << x;  // the wall
    }
  }
}

// The box nearest (x, y) if within `tolerance` (the evaluation's match distance, 1 m).
const Box3D* nearest(const std::vector<Box3D>& boxes, float x, float y, float tolerance) {
  const Box3D* best = nullptr;
  for (const Box3D& b : boxes) {
    const float d = std::hypot(b.center.x() - x, b.center.y() - y);
    if (d <= tolerance && b.num_points >= 10 && std::max(b.size.x(), b.size.y()) <= 2.0f) {
      best = &b;
      tolerance = d;
    }
  }
  return best;
}

// Two cyclists riding side by side 0.5 m apart (the grid links cells 0.5 m apart), ahead-left:
// a box for each within the evaluation's match distance (1 m), not one box for both.
TEST(RangeSplit, TwoCyclistsSideBySideAreTwo) {
  for (float x : {10.0f, 14.0f, 20.0f}) {
    sim::Scene scene;
    scene.objects = {object("cyclist", sim::Shape::kBox, {1.8f, 0.6f, 1.7f}, {x, 2.3f, 0.0f}),
                     object("cyclist", sim::Shape::kBox, {1.8f, 0.6f, 1.7f}, {x, 3.4f, 0.0f})};
    const Cloud cloud = render(scene, sim::LidarModel::hdl64e(), 2.0f);
    const auto on = detect(cloud, 2.0f, true), off = detect(cloud, 2.0f, false);
    const Box3D *a = nearest(on, x, 2.3f, 1.0f), *b = nearest(on, x, 3.4f, 1.0f);
    ASSERT_TRUE(a && b) << x;
    EXPECT_NE(a, b) << x;
    EXPECT_EQ(nearest(off, x, 2.3f, 1.0f), nearest(off, x, 3.4f, 1.0f)) << x;  // one for both
  }
}

// A pedestrian waiting 0.1 m beside a parked car's near side: its own box, and the car's.
TEST(RangeSplit, PedestrianBesideAParkedCarComesApart) {
  for (float x : {10.0f, 15.0f, 20.0f}) {
    sim::Scene scene;
    scene.objects = {object("car", sim::Shape::kBox, {4.5f, 1.8f, 1.5f}, {x + 0.5f, -3.4f, 0.0f}),
                     walker(x, -2.15f)};  // its edge 0.1 m from the car's near side
    const Cloud cloud = render(scene, sim::LidarModel::hdl64e(), 2.0f);
    const auto on = detect(cloud, 2.0f, true), off = detect(cloud, 2.0f, false);
    EXPECT_TRUE(found(on, x, -2.15f, 0.35f, 0.9f)) << x;
    EXPECT_FALSE(found(off, x, -2.15f, 0.35f, 0.9f)) << x;
    EXPECT_TRUE(found(on, x + 0.5f, -3.4f, 1.5f, 5.0f)) << x;  // the car
  }
}

// A car seen from its corner (yawed 35 deg, both faces seen) and one ahead whose long side the
// beams graze: nothing is carved out of them (the same boxes as without the split: one for the
// corner views; the grazed side's sparse cells are apart in the grid already), on a 64-, 32- and
// 16-beam unit.
TEST(RangeSplit, CarSeenFromItsCornerStaysOneBox) {
  for (const char* model : {"hdl64e", "hdl32e", "vlp16"}) {
    for (const auto& pose : {Eigen::Vector3f(10.0f, 4.0f, 0.6f), Eigen::Vector3f(15.0f, -4.0f, -0.6f),
                             Eigen::Vector3f(14.0f, 1.5f, 0.0f), Eigen::Vector3f(8.0f, -3.0f, 0.0f)}) {
      sim::Scene scene;
      scene.objects = {object("car", sim::Shape::kBox, {4.5f, 1.8f, 1.5f},
                              {pose.x(), pose.y(), 0.0f}, pose.z())};
      const float height = std::string(model) == "vlp16" ? 0.5f : 2.0f;
      const Cloud cloud = render(scene, sim::LidarModel::byName(model), height);
      const auto on = detect(cloud, height, true), off = detect(cloud, height, false);
      ASSERT_EQ(on.size(), off.size()) << model << " at " << pose.transpose();
      ASSERT_FALSE(on.empty());
      EXPECT_EQ(on[0].num_points, off[0].num_points) << model << " at " << pose.transpose();
      if (pose.z() != 0.0f) {
        EXPECT_EQ(on.size(), 1u) << model << " at " << pose.transpose();
      }
    }
  }
}

// The angular steps are measured on the scan: the preset's azimuth resolution and beam spacing.
TEST(RangeSplit, AngularStepsAreMeasuredFromTheScan) {
  sim::Scene scene;
  scene.objects = {object("wall", sim::Shape::kBox, {20.0f, 0.3f, 2.5f}, {15.0f, -6.0f, 0.0f})};
  struct Case {
    const char* model;
    float col_deg, row_deg;
  };
  for (const Case& c : {Case{"hdl32e", 0.16f, 1.33f}, Case{"vlp16", 0.2f, 2.0f},
                        Case{"carla128", 0.72f, 0.315f}}) {
    FastDetector detector(carlaRoi(), withSplit(true));
    detector.setSensorOrigin({0.0f, 0.0f, 2.0f});
    std::vector<Box3D> boxes;
    detector.detect(render(scene, sim::LidarModel::byName(c.model), 2.0f), boxes);
    EXPECT_NEAR(detector.rangeColumnDeg(), c.col_deg, 0.01f) << c.model;
    EXPECT_NEAR(detector.rangeRowDeg(), c.row_deg, 0.02f) << c.model;
  }
}

// Once measured, the steps are kept for FastDetector::kStepsEveryFrames frames, then measured
// again: a detector fed a 32-beam unit's scans, then a 16-beam unit's, keeps the first unit's
// steps for the first frames of the second and has the second's within that many frames.
TEST(RangeSplit, AngularStepsAreMeasuredAgainEveryFewFrames) {
  sim::Scene scene;
  scene.objects = {object("wall", sim::Shape::kBox, {20.0f, 0.3f, 2.5f}, {15.0f, -6.0f, 0.0f})};
  const Cloud hdl32 = render(scene, sim::LidarModel::byName("hdl32e"), 2.0f);
  const Cloud vlp16 = render(scene, sim::LidarModel::byName("vlp16"), 2.0f);
  FastDetector detector(carlaRoi(), withSplit(true));
  detector.setSensorOrigin({0.0f, 0.0f, 2.0f});
  std::vector<Box3D> boxes;
  for (int i = 0; i < 3; ++i) detector.detect(hdl32, boxes);
  ASSERT_NEAR(detector.rangeRowDeg(), 1.33f, 0.02f);
  int frames = 0;
  detector.detect(vlp16, boxes);
  ++frames;
  EXPECT_NEAR(detector.rangeRowDeg(), 1.33f, 0.02f) << "measured again on the next frame";
  while (std::abs(detector.rangeRowDeg() - 2.0f) > 0.02f && frames < 2 * FastDetector::kStepsEveryFrames) {
    detector.detect(vlp16, boxes);
    ++frames;
  }
  EXPECT_NEAR(detector.rangeRowDeg(), 2.0f, 0.02f);
  EXPECT_NEAR(detector.rangeColumnDeg(), 0.2f, 0.01f);
  EXPECT_LE(frames, FastDetector::kStepsEveryFrames);
  EXPECT_GE(frames, FastDetector::kStepsEveryFrames - 3);
}

// Off (angle 0) nothing is recorded or split; the keys are checked; ObstacleDetector hands its
// sensor origin on.
TEST(RangeSplit, OffByDefaultValidatedAndWired) {
  EXPECT_EQ(FastDetectorParams().range_split_angle_deg, 0.0f);
  FastDetectorParams p;
  p.range_split_angle_deg = 90.0f;
  EXPECT_NE(validate(p).find("fast.range_split_angle_deg"), std::string::npos);
  p = FastDetectorParams();
  p.range_split_min_extent_m = -1.0f;
  EXPECT_NE(validate(p).find("fast.range_split_min_extent_m"), std::string::npos);
  p = FastDetectorParams();
  p.range_piece_max_m = 0.0f;
  EXPECT_NE(validate(p).find("fast.range_piece_max_m"), std::string::npos);
  p = FastDetectorParams();
  p.range_piece_min_height_m = std::nanf("");
  EXPECT_NE(validate(p).find("fast.range_piece_min_height_m"), std::string::npos);
  p = FastDetectorParams();
  p.range_piece_foreground = 1.5f;
  EXPECT_NE(validate(p).find("fast.range_piece_foreground"), std::string::npos);

  sim::Scene scene;
  scene.objects = {object("wall", sim::Shape::kBox, {20.0f, 0.3f, 2.5f}, {15.0f, -6.0f, 0.0f}),
                   walker(12.0f, -5.3f)};
  const Cloud cloud = render(scene, sim::LidarModel::hdl64e(), 2.0f);
  ObstacleDetectorParams params;
  params.method = DetectorMethod::kFast;
  params.prep = carlaRoi();
  params.fast = withSplit(true);
  ObstacleDetector wired(params);
  wired.setSensorOrigin({0.0f, 0.0f, 2.0f});
  wired.process(0.0, cloud);
  EXPECT_TRUE(found(wired.detections(), 12.0f, -5.3f, 0.35f, 0.9f));
  wired.setParams(params);  // a new FastDetector keeps the origin
  wired.process(0.1, cloud);
  EXPECT_TRUE(found(wired.detections(), 12.0f, -5.3f, 0.35f, 0.9f));
}

}  // namespace
}  // namespace icanc
