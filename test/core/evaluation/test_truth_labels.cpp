// Pins the ground-truth labelling of object-frames (docs/design.md, "Ground truth for dangerous"):
// trajectories per track id, time to corridor per frame, in-corridor, velocities by difference
// and points inside a box.
#include <cmath>
#include <filesystem>
#include <limits>
#include <set>

#include <gtest/gtest.h>

#include "icanc/core/evaluation/truth_labels.hpp"
#include "icanc/core/common/yaml_params.hpp"

namespace icanc {
namespace {

CorridorParams corridor() {
  CorridorParams c;
  c.half_width_m = 1.0;
  c.margin_m = 0.5;           // |y| <= 1.5
  c.vehicle_front_m = 1.0;
  c.stopping_margin_m = 4.0;  // 0 <= x <= 5
  c.horizon_s = 2.0;
  return c;
}

TruthBox box(std::uint32_t id, double t, double x, double y, double l = 0.5, double w = 0.5,
             double yaw = 0.0) {
  TruthBox b;
  b.id = id;
  b.t = t;
  b.type = "pedestrian";
  b.center = Eigen::Vector3d(x, y, 0.85);
  b.size = Eigen::Vector3d(l, w, 1.7);
  b.yaw = yaw;
  return b;
}

// Frames every 0.1 s from 0 to `seconds` of an object moving from (x0, y0) at (vx, vy).
std::vector<TruthBox> track(std::uint32_t id, double x0, double y0, double vx, double vy,
                            double seconds, double l = 0.5, double w = 0.5) {
  std::vector<TruthBox> boxes;
  for (int k = 0; k <= static_cast<int>(std::lround(seconds * 10.0)); ++k) {
    const double t = 0.1 * k;
    boxes.push_back(box(id, t, x0 + vx * t, y0 + vy * t, l, w));
  }
  return boxes;
}

std::vector<double> dangerousTimes(const std::vector<TruthBox>& boxes,
                                   const std::vector<TruthLabel>& labels, std::uint32_t id) {
  std::vector<double> times;
  for (std::size_t i = 0; i < boxes.size(); ++i)
    if (boxes[i].id == id && labels[i].dangerous) times.push_back(boxes[i].t);
  return times;
}

TEST(TruthLabels, CrossingPedestrianIsDangerousFromTheHorizonBeforeItEnters) {
  // x = 3, from y = 4 toward -4 at 1.5 m/s: enters at centre y = 1.75 (t = 1.5 s), leaves after
  // centre y = -1.75 (t = 3.83 s).
  const std::vector<TruthBox> boxes = track(1, 3.0, 4.0, 0.0, -1.5, 6.0);
  const std::vector<TruthLabel> labels = labelTruths(boxes, corridor());
  ASSERT_EQ(labels.size(), boxes.size());
  // t = 0: 1.5 s to go, within the 2 s horizon.
  EXPECT_TRUE(labels[0].dangerous);
  EXPECT_FALSE(labels[0].in_corridor);
  EXPECT_NEAR(labels[0].time_to_corridor, 1.5, 1e-9);
  EXPECT_NEAR(labels[10].time_to_corridor, 0.5, 1e-9);
  for (int k : {15, 20, 30, 38}) {
    EXPECT_TRUE(labels[k].in_corridor) << k;
    EXPECT_DOUBLE_EQ(labels[k].time_to_corridor, 0.0) << k;
  }
  for (int k : {39, 45, 60}) {
    EXPECT_FALSE(labels[k].dangerous) << k;  // past: it only moves away
    EXPECT_DOUBLE_EQ(labels[k].time_to_corridor, -1.0) << k;
  }
}

TEST(TruthLabels, ApproachingIsDangerousOnlyWithinTheHorizon) {
  // Straight toward the vehicle from x = 15 at 2 m/s: enters when centre x = 5.25, t = 4.875 s.
  const std::vector<TruthBox> boxes = track(7, 15.0, 0.0, -2.0, 0.0, 7.0);
  const std::vector<TruthLabel> labels = labelTruths(boxes, corridor());
  const std::vector<double> times = dangerousTimes(boxes, labels, 7);
  ASSERT_FALSE(times.empty());
  EXPECT_NEAR(times.front(), 2.9, 1e-9);  // first frame with the entry (4.9 s) within 2 s
  EXPECT_NEAR(times.back(), 7.0, 1e-9);
  EXPECT_EQ(times.size(), 42u);           // 2.9 .. 7.0 s
  EXPECT_FALSE(labels[28].dangerous);     // t = 2.8 s: 2.1 s to go
  EXPECT_NEAR(labels[29].time_to_corridor, 2.0, 1e-9);
}

TEST(TruthLabels, MovingAwayIsNeverDangerous) {
  // Starts just beyond the corridor (centre x = 5.5) and walks away: never in it.
  const std::vector<TruthBox> boxes = track(3, 5.5, 0.0, 1.5, 0.0, 5.0);
  const std::vector<TruthLabel> labels = labelTruths(boxes, corridor());
  EXPECT_TRUE(dangerousTimes(boxes, labels, 3).empty());
}

TEST(TruthLabels, ParkedAlongsideIsNotDangerousButParkedInThePathIs) {
  // The vehicle drives at 5 m/s: parked cars come toward it at -5 m/s relative.
  const std::vector<TruthBox> alongside = track(1, 30.0, 3.0, -5.0, 0.0, 8.0, 4.5, 1.8);  // side at 2.1
  const std::vector<TruthBox> in_path = track(2, 30.0, -2.0, -5.0, 0.0, 8.0, 4.5, 1.8);  // side at -1.1
  std::vector<TruthBox> boxes = alongside;
  boxes.insert(boxes.end(), in_path.begin(), in_path.end());
  const std::vector<TruthLabel> labels = labelTruths(boxes, corridor());
  EXPECT_TRUE(dangerousTimes(boxes, labels, 1).empty());
  // Car 2 enters when its rear (x - 2.25) reaches x = 5: x = 7.25, t = 4.55 s; dangerous from
  // 2.55 s (first frame 2.6 s) until its front (x + 2.25) passes x = 0: x = -2.25, t = 6.45 s.
  const std::vector<double> times = dangerousTimes(boxes, labels, 2);
  ASSERT_FALSE(times.empty());
  EXPECT_NEAR(times.front(), 2.6, 1e-9);
  EXPECT_NEAR(times.back(), 6.4, 1e-9);
}

TEST(TruthLabels, WhereTheRecordingEndsWithinTheHorizonASafeLabelIsUnknown) {
  // A recording of 7 s: the approaching pedestrian (entry at 4.875 s, above) and one walking
  // away. Known until the last frame (7.0 s), labels from 5.0 s on look past it.
  std::vector<TruthBox> boxes = track(7, 15.0, 0.0, -2.0, 0.0, 7.0);
  const std::vector<TruthBox> away = track(3, 5.5, 0.0, 1.5, 0.0, 7.0);
  boxes.insert(boxes.end(), away.begin(), away.end());
  const std::vector<TruthLabel> labels = labelTruths(boxes, corridor(), 7.0);
  const std::vector<TruthLabel> unbounded = labelTruths(boxes, corridor());
  for (std::size_t i = 0; i < boxes.size(); ++i) {
    // The danger itself does not change; only a safe label of the last 2 s becomes unknown.
    EXPECT_EQ(labels[i].dangerous, unbounded[i].dangerous) << i;
    EXPECT_EQ(labels[i].time_to_corridor, unbounded[i].time_to_corridor) << i;
    EXPECT_FALSE(unbounded[i].horizon_cut) << i;
    const bool last_horizon = boxes[i].t > 5.0 + 1e-9;
    EXPECT_EQ(labels[i].horizon_cut, last_horizon && !labels[i].dangerous)
        << "id " << boxes[i].id << " t " << boxes[i].t;
  }
  // The one walking away is cut from 5.1 s on (its horizon reaches past 7.0 s), the approaching
  // one never: it is dangerous from 2.9 s on, which the labels show.
  std::size_t cut = 0;
  for (std::size_t i = 0; i < boxes.size(); ++i) {
    if (!labels[i].horizon_cut) continue;
    ++cut;
    EXPECT_EQ(boxes[i].id, 3u);
  }
  EXPECT_EQ(cut, 20u);  // 5.1 .. 7.0 s
}

TEST(TruthLabels, ATrackWhoseLabelsStopIsJudgedOnlyFromTheFramesItHas) {
  // Approaches at 2 m/s from x = 10 but its labels stop at t = 1.5 s (centre x = 7, not yet in the
  // corridor, 0.875 s before it would enter): no extrapolation, so never dangerous.
  const std::vector<TruthBox> cut = track(5, 10.0, 0.0, -2.0, 0.0, 1.5);
  const std::vector<TruthLabel> cut_labels = labelTruths(cut, corridor());
  EXPECT_TRUE(dangerousTimes(cut, cut_labels, 5).empty());
  // The same track labelled further is dangerous in those same frames.
  const std::vector<TruthBox> full = track(5, 10.0, 0.0, -2.0, 0.0, 4.0);
  const std::vector<TruthLabel> full_labels = labelTruths(full, corridor());
  EXPECT_TRUE(full_labels[15].dangerous);
  // A track that disappears and comes back: the frames before the gap see the frames after it
  // within the horizon (they are labelled positions), and nothing between.
  std::vector<TruthBox> gap;
  for (const TruthBox& b : full)
    if (b.t < 0.95 || b.t > 2.45) gap.push_back(b);
  const std::vector<TruthLabel> gap_labels = labelTruths(gap, corridor());
  // Labelled in the corridor from 2.4 s; with the labels of 1.0..2.4 s missing, the first one
  // after the gap is 2.5 s: t = 0.4 s is no longer dangerous (2.1 s ahead), t = 0.5 s is.
  ASSERT_NEAR(gap[4].t, 0.4, 1e-9);
  EXPECT_NEAR(full_labels[4].time_to_corridor, 2.0, 1e-9);
  EXPECT_FALSE(gap_labels[4].dangerous);
  EXPECT_NEAR(gap_labels[5].time_to_corridor, 2.0, 1e-9);
}

TEST(TruthLabels, TracksDoNotMixAndLabelsFollowTheBoxOrder) {
  // Two ids at the same positions but only id 1 continues into the corridor.
  std::vector<TruthBox> boxes;
  boxes.push_back(box(2, 0.0, 6.0, 0.0));
  boxes.push_back(box(1, 1.0, 4.0, 0.0));  // given out of time order
  boxes.push_back(box(1, 0.0, 6.0, 0.0));
  const std::vector<TruthLabel> labels = labelTruths(boxes, corridor());
  EXPECT_FALSE(labels[0].dangerous);
  EXPECT_TRUE(labels[1].in_corridor);
  EXPECT_NEAR(labels[2].time_to_corridor, 1.0, 1e-9);
  const Trajectories tr = buildTrajectories(boxes);
  ASSERT_EQ(tr.at(1).size(), 2u);
  EXPECT_LT(tr.at(1)[0].t, tr.at(1)[1].t);
}

TEST(TruthLabels, InTheCorridorIsDangerousWithoutASampleAtThatTime) {
  // Trajectory sampled elsewhere (e.g. a coarse simulation grid): the box itself decides "now".
  const TruthBox now = box(4, 0.05, 2.0, 0.0);
  Trajectories tr;
  tr[4].push_back(toTruthPose(box(4, 0.0, 20.0, 0.0)));
  const std::vector<TruthLabel> labels = labelTruths({now}, tr, corridor());
  EXPECT_TRUE(labels[0].in_corridor);
  EXPECT_TRUE(labels[0].dangerous);
  EXPECT_DOUBLE_EQ(labels[0].time_to_corridor, 0.0);
  // An id without a trajectory is judged from itself alone.
  const std::vector<TruthLabel> alone = labelTruths({box(9, 0.0, 8.0, 0.0)}, tr, corridor());
  EXPECT_FALSE(alone[0].dangerous);
}

TEST(TruthLabels, FinerTrajectoriesCatchWhatFramesMiss) {
  // A fast crossing at x = 3 (10 m/s in y) that is in the corridor only between two 0.5 s frames.
  std::vector<TruthBox> frames = {box(1, 0.0, 3.0, 2.5), box(1, 0.5, 3.0, -2.5)};
  EXPECT_FALSE(labelTruths(frames, corridor())[0].dangerous);
  std::vector<TruthBox> fine;
  for (int k = 0; k <= 50; ++k) fine.push_back(box(1, 0.01 * k, 3.0, 2.5 - 0.1 * k));
  const std::vector<TruthLabel> labels = labelTruths(frames, buildTrajectories(fine), corridor());
  EXPECT_TRUE(labels[0].dangerous);
  EXPECT_NEAR(labels[0].time_to_corridor, 0.08, 1e-9);  // centre y = 1.75 at 0.075 s
}

TEST(DifferenceVelocities, CentralOneSidedAndNotAcrossGaps) {
  std::vector<TruthBox> boxes;
  for (int k : {0, 1, 2, 3, 6, 7}) boxes.push_back(box(1, 0.1 * k, 1.0 * k * k, 0.5 * k));
  boxes.push_back(box(2, 0.3, 5.0, 5.0));  // seen once
  differenceVelocities(boxes, 0.1);
  EXPECT_NEAR(boxes[0].velocity.x(), 10.0, 1e-9);   // forward: (1 - 0) / 0.1
  EXPECT_NEAR(boxes[1].velocity.x(), 20.0, 1e-9);   // central: (4 - 0) / 0.2
  EXPECT_NEAR(boxes[2].velocity.x(), 40.0, 1e-9);   // (9 - 1) / 0.2
  EXPECT_NEAR(boxes[3].velocity.x(), 50.0, 1e-9);   // backward only: frame 6 is 0.3 s away
  EXPECT_NEAR(boxes[4].velocity.x(), 130.0, 1e-9);  // forward only: (49 - 36) / 0.1
  EXPECT_NEAR(boxes[5].velocity.x(), 130.0, 1e-9);
  EXPECT_NEAR(boxes[1].velocity.y(), 5.0, 1e-9);
  EXPECT_EQ(boxes[6].velocity, Eigen::Vector3d::Zero());
}

TEST(BoxContains, OrientedBoxAndFinitePointsOnly) {
  const TruthBox b = box(1, 0.0, 10.0, 0.0, 4.0, 2.0, M_PI / 2);  // long along y
  EXPECT_TRUE(boxContains(b, Eigen::Vector3d(10.0, 1.9, 0.5)));
  EXPECT_FALSE(boxContains(b, Eigen::Vector3d(11.5, 0.0, 0.5)));
  EXPECT_TRUE(boxContains(b, Eigen::Vector3d(11.5, 0.0, 0.5), 0.6));
  EXPECT_FALSE(boxContains(b, Eigen::Vector3d(10.0, 0.0, 1.8)));  // above: z in [0, 1.7]
  Cloud cloud;
  cloud.points.emplace_back(10.0f, 1.9f, 0.5f);
  cloud.points.emplace_back(11.5f, 0.0f, 0.5f);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  cloud.points.emplace_back(nan, nan, nan);
  cloud.points.emplace_back(9.5f, -1.0f, 1.0f);
  EXPECT_EQ(countPointsInside(b, cloud), 2u);
}

TEST(TruthLabels, KittiBoxesCarryFrameTimesTrackIdsAndVelocities) {
  kitti::VeloBox a;
  a.frame = 10;
  a.track_id = 4;
  a.type = "Car";
  a.center = Eigen::Vector3d(20.0, 1.0, -0.9);
  a.size = Eigen::Vector3d(4.0, 1.7, 1.5);
  a.yaw = 0.1;
  kitti::VeloBox b = a;
  b.frame = 11;
  b.center.x() = 19.3;  // closing at 7 m/s
  const std::vector<TruthBox> boxes = truthBoxesFromKitti({a, b});
  ASSERT_EQ(boxes.size(), 2u);
  EXPECT_NEAR(boxes[0].t, 1.0, 1e-12);
  EXPECT_EQ(boxes[1].id, 4u);
  EXPECT_EQ(boxes[1].type, "Car");
  EXPECT_DOUBLE_EQ(boxes[0].yaw, 0.1);
  EXPECT_NEAR(boxes[0].velocity.x(), -7.0, 1e-9);
  EXPECT_NEAR(boxes[1].velocity.x(), -7.0, 1e-9);
}

// The shared KITTI sequence (icanc_kitti2bag's data): with the kitti_hdl64e profile only the
// cyclist riding about 6 m ahead (track 1) is truly dangerous, in frames 0..30, all in the
// corridor; the cars closing in frames 110..153 are parked beside the road.
TEST(TruthLabels, KittiSequence0000) {
  namespace fs = std::filesystem;
  const std::string dir = std::string(ICANC_SHARED_DIR) + "/data/kitti_tracking_0000";
  if (!fs::is_directory(dir)) GTEST_SKIP() << "KITTI data not found at " << dir;
  const std::string here = __FILE__;
  const std::string repo = here.substr(0, here.rfind("/test/core/"));
  const CorridorParams c = loadProfile(repo + "/config/kitti_hdl64e.yaml").corridor;
  const std::vector<TruthBox> boxes = truthBoxesFromKitti(
      kitti::toVelodyne(kitti::readLabels(dir + "/label_02/0000.txt"),
                        kitti::readCalib(dir + "/calib/0000.txt")));
  const std::vector<TruthLabel> labels = labelTruths(boxes, c);
  EXPECT_EQ(boxes.size(), 711u);
  std::set<int> frames;
  std::size_t dangerous = 0;
  for (std::size_t i = 0; i < boxes.size(); ++i) {
    if (!labels[i].dangerous) continue;
    ++dangerous;
    EXPECT_EQ(boxes[i].id, 1u);
    EXPECT_EQ(boxes[i].type, "Cyclist");
    frames.insert(static_cast<int>(std::lround(boxes[i].t * 10.0)));
  }
  EXPECT_EQ(dangerous, 31u);
  ASSERT_FALSE(frames.empty());
  EXPECT_EQ(*frames.begin(), 0);
  EXPECT_EQ(*frames.rbegin(), 30);
  // The sequence ends at frame 153 (15.3 s): the labels of its last 2 s (the profile's horizon)
  // are of unknown danger, 220 of the 711 (icanc_kitti2bag prints the count).
  const std::vector<TruthLabel> ending = labelTruths(boxes, c, 15.3);
  std::size_t cut = 0;
  for (std::size_t i = 0; i < boxes.size(); ++i) {
    EXPECT_EQ(ending[i].dangerous, labels[i].dangerous);
    if (!ending[i].horizon_cut) continue;
    ++cut;
    EXPECT_GT(boxes[i].t, 15.3 - c.horizon_s);
  }
  EXPECT_EQ(cut, 220u);
}

}  // namespace
}  // namespace icanc
