// A line for the log, without ROS: what a core class decided to say and how loudly. Its nodelet
// writes it under its own name (icanc/ros/nodelet_support.hpp, log()).
#pragma once

#include <cstdint>
#include <string>

namespace icanc {

enum class LogSeverity : std::uint8_t { kDebug, kInfo, kWarn, kError, kFatal };

struct LogLine {
  LogSeverity severity = LogSeverity::kInfo;
  std::string text;
};

// printf into a std::string.
std::string formatText(const char* format, ...) __attribute__((format(printf, 1, 2)));

// At most one line per period_s: the first passes, then the next one period_s after the last
// printed (ROS's *_THROTTLE, with the time as an argument).
class LogThrottle {
 public:
  explicit LogThrottle(double period_s) : period_s_(period_s) {}
  bool allow(double now) {
    if (printed_ && now - last_s_ < period_s_) return false;
    printed_ = true;
    last_s_ = now;
    return true;
  }

 private:
  double period_s_;
  double last_s_ = 0.0;
  bool printed_ = false;
};

}  // namespace icanc
