// Whether an obstacle moves, as free space tells it (FreeSpaceMotion) and the tracker keeps it.
#pragma once

#include <cstdint>

namespace icanc {

// icanc/Obstacle motion_state: MOTION_UNKNOWN 0, MOTION_STATIC 1, MOTION_MOVING 2.
enum class MotionState : std::uint8_t { kUnknown = 0, kStatic = 1, kMoving = 2 };
const char* toString(MotionState state);

// What one detection's points say (Box3D::motion).
struct MotionEvidence {
  std::uint16_t tested = 0;  // points looked at from where the sensor was before
  std::uint16_t free = 0;    // ... that lie where earlier rays passed through
  std::uint16_t seen = 0;    // ... that lie on a surface seen there before
  // The detection's own reading: moving when enough of its points lie in free space, static when
  // most lie on surfaces seen before and almost none in free space, else unknown.
  MotionState state() const;
};

}  // namespace icanc
