// Pins the LightController nodelet's logic around the two lamps: danger of unknown place lights
// every segment, invalid illumination states are unknown, the stale watchdog is an event once,
// transitions and inputs are counted, the report's levels and messages, and the fault path.
#include <random>

#include <gtest/gtest.h>

#include "icanc/core/light/lamp_control.hpp"

namespace icanc {
namespace {

LightControllerParams params() {
  LightControllerParams p;
  p.tau_s = 3.0;
  p.recheck_below_s = 1.0;
  p.stale_timeout_s = 0.5;
  return p;
}

SegmentLampParams threeSegments() {
  SegmentLampParams lamp;
  lamp.segments = {LampSegment{-30.0, -10.0, 40.0}, LampSegment{-10.0, 10.0, 40.0}, LampSegment{10.0, 30.0, 40.0}};
  return lamp;
}

const std::vector<Eigen::AlignedBox2d> kNone;

TEST(LampControl, DangerTriggersBothLampsAndIsCounted) {
  LampControl c(params(), SegmentLampParams());
  EXPECT_FALSE(c.onInput(10.0, 0, false, kNone).triggered);
  const std::vector<Eigen::AlignedBox2d> ahead = {
      Eigen::AlignedBox2d(Eigen::Vector2d(10.0, -0.5), Eigen::Vector2d(11.0, 0.5))};
  const LampControl::InputResult r = c.onInput(10.1, 1, false, ahead);
  EXPECT_TRUE(r.triggered);
  EXPECT_FALSE(r.unlocated);
  EXPECT_TRUE(c.binary().on());
  EXPECT_TRUE(c.segmented().anyOn());
  const StatusReport rep = c.report();
  EXPECT_EQ(rep.level, StatusLevel::kOk);
  EXPECT_EQ(rep.message, "lamp on: danger");
  EXPECT_EQ(rep.value("inputs"), "2");
  EXPECT_EQ(rep.value("timer starts/resets"), "1");
  EXPECT_EQ(rep.value("lamp segments"), "1");
  EXPECT_EQ(rep.value("lamp segments lit"), "1");
}

TEST(LampControl, DangerWithoutItsBoxesLightsEverySegment) {
  LampControl c(params(), threeSegments());
  const LampControl::InputResult r = c.onInput(10.0, 2, false, kNone);
  EXPECT_TRUE(r.unlocated);
  for (float level : c.segmented().levels()) EXPECT_EQ(level, 1.0f);
  EXPECT_EQ(c.report().value("inputs with unlocated danger (all segments on)"), "1");
  EXPECT_EQ(c.report().value("lamp segments lit"), "3");
}

TEST(LampControl, StaleInputIsOneEventAndAWarning) {
  LampControl c(params(), SegmentLampParams());
  c.onInput(10.0, 0, false, kNone);
  bool stale = false;
  EXPECT_FALSE(c.tick(10.3, stale));
  EXPECT_FALSE(stale);
  EXPECT_TRUE(c.tick(10.6, stale));
  EXPECT_TRUE(stale);
  EXPECT_FALSE(c.tick(10.7, stale));
  EXPECT_FALSE(stale) << "counted once, not on every tick";
  const StatusReport rep = c.report();
  EXPECT_EQ(rep.level, StatusLevel::kWarn);
  EXPECT_EQ(rep.message, "lamp on: sensor stale (fail-safe)");
  EXPECT_EQ(rep.value("sensor stale events"), "1");
}

TEST(LampControl, BlindSensorIsAnErrorAndCounted) {
  LampControl c(params(), SegmentLampParams());
  c.onInput(10.0, 0, true, kNone);
  EXPECT_TRUE(c.binary().on());
  EXPECT_EQ(c.report().level, StatusLevel::kError);
  EXPECT_EQ(c.report().message, "lamp on: sensor blind (fail-safe)");
  EXPECT_EQ(c.report().value("sensor blind inputs"), "1");
}

TEST(LampControl, InvalidIlluminationIsUnknownAndCounted) {
  LightControllerParams p = params();
  p.illumination_enabled = true;
  LampControl c(p, SegmentLampParams());
  bool invalid = true;
  c.onIllumination(10.0, 2, invalid);  // bright
  EXPECT_FALSE(invalid);
  EXPECT_EQ(c.report().value("illumination"), toString(Illumination::kBright));
  c.onIllumination(10.1, 7, invalid);
  EXPECT_TRUE(invalid);
  EXPECT_EQ(c.report().value("illumination"), toString(Illumination::kUnknown));
  EXPECT_EQ(c.report().value("invalid illumination messages"), "1");
  EXPECT_EQ(LampControl(params(), SegmentLampParams()).report().value("illumination"), "")
      << "reported only with the gate on";
}

TEST(LampControl, TransitionsAreCountedAsPublished) {
  LampControl c(params(), SegmentLampParams());
  c.published(true);
  c.published(false);
  c.published(false);
  c.published(true);
  EXPECT_EQ(c.report().value("lamp transitions"), "2");
}

TEST(LampControl, LiveTuningReachesBothLamps) {
  LampControl c(params(), SegmentLampParams());
  LightControllerParams tuned = params();
  tuned.tau_s = 5.0;
  tuned.watchdog_enabled = false;
  c.setParams(tuned);
  c.onInput(10.0, 1, false, {Eigen::AlignedBox2d(Eigen::Vector2d(10.0, -0.5), Eigen::Vector2d(11.0, 0.5))});
  EXPECT_DOUBLE_EQ(c.binary().timeLeft(10.0), 5.0);
  const StatusReport rep = c.report();
  EXPECT_EQ(rep.value("tau_s"), "5");
  EXPECT_EQ(rep.value("watchdog enabled"), "False");
  EXPECT_EQ(rep.level, StatusLevel::kWarn);
  EXPECT_EQ(rep.message, "watchdog disabled (watchdog_enabled: false)");
}

TEST(LampControl, FaultPathLightsEverySegment) {
  EXPECT_EQ(faultLevels(SegmentLampParams()), std::vector<float>(1, 1.0f));
  EXPECT_EQ(faultLevels(threeSegments()), std::vector<float>(3, 1.0f));
  EXPECT_EQ(faultPublishRate(25.0), 25.0);
  EXPECT_EQ(faultPublishRate(0.5), 10.0);
  EXPECT_EQ(faultPublishRate(5000.0), 10.0);
  const StatusReport r = faultReport("tau_s must be > 0");
  EXPECT_EQ(r.level, StatusLevel::kError);
  EXPECT_EQ(r.message, "cannot start, lamp on (fail-safe): invalid parameters: tau_s must be > 0");
  EXPECT_EQ(r.value("lamp on"), "True");
  EXPECT_EQ(r.value("reason"), toString(LightReason::kFault));
}

// Both lamps, ticked only at inputs and at nextEvent(), are both lamps ticked every
// millisecond: the segments' timers run on their own and every one of them is an event.
TEST(LampControl, TickingOnlyAtNextEventMissesNoSegmentChange) {
  const std::vector<Eigen::AlignedBox2d> places = {
      Eigen::AlignedBox2d(Eigen::Vector2d(10.0, 3.0), Eigen::Vector2d(11.0, 4.0)),
      Eigen::AlignedBox2d(Eigen::Vector2d(10.0, -0.5), Eigen::Vector2d(11.0, 0.5)),
      Eigen::AlignedBox2d(Eigen::Vector2d(10.0, -4.0), Eigen::Vector2d(11.0, -3.0))};
  for (unsigned seed = 1; seed <= 10; ++seed) {
    std::mt19937 rng(seed);
    const auto roll = [&rng](unsigned n) { return static_cast<int>(rng() % n); };
    LampControl dense(params(), threeSegments()), lazy(params(), threeSegments());
    long next_input_ms = 0;
    for (long ms = 0; ms < 20000; ++ms) {
      const double now = ms * 1e-3;
      bool stale = false;
      dense.tick(now, stale);
      if (now >= lazy.nextEvent()) lazy.tick(now, stale);
      if (ms == next_input_ms) {
        std::vector<Eigen::AlignedBox2d> boxes;
        for (const auto& b : places)
          if (roll(5) == 0) boxes.push_back(b);
        const bool blind = roll(15) == 0;
        dense.onInput(now, boxes.size(), blind, boxes);
        lazy.onInput(now, boxes.size(), blind, boxes);
        next_input_ms += roll(8) == 0 ? 300 + roll(900) : 100;
      }
      ASSERT_EQ(lazy.segmented().levels(), dense.segmented().levels()) << "seed " << seed << " at " << now;
      ASSERT_EQ(lazy.segmented().reason(), dense.segmented().reason()) << "seed " << seed << " at " << now;
      ASSERT_EQ(lazy.binary().on(), dense.binary().on()) << "seed " << seed << " at " << now;
      ASSERT_EQ(lazy.binary().reason(), dense.binary().reason()) << "seed " << seed << " at " << now;
    }
  }
}

}  // namespace
}  // namespace icanc
