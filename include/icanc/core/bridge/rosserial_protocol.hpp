// The rosserial serial wire protocol (the "0xFE" revision used by ROS 1 rosserial since Hydro),
// as a ROS-free library: frame encoding, a resynchronising frame parser with fault counters, and
// by-hand serialization of the few messages the headlight bridge speaks (rosserial_msgs/TopicInfo,
// rosserial_msgs/Log, std_msgs/Time, std_msgs/Bool). Time is an argument (seconds), never read
// from a clock.
//
// Frame (all multi-byte fields little-endian):
//
//   0xFF  0xFE  len_lo len_hi  len_chk  topic_lo topic_hi  payload[len]  msg_chk
//   len_chk = 255 - ((len_lo + len_hi) % 256)
//   msg_chk = 255 - ((topic_lo + topic_hi + sum(payload)) % 256)
//
// A receiver accepts a frame when the byte sums including the checksum are 255 modulo 256.
#pragma once

#include <cstddef>
#include <cstdint>
#include <deque>
#include <string>
#include <vector>

namespace icanc {
namespace rosserial {

constexpr std::uint8_t kSyncByte = 0xFF;
constexpr std::uint8_t kProtocolVersion = 0xFE;  // ROS Hydro and later
constexpr std::size_t kHeaderBytes = 7;          // sync, version, len (2), len_chk, topic (2)
constexpr std::size_t kFrameOverheadBytes = 8;   // header + msg_chk

// Reserved topic ids (rosserial_msgs/TopicInfo constants); user topics start at kFirstUserTopic.
enum TopicId : std::uint16_t {
  kIdPublisher = 0,         // host -> device: empty = "request topics"; device -> host: TopicInfo
  kIdSubscriber = 1,        // device -> host: TopicInfo of a device subscriber
  kIdServiceServer = 2,
  kIdServiceClient = 4,
  kIdParameterRequest = 6,
  kIdLog = 7,               // device -> host: rosserial_msgs/Log
  kIdTime = 10,             // device -> host: time request; host -> device: std_msgs/Time
  kIdTxStop = 11,           // host -> device: stop, the device drops its configuration
};
constexpr std::uint16_t kFirstUserTopic = 100;

// Message types and md5sums (computed from the message definitions, as genmsg does).
constexpr const char* kBoolType = "std_msgs/Bool";
constexpr const char* kBoolMd5 = "8b94c1b53db61fb6aed406028ad6332a";
constexpr const char* kUInt8ArrayType = "std_msgs/UInt8MultiArray";  // segment levels
constexpr const char* kUInt8ArrayMd5 = "82373f1612381bb6ee473b5cd6f5d89c";
constexpr const char* kTimeType = "std_msgs/Time";
constexpr const char* kTimeMd5 = "cd7166c74c552c311fbcc2fe5a7bc289";
constexpr const char* kTopicInfoType = "rosserial_msgs/TopicInfo";
constexpr const char* kTopicInfoMd5 = "0ad51f88fc44892f8c10684077646005";
constexpr const char* kLogType = "rosserial_msgs/Log";
constexpr const char* kLogMd5 = "11abd731c25933261cd6183bd12d6295";

// --- Serialization (ROS 1: little-endian, string = uint32 length + bytes) --------------------

class Writer {
 public:
  explicit Writer(std::vector<std::uint8_t>& out) : out_(out) {}
  void u8(std::uint8_t v) { out_.push_back(v); }
  void u16(std::uint16_t v);
  void u32(std::uint32_t v);
  void i32(std::int32_t v) { u32(static_cast<std::uint32_t>(v)); }
  void str(const std::string& s);

 private:
  std::vector<std::uint8_t>& out_;
};

// Bounds-checked reader: a read past the end fails (returns false) and leaves the value alone.
class Reader {
 public:
  Reader(const std::uint8_t* data, std::size_t size) : data_(data), size_(size) {}
  bool u8(std::uint8_t& v);
  bool u16(std::uint16_t& v);
  bool u32(std::uint32_t& v);
  bool i32(std::int32_t& v);
  bool str(std::string& s);
  std::size_t remaining() const { return size_ - pos_; }

