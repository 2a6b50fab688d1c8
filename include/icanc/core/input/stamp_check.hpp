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
//
// A clock running fast or slow passes each of those tests (stamps 0.5 s apart arriving every
// 0.1 s) but scales every speed the tracker measures by the inverse factor: an approaching
// pedestrian reads five times too slow and never lights the lamp. Given the time each frame was
// received (on the host's clock), the stamps' progress is compared with the receipts' over about
// kStampRateWindowS: outside [1 / kMaxStampRate, kMaxStampRate] every frame is rejected (kRate)
// until a window within it. The bound: a LiDAR's frame period is fixed by its spin; receipt jitter
// (driver buffering, a loaded host) moves a 1 s span by tens of milliseconds, and frames lost in
// transport take their stamps and their receipts alike, so a factor of 2 is no transport effect
// but a wrong sensor clock. Only a continuous stream is judged: a gap of more than
// kStampRateMaxGapS between receipts (a stall, frames sent by hand) starts a new window. Without a
// receipt time (replay on sim time, where the clock is the bag's own) the rate is not judged.
// Time is an argument (stamps and receipts in seconds); no clock is read.
#pragma once

#include <cstdint>
#include <deque>
#include <limits>
#include <string>

namespace icanc {

struct StampCheckParams {
  double max_jump_s = 2.0;  // a stamp further ahead of the previous one than this is rejected [s]
};

// "" or why the parameters are invalid (naming the key).
std::string validate(const StampCheckParams& params);

enum class StampVerdict : std::uint8_t { kOk = 0, kZero, kRepeated, kBackwards, kJump, kRate };
const char* toString(StampVerdict verdict);
constexpr int kStampVerdicts = 6;

constexpr double kStampRateWindowS = 1.0;  // receipt time the stamps' rate is measured over [s]
constexpr double kMaxStampRate = 2.0;      // stamps advancing faster (or slower by 1 / this): a wrong clock
constexpr double kStampRateMaxGapS = 0.5;  // receipts further apart: no stream, a new window [s]

// The stamps' progress over the receipts' across a window of about kStampRateWindowS.
class StampRate {
 public:
  // The frame stamped stamp_s arrived at receipt_s: true unless a full window says the stamps
  // advance outside [1 / kMaxStampRate, kMaxStampRate] times the receipt clock. A stamp or a
  // receipt going backwards, or receipts more than kStampRateMaxGapS apart, start a new window.
  bool update(double stamp_s, double receipt_s);
  bool faulty() const { return faulty_; }
  // Stamps' progress / receipts' progress over the last full window (NaN before one).
  double ratio() const { return ratio_; }
  void reset();

 private:
  struct Sample {
    double stamp_s, receipt_s;
  };
  std::deque<Sample> window_;
  double ratio_ = std::numeric_limits<double>::quiet_NaN();
  bool faulty_ = false;
};

class StampCheck {
 public:
  explicit StampCheck(const StampCheckParams& params = StampCheckParams()) : params_(params) {}

  // Judges the stamp (seconds) of the next frame and remembers it as the previous one; with a
  // finite receipt_s (the host's clock when it arrived) also the stamps' rate (StampRate).
  StampVerdict check(double stamp_s, double receipt_s = std::numeric_limits<double>::quiet_NaN());
  // The stamps' rate over the receipt clock of the last full window (NaN before one).
  double rateRatio() const { return rate_.ratio(); }

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
  StampRate rate_;
};

template <class Reader>
void visitParams(Reader& r, StampCheckParams& p) {
  r("stamp_check/max_jump_s", p.max_jump_s);
}

}  // namespace icanc
