#include "icanc/core/bridge/rosserial_protocol.hpp"

#include <sstream>
#include <stdexcept>

namespace icanc {
namespace rosserial {

// --- Serialization ----------------------------------------------------------------------------

void Writer::u16(std::uint16_t v) {
  out_.push_back(static_cast<std::uint8_t>(v & 0xFF));
  out_.push_back(static_cast<std::uint8_t>(v >> 8));
}

void Writer::u32(std::uint32_t v) {
  for (int shift = 0; shift < 32; shift += 8) out_.push_back(static_cast<std::uint8_t>(v >> shift));
}

void Writer::str(const std::string& s) {
  u32(static_cast<std::uint32_t>(s.size()));
  out_.insert(out_.end(), s.begin(), s.end());
}

bool Reader::u8(std::uint8_t& v) {
  if (remaining() < 1) return false;
  v = data_[pos_++];
  return true;
}

bool Reader::u16(std::uint16_t& v) {
  if (remaining() < 2) return false;
  v = static_cast<std::uint16_t>(data_[pos_] | (data_[pos_ + 1] << 8));
  pos_ += 2;
  return true;
}

bool Reader::u32(std::uint32_t& v) {
  if (remaining() < 4) return false;
  v = 0;
  for (int i = 3; i >= 0; --i) v = (v << 8) | data_[pos_ + i];
  pos_ += 4;
  return true;
}

bool Reader::i32(std::int32_t& v) {
  std::uint32_t u = 0;
  if (!u32(u)) return false;
  v = static_cast<std::int32_t>(u);
  return true;
}

bool Reader::str(std::string& s) {
  const std::size_t start = pos_;
  std::uint32_t n = 0;
  if (!u32(n)) return false;
  if (remaining() < n) {
    pos_ = start;
    return false;
  }
  s.assign(reinterpret_cast<const char*>(data_ + pos_), n);
  pos_ += n;
  return true;
}

void serialize(const TopicInfo& m, std::vector<std::uint8_t>& out) {
  Writer w(out);
  w.u16(m.topic_id);
  w.str(m.topic_name);
  w.str(m.message_type);
  w.str(m.md5sum);
  w.i32(m.buffer_size);
}

bool deserialize(const std::uint8_t* data, std::size_t size, TopicInfo& m) {
  Reader r(data, size);
  TopicInfo t;
  if (!(r.u16(t.topic_id) && r.str(t.topic_name) && r.str(t.message_type) && r.str(t.md5sum) &&
        r.i32(t.buffer_size)))
    return false;
  m = std::move(t);
  return true;
}

void serialize(const LogMessage& m, std::vector<std::uint8_t>& out) {
  Writer w(out);
  w.u8(m.level);
  w.str(m.msg);
}

bool deserialize(const std::uint8_t* data, std::size_t size, LogMessage& m) {
  Reader r(data, size);
  LogMessage l;
  if (!(r.u8(l.level) && r.str(l.msg))) return false;
  m = std::move(l);
  return true;
}

void serialize(const Stamp& m, std::vector<std::uint8_t>& out) {
  Writer w(out);
  w.u32(m.sec);
  w.u32(m.nsec);
}

bool deserialize(const std::uint8_t* data, std::size_t size, Stamp& m) {
  Reader r(data, size);
  Stamp t;
  if (!(r.u32(t.sec) && r.u32(t.nsec))) return false;
  m = t;
  return true;
}

void serializeBool(bool value, std::vector<std::uint8_t>& out) { out.push_back(value ? 1 : 0); }

bool deserializeBool(const std::uint8_t* data, std::size_t size, bool& value) {
  if (size != 1) return false;
  value = data[0] != 0;
  return true;
}

void serializeUInt8Array(const std::vector<std::uint8_t>& data, std::vector<std::uint8_t>& out) {
  Writer w(out);
  w.u32(0);  // layout.dim: none
  w.u32(0);  // layout.data_offset
  w.str(std::string(data.begin(), data.end()));
}

bool deserializeUInt8Array(const std::uint8_t* payload, std::size_t size, std::vector<std::uint8_t>& data) {
  Reader r(payload, size);
  std::uint32_t dims = 0, offset = 0;
  if (!r.u32(dims) || dims > size) return false;
  for (std::uint32_t i = 0; i < dims; ++i) {
    std::string label;
    std::uint32_t dim_size = 0, stride = 0;
    if (!(r.str(label) && r.u32(dim_size) && r.u32(stride))) return false;
  }
  std::string bytes;
  if (!(r.u32(offset) && r.str(bytes)) || r.remaining() != 0) return false;
  data.assign(bytes.begin(), bytes.end());
  return true;
}

// --- Framing ----------------------------------------------------------------------------------

void appendFrame(std::uint16_t topic, const std::uint8_t* payload, std::size_t size,
                 std::vector<std::uint8_t>& out) {
  if (size > 0xFFFF) throw std::length_error("rosserial frame payload above 65535 bytes");
  const std::uint8_t len_lo = static_cast<std::uint8_t>(size & 0xFF);
  const std::uint8_t len_hi = static_cast<std::uint8_t>(size >> 8);
  const std::uint8_t topic_lo = static_cast<std::uint8_t>(topic & 0xFF);
  const std::uint8_t topic_hi = static_cast<std::uint8_t>(topic >> 8);
  out.reserve(out.size() + size + kFrameOverheadBytes);
  out.push_back(kSyncByte);
  out.push_back(kProtocolVersion);
  out.push_back(len_lo);
  out.push_back(len_hi);
  out.push_back(static_cast<std::uint8_t>(255 - ((len_lo + len_hi) % 256)));
  out.push_back(topic_lo);
  out.push_back(topic_hi);
  unsigned sum = topic_lo + topic_hi;
  for (std::size_t i = 0; i < size; ++i) {
    out.push_back(payload[i]);
    sum += payload[i];
  }
  out.push_back(static_cast<std::uint8_t>(255 - (sum % 256)));
}

std::vector<std::uint8_t> encodeFrame(std::uint16_t topic, const std::vector<std::uint8_t>& payload) {
  std::vector<std::uint8_t> out;
  appendFrame(topic, payload.data(), payload.size(), out);
  return out;
}

std::vector<std::uint8_t> requestTopicsFrame() { return encodeFrame(kIdPublisher, {}); }
std::vector<std::uint8_t> txStopFrame() { return encodeFrame(kIdTxStop, {}); }

std::string describeNewFaults(const ParserCounters& before, const ParserCounters& after) {
  std::ostringstream s;
  const auto item = [&](std::uint64_t a, std::uint64_t b, const char* what) {
    if (b <= a) return;
    if (s.tellp() > 0) s << ", ";
    s << (b - a) << ' ' << what;
  };
  item(before.garbage_bytes, after.garbage_bytes, "garbage bytes");
  item(before.bad_length_checksum, after.bad_length_checksum, "bad length checksum");
  item(before.oversize_length, after.oversize_length, "oversized length");
  item(before.bad_message_checksum, after.bad_message_checksum, "bad message checksum");
  item(before.truncated, after.truncated, "truncated frame");
  return s.str();
}

FrameParser::FrameParser(std::size_t max_payload, double frame_timeout_s)
    : max_payload_(max_payload), frame_timeout_s_(frame_timeout_s) {
  buf_.reserve(max_payload + kFrameOverheadBytes);
}

void FrameParser::reset() {
  buf_.clear();
  replay_.clear();
}

std::size_t FrameParser::expectedSize() const {
  return kFrameOverheadBytes + (static_cast<std::size_t>(buf_[2]) | (static_cast<std::size_t>(buf_[3]) << 8));
}

void FrameParser::reject(Reject why) {
  switch (why) {
    case Reject::kLengthChecksum: ++counters_.bad_length_checksum; break;
    case Reject::kOversize: ++counters_.oversize_length; break;
    case Reject::kMessageChecksum: ++counters_.bad_message_checksum; break;
    case Reject::kTruncated: ++counters_.truncated; break;
  }
  // The rejected candidate's sync byte is garbage; what followed it may hold a real frame.
  ++counters_.garbage_bytes;
  replay_.insert(replay_.begin(), buf_.begin() + 1, buf_.end());
  buf_.clear();
}

void FrameParser::consume(std::uint8_t byte, std::vector<Frame>& out) {
  if (buf_.empty()) {
    if (byte == kSyncByte)
      buf_.push_back(byte);
    else
      ++counters_.garbage_bytes;
    return;
  }
  if (buf_.size() == 1) {
    if (byte == kProtocolVersion) {
      buf_.push_back(byte);
      return;
    }
    // The 0xFF was not a frame start (noise, or another protocol revision); this byte may be one.
    ++counters_.garbage_bytes;
    buf_.clear();
    consume(byte, out);
    return;
  }
  buf_.push_back(byte);
  if (buf_.size() == 5) {
    if ((buf_[2] + buf_[3] + buf_[4]) % 256 != 255) {
      reject(Reject::kLengthChecksum);
    } else if (expectedSize() - kFrameOverheadBytes > max_payload_) {
      reject(Reject::kOversize);
    }
    return;
  }
  if (buf_.size() > 5 && buf_.size() == expectedSize()) {
    unsigned sum = 0;
    for (std::size_t i = 5; i < buf_.size(); ++i) sum += buf_[i];
    if (sum % 256 != 255) {
      reject(Reject::kMessageChecksum);
      return;
    }
    Frame frame;
    frame.topic = static_cast<std::uint16_t>(buf_[5] | (buf_[6] << 8));
    frame.payload.assign(buf_.begin() + kHeaderBytes, buf_.end() - 1);
    ++counters_.frames;
    counters_.frame_bytes += buf_.size();
    out.push_back(std::move(frame));
    buf_.clear();
  }
}

void FrameParser::drain(std::vector<Frame>& out) {
  while (!replay_.empty()) {
    const std::uint8_t b = replay_.front();
    replay_.pop_front();
    consume(b, out);
  }
}

void FrameParser::poll(double now, std::vector<Frame>& out) {
  if (buf_.empty() || !(now - last_byte_s_ >= frame_timeout_s_)) return;
  // The frame stalled: abandon it, but rescan what followed its sync byte (a device that reset
  // mid-frame starts a new, complete frame inside the old one's announced length). Whatever is
  // still incomplete after the rescan is just as stale and is dropped.
  reject(Reject::kTruncated);
  drain(out);
  counters_.garbage_bytes += buf_.size();
  buf_.clear();
}

void FrameParser::feed(const std::uint8_t* data, std::size_t size, double now, std::vector<Frame>& out) {
  poll(now, out);
  for (std::size_t i = 0; i < size; ++i) {
    ++counters_.bytes;
    consume(data[i], out);
    drain(out);
  }
  if (size > 0) last_byte_s_ = now;
}

}  // namespace rosserial
}  // namespace icanc
