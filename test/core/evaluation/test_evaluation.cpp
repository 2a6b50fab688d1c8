// Pins the evaluation's counting on hand-built frames.
#include <algorithm>
#include <cmath>

#include <gtest/gtest.h>

#include "icanc/core/evaluation/evaluation.hpp"

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

// Detection in the detector's region of interest: the true objects whose centre lies in it, and the
// unmatched detections there. The scored range still applies; the whole figure is unchanged.
TEST(Evaluate, DetectionInTheRoiCountsWhatTheDetectorLooksAt) {
  EvalParams p;
  p.roi = Eigen::AlignedBox2d(Eigen::Vector2d(-10.0, -20.0), Eigen::Vector2d(60.0, 20.0));
  std::vector<EvalFrame> frames{frame(0.0, false,
      {truth(1, 5, 0, false), truth(2, -15, 0, false), truth(3, 10, 25, false),
       truth(4, -9.5, 3, false), truth(5, 50, 0, false), truth(6, 20, -5, false)},
      {det(11, 5.2, 0, false), det(14, -9.6, 3, false), det(21, -15, -2.5, false),
       det(22, 30, 0, false), det(23, -20, 10, false)})};
  const EvalReport r = evaluate(frames, p);
  // 40 m all around: 1, 2, 3, 4, 6 scored (5 beyond 40 m), 1 and 4 found.
  EXPECT_EQ(r.detection.tp, 2u);
  EXPECT_EQ(r.detection.fn, 3u);
  EXPECT_EQ(r.detection.fp, 3u);
  // In the ROI: 1, 4 and 6 (2 is behind it, 3 beside it); the unmatched detection 22 only.
  EXPECT_EQ(r.detection_roi.tp, 2u);
  EXPECT_EQ(r.detection_roi.fn, 1u);
  EXPECT_EQ(r.detection_roi.fp, 1u);
  EXPECT_DOUBLE_EQ(r.detection_roi.recall(), 2.0 / 3.0);
  // Without a ROI (the default) the two are the same.
  const EvalReport all = evaluate(frames, EvalParams());
  EXPECT_EQ(all.detection_roi.tp, all.detection.tp);
  EXPECT_EQ(all.detection_roi.fn, all.detection.fn);
  EXPECT_EQ(all.detection_roi.fp, all.detection.fp);
  EXPECT_NE(toJson(r, "x").find("\"detection_roi\": {\"tp\": 2, \"fp\": 1, \"fn\": 1"), std::string::npos);
}

// A detection on a true object that is not scored (too few returns; just beyond the range) is not
// scored either: no false alarm, no detection false positive. One beside it still is.
TEST(Evaluate, ADetectionOfAnUnscoredObjectIsNotScored) {
  TruthObject sparse = truth(1, 24.0, -1.7, true, 1.0), far = truth(2, 40.6, 0.0, false);
  sparse.num_points = 4;
  const std::vector<EvalFrame> frames{frame(0.0, true, {sparse, far},
                                            {det(10, 24.1, -1.6, true), det(11, 39.8, 0.0, true),
                                             det(12, 24.0, 1.0, true)})};
  std::vector<ScoredRow> rows;
  const EvalReport r = evaluate(frames, EvalParams(), &rows);
  EXPECT_EQ(r.danger.fp, 1u);  // only the detection 2.7 m beside the sparse object
  EXPECT_EQ(r.false_alarms_unmatched, 1u);
  EXPECT_EQ(r.danger.tp + r.danger.fn + r.danger.tn, 0u);
  EXPECT_EQ(r.detection.fp, 1u);
  // The two dangerous detections of unscored objects light the lamp: listed as DC, not counted.
  ASSERT_EQ(rows.size(), 3u);
  std::vector<std::uint32_t> dont_care;
  for (const ScoredRow& row : rows) {
    if (row.outcome == Outcome::kFalsePositive) {
      EXPECT_FALSE(row.has_truth);
      EXPECT_EQ(row.detection.id, 12u);
      continue;
    }
    ASSERT_EQ(row.outcome, Outcome::kDontCare);
    ASSERT_TRUE(row.has_truth && row.has_detection);
    EXPECT_EQ(row.truth.id, row.detection.id - 9u);
    dont_care.push_back(row.detection.id);
  }
  EXPECT_EQ(dont_care, (std::vector<std::uint32_t>{10u, 11u}));
  EXPECT_NE(toCsv(rows).find(",DC,1,"), std::string::npos);
}

