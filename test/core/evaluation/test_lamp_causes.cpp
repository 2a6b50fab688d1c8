// Pins what keeps the lamp on: the causes a frame's flags are sorted into (evaluate) and the light
// controller re-run on some causes only (LampCauseLog).
#include <gtest/gtest.h>

#include "icanc/core/evaluation/evaluation.hpp"
#include "icanc/core/evaluation/lamp_causes.hpp"

namespace icanc {
namespace {

const LampCauseFigures& of(const LampCauses& r, LampCause cause) {
  return r.causes[static_cast<std::size_t>(cause)];
}

// 50 frames at 10 Hz, tau 2 s, reset only with at most 1 s left. A true danger at 0.0 s (lamp on
// 0.0-2.0); a standing false alarm at 2.5 s (on again, to 4.5) and twice at 4.4 s (0.1 s left: the
// timer restarts, on to the end). Each frame may be off by one at a timer's edge.
TEST(LampCauseLog, ReRunsTheLampOnEachCauseAloneAndOnAllButEach) {
  LightControllerParams lamp;
  lamp.tau_s = 2.0;
  lamp.recheck_below_s = 1.0;
  lamp.watchdog_enabled = false;
  LampCauseLog log(lamp);
  for (int i = 0; i < 50; ++i) {
    log.beginFrame(0.1 * i);
    if (i == 0) log.flag(LampCause::kTrueDanger);
    if (i == 25) log.flag(LampCause::kUnlabelledStanding);
    if (i == 44) {
      log.flag(LampCause::kUnlabelledStanding);
      log.flag(LampCause::kUnlabelledStanding);  // two objects, one frame
    }
  }
  const LampCauses r = log.result();
  const double frame = 1.0 / 50 + 1e-9;
  EXPECT_NEAR(r.duty_all, 45.0 / 50, frame);  // 0.0-2.0 and 2.5-4.9
  const LampCauseFigures& truth = of(r, LampCause::kTrueDanger);
  const LampCauseFigures& standing = of(r, LampCause::kUnlabelledStanding);
  EXPECT_EQ(truth.object_frames, 1u);
  EXPECT_EQ(standing.object_frames, 3u);
  EXPECT_NEAR(truth.duty_alone, 20.0 / 50, frame);
  EXPECT_NEAR(truth.duty_without, 25.0 / 50, frame);  // the false alarms alone: 2.5-4.9
  EXPECT_NEAR(standing.duty_alone, r.duty_all, 1e-12);
  EXPECT_NEAR(standing.duty_without, truth.duty_alone, 1e-12);
  // A cause never flagged changes nothing: alone it is the true danger's lamp, without it all.
  const LampCauseFigures& model = of(r, LampCause::kModel);
  EXPECT_EQ(model.object_frames, 0u);
  EXPECT_NEAR(model.duty_alone, truth.duty_alone, 1e-12);
  EXPECT_NEAR(model.duty_without, r.duty_all, 1e-12);
  EXPECT_NE(toText(r).find("unlabelled_standing      3 object-frames"), std::string::npos);
}

TEST(LampCauseLog, NoFramesNoLamp) {
  const LampCauses r = LampCauseLog(LightControllerParams()).result();
  EXPECT_EQ(r.duty_all, 0.0);
  EXPECT_EQ(of(r, LampCause::kTrueDanger).duty_alone, 0.0);
}

TruthObject truth(std::uint32_t id, double x, double y, bool dangerous, double vx) {
  TruthObject o;
  o.id = id;
  o.center = Eigen::Vector2d(x, y);
  o.velocity = Eigen::Vector2d(vx, 0.0);
  o.num_points = 50;
  o.dangerous = dangerous;
  o.time_to_corridor = dangerous ? 1.0 : -1.0;
  return o;
}

DetectedObject flagged(std::uint32_t id, double x, double y, Eigen::Vector2d over_ground) {
  DetectedObject d;
  d.id = id;
  d.center = Eigen::Vector2d(x, y);
  d.velocity_over_ground = over_ground;
  d.dangerous = true;
  return d;
}

// One frame, cause i flagged i + 1 times, so a cause taken for another shows (the paper's rule,
// 3 s, the scored sector +-45 deg, 40 m).
TEST(Evaluate, SortsEachFlagIntoItsLampCause) {
  EvalFrame f;
  f.processed = true;
  f.lamp_on = true;
  const Eigen::Vector2d still = Eigen::Vector2d::Zero();
  std::uint32_t id = 1;
  const auto labelled = [&](double x, double y, bool dangerous, double vx) {
    f.truth.push_back(truth(id, x, y, dangerous, vx));
    f.detections.push_back(flagged(100 + id++, x, y, still));
  };
  labelled(20, 10, true, -1.0);  // truly dangerous
  for (int k = 0; k < 2; ++k)    // not, though 4-6 m ahead closing at 5 m/s: the model's own
    labelled(4 + 2 * k, 0, false, -5.0);
  for (int k = 0; k < 3; ++k)    // not, nor on their perfect tracks: 10-16 m aside, 1 m/s
    labelled(10 + 3 * k, -5, false, -1.0);
  for (int k = 0; k < 4; ++k) f.detections.push_back(flagged(id++, 25, 2 * k - 3, still));
  for (int k = 0; k < 5; ++k)
    f.detections.push_back(flagged(id++, 30, 2 * k - 4, Eigen::Vector2d(0.0, 4.0)));
  for (int k = 0; k < 6; ++k) f.detections.push_back(flagged(id++, -5, 2 * k, still));  // behind
  EvalParams p;
  p.fov_half_angle_deg = 45.0;
  const EvalReport r = evaluate({f}, p);
  EXPECT_EQ(r.danger.tp, 1u);
  EXPECT_EQ(r.danger.fp, 2u + 3u + 4u + 5u);
  EXPECT_EQ(r.perfect_tracks.fp, 2u);
  for (std::size_t i = 0; i < kLampCauseCount; ++i)
    EXPECT_EQ(r.lamp_causes.causes[i].object_frames, i + 1) << toString(static_cast<LampCause>(i));
  EXPECT_NE(toJson(r, "t").find("\"lamp_causes\": {\"duty_all\": 1"), std::string::npos);
  EXPECT_NE(toTable(r, "t").find("unlabelled_moving        5 object-frames"), std::string::npos);
}

}  // namespace
}  // namespace icanc
