// Fail-safe headlight logic of the icanc_headlight sketch, in plain C++ (no Arduino, no STL, no
// allocation) so that the same header compiles for the board and in the host's unit tests
// (test/core/light/test_headlight_logic.cpp).
//
// The lamp is OFF only while all of these hold:
//   - the node handle is connected (the host negotiated the topics),
//   - a command has arrived since power-up and since the last disconnect,
//   - the newest command says OFF and is younger than command_timeout_ms.
// Otherwise it is ON: at power-up until the host speaks, when the link drops, when the commands
// stop (host crashed, cable cut, controller dead). Times are millis() values; the arithmetic is
// unsigned, so the 49.7-day wrap of millis() does not matter.
#ifndef ICANC_HEADLIGHT_LOGIC_H
#define ICANC_HEADLIGHT_LOGIC_H

#include <stdint.h>

namespace icanc_fw {

enum HeadlightReason {
  kNoCommandYet = 0,    // ON: power-up, or reconnected and no command since
  kDisconnected = 1,    // ON: the node handle is not connected
  kCommandTimeout = 2,  // ON: no command for command_timeout_ms
  kCommandedOn = 3,     // ON: the host says so
  kCommandedOff = 4     // OFF: the host says so, recently, over a live link
};

inline const char* reasonText(HeadlightReason r) {
  switch (r) {
    case kNoCommandYet: return "no command yet";
    case kDisconnected: return "disconnected";
    case kCommandTimeout: return "command timeout";
    case kCommandedOn: return "commanded on";
    case kCommandedOff: return "commanded off";
  }
  return "unknown";
}

class HeadlightLogic {
 public:
  static const uint32_t kDefaultTimeoutMs = 500;

  explicit HeadlightLogic(uint32_t command_timeout_ms = kDefaultTimeoutMs)
      : timeout_ms_(command_timeout_ms),
        has_command_(false),
        commanded_on_(true),
        last_command_ms_(0),
        reason_(kNoCommandYet) {}

  // A std_msgs/Bool arrived on the command topic at now_ms.
  void onCommand(bool on, uint32_t now_ms) {
    has_command_ = true;
    commanded_on_ = on;
    last_command_ms_ = now_ms;
  }

  // Call every loop() with nh.connected() and millis(); returns the lamp state (true = ON).
  bool update(bool connected, uint32_t now_ms) {
    if (!connected) {
      has_command_ = false;  // a command from before the link dropped is not trusted after it
      reason_ = kDisconnected;
    } else if (!has_command_) {
      reason_ = kNoCommandYet;
    } else if (static_cast<uint32_t>(now_ms - last_command_ms_) >= timeout_ms_) {
      reason_ = kCommandTimeout;
    } else {
      reason_ = commanded_on_ ? kCommandedOn : kCommandedOff;
    }
    return lampOn();
  }

  bool lampOn() const { return reason_ != kCommandedOff; }
  HeadlightReason reason() const { return reason_; }
  uint32_t commandTimeoutMs() const { return timeout_ms_; }

 private:
  uint32_t timeout_ms_;
  bool has_command_;
  bool commanded_on_;
  uint32_t last_command_ms_;
  HeadlightReason reason_;
};

// Segmented lamp: the PWM duty of each segment pin from the host's std_msgs/
// UInt8MultiArray levels. A segment follows its level only while the HeadlightLogic is in a
// commanded state (the link is up and the Bool command is fresh) and levels came within the
// command timeout; otherwise, and for a segment beyond the levels received, it is full ON (255).
// The Bool ON with every level 0 is no consistent command (the host never sends it; it is the
// new ON arriving before its levels): every segment is then full ON, never a dark lamp for ON.
class SegmentLevels {
 public:
  static const uint8_t kMaxSegments = 8;

  explicit SegmentLevels(uint32_t timeout_ms = HeadlightLogic::kDefaultTimeoutMs)
      : timeout_ms_(timeout_ms), count_(0), has_levels_(false), last_ms_(0) {
    for (uint8_t i = 0; i < kMaxSegments; ++i) levels_[i] = 255;  // never read before set; full ON
  }

  void onLevels(const uint8_t* levels, uint32_t n, uint32_t now_ms) {
    count_ = n < kMaxSegments ? static_cast<uint8_t>(n) : kMaxSegments;
    for (uint8_t i = 0; i < count_; ++i) levels_[i] = levels[i];
    has_levels_ = true;
    last_ms_ = now_ms;
  }

  // The duty of segment i (0..255) after HeadlightLogic::update at now_ms.
  uint8_t duty(uint8_t i, const HeadlightLogic& logic, uint32_t now_ms) const {
    const bool commanded = logic.reason() == kCommandedOn || logic.reason() == kCommandedOff;
    const bool fresh = has_levels_ && static_cast<uint32_t>(now_ms - last_ms_) < timeout_ms_;
    if (!commanded || !fresh || i >= count_) return 255;
    if (logic.reason() == kCommandedOn && allZero()) return 255;
    return levels_[i];
  }

  // A disconnect forgets the levels, as HeadlightLogic forgets its command.
  void onDisconnect() { has_levels_ = false; }

 private:
  bool allZero() const {
    for (uint8_t i = 0; i < count_; ++i)
      if (levels_[i] != 0) return false;
    return true;
  }

  uint32_t timeout_ms_;
  uint8_t levels_[kMaxSegments];
  uint8_t count_;
  bool has_levels_;
  uint32_t last_ms_;
};

}  // namespace icanc_fw

#endif  // ICANC_HEADLIGHT_LOGIC_H