// A true object whose labels end within the horizon (a recording's last frames) and that is not
// dangerous as far as they go: its danger is unknown, so a flag on it is no false alarm and no
// flag no true negative; its detection is still scored, its flag still lights the lamp (unscored).
TEST(Evaluate, ADangerCutByTheRecordingsEndIsNotScored) {
  TruthObject cut = truth(1, 8.0, -1.5, false), known = truth(2, 12.0, 3.0, false);
  cut.horizon_cut = true;
  std::vector<EvalFrame> frames;
  frames.push_back(frame(0.0, true, {cut, known}, {det(10, 8.1, -1.5, true), det(11, 12.0, 3.1, true)}));
  frames.push_back(frame(0.1, true, {cut, known}, {det(10, 8.0, -1.5, false), det(11, 12.0, 3.0, false)}));
  std::vector<ScoredRow> rows;
  const EvalReport r = evaluate(frames, EvalParams(), &rows);
  EXPECT_EQ(r.danger.fp, 1u);  // the known one's first frame only
  EXPECT_EQ(r.danger.tn, 1u);  // the known one's second frame only
  EXPECT_EQ(r.danger.tp + r.danger.fn, 0u);
  EXPECT_EQ(r.detection.tp, 4u);  // both are detected in both frames, cut or not
  EXPECT_EQ(r.perfect_tracks.tp + r.perfect_tracks.fp + r.perfect_tracks.fn + r.perfect_tracks.tn, 2u);
  EXPECT_EQ(r.lamp_causes.causes[static_cast<std::size_t>(LampCause::kUnscored)].object_frames, 1u);
  std::size_t dont_care = 0;
  for (const ScoredRow& row : rows) {
    if (row.truth.id != 1u) continue;
    EXPECT_EQ(row.outcome, Outcome::kDontCare);
    ++dont_care;
  }
  EXPECT_EQ(dont_care, 2u);
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

// The same frame as rows: one per scored object-frame, naming the detection that decided it (the
// match, or the dangerous fragment that flagged a true object whose match was safe).
TEST(Evaluate, RowsExplainEachCountedObjectFrame) {
  TruthObject car = truth(1, 18.0, -2.2, true, 1.0), parked = truth(2, 30.0, -4.0, false);
  car.size = parked.size = Eigen::Vector2d(4.7, 1.9);
  car.type = "car";
  std::vector<EvalFrame> frames{
      frame(0.5, true, {car, parked, truth(3, 8.0, 6.0, true, 2.0)},
            {det(10, 15.7, -2.2, true), det(11, 16.6, -2.2, false), det(20, 30.0, -4.0, false),
             det(21, 28.0, -4.0, true), det(30, 18.0, 3.0, true), det(31, 25.0, 9.0, false)})};
  std::vector<ScoredRow> rows;
  const EvalReport r = evaluate(frames, EvalParams(), &rows);
  ASSERT_EQ(rows.size(), 4u);  // three true objects and the false alarm at y = 3
  Confusion c;
  for (const ScoredRow& row : rows) {
    EXPECT_DOUBLE_EQ(row.t, 0.5);
    c.tp += row.outcome == Outcome::kTruePositive;
    c.fp += row.outcome == Outcome::kFalsePositive;
    c.fn += row.outcome == Outcome::kFalseNegative;
    c.tn += row.outcome == Outcome::kTrueNegative;
  }
  EXPECT_EQ(c.tp, r.danger.tp);
  EXPECT_EQ(c.fp, r.danger.fp);
  EXPECT_EQ(c.fn, r.danger.fn);
  EXPECT_EQ(c.tn, r.danger.tn);

  EXPECT_EQ(rows[0].outcome, Outcome::kTruePositive);  // the car, by its rear face's flag
  EXPECT_EQ(rows[0].truth.id, 1u);
  EXPECT_TRUE(rows[0].has_detection);
  EXPECT_EQ(rows[0].detection.id, 10u);
  EXPECT_TRUE(rows[0].fragment);  // the roof line (11) is the match; the rear face flagged it
  EXPECT_EQ(rows[1].outcome, Outcome::kFalsePositive);  // the parked car, by its fragment 21
  EXPECT_EQ(rows[1].detection.id, 21u);
  EXPECT_TRUE(rows[1].fragment);
  EXPECT_EQ(rows[2].outcome, Outcome::kFalseNegative);  // nothing seen at (8, 6)
  EXPECT_FALSE(rows[2].has_detection);
  EXPECT_EQ(rows[3].outcome, Outcome::kFalsePositive);  // the detection of nothing
  EXPECT_FALSE(rows[3].has_truth);
  EXPECT_EQ(rows[3].detection.id, 30u);

  const std::string csv = toCsv(rows);
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 5);  // header and four rows
  EXPECT_NE(csv.find("\n0.500,TP,1,car,18.000,-2.200,4.700,1.900,0.0000,"), std::string::npos) << csv;
  EXPECT_NE(csv.find("\n0.500,FN,3,,8.000,6.000,0.000,0.000,0.0000,-1.000,0.000,2.00,,,,"),
            std::string::npos) << csv;
  EXPECT_NE(csv.find("\n0.500,FP,,,,,,,,,,,30,0,1,18.000,3.000,"), std::string::npos) << csv;
  // The last columns: the model on the true object's perfect track, empty without a true object;
  // the box it is merged into, empty (nothing merged in this frame).
  EXPECT_NE(csv.find(",det_age,perfect_dangerous,merged_into\n"), std::string::npos) << csv;
  EXPECT_NE(csv.find(",det_vy_std,det_vgx,det_vgy,det_x_min,"), std::string::npos) << csv;
  EXPECT_EQ(csv.substr(csv.size() - 3), ",,\n") << csv;  // the detection of nothing
  const std::string fn_line = csv.substr(csv.find("\n0.500,FN,3,") + 1);
  EXPECT_EQ(fn_line.substr(fn_line.find('\n') - 3, 3), (rows[2].perfect_flagged ? ",1," : ",0,")) << csv;
  // Every line has the header's number of fields.
  std::size_t start = 0;
  while (start < csv.size()) {
    const std::size_t end = csv.find('\n', start);
    EXPECT_EQ(std::count(csv.begin() + start, csv.begin() + end, ','), 29) << csv.substr(start, end - start);
    start = end + 1;
  }
}

