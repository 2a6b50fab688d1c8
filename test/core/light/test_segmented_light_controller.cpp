// Pins the per-segment controller: the one-segment lamp replays icanc::LightController exactly,
// segments light only where the danger is, each with the paper's timer, low/high beam by distance,
// and every fail-safe lights every segment.
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "icanc/core/light/segmented_light_controller.hpp"

namespace icanc {
namespace {

LightControllerParams paperParams(bool watchdog = false) {
  LightControllerParams p;
  p.tau_s = 3.0;
  p.recheck_below_s = 1.0;
  p.watchdog_enabled = watchdog;  // false: the paper's machine alone
  return p;
}

// Eight 15-degree segments over [-60, 60] deg, 3.125 W each, low beam 1.875 W.
SegmentLampParams eightSegments() {
  SegmentLampParams p;
  for (int i = 0; i < 8; ++i) {
    LampSegment s;
    s.azimuth_min_deg = -60.0 + 15.0 * i;
    s.azimuth_max_deg = s.azimuth_min_deg + 15.0;
    s.watts = 3.125;
    s.low_watts = 1.875;
    p.segments.push_back(s);
  }
  p.segment_margin_deg = 1.0;
  p.low_beam_below_m = 15.0;
  return p;
}

// A 1 x 1 m box centred at (x, y).
Eigen::AlignedBox2d at(double x, double y) {
  return Eigen::AlignedBox2d(Eigen::Vector2d(x - 0.5, y - 0.5), Eigen::Vector2d(x + 0.5, y + 0.5));
}

std::vector<int> lit(const SegmentedLightController& c) {
  std::vector<int> out;
  const auto levels = c.levels();
  for (std::size_t i = 0; i < levels.size(); ++i)
    if (levels[i] > 0.0f) out.push_back(int(i));
  return out;
}

TEST(SegmentedLightController, OneSegmentReplaysTheLightControllerExactly) {
  // Random inputs, gaps (stale), blind frames, illumination reports and a bag loop, through both.
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (const bool gated : {false, true}) {
    LightControllerParams params = paperParams(true);
    params.illumination_enabled = gated;
    LightController single(params);
    SegmentedLightController seg(params, SegmentLampParams());
    ASSERT_EQ(seg.segments().size(), 1u);
    double t = 100.0;
    int lit_frames = 0;
    for (int i = 0; i < 5000; ++i) {
      const double r = u(rng);
      t += r < 0.02 ? 0.6 : 0.1;               // now and then a gap beyond the watchdog
      if (i == 2500) t -= 50.0;                // a bag loop
      if (r < 0.3) {
        std::vector<Eigen::AlignedBox2d> boxes;
        const int n = int(u(rng) * 3.0);
        for (int k = 0; k < n; ++k) boxes.push_back(at(40.0 * u(rng) - 20.0, 40.0 * u(rng) - 20.0));
        const bool blind = u(rng) < 0.05;
        single.onInput(t, !boxes.empty(), blind);
        seg.onInput(t, boxes, blind);
      } else if (r < 0.35) {
        const auto state = static_cast<Illumination>(int(u(rng) * 3.0));
        EXPECT_EQ(single.onIllumination(t, state), seg.onIllumination(t, state));
      } else {
        EXPECT_EQ(single.tick(t), seg.tick(t)) << "step " << i;
      }
      ASSERT_EQ(single.on(), seg.anyOn()) << "step " << i;
      ASSERT_EQ(single.reason(), seg.reason()) << "step " << i;
      ASSERT_EQ(seg.levels()[0], single.on() ? 1.0f : 0.0f);
      lit_frames += single.on() && single.reason() == LightReason::kDanger;
    }
    EXPECT_GT(lit_frames, 500);  // the replay did exercise the danger timer
  }
}

TEST(SegmentedLightController, LightsOnlyTheSegmentsTheBoxCovers) {
  SegmentedLightController c(paperParams(), eightSegments());
  c.onInput(0.0, {}, false);
  EXPECT_TRUE(lit(c).empty());
  EXPECT_EQ(c.reason(), LightReason::kOff);
  c.onInput(0.1, {at(20.0, 0.0)}, false);  // straight ahead: the segments either side of 0
  EXPECT_EQ(lit(c), (std::vector<int>{3, 4}));
  EXPECT_EQ(c.reason(), LightReason::kDanger);
  c.onInput(0.2, {at(20.0, -5.0)}, false);  // -14 deg (right): segment 3 = [-15, 0]
  c.onInput(0.3, {at(10.0, 10.0)}, false);  // +45 deg (left): segment 7 = [45, 60], 6 by the box
  EXPECT_EQ(lit(c), (std::vector<int>{2, 3, 4, 6, 7}));  // -14 deg +- box +- 1 deg reaches 2
  EXPECT_EQ(c.unlitObjects(), 0u);
  c.onInput(0.4, {at(-10.0, 0.0)}, false);  // behind: no segment covers it, so every one lights
  EXPECT_EQ(c.unlitObjects(), 1u);
  EXPECT_EQ(lit(c).size(), 8u);
}

// A danger beside the lamp's field (a pedestrian at 75 deg left of an 8 x 15 deg lamp over
// +-60 deg) lights every segment at high beam, for tau, as the binary lamp lights its beam.
TEST(SegmentedLightController, DangerOutsideEverySegmentLightsTheWholeLamp) {
  SegmentedLightController c(paperParams(), eightSegments());
  c.onInput(0.0, {}, false);
  const double a = 75.0 * M_PI / 180.0;
  c.onInput(0.1, {at(0.5 + 6.0 * std::cos(a), 6.0 * std::sin(a))}, false);
  EXPECT_EQ(c.unlitObjects(), 1u);
  EXPECT_EQ(c.levels(), std::vector<float>(8, 1.0f));
  EXPECT_EQ(c.reason(), LightReason::kDanger);
  EXPECT_TRUE(c.binaryLamp().on());
  c.tick(3.09);
  EXPECT_EQ(c.levels(), std::vector<float>(8, 1.0f));
  c.tick(3.1);
  EXPECT_TRUE(lit(c).empty());
  EXPECT_FALSE(c.binaryLamp().on());
}

// The binary lamp restarts its timer on a segment's danger that the segment's own timer ignores
// (more than recheck_below_s left there): the segment restarts with it, so the binary lamp never
// outlasts every segment.
TEST(SegmentedLightController, ASegmentLastsAsLongAsTheBinaryLamp) {
  SegmentedLightController c(paperParams(), eightSegments());
  LightController binary(paperParams());
  auto input = [&](double t, const std::vector<Eigen::AlignedBox2d>& boxes) {
    binary.onInput(t, !boxes.empty(), false);
    c.onInput(t, boxes, false);
  };
  input(0.0, {at(20.0, -3.0)});  // segment 3; binary until 3
  input(1.5, {at(20.0, 3.0)});   // segment 4 until 4.5; binary ignores it (1.5 s left)
  input(2.5, {at(20.0, 3.0)});   // binary restarts (0.5 s left) to 5.5; segment 4 had 2 s left
  for (int k = 30; k < 55; ++k) {  // segment 3 is off from 3 s on
    const double t = 0.1 * k;
    binary.tick(t);
    c.tick(t);
    ASSERT_TRUE(binary.on()) << t;
    ASSERT_EQ(lit(c), (std::vector<int>{4})) << t << ": the binary lamp is ON for danger";
  }
  c.tick(5.5);
  EXPECT_TRUE(lit(c).empty());
}

// Whatever the inputs (objects anywhere, gaps beyond the watchdog, blind frames, daylight, a bag
// loop), whenever the binary lamp fed the same inputs is ON some segment is lit, and a
// fail-safe lights all of them.
TEST(SegmentedLightController, NeverDarkerThanTheBinaryLamp) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (const bool gated : {false, true}) {
    LightControllerParams params = paperParams(true);
    params.illumination_enabled = gated;
    LightController binary(params);
    SegmentedLightController seg(params, eightSegments());
    double t = 100.0;
    int danger_steps = 0, outside = 0;
    for (int i = 0; i < 20000; ++i) {
      const double r = u(rng);
      t += r < 0.02 ? 0.6 : 0.1;
      if (i == 10000) t -= 50.0;
      if (r < 0.4) {
        std::vector<Eigen::AlignedBox2d> boxes;
        const int n = u(rng) < 0.5 ? 0 : 1 + int(u(rng) * 2.0);
        for (int k = 0; k < n; ++k) boxes.push_back(at(60.0 * u(rng) - 20.0, 60.0 * u(rng) - 30.0));
        const bool blind = u(rng) < 0.03;
        binary.onInput(t, !boxes.empty(), blind);
        seg.onInput(t, boxes, blind);
      } else if (r < 0.43) {
        const auto state = static_cast<Illumination>(int(u(rng) * 3.0));
        binary.onIllumination(t, state);
        seg.onIllumination(t, state);
      } else {
        binary.tick(t);
        seg.tick(t);
      }
      const std::vector<float> levels = seg.levels();
      if (binary.on()) {
        ASSERT_FALSE(lit(seg).empty()) << "step " << i << ": binary ON, every segment dark";
      }
      if (binary.on() && binary.reason() != LightReason::kDanger) {
        ASSERT_EQ(levels, std::vector<float>(8, 1.0f)) << "step " << i << ": fail-safe not full";
      }
      ASSERT_EQ(binary.on(), seg.binaryLamp().on()) << "step " << i;
      danger_steps += binary.on() && binary.reason() == LightReason::kDanger;
    }
    outside = int(seg.unlitObjects());
    EXPECT_GT(danger_steps, 2000);  // the danger timer was exercised
    EXPECT_GT(outside, 100);        // and so were objects outside every segment
  }
}

TEST(SegmentedLightController, EachSegmentRunsThePapersTimer) {
  SegmentedLightController c(paperParams(), eightSegments());
  c.onInput(0.0, {at(20.0, 3.0)}, false);  // 8.5 deg: segment 4 only
  EXPECT_EQ(lit(c), (std::vector<int>{4}));
  c.onInput(1.5, {at(20.0, 3.0), at(20.0, -3.0)}, false);  // segment 4 ignored (1.5 s left), 3 starts
  EXPECT_EQ(lit(c), (std::vector<int>{3, 4}));
  c.tick(2.99);
  EXPECT_EQ(lit(c), (std::vector<int>{3, 4}));
  c.tick(3.0);  // segment 4's timer reaches 0; segment 3 runs until 4.5
  EXPECT_EQ(lit(c), (std::vector<int>{3}));
  c.onInput(3.6, {at(20.0, -3.0)}, false);  // 0.9 s left: reset to 6.6
  c.tick(6.59);
  EXPECT_EQ(lit(c), (std::vector<int>{3}));
  c.tick(6.6);
  EXPECT_TRUE(lit(c).empty());
  EXPECT_EQ(c.reason(), LightReason::kOff);
}

TEST(SegmentedLightController, LowBeamForNearObjectsOnly) {
  SegmentedLightController c(paperParams(), eightSegments());
  c.onInput(0.0, {at(10.0, 1.2)}, false);  // 9.5 m: low beam, 1.875 / 3.125
  ASSERT_EQ(lit(c), (std::vector<int>{4}));
  EXPECT_FLOAT_EQ(c.levels()[4], 0.6f);
  c.onInput(0.5, {at(30.0, 6.0)}, false);  // far, same segment, timer ignores: high beam anyway
  EXPECT_FLOAT_EQ(c.levels()[4], 1.0f);
  // A segment without a low beam is always high.
  SegmentLampParams high_only = eightSegments();
  for (auto& s : high_only.segments) s.low_watts = 0.0;
  SegmentedLightController h(paperParams(), high_only);
  h.onInput(0.0, {at(5.0, 1.0)}, false);
  EXPECT_FLOAT_EQ(h.levels()[4], 1.0f);
}

TEST(SegmentedLightController, DimmedByDistanceToTheSameIlluminance) {
  SegmentLampParams lamp = eightSegments();
  for (auto& s : lamp.segments) s.low_watts = 0.0;
  lamp.full_power_range_m = 20.0;
  lamp.min_level = 0.05;
  SegmentedLightController c(paperParams(), lamp);
  c.onInput(0.0, {at(10.5, 1.2)}, false);  // near face 10 m (9.95 m to the corner): (10 / 20)^2
  ASSERT_EQ(lit(c), (std::vector<int>{4}));
  EXPECT_NEAR(c.levels()[4], 0.25, 0.01);
  // Illuminance on the object, level / d^2, equals full power's at 20 m.
  EXPECT_NEAR(c.levels()[4] / (10.0 * 10.0), 1.0 / (20.0 * 20.0), 1e-4);
  c.onInput(0.5, {at(2.5, 0.5)}, false);  // 2 m away while its timer runs: it keeps the higher level
  EXPECT_NEAR(c.levels()[4], 0.25, 0.01);
  c.onInput(2.5, {at(2.5, 0.5)}, false);  // 0.5 s left: restarted, the level this object needs
  EXPECT_NEAR(c.levels()[4], 0.05, 1e-6);  // (2 / 20)^2 = 0.01, held at the floor
  c.onInput(2.6, {at(40.0, 4.0)}, false);  // beyond the range: full power
  EXPECT_FLOAT_EQ(c.levels()[4], 1.0f);
  // Fail-safe is full power whatever the dimming.
  c.onInput(3.0, {}, true);
  for (float level : c.levels()) EXPECT_FLOAT_EQ(level, 1.0f);
}

TEST(SegmentedLightController, EveryFailSafeLightsEverySegment) {
  LightControllerParams params = paperParams(true);
  params.illumination_enabled = true;
  SegmentedLightController c(params, eightSegments());
  const std::vector<float> all(8, 1.0f);
  EXPECT_EQ(c.levels(), all);  // no input yet
  EXPECT_EQ(c.reason(), LightReason::kSensorStale);
  c.onInput(0.0, {at(10.0, 1.2)}, false);
  EXPECT_EQ(lit(c), (std::vector<int>{4}));
  c.tick(0.31);  // input stopped: stale
  EXPECT_EQ(c.levels(), all);
  EXPECT_EQ(c.reason(), LightReason::kSensorStale);
  c.onInput(0.4, {}, true);  // blind
  EXPECT_EQ(c.levels(), all);
  EXPECT_EQ(c.reason(), LightReason::kSensorBlind);
  c.onInput(0.5, {}, false);
  c.onIllumination(0.5, Illumination::kBright);  // daylight: no danger light
  c.onInput(0.6, {at(10.0, 1.2)}, false);
  EXPECT_TRUE(lit(c).empty());
  EXPECT_EQ(c.reason(), LightReason::kDaylight);
  c.tick(1.0);  // but stale input wins over daylight
  EXPECT_EQ(c.levels(), all);
  EXPECT_EQ(c.reason(), LightReason::kSensorStale);
  // Danger whose boxes are unknown lights every segment, high beam.
  SegmentedLightController u(paperParams(), eightSegments());
  u.onInput(0.0, {}, false, true);
  EXPECT_EQ(u.levels(), all);
  EXPECT_EQ(u.reason(), LightReason::kDanger);
}

}  // namespace
}  // namespace icanc
