// Pins what the tracker's Kalman filter measures (TrackAnchor): the faces of a box that stay on
// the object (nearest the sensor, not cut by the region of interest) rather than the centre of the
// visible points, the viewpoint deciding which faces those are, a passing car keeping its
// velocity as its visible part changes, a small object seen whole measured by its middle, a jump
// of the extent (a merge with what stands close) not read as motion, the edge of a nearer object's
// shadow not read as motion, and the anchor parameter's names and check.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "icanc/core/tracking/tracker.hpp"

namespace icanc {
namespace {

// An axis-aligned detection spanning [x0, x1] x [y0, y1], 1.5 m high.
Box3D span(double x0, double x1, double y0, double y1) {
  Box3D b;
  b.min = Eigen::Vector3f(x0, y0, 0.0f);
  b.max = Eigen::Vector3f(x1, y1, 1.5f);
  b.center = 0.5f * (b.min + b.max);
  b.size = b.max - b.min;
  b.num_points = 100;
  return b;
}

TrackerParams withAnchor(TrackAnchor anchor) {
  TrackerParams p;
  p.anchor = anchor;
  p.gate_distance_m = 3.5f;  // the road profile's: a car's visible centre jumps metres
  return p;
}

// A parked car ahead, seen from the origin, more of it visible every frame: its rear face (toward
// the sensor) stays at x = 10 while its far end grows 0.3 m a frame. The centre of what is seen
// moves 1.5 m/s; the object does not.
TEST(TrackerAnchor, NearestFaceIsBlindToTheFarSideGrowing) {
  MultiObjectTracker nearest(withAnchor(TrackAnchor::kNearestFace));
  MultiObjectTracker centre(withAnchor(TrackAnchor::kCentre));
  for (int f = 0; f < 10; ++f) {
    const Box3D seen = span(10.0, 10.5 + 0.3 * f, -4.9, -3.1);
    nearest.update(0.1 * f, {seen});
    centre.update(0.1 * f, {seen});
  }
  ASSERT_EQ(nearest.tracks().size(), 1u);
  ASSERT_EQ(centre.tracks().size(), 1u);
  EXPECT_NEAR(nearest.tracks()[0].velocity().x(), 0.0, 0.05);
  EXPECT_NEAR(nearest.tracks()[0].velocity().y(), 0.0, 0.05);
  EXPECT_GT(centre.tracks()[0].velocity().x(), 1.0);  // the centre reads the growth as motion
  // The box is what was seen, not a guess at the hidden part.
  EXPECT_NEAR(nearest.tracks()[0].box.min.x(), 10.0, 0.05);
  EXPECT_NEAR(nearest.tracks()[0].box.max.x(), 13.2, 0.05);
}

// The same boxes seen from x = 20 (a sensor beyond the object): the growing face is now the one
// toward the sensor, so it is followed.
TEST(TrackerAnchor, TheViewpointDecidesWhichFaceIsNear) {
  MultiObjectTracker t(withAnchor(TrackAnchor::kNearestFace));
  TrackerView view;
  view.origin = Eigen::Vector2f(20.0f, 0.0f);
  for (int f = 0; f < 10; ++f) t.update(0.1 * f, {span(10.0, 10.5 + 0.3 * f, -4.9, -3.1)}, view);
  ASSERT_EQ(t.tracks().size(), 1u);
  EXPECT_NEAR(t.tracks()[0].velocity().x(), 3.0, 0.5);
}

// A car 4.6 x 1.8 m at y = -4 passes the sensor at -10 m/s. Ahead of the sensor its rear face is
// seen across its width and its side to a random depth (occluded, sparse); alongside, its whole
// side, to a random depth across (the side away from the road); behind, its front face and its
// side to a random depth. From the third frame on, the velocity stays within 0.5 m/s of the truth
// with kNearestFace, including where the car comes alongside and where it leaves; the centre of
// what is seen is metres per second off.
TEST(TrackerAnchor, PassingCarKeepsItsVelocityAsItsVisiblePartChanges) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> seen_length(0.5, 4.6), seen_width(0.3, 1.8);
  MultiObjectTracker nearest(withAnchor(TrackAnchor::kNearestFace));
  MultiObjectTracker centre(withAnchor(TrackAnchor::kCentre));
  double worst_nearest = 0.0, worst_centre = 0.0;
  for (int f = 0; f < 45; ++f) {
    const double rear = 25.0 - 1.0 * f, front = rear + 4.6;  // 10 m/s at 10 Hz
    double x0 = rear, x1 = front, y1 = -3.1, y0 = y1 - 1.8;
    if (rear > 0.0) x1 = rear + seen_length(rng);    // ahead: the rear face is the near one
    if (front < 0.0) x0 = front - seen_length(rng);  // behind: the front face is
    if (rear <= 0.0 && front >= 0.0) y0 = y1 - seen_width(rng);  // alongside: the side
    const Box3D seen = span(x0, x1, y0, y1);
    nearest.update(0.1 * f, {seen});
    centre.update(0.1 * f, {seen});
    ASSERT_EQ(nearest.tracks().size(), 1u) << "frame " << f;
    ASSERT_EQ(nearest.tracks()[0].id, 1u) << "frame " << f;
    if (f < 3 || centre.tracks().size() != 1u) continue;
    const Eigen::Vector2d truth(-10.0, 0.0);
    worst_nearest = std::max(worst_nearest, (nearest.tracks()[0].velocity().head<2>() - truth).norm());
    worst_centre = std::max(worst_centre, (centre.tracks()[0].velocity().head<2>() - truth).norm());
  }
  EXPECT_LT(worst_nearest, 0.5);
  EXPECT_GT(worst_centre, 2.0);
}

// A truck alongside (it spans the sensor's x throughout), longer than the region of interest
// reaches behind: the region cuts its rear at x = -10 while it moves at -5 m/s. Its front face is
// followed; the middle of what is left would read half the speed.
TEST(TrackerAnchor, AFaceCutByTheRegionOfInterestIsNotFollowed) {
  TrackerView view;
  view.region_min = Eigen::Vector2f(-10.0f, -20.0f);
  view.region_max = Eigen::Vector2f(60.0f, 20.0f);
  view.region_tolerance_m = 0.2f;
  MultiObjectTracker with_region(withAnchor(TrackAnchor::kNearestFace));
  MultiObjectTracker without(withAnchor(TrackAnchor::kNearestFace));
  for (int f = 0; f < 15; ++f) {
    const double front = 8.0 - 0.5 * f;  // -5 m/s, 8 m to 1 m; 20 m long: its rear is cut
    const Box3D seen = span(std::max(-10.0, front - 20.0), front, -4.2, -1.8);
    with_region.update(0.1 * f, {seen}, view);
    without.update(0.1 * f, {seen});
  }
  EXPECT_NEAR(with_region.tracks()[0].velocity().x(), -5.0, 0.2);
  EXPECT_NEAR(without.tracks()[0].velocity().x(), -2.5, 0.3);
}

// A pedestrian-sized box (0.5 m) standing still, each face jittering on its own by 0.1 m (a
// return more or less at each edge): seen whole, its middle averages the two faces' noise, so its
// velocity is steadier than from the near face alone (face_min_extent_m 0).
TEST(TrackerAnchor, ASmallObjectSeenWholeIsMeasuredByItsMiddle) {
  TrackerParams whole = withAnchor(TrackAnchor::kNearestFace), face = whole;
  face.face_min_extent_m = 0.0f;
  std::mt19937 rng(11);
  std::normal_distribution<double> jitter(0.0, 0.1);
  MultiObjectTracker w(whole), n(face);
  double sum_w = 0.0, sum_n = 0.0;
  for (int f = 0; f < 200; ++f) {
    const Box3D seen = span(8.0 + jitter(rng), 8.5 + jitter(rng), 2.0 + jitter(rng), 2.5 + jitter(rng));
    w.update(0.1 * f, {seen});
    n.update(0.1 * f, {seen});
    if (f < 20) continue;
    sum_w += w.tracks()[0].velocity().head<2>().squaredNorm();
    sum_n += n.tracks()[0].velocity().head<2>().squaredNorm();
  }
  EXPECT_LT(std::sqrt(sum_w / 180), 0.8 * std::sqrt(sum_n / 180));
}

// mount_robot16_clutter through the fast path: a wall 2.9 m to the side, seen as a thin box, and a
// pedestrian walking along it 0.15 m off its face, who joins its box where a low 16-beam unit
// cannot tell their tops apart and leaves it again. The face toward the sensor jumps 0.65 m
// towards the vehicle and back: read as motion, 1.1 m/s sideways, into the vehicle's path within
// its 3 s (the predictive model's false danger on the wall). With face_jump_m the face that moved
// less (the wall's far side) is measured while the extent jumps: the wall stands still. A car
// passing at -10 m/s whose visible part jumps by metres keeps its velocity either way.
TEST(TrackerAnchor, AJumpOfTheExtentIsNotMotion) {
  TrackerParams jump = withAnchor(TrackAnchor::kNearestFace), plain = jump;
  jump.face_jump_m = 0.4f;
  MultiObjectTracker with_rule(jump), without(plain);
  double worst_with = 0.0, worst_without = 0.0;
  for (int f = 0; f < 40; ++f) {
    const bool joined = (f >= 10 && f < 20) || f >= 30;
    const Box3D seen = span(-2.0, 9.4, -2.93, joined ? -2.2 : -2.85);
    with_rule.update(0.1 * f, {seen});
    without.update(0.1 * f, {seen});
    ASSERT_EQ(with_rule.tracks().size(), 1u);
    ASSERT_EQ(without.tracks().size(), 1u);
    worst_with = std::max(worst_with, std::abs(with_rule.tracks()[0].velocity().y()));
    worst_without = std::max(worst_without, std::abs(without.tracks()[0].velocity().y()));
  }
  EXPECT_LT(worst_with, 0.1);
  EXPECT_GT(worst_without, 0.8);  // before: the joining pedestrian moved the wall

  std::mt19937 rng(7);
  std::uniform_real_distribution<double> seen_length(0.5, 4.6);
  MultiObjectTracker car(jump);
  double worst_car = 0.0;
  for (int f = 0; f < 20; ++f) {
    const double rear = 25.0 - 1.0 * f;  // ahead, -10 m/s; its far end seen to a random depth
    car.update(0.1 * f, {span(rear, rear + seen_length(rng), -4.9, -3.1)});
    ASSERT_EQ(car.tracks().size(), 1u);
    if (f >= 3)
      worst_car = std::max(worst_car, (car.tracks()[0].velocity().head<2>() -
                                       Eigen::Vector2d(-10.0, 0.0)).norm());
  }
  EXPECT_LT(worst_car, 0.5);
}

// mount_robot16_clutter through the fast path (the Zebra ships it): the same wall, 0.08 m deep as
// the 16-beam unit sees it, whose young track takes in the walker beside it for one frame: its
// face toward the sensor jumps 0.24 m, under face_jump_m (0.4) but three times the wall's own
// depth, which no wall does between two frames; read as motion, the wall came toward the robot at
// 1.1 m/s and the paper's rule kept the lamp on (duty 49.5 -> 79.2 %). Beyond its own depth (at
// least 0.15 m) the jump is a merge. A pedestrian seen whole (0.5 m, measured by its middle) that
// takes in the post beside it jumps by more than half its width: a merge too. A thin board that
// does move keeps its velocity: both its faces move.
TEST(TrackerAnchor, AJumpBeyondAThinObjectsOwnDepthIsNotMotion) {
  TrackerParams jump = withAnchor(TrackAnchor::kNearestFace);
  jump.face_jump_m = 0.4f;
  jump.face_min_extent_m = 1.5f;
  MultiObjectTracker wall(jump);
  double worst_wall = 0.0;
  for (int f = 0; f < 30; ++f) {
    const bool joined = f == 3 || f == 15;
    wall.update(0.1 * f, {span(-2.0, 9.4, -2.93, joined ? -2.61 : -2.85)});
    ASSERT_EQ(wall.tracks().size(), 1u);
    worst_wall = std::max(worst_wall, wall.tracks()[0].velocity().head<2>().norm());
  }
  EXPECT_LT(worst_wall, 0.1);

  MultiObjectTracker walker(jump);
  double worst_walker = 0.0;
  for (int f = 0; f < 30; ++f) {
    const bool joined = f == 4 || f == 5 || f == 16;  // the post 0.28 m beyond its far side
    walker.update(0.1 * f, {span(8.0, joined ? 8.78 : 8.5, 2.0, 2.5)});
    ASSERT_EQ(walker.tracks().size(), 1u);
    worst_walker = std::max(worst_walker, walker.tracks()[0].velocity().head<2>().norm());
  }
  EXPECT_LT(worst_walker, 0.1);

  MultiObjectTracker board(jump);
  for (int f = 0; f < 30; ++f) {
    const double near = -6.0 + 0.1 * f;  // toward the sensor's side at 1 m/s, 0.08 m deep
    board.update(0.1 * f, {span(-2.0, 9.4, near - 0.08, near)});
    ASSERT_EQ(board.tracks().size(), 1u);
  }
  EXPECT_NEAR(board.tracks()[0].velocity().y(), 1.0, 0.1);
  EXPECT_NEAR(board.tracks()[0].velocity().x(), 0.0, 0.1);
}

// pedestrian_near_toward through the fast path: a wall 14 m wide 25 m ahead, and a walker 0.5 m
// wide coming toward the sensor from 12 to 3 m. The walker's shadow splits the wall into two
// pieces whose inner ends move outward with it (to 2 m/s as the walker comes near). Each piece's
// face toward the sensor across the line of sight is that inner end: read as motion, the wall's
// pieces fly sideways. With occlusion_gap_deg the inner end, bordering on the nearer walker, is
// where the view ends: of each piece's two ends the one that moved less against the prediction
// (the outer end) is measured, and the wall stands still. The walker keeps its velocity either way.
TEST(TrackerAnchor, AShadowsEdgeIsNotMotion) {
  TrackerParams rule = withAnchor(TrackAnchor::kNearestFace), plain = rule;
  rule.occlusion_gap_deg = 1.0f;  // the profiles'
  MultiObjectTracker with_rule(rule), without(plain);
  double worst_with = 0.0, worst_without = 0.0, worst_walker = 0.0;
  const auto worst = [](const MultiObjectTracker& t, double& wall, double* walker) {
    for (const Track& track : t.tracks()) {
      if (track.age < 4) continue;
      const Eigen::Vector2d v = track.velocity().head<2>();
      if (std::abs(track.box.center.y()) > 1.0f)  // a piece of the wall
        wall = std::max(wall, v.norm());
      else if (walker)
        *walker = std::max(*walker, (v - Eigen::Vector2d(-3.0, 0.0)).norm());
    }
  };
  for (int f = 0; f < 31; ++f) {
    const double d = 12.0 - 0.3 * f;     // the walker's near face
    const double edge = 25.0 * 0.25 / d;  // its shadow's edges on the wall, y = +-edge
    const std::vector<Box3D> seen = {span(25.0, 25.15, -7.0, -edge), span(d, d + 0.3, -0.25, 0.25),
                                     span(25.0, 25.15, edge, 7.0)};
    with_rule.update(0.1 * f, seen);
    without.update(0.1 * f, seen);
    ASSERT_EQ(with_rule.tracks().size(), 3u);
    ASSERT_EQ(without.tracks().size(), 3u);
    worst(with_rule, worst_with, &worst_walker);
    worst(without, worst_without, &worst_walker);
  }
  EXPECT_LT(worst_with, 0.1);
  EXPECT_GT(worst_without, 1.0);  // before: the shadow's edge moved the wall
  EXPECT_LT(worst_walker, 0.3);

  // A nearer object that does not border on the face's end (a walker more than 5 deg to the side
  // of it) leaves it the face: a sliding door whose inner end moves 0.5 m/s keeps that velocity.
  // Beside the walker from the first frame on, its fixed outer end is measured instead.
  const auto door = [&rule](const Box3D& other) {
    MultiObjectTracker t(rule);
    for (int f = 0; f < 20; ++f)
      t.update(0.1 * f, {span(25.0, 25.15, -7.0, -2.0 + 0.05 * f), other});
    for (const Track& track : t.tracks()) {
      if (track.box.center.y() < -1.0f && track.box.center.x() > 24.0f) return track.velocity().y();
    }
    return std::nan("");
  };
  EXPECT_NEAR(door(span(10.0, 10.3, 0.5, 1.0)), 0.5, 0.1);
  // bearings -4.0 to -1.1 deg: 0.6 deg from the end, then over it
  EXPECT_NEAR(door(span(10.0, 10.3, -0.7, -0.2)), 0.0, 0.1);
  // A wall running from (10, -10) to (60, 10): its near end is 14 m away and its bearings cover the
  // door's end, but at that bearing it lies 29 m away, behind the door: it hides nothing there.
  Box3D diagonal = span(10.0, 60.0, -10.0, 10.0);
  diagonal.hull = {Eigen::Vector2f(10.0f, -10.0f), Eigen::Vector2f(60.0f, 10.0f),
                   Eigen::Vector2f(59.9f, 10.1f), Eigen::Vector2f(9.9f, -9.9f)};
  EXPECT_NEAR(door(diagonal), 0.5, 0.1);
}

TEST(TrackerAnchor, NamesAndValidation) {
  EXPECT_EQ(parseTrackAnchor("centre"), TrackAnchor::kCentre);
  EXPECT_EQ(parseTrackAnchor("nearest_face"), TrackAnchor::kNearestFace);
  EXPECT_EQ(parseTrackAnchor("center"), TrackAnchor::kInvalid);
  EXPECT_STREQ(toString(TrackAnchor::kCentre), "centre");
  EXPECT_STREQ(toString(TrackAnchor::kNearestFace), "nearest_face");
  EXPECT_EQ(TrackerParams().anchor, TrackAnchor::kNearestFace);
  TrackerParams p;
  p.anchor = TrackAnchor::kInvalid;
  EXPECT_EQ(validate(p), "tracker.anchor must be \"centre\" or \"nearest_face\"");
  p = TrackerParams();
  p.face_min_extent_m = -1.0f;
  EXPECT_EQ(validate(p), "tracker.face_min_extent_m must be >= 0 (got -1)");
  p = TrackerParams();
  p.face_jump_m = -0.1f;
  EXPECT_EQ(validate(p), "tracker.face_jump_m must be >= 0 (got -0.1)");
  p = TrackerParams();
  EXPECT_EQ(p.occlusion_gap_deg, 0.0f);  // off unless a profile asks
  p.occlusion_gap_deg = -1.0f;
  EXPECT_EQ(validate(p), "tracker.occlusion_gap_deg must be >= 0 and < 90 (got -1)");
  p.occlusion_gap_deg = std::nanf("");
  EXPECT_EQ(validate(p), "tracker.occlusion_gap_deg must be >= 0 and < 90 (got nan)");
  p.occlusion_gap_deg = 90.0f;
  EXPECT_EQ(validate(p), "tracker.occlusion_gap_deg must be >= 0 and < 90 (got 90)");
}

}  // namespace
}  // namespace icanc
