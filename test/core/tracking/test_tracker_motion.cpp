// The tracker keeps what free space says of each obstacle: the state follows its detections'
// readings and changes only on readings in a row.
#include <gtest/gtest.h>

#include "tracker_boxes.hpp"

namespace icanc {
namespace {

MotionEvidence reading(MotionState state) {
  if (state == MotionState::kMoving) return MotionEvidence{40, 20, 10};
  if (state == MotionState::kStatic) return MotionEvidence{40, 0, 35};
  return MotionEvidence{40, 1, 5};
}

Box3D withMotion(Box3D b, MotionState state) {
  b.motion = reading(state);
  return b;
}

TEST(TrackerMotion, JitteringFragmentStaysStatic) {
  // A wall fragment whose box centre jumps 0.3 m a frame (its visible part changes) but whose
  // returns lie on surfaces seen before: static, whatever its filter makes of the jumps.
  MultiObjectTracker tracker;
  for (int k = 0; k < 10; ++k) {
    const double jitter = (k % 2 == 0 ? 0.0 : 0.3);
    tracker.update(0.1 * k, {withMotion(test::box(10.0 + jitter, 3.0 + jitter), MotionState::kStatic)});
  }
  ASSERT_EQ(tracker.tracks().size(), 1u);
  const Track* t = &tracker.tracks().front();
  EXPECT_EQ(t->motion, MotionState::kStatic);
  EXPECT_EQ(t->evidence.seen, 35);
  // Held at zero: the jumps of its visible part are not read as motion.
  EXPECT_LT(t->velocity().head<2>().norm(), 0.05);
  EXPECT_LT(t->velocityStd(), 0.1);
}

TEST(TrackerMotion, WalkerMeasuredFromItsFirstFrames) {
  MultiObjectTracker tracker;
  for (int k = 0; k < 6; ++k)
    tracker.update(0.1 * k, {withMotion(test::box(10.0, -3.0 + 0.14 * k), MotionState::kMoving)});
  ASSERT_EQ(tracker.tracks().size(), 1u);
  const Track* t = &tracker.tracks().front();
  EXPECT_EQ(t->motion, MotionState::kMoving);
  EXPECT_NEAR(t->velocity().y(), 1.4, 0.3);
}

TEST(TrackerMotion, StandingWalkerStartsToWalk) {
  // Static for a second, then walking at 1.4 m/s: moving after two moving readings.
  MultiObjectTracker tracker;
  double y = -3.0;
  for (int k = 0; k < 10; ++k)
    tracker.update(0.1 * k, {withMotion(test::box(10.0, y), MotionState::kStatic)});
  EXPECT_EQ(tracker.tracks().front().motion, MotionState::kStatic);
  EXPECT_EQ(tracker.tracks().front().velocity().head<2>().norm(), 0.0);
  y += 0.14;
  tracker.update(1.0, {withMotion(test::box(10.0, y), MotionState::kMoving)});
  EXPECT_EQ(tracker.tracks().front().motion, MotionState::kStatic);  // one glimpse is not enough
  for (int k = 11; k < 16; ++k) {
    y += 0.14;
    tracker.update(0.1 * k, {withMotion(test::box(10.0, y), MotionState::kMoving)});
  }
  const Track* t = &tracker.tracks().front();
  EXPECT_EQ(t->motion, MotionState::kMoving);
  EXPECT_GT(t->velocity().y(), 0.7);
}

TEST(TrackerMotion, UnknownReadingsKeepTheState) {
  Track track;
  EXPECT_FALSE(updateMotionState(track, reading(MotionState::kUnknown)));
  EXPECT_EQ(track.motion, MotionState::kUnknown);
  EXPECT_TRUE(updateMotionState(track, reading(MotionState::kStatic)));
  EXPECT_FALSE(updateMotionState(track, reading(MotionState::kUnknown)));
  EXPECT_EQ(track.motion, MotionState::kStatic);
  // Moving: static again only after three static readings in a row.
  updateMotionState(track, reading(MotionState::kMoving));
  updateMotionState(track, reading(MotionState::kMoving));
  EXPECT_EQ(track.motion, MotionState::kMoving);
  updateMotionState(track, reading(MotionState::kStatic));
  updateMotionState(track, reading(MotionState::kStatic));
  EXPECT_EQ(track.motion, MotionState::kMoving);
  updateMotionState(track, reading(MotionState::kStatic));
  EXPECT_EQ(track.motion, MotionState::kStatic);
}

}  // namespace
}  // namespace icanc
