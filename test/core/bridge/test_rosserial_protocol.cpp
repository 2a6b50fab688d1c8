// Pins the rosserial framing and serialization to byte-exact frames worked out by hand from the
// public protocol description (wiki.ros.org/rosserial/Overview/Protocol), and the frame parser's
// resynchronisation and fault counting.
#include <gtest/gtest.h>

#include <random>

#include "icanc/core/bridge/rosserial_protocol.hpp"

namespace icanc {
namespace rosserial {
namespace {

using Bytes = std::vector<std::uint8_t>;

const Bytes kRequestTopics = {0xFF, 0xFE, 0x00, 0x00, 0xFF, 0x00, 0x00, 0xFF};
const Bytes kTxStop = {0xFF, 0xFE, 0x00, 0x00, 0xFF, 0x0B, 0x00, 0xF4};
// std_msgs/Bool on topic 100: len 1 (chk 255-1 = 0xFE), msg chk 255-(100+0+data).
const Bytes kBoolTrue100 = {0xFF, 0xFE, 0x01, 0x00, 0xFE, 0x64, 0x00, 0x01, 0x9A};
const Bytes kBoolFalse100 = {0xFF, 0xFE, 0x01, 0x00, 0xFE, 0x64, 0x00, 0x00, 0x9B};
const Bytes kBoolFalse125 = {0xFF, 0xFE, 0x01, 0x00, 0xFE, 0x7D, 0x00, 0x00, 0x82};
// std_msgs/Time {1700000000 s, 500000000 ns} on topic 10.
const Bytes kTime = {0xFF, 0xFE, 0x08, 0x00, 0xF7, 0x0A, 0x00, 0x00, 0xF1, 0x53,
                     0x65, 0x00, 0x65, 0xCD, 0x1D, 0xFD};
// rosserial_msgs/Log {level WARN (2), "hi"} on topic 7.
const Bytes kLogHi = {0xFF, 0xFE, 0x07, 0x00, 0xF8, 0x07, 0x00, 0x02, 0x02, 0x00, 0x00, 0x00, 0x68, 0x69, 0x23};
// rosserial_msgs/TopicInfo {100, "lamp_cmd", "std_msgs/Bool", md5, 512} on topic 1 (a subscriber).
const Bytes kTopicInfoLampCmd = {
    0xFF, 0xFE, 0x47, 0x00, 0xB8, 0x01, 0x00, 0x64, 0x00, 0x08, 0x00, 0x00, 0x00, 0x6C, 0x61, 0x6D,
    0x70, 0x5F, 0x63, 0x6D, 0x64, 0x0D, 0x00, 0x00, 0x00, 0x73, 0x74, 0x64, 0x5F, 0x6D, 0x73, 0x67,
    0x73, 0x2F, 0x42, 0x6F, 0x6F, 0x6C, 0x20, 0x00, 0x00, 0x00, 0x38, 0x62, 0x39, 0x34, 0x63, 0x31,
    0x62, 0x35, 0x33, 0x64, 0x62, 0x36, 0x31, 0x66, 0x62, 0x36, 0x61, 0x65, 0x64, 0x34, 0x30, 0x36,
    0x30, 0x32, 0x38, 0x61, 0x64, 0x36, 0x33, 0x33, 0x32, 0x61, 0x00, 0x02, 0x00, 0x00, 0x25};

Bytes cat(std::initializer_list<Bytes> parts) {
  Bytes out;
  for (const Bytes& p : parts) out.insert(out.end(), p.begin(), p.end());
  return out;
}

std::vector<Frame> parseAll(FrameParser& p, const Bytes& bytes, double now = 0.0) {
  std::vector<Frame> out;
  p.feed(bytes.data(), bytes.size(), now, out);
  return out;
}

// Every byte is in a good frame, discarded as garbage, or still pending.
void expectAccounted(const FrameParser& p) {
  const ParserCounters& c = p.counters();
  EXPECT_EQ(c.bytes, c.frame_bytes + c.garbage_bytes + p.pendingBytes());
}

TEST(RosserialFrames, HostControlFramesAreByteExact) {
  EXPECT_EQ(requestTopicsFrame(), kRequestTopics);
  EXPECT_EQ(txStopFrame(), kTxStop);
}

TEST(RosserialFrames, BoolTimeLogAndTopicInfoAreByteExact) {
  Bytes payload;
  serializeBool(true, payload);
  EXPECT_EQ(encodeFrame(100, payload), kBoolTrue100);
  payload.clear();
  serializeBool(false, payload);
  EXPECT_EQ(encodeFrame(100, payload), kBoolFalse100);
  EXPECT_EQ(encodeFrame(125, payload), kBoolFalse125);

  payload.clear();
  serialize(Stamp{1700000000u, 500000000u}, payload);
  EXPECT_EQ(encodeFrame(kIdTime, payload), kTime);

  payload.clear();
  LogMessage log;
  log.level = LogMessage::kWarn;
  log.msg = "hi";
  serialize(log, payload);
  EXPECT_EQ(encodeFrame(kIdLog, payload), kLogHi);

  TopicInfo ti;
  ti.topic_id = 100;
  ti.topic_name = "lamp_cmd";
  ti.message_type = kBoolType;
  ti.md5sum = kBoolMd5;
  ti.buffer_size = 512;
  payload.clear();
  serialize(ti, payload);
  EXPECT_EQ(encodeFrame(kIdSubscriber, payload), kTopicInfoLampCmd);
}

TEST(RosserialFrames, LengthAboveOneByteUsesBothLengthBytes) {
  const Bytes f = encodeFrame(300, Bytes(300, 0));
  ASSERT_EQ(f.size(), 308u);
  EXPECT_EQ(f[2], 0x2C);  // 300 = 0x012C, little-endian
  EXPECT_EQ(f[3], 0x01);
  EXPECT_EQ(f[4], 0xD2);  // 255 - (0x2C + 0x01)
  EXPECT_EQ(f[5], 0x2C);  // topic 300
  EXPECT_EQ(f[6], 0x01);
  EXPECT_EQ(f.back(), 0xD2);  // 255 - (0x2C + 0x01 + 0)
  EXPECT_THROW(encodeFrame(100, Bytes(70000, 0)), std::length_error);
}

TEST(RosserialFrames, DeserializeRoundTripsAndRejectsShortPayloads) {
  TopicInfo ti;
  ASSERT_TRUE(deserialize(kTopicInfoLampCmd.data() + 7, kTopicInfoLampCmd.size() - 8, ti));
  EXPECT_EQ(ti.topic_id, 100);
  EXPECT_EQ(ti.topic_name, "lamp_cmd");
  EXPECT_EQ(ti.message_type, "std_msgs/Bool");
  EXPECT_EQ(ti.md5sum, kBoolMd5);
  EXPECT_EQ(ti.buffer_size, 512);
  // Every truncation of the payload is malformed, never a crash or a partial message.
  for (std::size_t n = 0; n + 8 < kTopicInfoLampCmd.size(); ++n) {
    TopicInfo t;
    t.topic_id = 7;
    EXPECT_FALSE(deserialize(kTopicInfoLampCmd.data() + 7, n, t)) << n;
    EXPECT_EQ(t.topic_id, 7);
  }
  // A string length far beyond the payload.
  const Bytes huge = {0x64, 0x00, 0xFF, 0xFF, 0xFF, 0x7F, 'a'};
  EXPECT_FALSE(deserialize(huge.data(), huge.size(), ti));

  LogMessage log;
  ASSERT_TRUE(deserialize(kLogHi.data() + 7, kLogHi.size() - 8, log));
  EXPECT_EQ(log.level, LogMessage::kWarn);
  EXPECT_EQ(log.msg, "hi");
  Stamp t;
  ASSERT_TRUE(deserialize(kTime.data() + 7, 8, t));
  EXPECT_EQ(t.sec, 1700000000u);
  EXPECT_EQ(t.nsec, 500000000u);
  EXPECT_FALSE(deserialize(kTime.data() + 7, 7, t));
  bool b = false;
  EXPECT_TRUE(deserializeBool(kBoolTrue100.data() + 7, 1, b));
  EXPECT_TRUE(b);
  EXPECT_FALSE(deserializeBool(kBoolTrue100.data() + 7, 2, b));
  EXPECT_FALSE(deserializeBool(kBoolTrue100.data() + 7, 0, b));
}

TEST(FrameParser, ParsesFramesSplitAtEveryByte) {
  const Bytes stream = cat({kRequestTopics, kTopicInfoLampCmd, kBoolTrue100, kTime});
  FrameParser p;
  std::vector<Frame> frames;
  for (std::uint8_t b : stream) p.feed(&b, 1, 0.0, frames);
  ASSERT_EQ(frames.size(), 4u);
  EXPECT_EQ(frames[0].topic, kIdPublisher);
  EXPECT_TRUE(frames[0].payload.empty());
  EXPECT_EQ(frames[1].topic, kIdSubscriber);
  EXPECT_EQ(frames[1].payload.size(), kTopicInfoLampCmd.size() - 8);
  EXPECT_EQ(frames[2].topic, 100);
  EXPECT_EQ(frames[2].payload, Bytes{1});
  EXPECT_EQ(frames[3].topic, kIdTime);
  EXPECT_EQ(p.counters().frames, 4u);
  EXPECT_EQ(p.counters().faults(), 0u);
  EXPECT_EQ(p.counters().garbage_bytes, 0u);
  expectAccounted(p);
}

TEST(FrameParser, GarbageBeforeAFrameIsCountedAndSkipped) {
  // Noise including lone sync bytes and a sync byte right before the real frame.
  const Bytes noise = {0x00, 0x13, 0xFF, 0x42, 0xFE, 0xFF, 0xFF};
  FrameParser p;
  const auto frames = parseAll(p, cat({noise, kBoolFalse100}));
  ASSERT_EQ(frames.size(), 1u);
  EXPECT_EQ(frames[0].payload, Bytes{0});
  EXPECT_EQ(p.counters().garbage_bytes, noise.size());
  EXPECT_EQ(p.counters().faults(), 0u);
  expectAccounted(p);
}

TEST(FrameParser, BadLengthChecksumIsCountedAndTheNextFrameFound) {
  Bytes bad = kBoolTrue100;
  bad[4] ^= 0x01;
  FrameParser p;
  const auto frames = parseAll(p, cat({bad, kBoolFalse100}));
  ASSERT_EQ(frames.size(), 1u);
  EXPECT_EQ(frames[0].payload, Bytes{0});
  EXPECT_EQ(p.counters().bad_length_checksum, 1u);
  EXPECT_EQ(p.counters().garbage_bytes, bad.size());
  expectAccounted(p);
}

TEST(FrameParser, BadMessageChecksumIsCountedAndTheNextFrameFound) {
  Bytes bad = kBoolTrue100;
  bad.back() ^= 0x55;
  FrameParser p;
  const auto frames = parseAll(p, cat({bad, kTime}));
  ASSERT_EQ(frames.size(), 1u);
  EXPECT_EQ(frames[0].topic, kIdTime);
  EXPECT_EQ(p.counters().bad_message_checksum, 1u);
  expectAccounted(p);
}

TEST(FrameParser, OversizedLengthIsRejectedAtTheHeader) {
  // Length 0x4000 with a valid length checksum: rejected before any payload is buffered.
  const Bytes oversized = {0xFF, 0xFE, 0x00, 0x40, 0xBF, 0x64, 0x00};
  FrameParser p(512);
  const auto frames = parseAll(p, cat({oversized, kBoolFalse100}));
  ASSERT_EQ(frames.size(), 1u);
  EXPECT_EQ(p.counters().oversize_length, 1u);
  EXPECT_EQ(p.counters().bad_length_checksum, 0u);
  EXPECT_LE(p.pendingBytes(), 512u + kFrameOverheadBytes);
  // Exactly the maximum is accepted.
  FrameParser q(300);
  EXPECT_EQ(parseAll(q, encodeFrame(100, Bytes(300, 7))).size(), 1u);
  EXPECT_EQ(parseAll(q, encodeFrame(100, Bytes(301, 7))).size(), 0u);
  EXPECT_EQ(q.counters().oversize_length, 1u);
}

TEST(FrameParser, TruncatedFrameIsAbandonedAfterTheTimeout) {
  FrameParser p(512, 0.1);
  std::vector<Frame> out;
  const Bytes head(kTopicInfoLampCmd.begin(), kTopicInfoLampCmd.begin() + 20);
  p.feed(head.data(), head.size(), 1.0, out);
  p.poll(1.05, out);
  EXPECT_TRUE(p.midFrame());
  EXPECT_EQ(p.counters().truncated, 0u);
  p.poll(1.1, out);
  EXPECT_FALSE(p.midFrame());
  EXPECT_EQ(p.counters().truncated, 1u);
  // The next frame after the gap parses normally (the stale head was not glued to it).
  p.feed(kBoolTrue100.data(), kBoolTrue100.size(), 2.0, out);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].topic, 100);
  expectAccounted(p);
}

TEST(FrameParser, StalledFrameFoundOnTheNextFeedToo) {
  // No poll between: the late bytes' arrival time abandons the stalled frame first.
  FrameParser p(512, 0.1);
  std::vector<Frame> out;
  p.feed(kTime.data(), 6, 0.0, out);
  p.feed(kBoolFalse100.data(), kBoolFalse100.size(), 0.5, out);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].topic, 100);
  EXPECT_EQ(p.counters().truncated, 1u);
}

