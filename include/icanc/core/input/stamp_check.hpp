// Judges a sensor frame's header stamp before the frame is used. The tracker's velocity comes from
// the stamps: a zero stamp, a stamp equal to the previous one (duplicate message, frozen driver
// clock), one that goes backwards or one that jumps forward by more than max_jump_s gives dt = 0 or
// a tracker reset, i.e. speed 0 and nothing ever dangerous: a clear road by accident. Such a frame
// is rejected (not valid input), so the LightController's watchdog lights the lamp when they keep
// coming.
//
// Each stamp is compared with the one of the frame received just before it, accepted or not, so a
// stream switching to a new timeline (a bag loop, a driver restart) is accepted again from its
// second frame, while stamps alternating between two clocks are rejected frame after frame. The
// very first frame has nothing to be compared with and is accepted (unless its stamp is zero).
// Time is an argument (stamps in seconds); no clock is read.
#pragma once

#include <cstdint>
#include <string>

namespace icanc {

struct StampCheckParams {
  double max_jump_s = 2.0;  // a stamp further ahead of the previous one than this is rejected [s]
};

// "" or why the parameters are invalid (naming the key).
std::string validate(const StampCheckParams& params);

enum class StampVerdict : std::uint8_t { kOk = 0, kZero, kRepeated, kBackwards, kJump };
const char* toString(StampVerdict verdict);
constexpr int kStampVerdicts = 5;

class StampCheck {
 public:
  explicit StampCheck(const StampCheckParams& params = StampCheckParams()) : params_(params) {}

  // Judges the stamp (seconds) of the next frame and remembers it as the previous one.
  StampVerdict check(double stamp_s);

  // Frames rejected for `verdict` so far (kOk: frames accepted).
  std::uint64_t count(StampVerdict verdict) const { return counts_[static_cast<int>(verdict)]; }
  std::uint64_t rejected() const;
  // The previous stamp (valid once a frame was checked).
  double previousStamp() const { return previous_s_; }

  void setParams(const StampCheckParams& params) { params_ = params; }
  const StampCheckParams& params() const { return params_; }

 private:
  StampCheckParams params_;
  bool has_previous_ = false;
  double previous_s_ = 0.0;
  std::uint64_t counts_[kStampVerdicts] = {};
};

template <class Reader>
void visitParams(Reader& r, StampCheckParams& p) {
  r("stamp_check/max_jump_s", p.max_jump_s);
}

}  // namespace icanc
