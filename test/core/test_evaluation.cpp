// Pins the evaluation's counting on hand-built frames.
#include <cmath>

#include <gtest/gtest.h>

#include "icanc/core/evaluation.hpp"

namespace icanc {
namespace {

TruthObject truth(std::uint32_t id, double x, double y, bool dangerous, double ttc = -1.0) {
  TruthObject o;
  o.id = id;
  o.center = Eigen::Vector2d(x, y);
  o.velocity = Eigen::Vector2d(-1.0, 0.0);
  o.num_points = 50;
  o.dangerous = dangerous;
  o.time_to_corridor = ttc;
  return o;
}

DetectedObject det(std::uint32_t id, double x, double y, bool dangerous, double vx = -1.0) {
  DetectedObject d;
  d.id = id;
  d.center = Eigen::Vector2d(x, y);
  d.velocity = Eigen::Vector2d(vx, 0.0);
  d.dangerous = dangerous;
  return d;
}

EvalFrame frame(double t, bool lamp, std::vector<TruthObject> tr, std::vector<DetectedObject> d) {
  EvalFrame f;
  f.t = t;
  f.processed = true;
  f.lamp_on = lamp;
  f.latency_ms = 10.0 * t;
  f.truth = std::move(tr);
  f.detections = std::move(d);
  return f;
}

TEST(Evaluate, ConfusionPerObjectFrame) {
  std::vector<EvalFrame> frames;
  // TP (dangerous, flagged), FN (dangerous, not flagged), FP (safe, flagged), TN, FN (unseen).
  frames.push_back(frame(0.0, true, {truth(1, 5, 0, true, 1.0), truth(2, 10, 5, true, 1.0),
                                     truth(3, 8, -4, false), truth(4, 20, 0, false),
                                     truth(5, 30, 0, true, 1.0)},
                         {det(11, 5.2, 0, true), det(12, 10, 5.3, false), det(13, 8, -4, true),
                          det(14, 20.5, 0, false)}));
  const EvalReport r = evaluate(frames, EvalParams());
  EXPECT_EQ(r.danger.tp, 1u);
  EXPECT_EQ(r.danger.fn, 2u);
  EXPECT_EQ(r.danger.fp, 1u);
  EXPECT_EQ(r.danger.tn, 1u);
  EXPECT_DOUBLE_EQ(r.danger.precision(), 0.5);
  EXPECT_DOUBLE_EQ(r.danger.recall(), 1.0 / 3.0);
  EXPECT_DOUBLE_EQ(r.danger.accuracy(), 2.0 / 5.0);
  EXPECT_DOUBLE_EQ(r.danger.f1(), 2.0 / (2.0 + 1.0 + 2.0));
  EXPECT_EQ(r.detection.tp, 4u);
  EXPECT_EQ(r.detection.fn, 1u);
  EXPECT_EQ(r.detection.fp, 0u);
}

TEST(Evaluate, UnmatchedDangerousDetectionIsAFalseAlarmOnlyInScope) {
  EvalParams p;
  p.fov_half_angle_deg = 45.0;
  std::vector<EvalFrame> frames{frame(0.0, true, {}, {det(1, 5, 0, true), det(2, -5, 0, true),
                                                       det(3, 50, 0, true), det(4, 6, 1, false)})};
  const EvalReport r = evaluate(frames, p);
  EXPECT_EQ(r.danger.fp, 1u);  // behind (outside the 45 deg sector) and beyond 40 m are not scored
  EXPECT_EQ(r.false_alarms_unmatched, 1u);
  EXPECT_EQ(r.detection.fp, 2u);
}

// Two clusters on one car (its rear face, and a roof scan line at a fixed range from the sensor):
// the matching takes the one whose centre is nearer the true centre, the other is a fragment. The
// car counts as flagged when either is dangerous, once; a fragment flagged on a safe object is that
// object's false positive, not a false alarm of its own; detection still counts the extra cluster.
TEST(Evaluate, AFragmentOfATrueObjectCountsForItsDanger) {
  TruthObject car = truth(1, 18.0, -2.2, true, 1.0), parked = truth(2, 30.0, -4.0, false);
  car.size = parked.size = Eigen::Vector2d(4.7, 1.9);
  std::vector<EvalFrame> frames{
      frame(0.0, true, {car, parked},
            {det(10, 15.7, -2.2, true), det(11, 16.6, -2.2, false),     // the car: rear, roof line
             det(20, 30.0, -4.0, false), det(21, 28.0, -4.0, true),     // the parked car, a fragment
             det(30, 18.0, 3.0, true)})};                               // nothing there
  const EvalReport r = evaluate(frames, EvalParams());
  EXPECT_EQ(r.danger.tp, 1u);  // the car, through its rear face (the roof line is matched)
  EXPECT_EQ(r.danger.fn, 0u);
  EXPECT_EQ(r.danger.fp, 2u);  // the parked car through its fragment, and the detection at y = 3
  EXPECT_EQ(r.false_alarms_unmatched, 1u);
  EXPECT_EQ(r.danger.tn, 0u);
  EXPECT_EQ(r.detection.tp, 2u);
  EXPECT_EQ(r.detection.fp, 3u);
}

TEST(Evaluate, OptimalMatchingNotGreedy) {
  // True objects at x = 10.0 and 11.4, detections at 10.7 and 12.8 (gate 1.5). Nearest-first
  // greedy pairs 11.4 with 10.7 (0.7 m) and then 10.0 has nothing within the gate; the optimal
  // matching pairs 10.0-10.7 and 11.4-12.8.
  std::vector<EvalFrame> frames{frame(0.0, false, {truth(1, 10.0, 0, false), truth(2, 11.4, 0, false)},
                                      {det(7, 10.7, 0, false), det(8, 12.8, 0, false)})};
  EvalParams p;
  p.match_distance_m = 1.5;
  const EvalReport r = evaluate(frames, p);
  EXPECT_EQ(r.detection.tp, 2u);  // a greedy pass would pair 11.4 with 10.7 and lose 10.0
  EXPECT_EQ(r.detection.fn, 0u);
}

TEST(Evaluate, MatchesByDistanceToTheOrientedTrueFootprint) {
  // A car 4.5 x 1.8 m turned 90 deg (long side along y) at (10, 0): the LiDAR sees its near side,
  // so the cluster centre (10, 1.9) is 1.9 m from the true centre but inside the footprint.
  TruthObject car = truth(1, 10, 0, false);
  car.size = Eigen::Vector2d(4.5, 1.8);
  car.yaw = M_PI / 2;
  EXPECT_NEAR(distanceToFootprint(car, Eigen::Vector2d(10, 1.9)), 0.0, 1e-9);
  EXPECT_NEAR(distanceToFootprint(car, Eigen::Vector2d(12.0, 0)), 2.0 - 0.9, 1e-9);
  EXPECT_NEAR(distanceToFootprint(car, Eigen::Vector2d(10, -3.25)), 1.0, 1e-9);
  std::vector<EvalFrame> seen{frame(0.0, false, {car}, {det(7, 10, 1.9, false)})};
  EXPECT_EQ(evaluate(seen, EvalParams()).detection.tp, 1u);
  // 1.1 m beyond the footprint's side (gate 1.0): not the car.
  std::vector<EvalFrame> beside{frame(0.0, false, {car}, {det(7, 12.0, 0, false)})};
  const EvalReport r = evaluate(beside, EvalParams());
  EXPECT_EQ(r.detection.tp, 0u);
  EXPECT_EQ(r.detection.fn, 1u);
  EXPECT_EQ(r.detection.fp, 1u);
}

TEST(Evaluate, EpisodesLeadTimeIdSwitchesVelocityLatencyDuty) {
  std::vector<EvalFrame> frames;
  // Object 1 is truly dangerous from t = 1.0 to 1.2 (enters the corridor 2.0 s after t = 1.0).
  // The lamp comes on at t = 1.1: lead time = 3.0 - 1.1 = 1.9 s. Object 2's episode (t = 2.0)
  // never sees the lamp on: missed.
  frames.push_back(frame(0.9, false, {truth(1, 9, 0, false)}, {det(5, 9, 0, false)}));
  frames.push_back(frame(1.0, false, {truth(1, 8, 0, true, 2.0)}, {det(5, 8, 0, false)}));
  frames.push_back(frame(1.1, true, {truth(1, 7, 0, true, 1.9)}, {det(6, 7, 0, true, -2.0)}));
  frames.push_back(frame(1.2, true, {truth(1, 6, 0, true, 1.8)}, {det(6, 6, 0, true)}));
  frames.push_back(frame(1.3, false, {truth(1, 6, 0, false)}, {det(6, 6, 0, false)}));
  frames.push_back(frame(2.0, false, {truth(2, 6, 3, true, 0.5)}, {}));
  EvalFrame dropped;
  dropped.t = 2.1;
  frames.push_back(dropped);  // not processed: not counted
  const EvalReport r = evaluate(frames, EvalParams());
  EXPECT_EQ(r.frames, 7u);
  EXPECT_EQ(r.processed, 6u);
  EXPECT_EQ(r.episodes, 2u);
  EXPECT_EQ(r.caught, 1u);
  ASSERT_EQ(r.lead_times_s.size(), 1u);
  EXPECT_NEAR(r.lead_times_s[0], 1.9, 1e-9);
  EXPECT_EQ(r.id_switches, 1u);  // detection id 5 -> 6 on the same true object
  EXPECT_EQ(r.velocity_samples, 5u);
  EXPECT_NEAR(r.velocity_rmse, std::sqrt(1.0 / 5.0), 1e-9);  // one sample 1 m/s off
  EXPECT_DOUBLE_EQ(r.duty_cycle, 2.0 / 6.0);
  EXPECT_NEAR(r.latency_max_ms, 20.0, 1e-9);
  EXPECT_NE(toTable(r, "t").find("1 caught of 2"), std::string::npos);
  EXPECT_NE(toJson(r, "t").find("\"caught\": 1"), std::string::npos);
}

// The velocity error's two diagnostics: a track's box whose centre jumps 0.2 m sideways every
// frame (offset steps of 0.2 m), velocity judged only once the track is settled, and no step
// counted across an id switch or a missed frame.
TEST(Evaluation, SettledVelocityAndCentreOffsetSteps) {
  std::vector<EvalFrame> frames;
  for (int i = 0; i < 14; ++i) {
    const double x = 20.0 - i;  // the true object comes 1 m closer per frame
    DetectedObject d = det(7, x, (i % 2) ? 0.2 : 0.0, false, i < 10 ? -5.0 : -1.5);
    d.age = static_cast<std::uint32_t>(i + 1);
    std::vector<DetectedObject> dets{d};
    if (i == 6) dets.clear();  // missed: no step from frame 5 to 7
    frames.push_back(frame(0.1 * i, false, {truth(1, x, 0, false)}, dets));
  }
  frames.push_back(frame(1.4, false, {truth(1, 6, 0, false)}, {det(8, 6, 0.2, false)}));  // new id
  EvalParams params;
  params.settled_age = 10;
  const EvalReport r = evaluate(frames, params);
  // Steps: frames 0->1 ... 5->6 is gone (6 missed), 7->8 ... 12->13: 5 + 6 = 11, each 0.2 m.
  EXPECT_EQ(r.offset_steps, 11u);
  EXPECT_NEAR(r.offset_step_rms_m, 0.2, 1e-9);
  // Ages 10..14 settled (frames 9..13): frame 9 is 4 m/s off, frames 10..13 0.5 m/s off.
  EXPECT_EQ(r.velocity_samples_settled, 5u);
  EXPECT_NEAR(r.velocity_rmse_settled, std::sqrt((16.0 + 4 * 0.25) / 5.0), 1e-9);
  EXPECT_GT(r.velocity_rmse, r.velocity_rmse_settled);
  EXPECT_NE(toJson(r, "t").find("\"offset_step_rms_m\": 0.2"), std::string::npos);
}

}  // namespace
}  // namespace icanc
