// Pins MultiObjectTracker: optimal association keeps ids where greedy nearest would swap, coasting
// through misses and deletion, velocity from stamps, resets on time going backwards or a gap,
// confirmation, and the parameter checks.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "icanc/core/tracking/tracker.hpp"
#include "tracker_boxes.hpp"

namespace icanc {
namespace {

using Result = MultiObjectTracker::UpdateResult;

using test::box;
using test::findId;

std::uint32_t maxId(const MultiObjectTracker& t) {
  std::uint32_t m = 0;
  for (const Track& track : t.tracks()) m = std::max(m, track.id);
  return m;
}

TEST(Tracker, FirstFrameStartsTentativeTracks) {
  MultiObjectTracker t;
  EXPECT_EQ(t.update(3.0, {box(5, 0), box(10, 2)}), Result::kOk);
  ASSERT_EQ(t.tracks().size(), 2u);
  EXPECT_EQ(t.tracks()[0].id, 1u);
  EXPECT_EQ(t.tracks()[1].id, 2u);
  for (const Track& track : t.tracks()) {
    EXPECT_EQ(track.age, 1);
    EXPECT_EQ(track.hits, 1);
    EXPECT_EQ(track.missed, 0);
    EXPECT_FALSE(track.confirmed);
    EXPECT_TRUE(track.velocity().isZero());
    EXPECT_NEAR(track.velocityStd(), std::sqrt(2.0) * t.params().initial_velocity_std, 1e-9);
  }
  EXPECT_EQ(t.tracks()[1].box.center, box(10, 2).center);
}

// Two new tracks 1 m apart (zero velocity yet) both move +0.6 m. Cheapest pair first (greedy
// nearest) takes track 2 -> detection at 0.6 and then track 1 -> 1.6, swapping the ids; the
// optimal assignment keeps them.
TEST(Tracker, OptimalAssociationKeepsIdsWhereGreedyWouldSwap) {
  const TrackerParams p;  // gate 2 m, IoU weight 1
  const auto cost = [&](const Box3D& a, const Box3D& b) {
    const double d = std::hypot(a.center.x() - b.center.x(), a.center.y() - b.center.y());
    return d / p.gate_distance_m + p.iou_weight * (1.0 - bevIoU(a, b));
  };
  const Box3D a0 = box(0, 0), b0 = box(1, 0), a1 = box(0.6, 0), b1 = box(1.6, 0);
  // The trap is real: the cheapest single pair is the wrong one...
  EXPECT_LT(cost(b0, a1), std::min({cost(a0, a1), cost(b0, b1), cost(a0, b1)}));
  // ...and the right pairing is cheaper in total.
  EXPECT_LT(cost(a0, a1) + cost(b0, b1), cost(b0, a1) + cost(a0, b1));

  MultiObjectTracker t(p);
  t.update(0.0, {a0, b0});
  ASSERT_EQ(t.update(0.1, {b1, a1}), Result::kOk);  // reversed order: no help from indices
  ASSERT_EQ(t.tracks().size(), 2u);
  const Track* first = findId(t, 1);
  const Track* second = findId(t, 2);
  ASSERT_TRUE(first && second);
  EXPECT_NEAR(first->box.center.x(), 0.6, 0.1);
  EXPECT_NEAR(second->box.center.x(), 1.6, 0.1);
  EXPECT_EQ(first->hits, 2);
  EXPECT_EQ(second->hits, 2);
  EXPECT_GT(first->velocity().x(), 0.0);
}

// Two pedestrians pass each other 0.6 m apart (boxes overlapping at the crossing), 2 m/s each,
// noisy detections in shuffled order: both keep their id throughout.
TEST(Tracker, CrossingObjectsKeepTheirIds) {
  std::mt19937 rng(11);
  std::normal_distribution<double> noise(0.0, 0.03);
  MultiObjectTracker t;
  std::uint32_t id_a = 0, id_b = 0;
  for (int f = 0; f <= 40; ++f) {
    const double s = 0.1 * f;
    const double xa = -4.0 + 2.0 * s, xb = 4.0 - 2.0 * s;
    std::vector<Box3D> dets{box(xa + noise(rng), 0.3 + noise(rng)),
                            box(xb + noise(rng), -0.3 + noise(rng))};
    std::shuffle(dets.begin(), dets.end(), rng);
    ASSERT_EQ(t.update(100.0 + s, dets), Result::kOk);
    ASSERT_EQ(t.tracks().size(), 2u) << "frame " << f;
    if (f == 0) {
      for (const Track& track : t.tracks()) (track.box.center.y() > 0 ? id_a : id_b) = track.id;
      ASSERT_NE(id_a, id_b);
      continue;
    }
    const Track* a = findId(t, id_a);
    const Track* b = findId(t, id_b);
    ASSERT_TRUE(a && b) << "frame " << f;
    EXPECT_NEAR(a->box.center.x(), xa, 0.2) << "frame " << f;
    EXPECT_NEAR(a->box.center.y(), 0.3, 0.2) << "frame " << f;
    EXPECT_NEAR(b->box.center.x(), xb, 0.2) << "frame " << f;
    EXPECT_NEAR(b->box.center.y(), -0.3, 0.2) << "frame " << f;
  }
  EXPECT_NEAR(findId(t, id_a)->velocity().x(), 2.0, 0.4);
  EXPECT_NEAR(findId(t, id_b)->velocity().x(), -2.0, 0.4);
}

TEST(Tracker, SurvivesMissedFramesThenIsDeleted) {
  TrackerParams p;
  p.max_missed_frames = 2;
  MultiObjectTracker t(p);
  // 1 m/s along x at 10 Hz.
  for (int f = 0; f < 5; ++f) t.update(0.1 * f, {box(0.1 * f, 0)});
  ASSERT_EQ(t.tracks().size(), 1u);
  const std::uint32_t id = t.tracks()[0].id;
  const double vx = t.tracks()[0].velocity().x();
  EXPECT_GT(vx, 0.5);

  // Frame 5 missing: the track coasts, its box moving with the prediction.
  const Box3D before = t.tracks()[0].box;
  t.update(0.5, {});
  ASSERT_EQ(t.tracks().size(), 1u);
  const Track& coasting = t.tracks()[0];
  EXPECT_EQ(coasting.id, id);
  EXPECT_EQ(coasting.missed, 1);
  EXPECT_EQ(coasting.hits, 5);
  EXPECT_EQ(coasting.age, 6);
  EXPECT_TRUE(coasting.confirmed);
  EXPECT_NEAR(coasting.box.center.x() - before.center.x(), 0.1 * vx, 1e-4);
  EXPECT_NEAR(coasting.box.min.x() - before.min.x(), 0.1 * vx, 1e-4);  // extent moves along
  EXPECT_NEAR(coasting.box.size.x(), before.size.x(), 1e-6);

  // Back in frame 6: same id, no new track.
  t.update(0.6, {box(0.6, 0)});
  ASSERT_EQ(t.tracks().size(), 1u);
  EXPECT_EQ(t.tracks()[0].id, id);
  EXPECT_EQ(t.tracks()[0].missed, 0);
  EXPECT_EQ(t.tracks()[0].hits, 6);

  // max_missed_frames (2) misses survive, the third deletes.
  t.update(0.7, {});
  t.update(0.8, {});
  ASSERT_EQ(t.tracks().size(), 1u);
  EXPECT_EQ(t.tracks()[0].missed, 2);
  EXPECT_EQ(t.tracks()[0].age, 9);
  t.update(0.9, {});
  EXPECT_TRUE(t.tracks().empty());

  // The object comes back: a new id, never the deleted one.
  t.update(1.0, {box(1.0, 0)});
  ASSERT_EQ(t.tracks().size(), 1u);
  EXPECT_GT(t.tracks()[0].id, id);
  EXPECT_FALSE(t.tracks()[0].confirmed);
}

TEST(Tracker, DetectionOutsideTheGateStartsANewTrack) {
  MultiObjectTracker t;  // gate 2 m
  t.update(0.0, {box(0, 0)});
  t.update(0.1, {box(2.5, 0)});
  ASSERT_EQ(t.tracks().size(), 2u);
  EXPECT_EQ(findId(t, 1)->missed, 1);
  EXPECT_EQ(findId(t, 1)->hits, 1);
  EXPECT_EQ(findId(t, 2)->hits, 1);
  EXPECT_NEAR(findId(t, 2)->box.center.x(), 2.5, 1e-6);

  // Inside the gate (1.9 m): associated, even with no overlap.
  MultiObjectTracker u;
  u.update(0.0, {box(0, 0)});
  u.update(0.1, {box(0, 1.9)});
  ASSERT_EQ(u.tracks().size(), 1u);
  EXPECT_EQ(u.tracks()[0].hits, 2);
}

// A car track next to a pedestrian: the pedestrian's centre is nearer (0.4 m vs 0.5 m) but the
// car's box overlaps; with the IoU term the car keeps its track and the pedestrian gets a new one.
TEST(Tracker, OverlapBreaksNearDistanceTies) {
  MultiObjectTracker t;  // gate 2 m, IoU weight 1
  t.update(0.0, {box(0, 0, 4.0, 2.0)});
  t.update(0.1, {box(0, 0.4, 0.5, 0.5), box(0.5, 0, 4.0, 2.0)});
  ASSERT_EQ(t.tracks().size(), 2u);
  const Track* car = findId(t, 1);
  ASSERT_TRUE(car);
  EXPECT_EQ(car->hits, 2);
  EXPECT_FLOAT_EQ(car->box.size.x(), 4.0f);
  EXPECT_FLOAT_EQ(findId(t, 2)->box.size.x(), 0.5f);

  // Without the IoU term the nearer centre wins.
  TrackerParams p;
  p.iou_weight = 0;
  MultiObjectTracker u(p);
  u.update(0.0, {box(0, 0, 4.0, 2.0)});
  u.update(0.1, {box(0, 0.4, 0.5, 0.5), box(0.5, 0, 4.0, 2.0)});
  EXPECT_FLOAT_EQ(findId(u, 1)->box.size.x(), 0.5f);
}

// Approaching at -2 m/s along x with irregular frame spacing and epoch-sized stamps: the velocity
// (from stamp differences, not a frame rate) converges, with the right sign early on.
TEST(Tracker, VelocityOfAnApproachingObjectConverges) {
  for (unsigned seed : {3u, 4u, 5u}) {
    SCOPED_TRACE(seed);
    std::mt19937 rng(seed);
    std::normal_distribution<double> noise(0.0, 0.05);
    MultiObjectTracker t;
    const double t0 = 1.7e9;
    double s = 0.0, previous_std = std::numeric_limits<double>::infinity();
    for (int f = 0; f < 40; ++f) {
      // Irregular spacing 0.05, 0.05, 0.1 s (mean 1/15 s): a tracker assuming 10 Hz would report
      // about -3 m/s, one assuming 20 Hz about -1.3 m/s.
      s += f == 0 ? 0.0 : (f % 3 ? 0.05 : 0.1);
      ASSERT_EQ(t.update(t0 + s, {box(20.0 - 2.0 * s + noise(rng), 1.0 + noise(rng))}),
                Result::kOk);
      ASSERT_EQ(t.tracks().size(), 1u);
      const Track& track = t.tracks()[0];
      EXPECT_EQ(track.id, 1u);
      if (f >= 5) {
        EXPECT_LT(track.velocity().x(), -1.0) << "frame " << f;
      }
      if (f < 5) {
        EXPECT_LT(track.velocityStd(), previous_std);
        previous_std = track.velocityStd();
      }
    }
    const Track& track = t.tracks()[0];
    EXPECT_TRUE(track.confirmed);
    EXPECT_NEAR(track.velocity().x(), -2.0, 0.3);
    EXPECT_NEAR(track.velocity().y(), 0.0, 0.3);
    EXPECT_LT(track.velocityStd(), 1.0);
    EXPECT_NEAR(track.box.center.x(), 20.0 - 2.0 * s, 0.15);
  }
}

TEST(Tracker, StampGoingBackwardsResets) {
  MultiObjectTracker t;
  for (int f = 0; f < 3; ++f) {
    EXPECT_EQ(t.update(10.0 + 0.1 * f, {box(5 - 0.1 * f, 0), box(8, 3)}), Result::kOk);
  }
  ASSERT_EQ(t.tracks().size(), 2u);
  EXPECT_TRUE(t.tracks()[0].confirmed);
  const std::uint32_t last_id = maxId(t);

  // Bag loop: back to 5 s. Old tracks gone, new ones from this frame, fresh ids.
  EXPECT_EQ(t.update(5.0, {box(5, 0), box(8, 3)}), Result::kResetTimeBackwards);
  ASSERT_EQ(t.tracks().size(), 2u);
  for (const Track& track : t.tracks()) {
    EXPECT_GT(track.id, last_id);
    EXPECT_EQ(track.age, 1);
    EXPECT_EQ(track.hits, 1);
    EXPECT_FALSE(track.confirmed);
    EXPECT_TRUE(track.velocity().isZero());
  }
  const std::uint32_t reset_id = t.tracks()[0].id;

  // Continues normally from the new time base.
  EXPECT_EQ(t.update(5.1, {box(5, 0), box(8, 3)}), Result::kOk);
  ASSERT_EQ(t.tracks().size(), 2u);
  EXPECT_EQ(t.tracks()[0].id, reset_id);
  EXPECT_EQ(t.tracks()[0].hits, 2);
}

TEST(Tracker, GapLargerThanMaxDtResets) {
  TrackerParams p;
  p.max_dt_s = 1.0;
  MultiObjectTracker t(p);
  t.update(0.5, {box(5, 0)});
  EXPECT_EQ(t.update(1.5, {box(5, 0)}), Result::kOk);  // exactly max_dt_s: fine
  ASSERT_EQ(t.tracks().size(), 1u);
  EXPECT_EQ(t.tracks()[0].hits, 2);

  EXPECT_EQ(t.update(2.75, {box(5, 0)}), Result::kResetGap);
  ASSERT_EQ(t.tracks().size(), 1u);
  EXPECT_EQ(t.tracks()[0].id, 2u);
  EXPECT_EQ(t.tracks()[0].hits, 1);
  EXPECT_EQ(t.update(2.85, {box(5, 0)}), Result::kOk);
  EXPECT_EQ(t.tracks()[0].id, 2u);

  // A non-finite stamp cannot be predicted to: treated as a gap.
  EXPECT_EQ(t.update(std::numeric_limits<double>::quiet_NaN(), {box(5, 0)}), Result::kResetGap);
  EXPECT_EQ(t.tracks()[0].id, 3u);
}

TEST(Tracker, EqualStampIsAZeroDtFrame) {
  MultiObjectTracker t;
  t.update(1.0, {box(5, 0)});
  EXPECT_EQ(t.update(1.0, {box(5.05, 0)}), Result::kOk);
  ASSERT_EQ(t.tracks().size(), 1u);
  EXPECT_EQ(t.tracks()[0].id, 1u);
  EXPECT_EQ(t.tracks()[0].hits, 2);
  EXPECT_TRUE(t.tracks()[0].velocity().allFinite());
  EXPECT_TRUE(t.tracks()[0].velocity().isZero());  // no time passed: nothing to learn a speed from
}

TEST(Tracker, ExplicitResetKeepsCountingIds) {
  MultiObjectTracker t;
  t.update(0.0, {box(1, 0)});
  t.update(0.1, {box(1, 0)});
  t.reset();
  EXPECT_TRUE(t.tracks().empty());
  EXPECT_EQ(t.update(0.0, {box(1, 0)}), Result::kOk);  // first frame after reset: no comparison
  ASSERT_EQ(t.tracks().size(), 1u);
  EXPECT_EQ(t.tracks()[0].id, 2u);
}

TEST(Tracker, TentativeUntilMinHitsThenConfirmedForGood) {
  TrackerParams p;
  p.min_hits_to_confirm = 3;
  p.max_missed_frames = 3;
  MultiObjectTracker t(p);
  t.update(0.0, {box(3, 0)});
  EXPECT_FALSE(t.tracks()[0].confirmed);
  t.update(0.1, {box(3, 0)});
  EXPECT_FALSE(t.tracks()[0].confirmed);
  EXPECT_EQ(t.tracks()[0].hits, 2);
  t.update(0.2, {box(3, 0)});
  EXPECT_TRUE(t.tracks()[0].confirmed);
  t.update(0.3, {});
  t.update(0.4, {});
  ASSERT_EQ(t.tracks().size(), 1u);
  EXPECT_TRUE(t.tracks()[0].confirmed);  // stays confirmed while coasting
  EXPECT_EQ(t.tracks()[0].age, 5);

  // Misses do not count as hits: a tentative track coasting stays tentative.
  MultiObjectTracker u(p);
  u.update(0.0, {box(3, 0)});
  u.update(0.1, {});
  u.update(0.2, {});
  EXPECT_FALSE(u.tracks()[0].confirmed);
  EXPECT_EQ(u.tracks()[0].age, 3);

  p.min_hits_to_confirm = 1;
  MultiObjectTracker v(p);
  v.update(0.0, {box(3, 0)});
  EXPECT_TRUE(v.tracks()[0].confirmed);
}

// min_birth_points: a sparse detection starts no track, but keeps the track of its object alive
// and counts as its hit (a far car whose sliver falls to a few returns between denser frames).
TEST(Tracker, ASparseDetectionUpdatesATrackButStartsNone) {
  TrackerParams p;
  p.min_birth_points = 10;
  const auto sparse = [](double x, double y) {
    Box3D b = box(x, y);
    b.num_points = 6;
    return b;
  };
  MultiObjectTracker t(p);
  t.update(0.0, {sparse(20, 5)});
  EXPECT_TRUE(t.tracks().empty());
  t.update(0.1, {box(3, 0), sparse(20, 5)});
  ASSERT_EQ(t.tracks().size(), 1u);  // the dense one only
  t.update(0.2, {sparse(3, 0)});
  ASSERT_EQ(t.tracks().size(), 1u);
  EXPECT_EQ(t.tracks()[0].hits, 2);
  EXPECT_EQ(t.tracks()[0].missed, 0);
  EXPECT_TRUE(t.tracks()[0].confirmed);

  p.min_birth_points = 0;  // off: any detection starts a track
  MultiObjectTracker u(p);
  u.update(0.0, {sparse(20, 5)});
  EXPECT_EQ(u.tracks().size(), 1u);
}

// The matched box is the detection as seen (extent, point count) moved by the filter's
// correction: its near face (x, toward the sensor at the origin) lands between the predicted
// face (4.6) and the detected one (4.7), and its whole extent moves with it.
TEST(Tracker, MatchedBoxIsTheDetectionMovedByTheFilter) {
  MultiObjectTracker t;
  t.update(0.0, {box(5, 0)});
  Box3D det = box(5.3, 0.1, 1.2, 0.6, 1.5);
  det.footprint = {{det.min.head<2>(), Eigen::Vector2f(5.3f, det.max.y())},
                   {Eigen::Vector2f(5.3f, det.min.y()), det.max.head<2>()}};
  t.update(0.1, {det});
  ASSERT_EQ(t.tracks().size(), 1u);
  const Track& track = t.tracks()[0];
  EXPECT_EQ(track.box.size, det.size);
  EXPECT_EQ(track.box.num_points, det.num_points);
  const Eigen::Vector3f shift = track.box.center - det.center;
  EXPECT_TRUE((track.box.min - det.min).isApprox(shift, 1e-5f));
  EXPECT_TRUE((track.box.max - det.max).isApprox(shift, 1e-5f));
  EXPECT_GT(track.box.min.x(), 4.6f);  // pulled towards the measurement...
  EXPECT_LT(track.box.min.x(), 4.7f);  // ...but filtered
  // The footprint's parts move with it, while matched and while coasting.
  ASSERT_EQ(track.box.footprint.size(), 2u);
  for (std::size_t i = 0; i < 2; ++i) {
    EXPECT_TRUE((track.box.footprint[i].min - det.footprint[i].min).isApprox(shift.head<2>(), 1e-5f));
    EXPECT_TRUE((track.box.footprint[i].max - det.footprint[i].max).isApprox(shift.head<2>(), 1e-5f));
  }
  const Box3D before = track.box;
  t.update(0.2, {});
  const Box3D& coasting = t.tracks()[0].box;
  const Eigen::Vector2f moved = (coasting.min - before.min).head<2>();
  EXPECT_GT(moved.norm(), 0.01f);
  EXPECT_TRUE((coasting.footprint[1].max - before.footprint[1].max).isApprox(moved, 1e-5f));
}

TEST(Tracker, NonFiniteDetectionsAreIgnored) {
  MultiObjectTracker t;
  Box3D bad = box(0, 0);
  bad.center.x() = std::numeric_limits<float>::quiet_NaN();
  t.update(0.0, {bad, box(4, 0)});
  ASSERT_EQ(t.tracks().size(), 1u);
  t.update(0.1, {box(4, 0), bad});
  ASSERT_EQ(t.tracks().size(), 1u);
  EXPECT_EQ(t.tracks()[0].hits, 2);
  EXPECT_TRUE(t.tracks()[0].filter.state().allFinite());
}

TEST(Tracker, ManyObjectsAllAssociated) {
  // 200 objects on a grid, 2 m apart, all moving: every track keeps its id and is hit each frame.
  std::vector<Box3D> dets;
  MultiObjectTracker t;
  for (int f = 0; f < 10; ++f) {
    dets.clear();
    for (int k = 0; k < 200; ++k) {
      dets.push_back(box(2.0 * (k % 20) + 0.05 * f, 2.0 * (k / 20) - 0.03 * f));
    }
    t.update(0.1 * f, dets);
  }
  ASSERT_EQ(t.tracks().size(), 200u);
  for (const Track& track : t.tracks()) {
    EXPECT_EQ(track.hits, 10);
    EXPECT_LE(track.id, 200u);
    const int k = static_cast<int>(track.id) - 1;
    EXPECT_NEAR(track.box.center.x(), 2.0 * (k % 20) + 0.45, 0.05);
  }
}

// A still object whose box jumps 1.5 m for one frame (a stray return merged into its cluster):
// the Huber-robust update lets it count as a 3-sigma innovation, the plain update as all of it.
TEST(Tracker, RobustUpdateLimitsWhatAOneFrameJumpDoesToTheVelocity) {
  TrackerParams robust, plain;
  plain.robust_sigma = 0.0;
  MultiObjectTracker r(robust), k(plain);
  for (int f = 0; f < 30; ++f) {
    const double x = f == 20 ? 11.5 : 10.0;
    r.update(0.1 * f, {box(x, 2.0)});
    k.update(0.1 * f, {box(x, 2.0)});
    if (f != 20) continue;
    EXPECT_LT(std::abs(r.tracks()[0].velocity().x()), 0.6);  // measured 0.37 m/s
    EXPECT_GT(k.tracks()[0].velocity().x(), 1.5);            // measured 2.19 m/s
  }
  EXPECT_LT(std::abs(r.tracks()[0].velocity().x()), 0.3);
}

// ...while an object that really starts moving (still, then 2 m/s) is followed: the innovations
// keep coming, and the filter catches up within a second.
TEST(Tracker, RobustUpdateStillFollowsARealStart) {
  MultiObjectTracker t;
  double x = 10.0;
  for (int f = 0; f < 40; ++f) {
    if (f >= 20) x -= 0.2;
    t.update(0.1 * f, {box(x, 2.0)});
    if (f == 30) {
      EXPECT_LT(t.tracks()[0].velocity().x(), -1.6);
    }
  }
  ASSERT_EQ(t.tracks().size(), 1u);
  EXPECT_NEAR(t.tracks()[0].velocity().x(), -2.0, 0.2);
}

TEST(TrackerParams, Validate) {
  EXPECT_EQ(validate(TrackerParams()), "");
  TrackerParams p;
  p.gate_distance_m = -1;
  EXPECT_EQ(validate(p), "tracker.gate_distance_m must be > 0 (got -1)");

  const auto expectBad = [](TrackerParams bad, const std::string& name, const std::string& value) {
    const std::string why = validate(bad);
    EXPECT_NE(why.find("tracker." + name), std::string::npos) << why;
    EXPECT_NE(why.find("(got " + value + ")"), std::string::npos) << why;
  };
  p = TrackerParams();
  p.gate_distance_m = 0;
  expectBad(p, "gate_distance_m", "0");
  p = TrackerParams();
  p.gate_distance_m = std::numeric_limits<float>::quiet_NaN();
  expectBad(p, "gate_distance_m", "nan");
  p = TrackerParams();
  p.iou_weight = -0.5f;
  expectBad(p, "iou_weight", "-0.5");
  p = TrackerParams();
  p.min_hits_to_confirm = 0;
  expectBad(p, "min_hits_to_confirm", "0");
  p = TrackerParams();
  p.min_birth_points = -1;
  expectBad(p, "min_birth_points", "-1");
  p = TrackerParams();
  p.max_missed_frames = -1;
  expectBad(p, "max_missed_frames", "-1");
  p = TrackerParams();
  p.accel_std = -3;
  expectBad(p, "accel_std", "-3");
  p = TrackerParams();
  p.measurement_std_m = 0;
  expectBad(p, "measurement_std_m", "0");
  p = TrackerParams();
  p.initial_velocity_std = -5;
  expectBad(p, "initial_velocity_std", "-5");
  p = TrackerParams();
  p.max_dt_s = 0;
  expectBad(p, "max_dt_s", "0");
  p = TrackerParams();
  p.robust_sigma = -1;
  expectBad(p, "robust_sigma", "-1");
  p = TrackerParams();
  p.max_dt_s = std::numeric_limits<double>::infinity();
  expectBad(p, "max_dt_s", "inf");
  p = TrackerParams();
  p.steady_accel_std = -0.1;
  expectBad(p, "steady_accel_std", "-0.1");
  p = TrackerParams();
  p.mode_switch_rate_per_s = 0;
  expectBad(p, "mode_switch_rate_per_s", "0");

  // Boundaries that are allowed.
  p = TrackerParams();
  p.iou_weight = 0;
  p.max_missed_frames = 0;
  p.accel_std = 0;
  p.steady_accel_std = 0;
  p.min_hits_to_confirm = 1;
  EXPECT_EQ(validate(p), "");
}

}  // namespace
}  // namespace icanc
