// Pins the sketch's fail-safe (firmware/icanc_headlight/headlight_logic.h, compiled here as on
// the board): ON at power-up until the host speaks, ON when disconnected, ON when commands stop
// for the timeout, OFF only on a fresh OFF command over a live link; millis() wrap-around.
#include <gtest/gtest.h>

#include "../../../firmware/icanc_headlight/headlight_logic.h"

namespace icanc_fw {
namespace {

TEST(HeadlightLogic, OnAtPowerUpUntilTheHostSpeaks) {
  HeadlightLogic l;
  EXPECT_EQ(l.commandTimeoutMs(), 500u);
  EXPECT_TRUE(l.lampOn());  // before the first update()
  EXPECT_TRUE(l.update(false, 0));
  EXPECT_EQ(l.reason(), kDisconnected);
  EXPECT_TRUE(l.update(true, 10));  // connected, no command yet
  EXPECT_EQ(l.reason(), kNoCommandYet);
  l.onCommand(false, 20);
  EXPECT_FALSE(l.update(true, 20));
  EXPECT_EQ(l.reason(), kCommandedOff);
}

TEST(HeadlightLogic, CommandTimeoutTurnsTheLampOn) {
  HeadlightLogic l(500);
  l.update(true, 0);
  l.onCommand(false, 1000);
  EXPECT_FALSE(l.update(true, 1499));
  EXPECT_TRUE(l.update(true, 1500));  // exactly the timeout: ON
  EXPECT_EQ(l.reason(), kCommandTimeout);
  l.onCommand(false, 1600);  // the heartbeat resumes
  EXPECT_FALSE(l.update(true, 1600));
}

TEST(HeadlightLogic, OnCommandKeepsTheLampOn) {
  HeadlightLogic l;
  l.onCommand(true, 5);
  EXPECT_TRUE(l.update(true, 5));
  EXPECT_EQ(l.reason(), kCommandedOn);
}

TEST(HeadlightLogic, DisconnectForgetsTheCommand) {
  HeadlightLogic l;
  l.onCommand(false, 100);
  EXPECT_FALSE(l.update(true, 100));
  EXPECT_TRUE(l.update(false, 150));  // link dropped (TX stop, sync timeout)
  EXPECT_EQ(l.reason(), kDisconnected);
  // Reconnected 50 ms later: the OFF from before the drop is young but not trusted.
  EXPECT_TRUE(l.update(true, 200));
  EXPECT_EQ(l.reason(), kNoCommandYet);
  l.onCommand(false, 210);
  EXPECT_FALSE(l.update(true, 210));
}

TEST(HeadlightLogic, MillisWrapAroundDoesNotTimeOutOrFreeze) {
  HeadlightLogic l(500);
  const uint32_t before_wrap = 0xFFFFFF00u;
  l.onCommand(false, before_wrap);
  EXPECT_FALSE(l.update(true, before_wrap + 0x100u));  // = 0 after the wrap, 256 ms later
  EXPECT_FALSE(l.update(true, 0x000000F0u));           // 496 ms later
  EXPECT_TRUE(l.update(true, 0x000000F4u));            // 500 ms later
}

TEST(HeadlightLogic, ReasonTextsAreDistinct) {
  EXPECT_STREQ(reasonText(kNoCommandYet), "no command yet");
  EXPECT_STREQ(reasonText(kCommandedOff), "commanded off");
  EXPECT_STRNE(reasonText(kDisconnected), reasonText(kCommandTimeout));
}

TEST(SegmentLevels, FullOnUnlessCommandedWithFreshLevels) {
  HeadlightLogic l(500);
  SegmentLevels seg(500);
  const uint8_t levels[3] = {0, 153, 255};
  l.update(true, 0);
  EXPECT_EQ(seg.duty(0, l, 0), 255);  // power-up: no command yet
  seg.onLevels(levels, 3, 10);
  EXPECT_EQ(seg.duty(0, l, 10), 255);  // levels, but no Bool command yet
  l.onCommand(false, 20);
  l.update(true, 20);
  EXPECT_EQ(seg.duty(0, l, 20), 0);
  EXPECT_EQ(seg.duty(1, l, 20), 153);
  EXPECT_EQ(seg.duty(2, l, 20), 255);
  EXPECT_EQ(seg.duty(3, l, 20), 255);  // beyond the levels received
  l.onCommand(false, 400);
  l.update(true, 510);
  EXPECT_EQ(seg.duty(0, l, 510), 255);  // the command is fresh, the levels are 500 ms old
  seg.onLevels(levels, 3, 520);
  l.update(true, 920);
  EXPECT_EQ(seg.duty(0, l, 920), 255);  // command timeout
  l.onCommand(false, 930);
  l.update(false, 940);
  EXPECT_EQ(seg.duty(0, l, 940), 255);  // disconnected
  seg.onDisconnect();
  l.onCommand(false, 950);
  l.update(true, 950);
  EXPECT_EQ(seg.duty(0, l, 950), 255);  // reconnected: levels forgotten until new ones come
  const uint8_t many[10] = {1, 2, 3, 4, 5, 6, 7, 8, 9, 10};
  seg.onLevels(many, 10, 960);
  EXPECT_EQ(seg.duty(7, l, 960), 8);
  EXPECT_EQ(seg.duty(8, l, 960), 255);  // at most kMaxSegments pins
}

// The host's ON can reach the board before its levels: ON with every level still 0 (the levels of
// the OFF before) lights every segment instead of a dark lamp; ON with some level lit follows the
// levels, and OFF with every level 0 is dark.
TEST(SegmentLevels, OnWithEveryLevelZeroLightsEverySegment) {
  HeadlightLogic l(500);
  SegmentLevels seg(500);
  const uint8_t off[3] = {0, 0, 0};
  const uint8_t one[3] = {0, 200, 0};
  seg.onLevels(off, 3, 0);
  l.onCommand(false, 0);
  l.update(true, 0);
  for (uint8_t i = 0; i < 3; ++i) EXPECT_EQ(seg.duty(i, l, 0), 0) << int(i);
  l.onCommand(true, 10);  // the ON, its levels not yet here
  l.update(true, 10);
  for (uint8_t i = 0; i < 3; ++i) EXPECT_EQ(seg.duty(i, l, 10), 255) << int(i);
  seg.onLevels(one, 3, 15);  // the levels follow
  EXPECT_EQ(seg.duty(0, l, 15), 0);
  EXPECT_EQ(seg.duty(1, l, 15), 200);
}

}  // namespace
}  // namespace icanc_fw
