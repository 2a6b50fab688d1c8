// Runs the libFuzzer target's checks (test/fuzz/rosserial_parser_fuzzer.cpp) on deterministic
// random inputs, biased towards frame-like bytes, so the invariants hold in the regular suite
// too; scripts/fuzz explores further with coverage guidance.
#include <gtest/gtest.h>

#include <random>

#include "../../fuzz/rosserial_parser_fuzzer.cpp"

namespace {

TEST(RosserialFuzzReplay, ParserAndSessionInvariantsHoldOnRandomStreams) {
  std::mt19937 rng(20240611);
  const std::vector<std::uint8_t> good = icanc::rosserial::encodeFrame(125, {1});
  for (int round = 0; round < 3000; ++round) {
    std::vector<std::uint8_t> input(1 + rng() % 600);
    for (auto& b : input) {
      const unsigned r = rng() % 16;
      b = r < 3 ? 0xFF : r < 5 ? 0xFE : r < 6 ? 0x00 : static_cast<std::uint8_t>(rng());
    }
    // Splice in good frames here and there.
    for (std::size_t at = 3 + rng() % 50; at + good.size() < input.size(); at += 20 + rng() % 100)
      std::copy(good.begin(), good.end(), input.begin() + at);
    ASSERT_EQ(LLVMFuzzerTestOneInput(input.data(), input.size()), 0);
  }
}

}  // namespace
