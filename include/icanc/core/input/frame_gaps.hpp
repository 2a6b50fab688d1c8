// Frames missing from an input stream, judged from the stamps of consecutive messages and the
// rate the sensor is expected to run at (diagnostics: "dropped frames"). Time is an argument.
#pragma once

#include <cstdint>

namespace icanc {

// Frames that should have arrived between stamps previous_s and stamp_s at expected_rate_hz:
// round(gap * rate) - 1 when the gap exceeds 1.5 periods, else 0. A repeated or backwards stamp
// (duplicate, bag loop) and a non-positive rate give 0.
std::uint64_t missedFrames(double previous_s, double stamp_s, double expected_rate_hz);

}  // namespace icanc