// How far the true footprint reaches beyond the detected box: the face toward the vehicle along x
// (x_min ahead, x_max behind) and both faces along y, of a yawed true box by its axis-aligned
// bounds; medians; a detection without a box is not counted.
TEST(Evaluate, BoxBiasOfTheTrueFootprintBeyondTheDetectedBox) {
  const auto sized = [](std::uint32_t id, double x, double y, double yaw) {
    TruthObject o = truth(id, x, y, false);
    o.size = Eigen::Vector2d(4.0, 2.0);
    o.yaw = yaw;
    return o;
  };
  const auto boxed = [](std::uint32_t id, double x, double y, double x0, double x1, double y0, double y1) {
    DetectedObject d = det(id, x, y, false);
    d.has_aabb = true;
    d.aabb_min = Eigen::Vector2d(x0, y0);
    d.aabb_max = Eigen::Vector2d(x1, y1);
    return d;
  };
  const std::vector<EvalFrame> frames{frame(
      0.0, false,
      {sized(1, 10, 0, 0.0), sized(2, -10, 3, 0.0), sized(3, 5, 10, M_PI / 2), sized(4, 20, -5, 0.0)},
      {boxed(11, 10, 0, 8.2, 12.0, -0.8, 0.9),      // near 0.2, sides 0.2 and 0.1
       boxed(12, -10, 3, -12.0, -8.3, 2.0, 3.9),    // behind: near 0.3, sides 0 and 0.1
       boxed(13, 5, 10, 4.4, 6.0, 8.0, 11.5),       // yawed 90 deg: near 0.4, sides 0 and 0.5
       det(14, 20, -5, false)})};                    // no box
  const EvalReport r = evaluate(frames, EvalParams());
  EXPECT_EQ(r.box_bias_samples, 3u);
  EXPECT_NEAR(r.box_bias_near_m, 0.3, 1e-9);
  EXPECT_NEAR(r.box_bias_side_m, 0.1, 1e-9);
}