 private:
  const std::uint8_t* data_;
  std::size_t size_;
  std::size_t pos_ = 0;
};

struct TopicInfo {  // rosserial_msgs/TopicInfo
  std::uint16_t topic_id = 0;
  std::string topic_name;
  std::string message_type;
  std::string md5sum;
  std::int32_t buffer_size = 0;
};
void serialize(const TopicInfo& m, std::vector<std::uint8_t>& out);
bool deserialize(const std::uint8_t* data, std::size_t size, TopicInfo& m);  // false: malformed

struct LogMessage {  // rosserial_msgs/Log
  enum Level : std::uint8_t { kDebug = 0, kInfo = 1, kWarn = 2, kError = 3, kFatal = 4 };
  std::uint8_t level = kInfo;
  std::string msg;
};
void serialize(const LogMessage& m, std::vector<std::uint8_t>& out);
bool deserialize(const std::uint8_t* data, std::size_t size, LogMessage& m);

struct Stamp {  // std_msgs/Time (a ROS time: seconds and nanoseconds)
  std::uint32_t sec = 0;
  std::uint32_t nsec = 0;
};
void serialize(const Stamp& m, std::vector<std::uint8_t>& out);
bool deserialize(const std::uint8_t* data, std::size_t size, Stamp& m);

void serializeBool(bool value, std::vector<std::uint8_t>& out);  // std_msgs/Bool
bool deserializeBool(const std::uint8_t* data, std::size_t size, bool& value);  // exactly 1 byte
// std_msgs/UInt8MultiArray with an empty layout (no dims, offset 0) and `data`; deserializing
// skips any layout and fails on a truncated payload or bytes left over.
void serializeUInt8Array(const std::vector<std::uint8_t>& data, std::vector<std::uint8_t>& out);
bool deserializeUInt8Array(const std::uint8_t* payload, std::size_t size, std::vector<std::uint8_t>& data);

// --- Framing ------------------------------------------------------------------------------

// Appends one frame to `out`. Payloads longer than 65535 bytes cannot be framed (std::length_error).
void appendFrame(std::uint16_t topic, const std::uint8_t* payload, std::size_t size,
                 std::vector<std::uint8_t>& out);
std::vector<std::uint8_t> encodeFrame(std::uint16_t topic, const std::vector<std::uint8_t>& payload);

// The host's "request topics" (empty frame on topic 0) and "stop" (empty frame on topic 11).
std::vector<std::uint8_t> requestTopicsFrame();
std::vector<std::uint8_t> txStopFrame();

struct Frame {
  std::uint16_t topic = 0;
  std::vector<std::uint8_t> payload;
};

// Faults seen by the parser. Every input byte ends up in exactly one of: a good frame, a garbage
// (discarded) byte, or the parser's pending buffer.
struct ParserCounters {
  std::uint64_t bytes = 0;                 // all bytes fed
  std::uint64_t frames = 0;                // good frames
  std::uint64_t frame_bytes = 0;           // bytes of good frames
  std::uint64_t garbage_bytes = 0;         // discarded bytes (noise, resync, abandoned frames)
  std::uint64_t bad_length_checksum = 0;   // header whose length checksum failed
  std::uint64_t oversize_length = 0;       // length above the receive buffer
  std::uint64_t bad_message_checksum = 0;  // complete frame whose message checksum failed
  std::uint64_t truncated = 0;             // frame cut off: no byte for frame_timeout mid-frame

  std::uint64_t faults() const {
    return bad_length_checksum + oversize_length + bad_message_checksum + truncated;
  }
};

// "3 garbage bytes, 1 bad message checksum": the faults counted in `after` but not in `before`
// ("" when none).
std::string describeNewFaults(const ParserCounters& before, const ParserCounters& after);

// Byte-stream -> frames. Resynchronises after any fault by rescanning the bytes that followed the
// rejected frame's first sync byte, so a good frame hidden behind noise, a truncated frame or a
// corrupted header is still found. A frame that stops mid-way for longer than frame_timeout_s is
// abandoned (counted as truncated). Never throws on any input; memory is bounded by
// max_payload + kFrameOverheadBytes.
class FrameParser {
 public:
  explicit FrameParser(std::size_t max_payload = 512, double frame_timeout_s = 0.1);

  // Feeds bytes received at `now` [s]; appends the complete good frames to `out`.
  void feed(const std::uint8_t* data, std::size_t size, double now, std::vector<Frame>& out);
  // Advances the clock without bytes: abandons a frame that has stalled for frame_timeout_s.
  void poll(double now, std::vector<Frame>& out);
  // Drops any partial frame (e.g. the port was reopened); counts nothing.
  void reset();

  bool midFrame() const { return !buf_.empty(); }
  std::size_t pendingBytes() const { return buf_.size(); }
  const ParserCounters& counters() const { return counters_; }
  std::size_t maxPayload() const { return max_payload_; }

 private:
  enum class Reject { kLengthChecksum, kOversize, kMessageChecksum, kTruncated };
  void consume(std::uint8_t byte, std::vector<Frame>& out);
  void reject(Reject why);
  void drain(std::vector<Frame>& out);
  std::size_t expectedSize() const;  // full frame size once the header is in

  std::size_t max_payload_;
  double frame_timeout_s_;
  std::vector<std::uint8_t> buf_;      // the candidate frame, starting with 0xFF
  std::deque<std::uint8_t> replay_;    // bytes to rescan after a rejected candidate
  double last_byte_s_ = 0.0;
  ParserCounters counters_;
};

}  // namespace rosserial
}  // namespace icanc
