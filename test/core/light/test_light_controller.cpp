// Pins the light controller to the paper's state diagram and the fail-safe watchdog.
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "icanc/core/light/light_controller.hpp"

namespace icanc {
namespace {

LightControllerParams paperParams() {
  LightControllerParams p;
  p.tau_s = 3.0;
  p.recheck_below_s = 1.0;
  p.watchdog_enabled = false;  // the paper's machine alone
  return p;
}

TEST(LightController, OffUntilDangerThenOnForTau) {
  LightController lc(paperParams());
  lc.onInput(10.0, false);
  EXPECT_FALSE(lc.on());
  EXPECT_EQ(lc.reason(), LightReason::kOff);
  EXPECT_TRUE(lc.onInput(10.5, true));
  EXPECT_TRUE(lc.on());
  EXPECT_EQ(lc.reason(), LightReason::kDanger);
  EXPECT_DOUBLE_EQ(lc.timeLeft(10.5), 3.0);
  EXPECT_DOUBLE_EQ(lc.lastTriggerTime(), 10.5);
  lc.tick(13.49);
  EXPECT_TRUE(lc.on());
  EXPECT_TRUE(lc.tick(13.5));  // timer reaches 0 -> off
  EXPECT_FALSE(lc.on());
  EXPECT_DOUBLE_EQ(lc.timeLeft(13.5), 0.0);
}

TEST(LightController, DangerIgnoredAboveOneSecondLeft) {
  LightController lc(paperParams());
  lc.onInput(0.0, true);             // on, ends at 3.0
  EXPECT_FALSE(lc.onInput(1.99, true));  // 1.01 s left: ignored
  EXPECT_DOUBLE_EQ(lc.lastTriggerTime(), 0.0);
  lc.tick(3.0);
  EXPECT_FALSE(lc.on());  // the ignored danger did not extend the timer
}

TEST(LightController, DangerResetsTimerAtOrBelowOneSecond) {
  LightController lc(paperParams());
  lc.onInput(0.0, true);
  EXPECT_TRUE(lc.onInput(2.0, true));  // exactly 1 s left: reset
  EXPECT_DOUBLE_EQ(lc.timeLeft(2.0), 3.0);
  EXPECT_FALSE(lc.onInput(3.5, true));  // 1.5 s left on the new timer: ignored
  EXPECT_TRUE(lc.onInput(4.0, true));   // 1.0 s left: reset again
  lc.tick(6.99);
  EXPECT_TRUE(lc.on());
  lc.tick(7.0);
  EXPECT_FALSE(lc.on());
}

TEST(LightController, ContinuousDangerKeepsTheLampOnAndEndsTauAfterTheLastReset) {
  LightController lc(paperParams());
  double last_reset = -1.0;
  for (int k = 0; k <= 100; ++k) {  // 10 s of danger at 10 Hz
    const double t = k * 0.1;
    if (lc.onInput(t, true)) last_reset = t;
    ASSERT_TRUE(lc.on()) << t;
  }
  // Resets happen each time at most 1 s is left: every ~2 s with tau = 3.
  EXPECT_NEAR(last_reset, 10.0, 2.0 + 1e-9);
  for (int k = 101; k <= 160; ++k) {
    const double t = k * 0.1;
    lc.onInput(t, false);
    EXPECT_EQ(lc.on(), t < last_reset + 3.0 - 1e-9) << t;
  }
}

TEST(LightController, WatchdogTurnsTheLampOnWhenInputStopsAndReleasesWhenItResumes) {
  LightControllerParams p = paperParams();
  p.stale_timeout_s = 0.3;
  p.watchdog_enabled = true;
  LightController lc(p);
  EXPECT_TRUE(lc.on());  // no input yet: fail-safe on
  EXPECT_EQ(lc.reason(), LightReason::kSensorStale);
  lc.onInput(1.0, false);
  EXPECT_FALSE(lc.on());
  EXPECT_FALSE(lc.tick(1.3));  // exactly at the timeout: still fresh
  EXPECT_TRUE(lc.tick(1.31));
  EXPECT_TRUE(lc.on());
  EXPECT_EQ(lc.reason(), LightReason::kSensorStale);
  lc.onInput(2.0, false);
  EXPECT_FALSE(lc.on());
  EXPECT_EQ(lc.reason(), LightReason::kOff);
}

TEST(LightController, TimeGoingBackwardsResetsToFailSafe) {
  LightControllerParams p = paperParams();
  p.stale_timeout_s = 0.3;
  p.watchdog_enabled = true;
  LightController lc(p);
  lc.onInput(100.0, true);
  lc.onInput(100.1, false);
  EXPECT_TRUE(lc.tick(50.0));  // bag looped: danger -> sensor stale is a change
  EXPECT_TRUE(lc.on());
  EXPECT_EQ(lc.reason(), LightReason::kSensorStale);
  lc.onInput(50.1, false);
  EXPECT_FALSE(lc.on());  // the old timer (ending at 103) does not survive the loop
}

TEST(LightController, ValidateNamesTheParameter) {
  EXPECT_EQ(validate(LightControllerParams{}), "");
  EXPECT_NE(validate(LightControllerParams{0.0, 1.0, 0.3}).find("tau_s"), std::string::npos);
  EXPECT_NE(validate(LightControllerParams{3.0, 4.0, 0.3}).find("recheck_below_s"),
            std::string::npos);
  EXPECT_NE(validate(LightControllerParams{3.0, 1.0, -1.0}).find("stale_timeout_s"),
            std::string::npos);
}

// A timeout never switches the watchdog off; 0, negative, NaN and huge are refused and
// the message names the explicit switch.
TEST(LightController, WatchdogTimeoutZeroNegativeOrHugeIsRefused) {
  for (double bad : {0.0, -5.0, 1e9, 5.01, std::nan("")}) {
    LightControllerParams p;
    p.stale_timeout_s = bad;
    const std::string why = validate(p);
    EXPECT_NE(why.find("stale_timeout_s"), std::string::npos) << bad;
    EXPECT_NE(why.find("watchdog_enabled"), std::string::npos) << bad;
  }
  LightControllerParams p;
  p.stale_timeout_s = kMaxStaleTimeoutS;
  EXPECT_EQ(validate(p), "");
}

// A slow publish rate never silences the lamp side: rates below the floor are refused with the
// key named.
TEST(LightController, PublishRatesBelowTheFloorAreRefused) {
  EXPECT_EQ(validatePublishRate(10.0), "");
  EXPECT_EQ(validatePublishRate(kMinPublishRateHz), "");
  for (double bad : {0.01, 0.0, -1.0, 1.99, 1e4, std::nan("")})
    EXPECT_NE(validatePublishRate(bad).find("publish_rate_hz"), std::string::npos) << bad;
}

// The nodelet wakes only at nextEvent(): the timer's end, the watchdog's instant, a bright report
// going stale.
TEST(LightController, NextEventIsTheTimersEndOrTheWatchdogsInstant) {
  LightControllerParams p;
  p.tau_s = 2.0;
  p.stale_timeout_s = 0.3;
  LightController c(p);
  EXPECT_TRUE(std::isinf(c.nextEvent()));  // no input yet: stale until one comes
  c.onInput(10.0, false);
  EXPECT_NEAR(c.nextEvent(), 10.3, 1e-5);
  EXPECT_FALSE(c.tick(c.nextEvent() - 1e-4));
  EXPECT_TRUE(c.tick(c.nextEvent()));
  EXPECT_EQ(c.reason(), LightReason::kSensorStale);
  EXPECT_TRUE(std::isinf(c.nextEvent()));  // stale until the next input
  c.onInput(11.0, true);
  c.onInput(11.2, false);
  EXPECT_NEAR(c.nextEvent(), 11.5, 1e-5);
  p.watchdog_enabled = false;
  c.setParams(p);
  EXPECT_NEAR(c.nextEvent(), 13.0, 1e-6);  // only the timer's end
  EXPECT_TRUE(c.tick(13.0));
  EXPECT_FALSE(c.on());
}

// A controller ticked only at inputs and at its nextEvent() is the controller ticked every
// millisecond, at every millisecond, over random inputs, blind frames, illumination reports
// and gaps longer than the watchdog.
TEST(LightController, TickingOnlyAtNextEventMissesNoChange) {
  LightControllerParams p;
  p.tau_s = 1.5;
  p.recheck_below_s = 0.5;
  p.stale_timeout_s = 0.3;
  p.illumination_enabled = true;
  p.illumination_stale_timeout_s = 0.7;
  for (unsigned seed = 1; seed <= 20; ++seed) {
    std::mt19937 rng(seed);
    const auto roll = [&rng](unsigned n) { return static_cast<int>(rng() % n); };
    LightController dense(p), lazy(p);
    long next_input_ms = 0, next_report_ms = 0;
    for (long ms = 0; ms < 20000; ++ms) {
      const double now = ms * 1e-3;
      dense.tick(now);
      if (now >= lazy.nextEvent()) lazy.tick(now);
      if (ms == next_report_ms) {
        const Illumination state = roll(2) ? Illumination::kBright : Illumination::kDark;
        dense.onIllumination(now, state);
        lazy.onIllumination(now, state);
        next_report_ms += 200 + roll(1500);
      }
      if (ms == next_input_ms) {
        const bool danger = roll(4) == 0, blind = roll(10) == 0;
        dense.onInput(now, danger, blind);
        lazy.onInput(now, danger, blind);
        next_input_ms += roll(8) == 0 ? 200 + roll(800) : 100;
      }
      ASSERT_EQ(lazy.on(), dense.on()) << "seed " << seed << " at " << now;
      ASSERT_EQ(lazy.reason(), dense.reason()) << "seed " << seed << " at " << now;
    }
  }
}

TEST(LightController, OnlyTheExplicitSwitchDisablesTheWatchdog) {
  LightControllerParams p;
  p.stale_timeout_s = 0.3;
  LightController on(p);
  on.onInput(1.0, false);
  EXPECT_TRUE(on.tick(2.0));
  EXPECT_EQ(on.reason(), LightReason::kSensorStale);
  p.watchdog_enabled = false;
  LightController off(p);
  off.onInput(1.0, false);
  EXPECT_FALSE(off.tick(100.0));
  EXPECT_FALSE(off.on());
}

// A blind sensor is no clear road. Lamp ON with kSensorBlind for as long as the inputs
// say blind, over the timer's state, and back to the timer when the returns come back.
TEST(LightController, BlindSensorLightsTheLampUntilTheReturnsComeBack) {
  LightControllerParams p;
  LightController lc(p);
  lc.onInput(1.0, false);
  EXPECT_FALSE(lc.on());
  lc.onInput(1.1, false, true);
  EXPECT_TRUE(lc.on());
  EXPECT_EQ(lc.reason(), LightReason::kSensorBlind);
  EXPECT_FALSE(lc.tick(1.2));  // still blind between inputs
  EXPECT_TRUE(lc.on());
  lc.onInput(1.2, true, true);  // danger while blind: the timer runs underneath
  EXPECT_EQ(lc.reason(), LightReason::kSensorBlind);
  lc.onInput(1.3, false, false);
  EXPECT_EQ(lc.reason(), LightReason::kDanger);
  lc.onInput(4.3, false, false);  // the timer (3 s from 1.2) has run out
  EXPECT_FALSE(lc.on());
  EXPECT_EQ(lc.reason(), LightReason::kOff);
  EXPECT_STREQ(toString(LightReason::kSensorBlind), "sensor blind");
}

TEST(LightControllerIllumination, BlindSensorWinsOverDaylight) {
  LightControllerParams p;
  p.illumination_enabled = true;
  LightController lc(p);
  lc.onIllumination(0.0, Illumination::kBright);
  lc.onInput(0.1, false, true);
  EXPECT_TRUE(lc.on());
  EXPECT_EQ(lc.reason(), LightReason::kSensorBlind);
}

// The illumination gate: off by default, the paper's machine unchanged.
LightControllerParams gatedParams() {
  LightControllerParams p = paperParams();
  p.stale_timeout_s = 0.3;
  p.watchdog_enabled = true;
  p.illumination_enabled = true;
  p.illumination_stale_timeout_s = 1.0;
  return p;
}

TEST(LightControllerIllumination, DisabledGateIgnoresDaylight) {
  LightControllerParams p = gatedParams();
  p.illumination_enabled = false;
  LightController lc(p);
  EXPECT_FALSE(lc.onIllumination(0.0, Illumination::kBright));
  EXPECT_TRUE(lc.onInput(0.05, true));
  EXPECT_TRUE(lc.on());
  EXPECT_EQ(lc.reason(), LightReason::kDanger);
}

TEST(LightControllerIllumination, NoDangerLampInDaylightButAtNight) {
  LightController lc(gatedParams());
  lc.onIllumination(0.0, Illumination::kBright);
  EXPECT_FALSE(lc.onInput(0.1, true));  // danger in daylight: no timer
  EXPECT_FALSE(lc.on());
  EXPECT_EQ(lc.reason(), LightReason::kDaylight);
  EXPECT_STREQ(toString(lc.reason()), "daylight");
  lc.onIllumination(0.15, Illumination::kDark);
  EXPECT_EQ(lc.reason(), LightReason::kOff);
  EXPECT_TRUE(lc.onInput(0.2, true));  // night: the paper's rule
  EXPECT_TRUE(lc.on());
  EXPECT_EQ(lc.reason(), LightReason::kDanger);
}

TEST(LightControllerIllumination, DaylightCancelsARunningTimer) {
  LightController lc(gatedParams());
  lc.onIllumination(0.0, Illumination::kDark);
  ASSERT_TRUE(lc.onInput(0.1, true));
  EXPECT_TRUE(lc.onIllumination(0.2, Illumination::kBright));
  EXPECT_FALSE(lc.on());
  EXPECT_EQ(lc.reason(), LightReason::kDaylight);
  lc.onInput(0.3, false);
  lc.onIllumination(0.35, Illumination::kDark);  // night again: the old timer does not come back
  EXPECT_FALSE(lc.on());
  EXPECT_EQ(lc.reason(), LightReason::kOff);
}

TEST(LightControllerIllumination, UnknownOrStaleIlluminationIsThePaper) {
  LightController lc(gatedParams());
  lc.onIllumination(0.0, Illumination::kUnknown);
  EXPECT_TRUE(lc.onInput(0.1, true));
  EXPECT_EQ(lc.reason(), LightReason::kDanger);

  LightController stale(gatedParams());
  stale.onIllumination(0.0, Illumination::kBright);
  stale.onInput(0.9, true);
  EXPECT_FALSE(stale.on());  // 0.9 s old: still daylight
  for (double t = 1.0; t < 1.05; t += 0.01) stale.onInput(t, false);
  EXPECT_EQ(stale.reason(), LightReason::kOff);  // report older than 1 s: gate open
  EXPECT_TRUE(stale.onInput(1.1, true));
  EXPECT_TRUE(stale.on());
  EXPECT_EQ(stale.reason(), LightReason::kDanger);
}

TEST(LightControllerIllumination, WatchdogStillWinsInDaylight) {
  LightController lc(gatedParams());
  EXPECT_TRUE(lc.on());  // no input yet
  lc.onIllumination(0.0, Illumination::kBright);
  EXPECT_TRUE(lc.on());
  EXPECT_EQ(lc.reason(), LightReason::kSensorStale);
  lc.onInput(0.1, false);
  EXPECT_EQ(lc.reason(), LightReason::kDaylight);
  lc.onIllumination(0.3, Illumination::kBright);
  EXPECT_TRUE(lc.tick(0.45));  // input 0.35 s ago, illumination fresh: sensor stale, lamp ON
  EXPECT_TRUE(lc.on());
  EXPECT_EQ(lc.reason(), LightReason::kSensorStale);
}

TEST(LightControllerIllumination, ValidateNamesTheTimeout) {
  LightControllerParams p = gatedParams();
  p.illumination_stale_timeout_s = 0.0;
  EXPECT_NE(validate(p).find("illumination"), std::string::npos);
}

}  // namespace
}  // namespace icanc
