// Pins the offline segmented-lamp measurement on scored frames: the one-segment lamp is the binary
// lamp (coverage 1, same energy); eight segments light a quarter of the lamp for an object
// straight ahead and still cover it; a truly dangerous object the lamp was not lit for (another
// object's danger lit it) is not covered. Where the lamp is decides how many segments a near
// object lights (lamp_position_m); the low beam draws low_watts / watts.
#include <gtest/gtest.h>

#include "icanc/core/evaluation/segment_coverage.hpp"

namespace icanc {
namespace {

TruthObject truth(double x, double y, bool dangerous) {
  TruthObject o;
  o.id = 1;
  o.center = Eigen::Vector2d(x, y);
  o.size = Eigen::Vector2d(0.5, 0.5);
  o.num_points = 50;
  o.dangerous = dangerous;
  return o;
}

DetectedObject detection(double x, double y, bool dangerous) {
  DetectedObject d;
  d.center = Eigen::Vector2d(x, y);
  d.dangerous = dangerous;
  d.has_aabb = true;
  d.aabb_min = d.center - Eigen::Vector2d(0.25, 0.25);
  d.aabb_max = d.center + Eigen::Vector2d(0.25, 0.25);
  return d;
}

// 10 s at 10 Hz: a pedestrian straight ahead, dangerous (truth and detection) from 2 s to 5 s.
std::vector<EvalFrame> ahead() {
  std::vector<EvalFrame> frames;
  for (int k = 0; k < 100; ++k) {
    EvalFrame f;
    f.t = 0.1 * k;
    f.processed = true;
    const bool danger = f.t >= 2.0 && f.t < 5.0;
    f.truth.push_back(truth(8.0, 0.0, danger));
    f.detections.push_back(detection(8.0, 0.0, danger));
    frames.push_back(f);
  }
  return frames;
}

LightControllerParams paper() {
  LightControllerParams p;
  p.tau_s = 3.0;
  return p;
}

TEST(SegmentCoverage, OneSegmentIsTheBinaryLamp) {
  const SegmentCoverage c = segmentCoverage(ahead(), paper(), SegmentLampParams(), 10);
  EXPECT_EQ(c.segments, 1u);
  EXPECT_EQ(c.binary_tp_object_frames, 30u);
  EXPECT_EQ(c.covered_object_frames, 30u);
  EXPECT_DOUBLE_EQ(c.coverage, 1.0);
  // On from 2.0 s to 7.0 s (reset at 4.0 s, 1 s left): 5 s at 25 W.
  EXPECT_NEAR(c.binary_wh, 25.0 * 5.0 / 3600.0, 1e-9);
  EXPECT_NEAR(c.segmented_wh, c.binary_wh, 1e-12);
  EXPECT_NEAR(c.energy_ratio, 1.0, 1e-12);
}

TEST(SegmentCoverage, EightSegmentsLightAQuarterAndCoverTheObject) {
  const SegmentLampParams lamp = evenLamp(8, 120.0, 25.0);
  ASSERT_EQ(validate(lamp), "");
  EXPECT_DOUBLE_EQ(lamp.segments[3].azimuth_max_deg, 0.0);
  const SegmentCoverage c = segmentCoverage(ahead(), paper(), lamp, 10);
  EXPECT_EQ(c.covered_object_frames, 30u);
  EXPECT_DOUBLE_EQ(c.coverage, 1.0);
  EXPECT_NEAR(c.energy_ratio, 0.25, 1e-12);  // segments 3 and 4 of 8 (the object straddles 0)
}

TEST(SegmentCoverage, ADangerousObjectLitOnlyByAnothersDangerIsNotCovered) {
  std::vector<EvalFrame> frames = ahead();
  for (EvalFrame& f : frames) {
    f.detections.front().dangerous = false;  // the pedestrian ahead missed by the detector
    if (f.t >= 2.0 && f.t < 5.0) f.detections.push_back(detection(5.0, 5.0, true));  // 45 deg left
  }
  const SegmentCoverage one = segmentCoverage(frames, paper(), SegmentLampParams(), 10);
  EXPECT_DOUBLE_EQ(one.coverage, 1.0);  // the binary lamp lights everything
  std::vector<ScoredRow> rows;
  evaluate(frames, EvalParams(), &rows);
  const SegmentCoverage eight = segmentCoverage(frames, paper(), evenLamp(8, 120.0, 25.0), 10, &rows);
  EXPECT_EQ(eight.binary_tp_object_frames, 30u);
  EXPECT_EQ(eight.covered_object_frames, 0u);
  EXPECT_DOUBLE_EQ(eight.coverage, 0.0);
  // The detector never flagged the pedestrian: the binary lamp lit it by chance, and of the
  // object-frames it flagged none was left dark.
  EXPECT_EQ(eight.flagged_object_frames, 0u);
  EXPECT_DOUBLE_EQ(eight.flagged_coverage, 1.0);
  // Flagged, it is covered: the rows say which object-frames the detector flagged.
  const std::vector<EvalFrame> seen = ahead();
  rows.clear();
  evaluate(seen, EvalParams(), &rows);
  const SegmentCoverage flagged = segmentCoverage(seen, paper(), evenLamp(8, 120.0, 25.0), 10, &rows);
  EXPECT_EQ(flagged.flagged_object_frames, 30u);
  EXPECT_EQ(flagged.flagged_covered_object_frames, 30u);
}

// 10 s at 10 Hz: a pedestrian 1 m ahead of base_link, dangerous from 2 s to 5 s.
std::vector<EvalFrame> near() {
  std::vector<EvalFrame> frames = ahead();
  for (EvalFrame& f : frames) {
    f.truth.front().center.x() = 1.0;
    f.detections.front() = detection(1.0, 0.0, f.detections.front().dangerous);
  }
  return frames;
}

TEST(SegmentCoverage, WhereTheLampIsDecidesTheSegmentsANearObjectLights) {
  SegmentLampParams lamp = evenLamp(8, 120.0, 25.0);
  const SegmentCoverage at_origin = segmentCoverage(near(), paper(), lamp, 10);
  EXPECT_DOUBLE_EQ(at_origin.coverage, 1.0);
  // Seen from base_link the 0.5 m box 1 m ahead spans +-18.4 deg, +-20.4 with the margin: 4 segments.
  EXPECT_NEAR(at_origin.energy_ratio, 0.5, 1e-12);
  lamp.lamp_position_m.x() = -2.0;  // 2.75 m behind the near face: +-5.2 deg, +-7.2 with the margin
  const SegmentCoverage behind = segmentCoverage(near(), paper(), lamp, 10);
  EXPECT_DOUBLE_EQ(behind.coverage, 1.0);
  EXPECT_NEAR(behind.energy_ratio, 0.25, 1e-12);
  lamp.lamp_position_m.x() = 0.6;  // 0.15 m behind the near face: +-59 deg, +-61: every segment
  const SegmentCoverage close = segmentCoverage(near(), paper(), lamp, 10);
  EXPECT_DOUBLE_EQ(close.coverage, 1.0);
  EXPECT_NEAR(close.energy_ratio, 1.0, 1e-12);
}

TEST(SegmentCoverage, TheLowBeamDrawsItsShareForNearObjects) {
  const SegmentLampParams lamp = evenLamp(8, 120.0, 25.0, 15.0);  // the catalogue LED: 15 of 25 W
  ASSERT_EQ(validate(lamp), "");
  EXPECT_DOUBLE_EQ(lamp.segments[0].low_watts, 15.0 / 8.0);
  const SegmentCoverage c = segmentCoverage(ahead(), paper(), lamp, 10);  // 8 m < low_beam_below_m
  EXPECT_DOUBLE_EQ(c.coverage, 1.0);
  EXPECT_NEAR(c.energy_ratio, 0.25 * 15.0 / 25.0, 1e-6);  // levels are float
  SegmentLampParams far = lamp;
  far.low_beam_below_m = 5.0;  // the object 8 m away needs the high beam
  EXPECT_NEAR(segmentCoverage(ahead(), paper(), far, 10).energy_ratio, 0.25, 1e-12);
}

TEST(SegmentCoverage, TheBinaryHeadlightLightsOnlyItsOwnBeam) {
  // The truly dangerous pedestrian stands beside the lamp (90 deg left), the binary lamp is on for
  // it; a forward lamp of +-60 deg lights it with no segment and, all segments on, not at all.
  std::vector<EvalFrame> frames = ahead();
  for (EvalFrame& f : frames) {
    f.truth.front().center = Eigen::Vector2d(0.0, 3.0);
    f.detections.front() = detection(0.0, 3.0, f.detections.front().dangerous);
  }
  const SegmentCoverage one = segmentCoverage(frames, paper(), SegmentLampParams(), 10);
  EXPECT_EQ(one.binary_tp_object_frames, 30u);  // the paper's lamp: every direction
  EXPECT_EQ(one.outside_beam_object_frames, 0u);
  const SegmentCoverage forward = segmentCoverage(frames, paper(), evenLamp(8, 120.0, 25.0), 10);
  EXPECT_EQ(forward.binary_tp_object_frames, 0u);
  EXPECT_EQ(forward.outside_beam_object_frames, 30u);
  EXPECT_DOUBLE_EQ(forward.coverage, 1.0);  // nothing the binary headlight lit was left dark
  // A lamp wide enough to reach it: in the beam, and covered.
  const SegmentCoverage wide = segmentCoverage(frames, paper(), evenLamp(8, 240.0, 25.0), 10);
  EXPECT_EQ(wide.binary_tp_object_frames, 30u);
  EXPECT_EQ(wide.covered_object_frames, 30u);
}

TEST(SegmentCoverage, DimmingDrawsTheShareTheDistanceNeeds) {
  SegmentLampParams lamp = evenLamp(8, 120.0, 25.0);
  lamp.full_power_range_m = 15.5;  // the pedestrian's near face is 7.75 m away: level 1/4
  ASSERT_EQ(validate(lamp), "");
  const SegmentCoverage c = segmentCoverage(ahead(), paper(), lamp, 10);
  EXPECT_DOUBLE_EQ(c.coverage, 1.0);
  EXPECT_NEAR(c.energy_ratio, 0.25 * 0.25, 1e-6);
}

}  // namespace
}  // namespace icanc