TEST(FrameParser, FrameInsideATruncatedOneIsRecovered) {
  // A device reset mid-frame: a header announcing 71 bytes, 10 of them, then a complete frame
  // that the old length swallows. The message checksum fails when the length is reached, or the
  // frame stalls; either way the complete frame is found by the rescan.
  const Bytes partial(kTopicInfoLampCmd.begin(), kTopicInfoLampCmd.begin() + 10);
  FrameParser p(512, 0.1);
  std::vector<Frame> out;
  const Bytes s = cat({partial, kTime});
  p.feed(s.data(), s.size(), 0.0, out);
  EXPECT_TRUE(out.empty());
  p.poll(0.2, out);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].topic, kIdTime);
  EXPECT_EQ(p.counters().truncated, 1u);
  expectAccounted(p);

  // The same followed by enough bytes to complete the swallowing frame: checksum fault, rescan.
  FrameParser q(512, 0.1);
  out.clear();
  const Bytes s2 = cat({partial, kTime, Bytes(60, 0x00), kBoolTrue100});
  q.feed(s2.data(), s2.size(), 0.0, out);
  ASSERT_EQ(out.size(), 2u);
  EXPECT_EQ(out[0].topic, kIdTime);
  EXPECT_EQ(out[1].topic, 100);
  EXPECT_EQ(q.counters().bad_message_checksum, 1u);
  expectAccounted(q);
}

