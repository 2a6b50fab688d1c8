// Pins TrackerParams::hidden_hold_frames: a pedestrian standing beside a parked car is hidden for
// a few frames behind a walker passing close to the sensor (mount_robot16_clutter: walker 5
// behind walker 3). Meanwhile a sliver of the car's side shows beside the near walker, its edge
// moving with that walker's shadow. The standing pedestrian's track does not take the sliver (and
// its motion): it coasts hidden, outlives the occlusion, and takes its pedestrian back, standing.
// A hidden track still takes a detection where it is predicted.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "icanc/core/tracking/tracker.hpp"
#include "tracker_boxes.hpp"

namespace icanc {
namespace {

using test::box;
using test::findId;

constexpr double kPedX = 6.0, kPedY = 2.0;     // standing, seen from the origin
constexpr int kHiddenFrom = 8, kHiddenTo = 11;  // frames it is hidden (4)
constexpr int kFrames = 20;

// One frame's detections: the pedestrian (0.5 m across) while seen; while hidden, the near walker
// (1.2 m across at x 2, wholly in front of it) and a sliver of the car's side (y 2.5) that slides
// 0.3 m toward the sensor a frame.
std::vector<Box3D> frame(int k) {
  if (k < kHiddenFrom || k > kHiddenTo) return {box(kPedX, kPedY, 0.5, 0.5)};
  return {box(2.0, 0.8, 0.4, 1.2), box(5.3 - 0.3 * (k - kHiddenFrom), 2.5, 0.5, 0.05)};
}

TrackerParams params(int hidden_hold_frames) {
  TrackerParams p;
  p.hidden_hold_frames = hidden_hold_frames;
  return p;
}

struct Replayed {
  double fastest = 0.0;  // the pedestrian's track's speed, the largest over the frames [m/s]
  double farthest = 0.0;  // its box centre from the pedestrian, the largest [m]
  int held_max = 0;
  const Track* pedestrian = nullptr;
};

Replayed replay(MultiObjectTracker& t) {
  Replayed run;
  for (int k = 0; k < kFrames; ++k) {
    t.update(0.1 * k, frame(k));
    const Track* track = findId(t, 1);
    if (track == nullptr) continue;
    run.fastest = std::max(run.fastest, track->velocity().head<2>().norm());
    run.farthest = std::max(run.farthest, std::hypot(track->box.center.x() - kPedX,
                                                     track->box.center.y() - kPedY));
    run.held_max = std::max(run.held_max, track->held);
  }
  run.pedestrian = findId(t, 1);
  return run;
}

TEST(TrackerHidden, AHiddenTrackCoastsInsteadOfTakingWhatShowsBesideTheNearerObject) {
  MultiObjectTracker held(params(5));
  const Replayed run = replay(held);
  ASSERT_NE(run.pedestrian, nullptr);  // the same track, back on its pedestrian
  EXPECT_NEAR(run.pedestrian->box.center.x(), kPedX, 0.05);
  EXPECT_NEAR(run.pedestrian->box.center.y(), kPedY, 0.05);
  EXPECT_LT(run.fastest, 0.1);
  EXPECT_LT(run.farthest, 0.1);
  EXPECT_EQ(run.held_max, kHiddenTo - kHiddenFrom + 1);
  EXPECT_EQ(run.pedestrian->held, 0);
  EXPECT_EQ(run.pedestrian->missed, 0);

  MultiObjectTracker off(params(0));  // as before: the track takes the sliver and its motion
  const Replayed taken = replay(off);
  EXPECT_GT(taken.farthest, 1.0);
  EXPECT_GT(taken.fastest, 1.0);
}

// Beyond hidden_hold_frames a hidden track counts misses again, and is dropped after
// max_missed_frames of them, as any track that is not seen.
TEST(TrackerHidden, TheHoldEndsAfterHiddenHoldFrames) {
  MultiObjectTracker t(params(2));
  for (int k = 0; k < kHiddenFrom; ++k) t.update(0.1 * k, frame(k));
  const Box3D near = box(2.0, 0.8, 0.4, 1.2);
  for (int k = kHiddenFrom; k < kHiddenFrom + 2; ++k) {
    t.update(0.1 * k, {near});
    ASSERT_NE(findId(t, 1), nullptr) << k;
    EXPECT_EQ(findId(t, 1)->missed, 0) << k;
  }
  for (int k = kHiddenFrom + 2; k < kHiddenFrom + 2 + t.params().max_missed_frames; ++k) {
    t.update(0.1 * k, {near});
    ASSERT_NE(findId(t, 1), nullptr) << k;
  }
  t.update(0.1 * (kHiddenFrom + 2 + t.params().max_missed_frames), {near});
  EXPECT_EQ(findId(t, 1), nullptr);
}

// Side by side, or in front, a nearer object hides nothing: the track takes its own detection.
TEST(TrackerHidden, WhatStandsBesideOrInFrontIsNotHidden) {
  MultiObjectTracker t(params(5));
  for (int k = 0; k < kFrames; ++k) {
    // A walker at the pedestrian's range beside it, and one behind it (farther).
    t.update(0.1 * k, {box(kPedX, kPedY, 0.5, 0.5), box(kPedX, kPedY - 0.8, 0.5, 0.5),
                       box(kPedX + 3.0, kPedY + 1.0, 0.5, 2.0)});
  }
  ASSERT_EQ(t.tracks().size(), 3u);
  for (const Track& track : t.tracks()) {
    EXPECT_EQ(track.held, 0) << track.id;
    EXPECT_EQ(track.hits, kFrames) << track.id;
  }
}

// A box's outline overstates what a near object hides (indoor: a walker 1 m from the sensor
// "hid" a bin 5 m away beside it). A hidden track still takes the detection where it is
// predicted: the bin keeps its track, not held, and a detection away from it stays another's.
TEST(TrackerHidden, AHiddenTrackStillTakesItsOwnDetection) {
  MultiObjectTracker t(params(5));
  const Box3D bin = box(kPedX, kPedY + 0.5, 0.5, 0.5);
  const Box3D walker = box(1.2, 0.2, 0.6, 0.8);
  // The premise: seen from the origin, the walker's outline covers every bearing of the bin's.
  const BearingSpan w = bearingSpan(walker, Eigen::Vector2f::Zero());
  const BearingSpan b = bearingSpan(bin, Eigen::Vector2f::Zero());
  ASSERT_TRUE(w.valid && b.valid);
  EXPECT_LT(w.bearing + w.lo, b.bearing + b.lo);
  EXPECT_GT(w.bearing + w.hi, b.bearing + b.hi);
  for (int k = 0; k < kHiddenFrom; ++k) t.update(0.1 * k, {bin});
  for (int k = kHiddenFrom; k < kFrames; ++k) {
    t.update(0.1 * k, {walker, bin, box(kPedX - 1.0, kPedY + 0.5, 0.5, 0.05)});
    const Track* track = findId(t, 1);
    ASSERT_NE(track, nullptr) << k;
    EXPECT_EQ(track->held, 0) << k;
    EXPECT_EQ(track->hits, k + 1) << k;
    EXPECT_NEAR(track->box.center.x(), kPedX, 0.05) << k;
  }
}

TEST(TrackerHidden, Validate) {
  TrackerParams p = params(5);
  EXPECT_TRUE(validate(p).empty());
  p.hidden_hold_frames = -1;
  EXPECT_NE(validate(p).find("hidden_hold_frames"), std::string::npos);
}

}  // namespace
}  // namespace icanc
