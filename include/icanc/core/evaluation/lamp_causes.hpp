// What keeps the lamp on: each scored frame's dangerous flags sorted by cause against the ground
// truth, and the light controller re-run on the flags of some causes only. A lamp on for most of a
// drive is on because no cause ever leaves it a timer's length of quiet; this says which causes
// would each keep it on by themselves, and what it would be without each one. ROS-free.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "icanc/core/light/light_controller.hpp"

namespace icanc {

enum class LampCause : std::uint8_t {
  kTrueDanger,          // a truly dangerous object, flagged (TP)
  kModel,               // a true object not dangerous, flagged, and flagged on its perfect track
                        // too: the danger model's own false alarm (FP)
  kLabelledPerception,  // a true object not dangerous, flagged only on the graph's track (FP)
  kUnlabelledStanding,  // a detection of no true object, standing still over ground (FP): its
                        // Obstacle velocity_over_ground below EvalParams::static_speed_mps. With
                        // ego_motion source none that velocity is the relative one, so on a
                        // moving vehicle what stands still counts as moving
  kUnlabelledMoving,    // ... moving over ground: a ghost velocity, or a road user not labelled (FP)
  kUnscored,            // a dangerous detection outside the scored range or view, or on a true
                        // object too sparse to score or whose danger the labels cannot tell
                        // (TruthObject::horizon_cut; not in the confusion counts)
  kCount
};
constexpr std::size_t kLampCauseCount = static_cast<std::size_t>(LampCause::kCount);
const char* toString(LampCause cause);  // "true_danger", "model", ...

using LampCauseMask = std::uint8_t;  // bit (1 << cause) per cause flagged in a frame
constexpr LampCauseMask bitOf(LampCause cause) {
  return static_cast<LampCauseMask>(1u << static_cast<unsigned>(cause));
}

struct LampCauseFigures {
  std::uint64_t object_frames = 0;  // flagged object-frames of this cause
  // The lamp driven by the true danger's flags and this cause's (for kTrueDanger: its own alone):
  // this cause's share of the lamp's time, as if every other false alarm were gone.
  double duty_alone = 0.0;
  double duty_without = 0.0;        // the lamp driven by every cause but this one
};

struct LampCauses {
  double duty_all = 0.0;  // the lamp driven by every cause (close to the run's own duty cycle)
  std::array<LampCauseFigures, kLampCauseCount> causes{};
};

// Collects, frame by frame, the causes flagged; then re-runs the light controller (the run's
// tau_s and recheck_below_s, no watchdog: frames are given) over them.
class LampCauseLog {
 public:
  explicit LampCauseLog(const LightControllerParams& lamp) : lamp_(lamp) {}
  void beginFrame(double t) { frames_.emplace_back(t, 0); }
  void flag(LampCause cause);  // one object-frame of `cause` in the current frame
  LampCauses result() const;

 private:
  double dutyOf(LampCauseMask keep) const;
  LightControllerParams lamp_;
  std::vector<std::pair<double, LampCauseMask>> frames_;
  std::array<std::uint64_t, kLampCauseCount> counts_{};
};

// "cause: N object-frames, lamp X % alone, Y % without" lines, and the same as a JSON object.
std::string toText(const LampCauses& causes);
std::string toJson(const LampCauses& causes);

}  // namespace icanc
