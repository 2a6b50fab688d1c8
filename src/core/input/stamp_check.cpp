#include "icanc/core/input/stamp_check.hpp"

#include <cmath>
#include <sstream>

namespace icanc {

std::string validate(const StampCheckParams& params) {
  std::ostringstream why;
  if (!(params.max_jump_s > 0.0 && params.max_jump_s <= 60.0))
    why << "stamp_check/max_jump_s must be in (0, 60] s (got " << params.max_jump_s << ")";
  return why.str();
}

const char* toString(StampVerdict verdict) {
  switch (verdict) {
    case StampVerdict::kOk: return "ok";
    case StampVerdict::kZero: return "zero stamp";
    case StampVerdict::kRepeated: return "stamp repeats the previous frame's";
    case StampVerdict::kBackwards: return "stamp went backwards";
    case StampVerdict::kJump: return "stamp jumped forward beyond stamp_check/max_jump_s";
    case StampVerdict::kRate: return "stamps advance at a rate off the receipt clock (sensor clock fast or slow)";
  }
  return "unknown";
}

void StampRate::reset() {
  window_.clear();
  ratio_ = std::numeric_limits<double>::quiet_NaN();
  faulty_ = false;
}

bool StampRate::update(double stamp_s, double receipt_s) {
  if (!window_.empty() && (stamp_s < window_.back().stamp_s || receipt_s < window_.back().receipt_s ||
                           receipt_s - window_.back().receipt_s > kStampRateMaxGapS))
    reset();
  window_.push_back({stamp_s, receipt_s});
  // Keep the newest sample at least a window older than this one as the window's start; a bound
  // on the samples keeps memory fixed for any frame rate.
  while (window_.size() > 2 && (receipt_s - window_[1].receipt_s >= kStampRateWindowS || window_.size() > 4096))
    window_.pop_front();
  const double span = receipt_s - window_.front().receipt_s;
  if (span >= kStampRateWindowS) {
    ratio_ = (stamp_s - window_.front().stamp_s) / span;
    faulty_ = !(ratio_ <= kMaxStampRate && ratio_ >= 1.0 / kMaxStampRate);
  }
  return !faulty_;
}

StampVerdict StampCheck::check(double stamp_s, double receipt_s) {
  StampVerdict verdict = StampVerdict::kOk;
  if (!(stamp_s > 0.0) || !std::isfinite(stamp_s)) {
    verdict = StampVerdict::kZero;
  } else if (has_previous_) {
    const double dt = stamp_s - previous_s_;
    if (dt == 0.0)
      verdict = StampVerdict::kRepeated;
    else if (dt < 0.0)
      verdict = StampVerdict::kBackwards;
    else if (dt > params_.max_jump_s + 1e-9)
      verdict = StampVerdict::kJump;
  }
  if (verdict == StampVerdict::kOk && std::isfinite(receipt_s) && !rate_.update(stamp_s, receipt_s))
    verdict = StampVerdict::kRate;
  // A zero stamp is no timeline: the next frame is compared with the last real stamp.
  if (verdict != StampVerdict::kZero) {
    has_previous_ = true;
    previous_s_ = stamp_s;
  }
  ++counts_[static_cast<int>(verdict)];
  return verdict;
}

std::uint64_t StampCheck::rejected() const {
  std::uint64_t n = 0;
  for (int i = 1; i < kStampVerdicts; ++i) n += counts_[i];
  return n;
}

}  // namespace icanc