// Two walkers side by side seen as one box (mount_robot16_clutter): the box is matched to one of
// them, the other is missed, merged into it, not unseen. A dangerous walker so merged into a box
// flagged dangerous is counted apart (the lamp came on for the box that holds it). A walker whose
// centre lies outside every matched box, or inside an unmatched one, is not merged.
TEST(Evaluate, AnObjectInsideAnotherObjectsBoxIsMissedAsMerged) {
  const auto boxed = [](std::uint32_t id, double x, double y, double half_x, double half_y,
                        bool dangerous) {
    DetectedObject d = det(id, x, y, dangerous);
    d.has_aabb = true;
    d.aabb_min = Eigen::Vector2d(x - half_x, y - half_y);
    d.aabb_max = Eigen::Vector2d(x + half_x, y + half_y);
    return d;
  };
  // The pair's box (y 0.31..1.57) a hair nearer the safe walker at y 1.35: matched to it.
  const TruthObject inner = truth(3, 9.2, 0.55, true, 1.0), outer = truth(4, 9.2, 1.35, false);
  const TruthObject apart = truth(5, 20.0, -6.0, true, 1.5);  // its box is not there
  std::vector<EvalFrame> frames{
      frame(0.0, true, {inner, outer, apart}, {boxed(7, 9.07, 0.97, 0.16, 0.63, true)}),
      frame(0.1, true, {inner, outer, apart}, {boxed(7, 9.07, 0.97, 0.16, 0.63, false)})};
  std::vector<ScoredRow> rows;
  const EvalReport r = evaluate(frames, EvalParams(), &rows);
  EXPECT_EQ(r.detection.tp, 2u);  // the box matched to walker 4 in both frames
  EXPECT_EQ(r.detection.fn, 4u);  // walker 3 (merged) and walker 5 (unseen), twice
  EXPECT_EQ(r.detection_merged, 2u);
  EXPECT_EQ(r.danger.fn, 4u);
  EXPECT_EQ(r.danger_fn_in_flagged_merge, 1u);  // the first frame: the box was flagged
  EXPECT_EQ(r.danger.fp, 1u);                   // walker 4, through the flagged box
  int merged_rows = 0;
  for (const ScoredRow& row : rows) {
    if (row.truth.id == 3) {
      EXPECT_EQ(row.merged_into, 7u);
      ++merged_rows;
    } else {
      EXPECT_EQ(row.merged_into, 0u);
    }
  }
  EXPECT_EQ(merged_rows, 2);
  EXPECT_NE(toJson(r, "x").find("\"detection_merged\": 2, \"danger_fn_in_flagged_merge\": 1"),
            std::string::npos);
  EXPECT_NE(toCsv(rows).find(",merged_into\n"), std::string::npos);

  // The same box left unmatched (no true object near its centre): nothing is merged into it.
  const TruthObject far_pair = truth(3, 9.2, 0.55, true, 1.0);
  const std::vector<EvalFrame> alone{
      frame(0.0, true, {far_pair}, {boxed(8, 9.07, 3.5, 0.16, 3.0, true)})};
  const EvalReport u = evaluate(alone, EvalParams());
  EXPECT_EQ(u.detection.tp, 0u);
  EXPECT_EQ(u.detection_merged, 0u);
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

// "Caught" means the object itself (or a fragment of it) was flagged, not the lamp on
// for any reason. Object 1 is dangerous while the lamp is on because of object 3 (a dangerous
// detection elsewhere) and its own detection is never flagged: missed. Object 2's fragment (a
// detection left over within the match distance) is flagged: caught.
TEST(Evaluate, CaughtNeedsTheObjectItselfFlagged) {
  std::vector<EvalFrame> frames;
  frames.push_back(frame(1.0, true, {truth(1, 8, 0, true, 2.0), truth(3, 20, 10, false)},
                         {det(5, 8, 0, false), det(7, 20, 10, true)}));
  frames.push_back(frame(1.1, true, {truth(1, 7, 0, true, 1.9), truth(3, 20, 10, false)},
                         {det(5, 7, 0, false), det(7, 20, 10, true)}));
  TruthObject car = truth(2, 10, -3, true, 1.0);
  car.size = Eigen::Vector2d(4.5, 1.8);
  frames.push_back(frame(2.0, true, {car}, {det(8, 10, -3, false), det(9, 11.5, -3, true)}));
  const EvalReport r = evaluate(frames, EvalParams());
  EXPECT_EQ(r.episodes, 2u);
  EXPECT_EQ(r.caught, 1u) << "the lamp on for object 3 must not count as catching object 1";
  ASSERT_EQ(r.lead_times_s.size(), 1u);
  EXPECT_NEAR(r.lead_times_s[0], 1.0, 1e-9);
}

// The danger model on perfect tracks: each scored true object's own box and velocity, whatever
// was detected. A 0.5 m pedestrian 4 m ahead closing at 2 m/s (truly dangerous) and one standing
// 3 m to the side (safe), five frames at 10 Hz, nothing detected; zebra's corridor (x <= 1.5 m).
TEST(Evaluate, DangerModelOnPerfectTracks) {
  const auto run = [](DangerModel model) {
    std::vector<EvalFrame> frames;
    for (int i = 0; i < 5; ++i) {
      TruthObject walker = truth(1, 4.0 - 0.2 * i, 0.0, true, 1.0), aside = truth(2, 3.0, 3.0, false);
      walker.size = aside.size = Eigen::Vector2d(0.5, 0.5);
      walker.velocity = Eigen::Vector2d(-2.0, 0.0);
      aside.velocity = Eigen::Vector2d::Zero();
      frames.push_back(frame(0.1 * i, false, {walker, aside}, {}));
    }
    EvalParams p;
    p.danger.model = model;
    const EvalReport r = evaluate(frames, p);
    EXPECT_EQ(r.danger.fn, 5u);  // nothing was detected
    EXPECT_EQ(r.danger.tn, 5u);
    EXPECT_EQ(r.perfect_tracks.tn, 5u);
    EXPECT_EQ(r.perfect_tracks.fp, 0u);
    EXPECT_NE(toJson(r, "t").find("\"perfect_tracks\": {\"tp\": " + std::to_string(r.perfect_tracks.tp)),
              std::string::npos);
    // The lamp driven by those flags: on from the first flagged frame (tau 3 s > the run).
    const double first_flag = r.perfect_tracks.tp == 5 ? 0 : 5 - static_cast<double>(r.perfect_tracks.tp);
    EXPECT_DOUBLE_EQ(r.perfect_tracks_duty_cycle, (5.0 - first_flag) / 5.0);
    EXPECT_NE(toJson(r, "t").find("\"perfect_tracks_duty_cycle\": "), std::string::npos);
    EXPECT_EQ(r.duty_cycle, 0.0);  // the graph's lamp (no frame says it was on)
    return r.perfect_tracks;
  };
  // The paper's rule: 3.75 m <= 2 m/s * 3 s, heading 180 in the front section, every frame.
  EXPECT_EQ(run(DangerModel::kPaper).tp, 5u);
  // Predictive: the near face reaches 1.5 m after 1.125 s at the first frame, more than
  // immediate_ttc_s (1 s): the hysteresis waits for the second frame, as it does on the vehicle.
  const Confusion predictive = run(DangerModel::kPredictive);
  EXPECT_EQ(predictive.tp, 4u);
  EXPECT_EQ(predictive.fn, 1u);
}

// The predictive model judges what stands still by the vehicle's swept path, the truth by its
// wider corridor: a parked car standing in the corridor but beside the swept path is counted apart
// (not a miss, no episode); one protruding into the swept path is scored as any danger.
TEST(Evaluate, StandingBesideTheSweptPathIsCountedApart) {
  const auto run = [](DangerModel model) {
    std::vector<EvalFrame> frames;
    for (int i = 0; i < 5; ++i) {
      // Road car at 8 m/s: corridor |y| <= 1.5 m, swept path |y| <= 1.4 m.
      TruthObject kerb = truth(1, 12.0 - 0.8 * i, 2.4, true, 0.5);  // y 1.5 .. 3.3
      TruthObject protruding = truth(2, 20.0 - 0.8 * i, -2.0, true, 1.5);  // y -2.9 .. -1.1
      kerb.size = protruding.size = Eigen::Vector2d(4.5, 1.8);
      kerb.velocity = protruding.velocity = Eigen::Vector2d(-8.0, 0.0);  // standing still
      EvalFrame f = frame(0.1 * i, true, {kerb, protruding},
                          {det(11, kerb.center.x(), kerb.center.y(), false, -8.0),
                           det(12, protruding.center.x(), protruding.center.y(), true, -8.0)});
      f.ego_motion = true;
      f.ego_velocity = Eigen::Vector2d(8.0, 0.0);
      frames.push_back(f);
    }
    EvalParams p;
    p.danger.model = model;
    p.danger.half_width_m = 1.2;
    p.danger.reaction_time_s = 2.0;
    p.danger.vehicle_front_m = 2.0;
    p.danger.stopping_margin_m = 5.0;
    std::vector<ScoredRow> rows;
    const EvalReport r = evaluate(frames, p, &rows);
    EXPECT_EQ(r.danger.tp, 5u);
    EXPECT_EQ(std::count_if(rows.begin(), rows.end(),
                            [](const ScoredRow& row) { return row.outcome == Outcome::kStandingApart; }),
              static_cast<long>(r.danger_standing_apart));
    return r;
  };
  const EvalReport predictive = run(DangerModel::kPredictive);
  EXPECT_EQ(predictive.danger.fn, 0u);
  EXPECT_EQ(predictive.danger_standing_apart, 5u);
  EXPECT_EQ(predictive.danger_standing_apart_flagged, 0u);
  EXPECT_EQ(predictive.episodes, 1u);  // the protruding car's only
  EXPECT_EQ(predictive.caught, 1u);
  EXPECT_NE(toJson(predictive, "t").find("\"danger_standing_apart\": {\"n\": 5, \"flagged\": 0}"),
            std::string::npos);
  EXPECT_NE(toTable(predictive, "t").find("beside the swept path"), std::string::npos);
  // The paper's rule has no swept path: the car at the kerb is a miss.
  const EvalReport paper = run(DangerModel::kPaper);
  EXPECT_EQ(paper.danger.fn, 5u);
  EXPECT_EQ(paper.danger_standing_apart, 0u);
  EXPECT_EQ(paper.episodes, 2u);
  // Without ego motion nothing is known to stand still: scored as before.
  std::vector<EvalFrame> relative{frame(0.0, true, {truth(1, 12.0, 2.4, true, 0.5)}, {})};
  relative[0].truth[0].size = Eigen::Vector2d(4.5, 1.8);
  EvalParams p;
  p.danger.model = DangerModel::kPredictive;
  EXPECT_EQ(evaluate(relative, p).danger.fn, 1u);
}

// Perfect tracks hand the model the true oriented box (as parts) and no footprint margin (the
// true box lacks nothing the LiDAR did not see). Zebra's corridor: |y| <= 1.0 m, 0 <= x <= 1.5 m.
TEST(Evaluate, PerfectTracksAreTheOrientedBoxWithoutTheLidarMargin) {
  const auto perfect = [](const TruthObject& o, const DangerParams& danger) {
    std::vector<EvalFrame> frames;
    for (int i = 0; i < 5; ++i) frames.push_back(frame(0.1 * i, false, {o}, {}));
    EvalParams p;
    p.danger = danger;
    return evaluate(frames, p).perfect_tracks;
  };
  DangerParams danger;
  danger.model = DangerModel::kPredictive;
  // A 2.0 x 0.4 m bar standing diagonally 0.65 m past the corridor's corner (1.5, 1.0): its
  // axis-aligned bounds, [1.25, 2.95] x [0.75, 2.45], overlap the corridor, the bar does not.
  TruthObject bar = truth(1, 2.1, 1.6, false);
  bar.size = Eigen::Vector2d(2.0, 0.4);
  bar.yaw = 0.75 * M_PI;
  bar.velocity.setZero();
  Confusion c = perfect(bar, danger);
  EXPECT_EQ(c.fp, 0u);
  EXPECT_EQ(c.tn, 5u);
  // Turned across the corner it is in the corridor: flagged.
  bar.yaw = 0.25 * M_PI;
  bar.center = Eigen::Vector2d(1.9, 1.2);
  EXPECT_EQ(perfect(bar, danger).fp, 5u);
  // A 0.5 m box standing 0.05 m beside the corridor: the model flags it with a 0.2 m footprint
  // margin (what a LiDAR box lacks), perfect tracks do not add it.
  TruthObject beside = truth(2, 3.0, 1.3, false);
  beside.size = Eigen::Vector2d(0.5, 0.5);
  beside.velocity = Eigen::Vector2d(-0.5, 0.0);
  danger.footprint_margin_m = 0.2;
  ObjectKinematics k;
  k.center << beside.center, 0.0;
  k.aabb_min << beside.center - Eigen::Vector2d(0.25, 0.25), 0.0;
  k.aabb_max << beside.center + Eigen::Vector2d(0.25, 0.25), 0.0;
  k.velocity << beside.velocity, 0.0;
  ASSERT_TRUE(assessDanger(k, danger).dangerous);
  c = perfect(beside, danger);
  EXPECT_EQ(c.fp, 0u);
  EXPECT_EQ(c.tn, 5u);
}

// The duty cycle of a perfect danger detector: the paper's light controller given the ground
// truth's danger each frame. 50 frames at 10 Hz, danger at t = 1.0 only: on for tau; a second
// danger at t = 2.5, with 0.5 s left (<= recheck_below_s), restarts the timer.
TEST(Evaluate, TruthDutyCycleIsTheLightControllerOnTheTruth) {
  const auto run = [](double tau, std::vector<double> danger_at) {
    std::vector<EvalFrame> frames;
    for (int i = 0; i < 50; ++i) {
      const double t = 0.1 * i;
      bool dangerous = false;
      for (double d : danger_at) dangerous |= std::abs(t - d) < 1e-6;
      frames.push_back(frame(t, false, {truth(1, 10, 3, dangerous, dangerous ? 1.0 : -1.0)}, {}));
    }
    EvalParams p;
    p.lamp_tau_s = tau;
    p.lamp_recheck_below_s = 1.0;
    const EvalReport r = evaluate(frames, p);
    EXPECT_DOUBLE_EQ(r.duty_cycle, 0.0);  // the graph's lamp stayed off throughout
    return r.truth_duty_cycle;
  };
  EXPECT_NEAR(run(2.0, {1.0}), 20.0 / 50, 1.0 / 50 + 1e-9);       // 1.0 .. 3.0
  EXPECT_NEAR(run(3.0, {1.0}), 30.0 / 50, 1.0 / 50 + 1e-9);       // 1.0 .. 4.0
  EXPECT_NEAR(run(2.0, {1.0, 2.5}), 35.0 / 50, 1.0 / 50 + 1e-9);  // reset at 2.5: .. 4.5
  EXPECT_NEAR(run(2.0, {1.0, 1.5}), 20.0 / 50, 1.0 / 50 + 1e-9);  // 1.5 s left: ignored
  EXPECT_DOUBLE_EQ(run(2.0, {}), 0.0);
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

// The speed over ground of settled tracks of objects that stand still, judged with the
// frame's ego twist; frames without ego motion and moving objects do not count.
TEST(Evaluate, StaticObjectsSpeedOverGround) {
  std::vector<EvalFrame> frames;
  for (int i = 0; i < 4; ++i) {
    TruthObject parked = truth(1, 12, 4, false);
    parked.velocity = Eigen::Vector2d(-10.0 + 0.1 * 4, -0.1 * 12);  // seen from 10 m/s, 0.1 rad/s
    TruthObject walker = truth(2, 15, -5, false);
    walker.velocity = Eigen::Vector2d(-10.0 - 0.1 * 5, 1.5 - 0.1 * 15);  // walks 1.5 m/s over ground
    DetectedObject car = det(11, 12, 4, false);
    car.velocity_over_ground = Eigen::Vector2d(0.1 * (i + 1), 0.0);
    car.age = 20;
    DetectedObject person = det(12, 15, -5, false);
    person.velocity_over_ground = Eigen::Vector2d(0.0, 1.4);
    person.age = 20;
    EvalFrame f = frame(0.1 * i, false, {parked, walker}, {car, person});
    f.ego_velocity = Eigen::Vector2d(10.0, 0.0);
    f.ego_yaw_rate = 0.1;
    f.ego_motion = i != 3;  // the last frame had no ego motion: not counted
    f.ego_motion_fault = i == 3;
    frames.push_back(f);
  }
  const EvalReport r = evaluate(frames, EvalParams());
  EXPECT_EQ(r.ego_motion_faults, 1u);
  EXPECT_NE(toTable(r, "x").find("ego motion extrapolated, jumped or lost in 1)"), std::string::npos);
  EXPECT_EQ(r.static_speed_samples, 3u);
  EXPECT_NEAR(r.static_speed_p50_mps, 0.2, 1e-9);
  EXPECT_NE(toJson(r, "x").find("\"static_speed_mps\": {\"p50\": 0.2"), std::string::npos);
  for (EvalFrame& f : frames) f.detections[0].age = 3;  // young tracks do not count
  EXPECT_EQ(evaluate(frames, EvalParams()).static_speed_samples, 0u);
}

// A box on a parked car whose track moves with the vehicle (a scan line sliding along
// it) is found, but its velocity does not agree with the car's; objects without a known velocity
// never agree.
TEST(Evaluate, FoundWithTheVelocityWithinTheTolerance) {
  TruthObject parked = truth(1, 12, -4, false);
  parked.velocity = Eigen::Vector2d(-10.0, 0.0);  // seen from 10 m/s
  TruthObject behind = truth(2, 20, -4, false);
  behind.velocity = Eigen::Vector2d(-10.0, 0.0);
  TruthObject unknown = truth(3, 25, 4, false);
  unknown.has_velocity = false;
  TruthObject missed = truth(4, 30, 4, false);
  const DetectedObject car = det(11, 12, -4, false, -8.5);  // 1.5 m/s off
  const DetectedObject band = det(12, 20, -4, false, -0.5);  // moves with the vehicle
  const DetectedObject any = det(13, 25, 4, false, -10.0);
  const std::vector<EvalFrame> frames{
      frame(0.0, false, {parked, behind, unknown, missed}, {car, band, any})};
  const EvalReport r = evaluate(frames, EvalParams());
  EXPECT_EQ(r.detection.tp, 3u);
  EXPECT_EQ(r.detection_velocity_agrees, 1u);
  EvalParams loose;
  loose.velocity_agree_mps = 10.0;
  EXPECT_EQ(evaluate(frames, loose).detection_velocity_agrees, 2u);
  EXPECT_NE(toJson(r, "x").find("\"detection_velocity_agrees\": {\"n\": 1, \"within_mps\": 2}"),
            std::string::npos);
  EXPECT_NE(toTable(r, "x").find("velocity within 2.0 m/s of the truth's: 1 (25.00 % of true"),
            std::string::npos);
}

}  // namespace
}  // namespace icanc
