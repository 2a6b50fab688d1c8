// Pins TrackerParams::merge_hold_m / merge_hold_frames: two walkers side by side seen as one box
// for a few frames (mount_robot16_clutter with the range split), a pedestrian standing 1.3 m from
// the one whose track did not get that box. The track stays where it is instead of jumping to the
// pedestrian, outlives the merge, and takes its own walker back when the two come apart.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "icanc/core/tracking/tracker.hpp"
#include "tracker_boxes.hpp"

namespace icanc {
namespace {

using test::box;
using test::findId;

constexpr double kSpeed = -1.2;            // both walkers toward the sensor [m/s]
constexpr double kLeftY = 0.55, kRightY = 1.35;
constexpr int kMergeFrom = 10, kMergeTo = 13;  // frames seen as one box (4 frames)
constexpr int kFrames = 30;

// One frame's detections: the walkers (0.2 m deep, 0.45 m across as seen from the front), as one
// box while merged; the pedestrian standing at (9.7, 2.15) from the second merged frame on.
std::vector<Box3D> frame(int k) {
  const double x = 12.0 + kSpeed * 0.1 * k;
  std::vector<Box3D> detections;
  if (k >= kMergeFrom && k <= kMergeTo) {
    detections.push_back(box(x, 0.5 * (kLeftY + kRightY), 0.2, 1.25));
  } else {
    detections.push_back(box(x, kLeftY, 0.2, 0.45));
    detections.push_back(box(x, kRightY, 0.2, 0.45));
  }
  if (k > kMergeFrom) detections.push_back(box(9.7, 2.15, 0.2, 0.45));
  return detections;
}

struct Replayed {
  double closest_to_pedestrian = 1e9;  // of the walkers' tracks (ids 1, 2), over the frames [m]
  const Track* left = nullptr;
  const Track* right = nullptr;
};

Replayed replay(MultiObjectTracker& t) {
  Replayed run;
  for (int k = 0; k < kFrames; ++k) {
    t.update(0.1 * k, frame(k));
    for (std::uint32_t id : {1u, 2u}) {
      if (const Track* walker = findId(t, id)) {
        const double d = std::hypot(walker->box.center.x() - 9.7, walker->box.center.y() - 2.15);
        run.closest_to_pedestrian = std::min(run.closest_to_pedestrian, d);
      }
    }
  }
  run.left = findId(t, 1);
  run.right = findId(t, 2);
  return run;
}

TrackerParams held() {
  TrackerParams p;
  p.merge_hold_m = 0.3f;
  p.merge_hold_frames = 10;
  return p;
}

TEST(TrackerMerge, TheTrackInsideAMergeCoastsAndTakesItsOwnWalkerBack) {
  // The trap is real: without the rule, the walker whose track did not get the merged box takes
  // the pedestrian's (1.27 m from where it is predicted, inside the fixed 2 m gate).
  MultiObjectTracker plain;
  const Replayed trapped = replay(plain);
  EXPECT_LT(trapped.closest_to_pedestrian, 0.4);

  MultiObjectTracker t(held());
  const Replayed run = replay(t);
  EXPECT_GT(run.closest_to_pedestrian, 0.8);
  ASSERT_TRUE(run.left && run.right);
  EXPECT_NEAR(run.left->box.center.y(), kLeftY, 0.05);
  EXPECT_NEAR(run.right->box.center.y(), kRightY, 0.05);
  for (const Track* walker : {run.left, run.right}) {
    EXPECT_NEAR(walker->velocity().x(), kSpeed, 0.1);
    EXPECT_NEAR(walker->velocity().y(), 0.0, 0.15);
    EXPECT_EQ(walker->missed, 0);
    EXPECT_EQ(walker->held, 0);
  }
  // The pedestrian got a track of its own, standing.
  const Track* standing = findId(t, 3);
  ASSERT_TRUE(standing);
  EXPECT_NEAR(standing->box.center.x(), 9.7, 0.05);
  EXPECT_LT(standing->velocity().head<2>().norm(), 0.1);
}

TEST(TrackerMerge, AHeldTrackIsDroppedAfterMergeHoldFramesAndTheMisses) {
  // A pedestrian standing against a parked car: from frame 5 on seen only as part of the car's
  // box, which the car's track takes. The pedestrian's track is held 10 frames, then missed 3.
  TrackerParams p = held();
  MultiObjectTracker t(p);
  const Box3D car = box(10.0, 3.4, 4.5, 1.8);
  const Box3D pedestrian = box(10.0, 2.25, 0.45, 0.45);
  const Box3D both = box(10.0, 3.05, 4.5, 2.5);
  int last_frame_alive = -1;
  for (int k = 0; k < 40; ++k) {
    if (k < 5) {
      t.update(0.1 * k, {car, pedestrian});
    } else {
      t.update(0.1 * k, {both});
    }
    const Track* track = findId(t, 2);
    if (track) {
      last_frame_alive = k;
      if (k >= 5) {
        EXPECT_EQ(track->held, std::min(k - 4, p.merge_hold_frames)) << k;
        EXPECT_EQ(track->missed, std::max(0, k - 4 - p.merge_hold_frames)) << k;
      }
    }
  }
  EXPECT_EQ(last_frame_alive, 4 + p.merge_hold_frames + p.max_missed_frames);
  // Without the rule it is gone after the misses alone.
  MultiObjectTracker plain;
  last_frame_alive = -1;
  for (int k = 0; k < 40; ++k) {
    plain.update(0.1 * k, k < 5 ? std::vector<Box3D>{car, pedestrian} : std::vector<Box3D>{both});
    if (findId(plain, 2)) last_frame_alive = k;
  }
  EXPECT_EQ(last_frame_alive, 4 + p.max_missed_frames);
}

// A pedestrian standing against a parked car, then seen only in one box with it (the classic
// chain's 0.6 m clustering, mount_roof64_clutter), a sliver of the car's far side beside. Both
// tracks lie inside the merged box. It goes to the car's track, which it fits best; the
// pedestrian's coasts inside it. (When the pedestrian's track could take the merged box, the
// assignment, which pairs as many tracks as it can, gave it the merged box and the car's track
// the sliver, 1.7 m off. Checked with the rule removed.)
TEST(TrackerMerge, AMergedBoxGoesToTheTrackItFitsBest) {
  MultiObjectTracker t(held());
  const Box3D car = box(10.0, 3.4, 4.5, 1.8);
  const Box3D pedestrian = box(10.0, 2.25, 0.45, 0.45);
  const Box3D both = box(10.0, 3.05, 4.5, 2.5);
  const Box3D sliver = box(11.5, 4.2, 1.5, 0.06);
  for (int k = 0; k < 10; ++k) t.update(0.1 * k, {car, pedestrian});
  for (int k = 10; k < 15; ++k) {
    t.update(0.1 * k, {both, sliver});
    const Track* car_track = findId(t, 1);
    const Track* pedestrian_track = findId(t, 2);
    ASSERT_TRUE(car_track && pedestrian_track) << k;
    EXPECT_GT(car_track->box.size.y(), 2.0f) << k;  // the merged box, not the sliver
    EXPECT_EQ(pedestrian_track->held, k - 9) << k;
    EXPECT_NEAR(pedestrian_track->box.center.y(), 2.25, 0.01) << k;
  }
}

// A walker entering another object's box (a U-shaped counter's, 3 x 3 m, which its own track
// takes), its box jittering 0.4 m across. Its young track does not know yet where it will be:
// held to its prediction plus merge_hold_m alone (0.3 m), it was refused its own box and took the
// counter's, the counter's track took the walker's and both restarted again and again. With three
// standard deviations of the predicted position added, both keep their ids.
TEST(TrackerMerge, AYoungTrackIsNotHeldToAPlaceItDoesNotKnow) {
  MultiObjectTracker t(held());
  const Box3D counter = box(10.0, 0.0, 3.0, 3.0, 1.0);
  for (int k = 0; k < 10; ++k) t.update(0.1 * k, {counter});  // the counter's track first
  for (int k = 10; k < 40; ++k) {
    const double y = 0.9 + (k % 2 ? 0.2 : -0.2);  // the walker's box, 0.3 m wide
    t.update(0.1 * k, {counter, box(7.5 + 0.1 * k, y, 0.3, 0.3)});
    ASSERT_EQ(t.tracks().size(), 2u) << k;
    EXPECT_EQ(t.tracks()[0].id, 1u) << k;
    EXPECT_NEAR(t.tracks()[0].box.center.x(), 10.0, 0.1) << k;
    EXPECT_EQ(t.tracks()[1].id, 2u) << k;
  }
  EXPECT_NEAR(t.tracks()[1].velocity().x(), 1.0, 0.1);
}

TEST(TrackerMerge, Validate) {
  TrackerParams p = held();
  EXPECT_TRUE(validate(p).empty());
  p.merge_hold_m = -0.1f;
  EXPECT_NE(validate(p).find("merge_hold_m"), std::string::npos);
  p = held();
  p.merge_hold_m = std::nanf("");
  EXPECT_NE(validate(p).find("merge_hold_m"), std::string::npos);
  p = held();
  p.merge_hold_frames = -1;
  EXPECT_NE(validate(p).find("merge_hold_frames"), std::string::npos);
}

}  // namespace
}  // namespace icanc
