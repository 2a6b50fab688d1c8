#include "icanc/sim/path.hpp"

#include <cmath>
#include <stdexcept>

namespace icanc {
namespace sim {
namespace {

// The pose after moving for tau seconds along `seg` from `pose`: the exact arc.
PlanarPose advance(const PlanarPose& pose, const PathSegment& seg, double tau) {
  PlanarPose out = pose;
  const double w = seg.yaw_rate_rad_s, v = seg.speed_mps;
  if (std::abs(w * tau) < 1e-9) {  // straight (the arc's formula divides by w)
    out.x += v * tau * std::cos(pose.theta);
    out.y += v * tau * std::sin(pose.theta);
    return out;
  }
  out.theta = pose.theta + w * tau;
  out.x += v / w * (std::sin(out.theta) - std::sin(pose.theta));
  out.y += v / w * (std::cos(pose.theta) - std::cos(out.theta));
  return out;
}

struct Located {
  std::size_t index = 0;  // segment in effect
  double start_s = 0.0;   // when it starts ...
  PlanarPose start;       // ... and where
};

Located locate(const std::vector<PathSegment>& segments, double t) {
  if (segments.empty()) throw std::invalid_argument("path: no segments");
  Located at;
  while (at.index + 1 < segments.size() && t >= at.start_s + segments[at.index].duration_s) {
    at.start = advance(at.start, segments[at.index], segments[at.index].duration_s);
    at.start_s += segments[at.index].duration_s;
    ++at.index;
  }
  return at;
}

}  // namespace

PlanarPose poseAlong(const std::vector<PathSegment>& segments, double t) {
  const Located at = locate(segments, t);
  return advance(at.start, segments[at.index], t - at.start_s);
}

const PathSegment& segmentAt(const std::vector<PathSegment>& segments, double t) {
  return segments[locate(segments, t).index];
}

}  // namespace sim
}  // namespace icanc
