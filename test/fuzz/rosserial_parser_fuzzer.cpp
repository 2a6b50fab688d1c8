// libFuzzer target for the rosserial frame parser and the bridge's host session
// (scripts/fuzz builds and runs it for a bounded time; test/core/bridge/test_rosserial_fuzz_replay.cpp
// runs the same checks on deterministic random inputs in the regular suite).
//
// Input layout: the first byte picks the parser's maximum payload, then chunks of
// [length byte, time-step byte, bytes...] are fed with a clock that advances by the time-step
// (so frame timeouts fire too). Checks, aborting on violation:
//   - every byte is in a good frame, counted as garbage, or pending;
//   - the pending buffer never exceeds max payload + 8 bytes;
//   - every frame has a payload within the maximum and re-encodes to a frame the parser accepts;
//   - the host session survives the same bytes (answers, events) without throwing.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <vector>

#include "icanc/core/bridge/rosserial_protocol.hpp"
#include "icanc/core/bridge/rosserial_session.hpp"

namespace {

void check(bool ok) {
  if (!ok) std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace icanc;
  using namespace icanc::rosserial;
  if (size < 1) return 0;
  const std::size_t max_payload = 16 + data[0] * 2;  // 16 ... 526
  FrameParser parser(max_payload, 0.1);
  LightBridgeParams params;
  params.max_payload_bytes = static_cast<int>(std::max<std::size_t>(64, max_payload));
  LightBridgeSession session(params);
  SessionOutput out;
  session.onOpened(0.0, out);
  std::vector<Frame> frames;
  double now = 0.0;
  std::size_t i = 1;
  while (i < size) {
    const std::size_t len = data[i++];
    const double dt = (i < size ? data[i++] : 0) * 0.002;  // 0 ... 0.51 s
    const std::size_t n = std::min(len, size - i);
    now += dt;
    parser.feed(data + i, n, now, frames);
    session.onBytes(data + i, n, now, Stamp{1u, 2u}, out);
    session.onCommand((data[i - 1] & 1) != 0, now, out);
    session.tick(now, Stamp{1u, 2u}, out);
    out = SessionOutput();
    i += n;
    const ParserCounters& c = parser.counters();
    check(c.bytes == c.frame_bytes + c.garbage_bytes + parser.pendingBytes());
    check(parser.pendingBytes() <= max_payload + kFrameOverheadBytes);
  }
  parser.poll(now + 1.0, frames);
  check(!parser.midFrame());
  for (const Frame& f : frames) {
    check(f.payload.size() <= max_payload);
    const std::vector<std::uint8_t> again = encodeFrame(f.topic, f.payload);
    FrameParser p(max_payload, 0.1);
    std::vector<Frame> back;
    p.feed(again.data(), again.size(), 0.0, back);
    check(back.size() == 1 && back[0].topic == f.topic && back[0].payload == f.payload);
  }
  return 0;
}