TEST(FrameParser, RandomNoiseNeverHidesLaterFramesAndEveryByteIsAccounted) {
  std::mt19937 rng(42);
  std::uniform_int_distribution<int> byte(0, 255), len(0, 40);
  FrameParser p(512, 0.1);
  std::vector<Frame> out;
  double now = 0.0;
  int sent = 0;
  for (int round = 0; round < 500; ++round) {
    Bytes noise(len(rng));
    for (auto& b : noise) b = static_cast<std::uint8_t>(byte(rng));
    p.feed(noise.data(), noise.size(), now, out);
    now += 0.2;  // a gap: whatever the noise started is abandoned
    p.feed(kBoolTrue100.data(), kBoolTrue100.size(), now, out);
    ++sent;
    now += 0.01;
  }
  int good = 0;
  for (const Frame& f : out) good += f.topic == 100 && f.payload == Bytes{1};
  EXPECT_GE(good, sent);  // noise can contain frames by chance, never hide one
  expectAccounted(p);
  EXPECT_GT(p.counters().garbage_bytes, 0u);
}

TEST(FrameParser, DescribeNewFaultsNamesEachKind) {
  ParserCounters a, b;
  EXPECT_EQ(describeNewFaults(a, b), "");
  b.garbage_bytes = 3;
  b.bad_message_checksum = 1;
  b.truncated = 2;
  EXPECT_EQ(describeNewFaults(a, b), "3 garbage bytes, 1 bad message checksum, 2 truncated frame");
}

}  // namespace
}  // namespace rosserial
}  // namespace icanc
