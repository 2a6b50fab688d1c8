#include "icanc/core/evaluation/lamp_causes.hpp"

#include <cstdio>
#include <sstream>

namespace icanc {

const char* toString(LampCause cause) {
  switch (cause) {
    case LampCause::kTrueDanger: return "true_danger";
    case LampCause::kModel: return "model";
    case LampCause::kLabelledPerception: return "labelled_perception";
    case LampCause::kUnlabelledStanding: return "unlabelled_standing";
    case LampCause::kUnlabelledMoving: return "unlabelled_moving";
    case LampCause::kUnscored: return "unscored";
    case LampCause::kCount: break;
  }
  return "?";
}

void LampCauseLog::flag(LampCause cause) {
  if (frames_.empty() || cause == LampCause::kCount) return;
  frames_.back().second |= bitOf(cause);
  ++counts_[static_cast<std::size_t>(cause)];
}

double LampCauseLog::dutyOf(LampCauseMask keep) const {
  if (frames_.empty()) return 0.0;
  LightController lamp(lamp_);
  std::size_t on = 0;
  for (const auto& frame : frames_) {
    lamp.onInput(frame.first, (frame.second & keep) != 0);
    on += lamp.on();
  }
  return static_cast<double>(on) / static_cast<double>(frames_.size());
}

LampCauses LampCauseLog::result() const {
  LampCauses r;
  const LampCauseMask all = static_cast<LampCauseMask>((1u << kLampCauseCount) - 1u);
  const LampCauseMask truth = bitOf(LampCause::kTrueDanger);
  r.duty_all = dutyOf(all);
  for (std::size_t i = 0; i < kLampCauseCount; ++i) {
    const LampCauseMask bit = bitOf(static_cast<LampCause>(i));
    LampCauseFigures& c = r.causes[i];
    c.object_frames = counts_[i];
    c.duty_alone = dutyOf(static_cast<LampCauseMask>(truth | bit));
    c.duty_without = dutyOf(static_cast<LampCauseMask>(all & ~bit));
  }
  return r;
}

std::string toText(const LampCauses& r) {
  std::ostringstream s;
  char buf[160];
  std::snprintf(buf, sizeof(buf),
                "lamp duty by cause (re-run on the flags: all %.1f %%; a cause alone = with the true "
                "danger's flags):\n",
                100 * r.duty_all);
  s << buf;
  for (std::size_t i = 0; i < kLampCauseCount; ++i) {
    const LampCauseFigures& c = r.causes[i];
    std::snprintf(buf, sizeof(buf), "  %-20s %5llu object-frames, alone %5.1f %%, without %5.1f %%\n",
                  toString(static_cast<LampCause>(i)),
                  static_cast<unsigned long long>(c.object_frames), 100 * c.duty_alone,
                  100 * c.duty_without);
    s << buf;
  }
  return s.str();
}

std::string toJson(const LampCauses& r) {
  std::ostringstream j;
  j << "{\"duty_all\": " << r.duty_all;
  for (std::size_t i = 0; i < kLampCauseCount; ++i) {
    const LampCauseFigures& c = r.causes[i];
    j << ", \"" << toString(static_cast<LampCause>(i)) << "\": {\"object_frames\": "
      << c.object_frames << ", \"duty_alone\": " << c.duty_alone
      << ", \"duty_without\": " << c.duty_without << "}";
  }
  j << "}";
  return j.str();
}

}  // namespace icanc
