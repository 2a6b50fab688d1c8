#include "icanc/sim/path.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <stdexcept>

namespace icanc {
namespace sim {
namespace {

// f(phi) = integral of exp(i phi u) over u in [0, 1], and g(phi) the same of u exp(i phi u): the
// displacement of an arc turning by phi, at a constant speed and at an even change of speed. Their
// series near phi = 0, where the closed forms cancel.
std::complex<double> arcF(double phi) {
  const std::complex<double> ip(0.0, phi);
  if (std::abs(phi) < 1e-2) return 1.0 + ip / 2.0 + ip * ip / 6.0 + ip * ip * ip / 24.0 + ip * ip * ip * ip / 120.0;
  return (std::exp(ip) - 1.0) / ip;
}
std::complex<double> arcG(double phi) {
  const std::complex<double> ip(0.0, phi);
  if (std::abs(phi) < 1e-2) return 0.5 + ip / 3.0 + ip * ip / 8.0 + ip * ip * ip / 30.0 + ip * ip * ip * ip / 144.0;
  return std::exp(ip) / ip - (std::exp(ip) - 1.0) / (ip * ip);
}

// The pose after tau seconds of `seg` from `pose` while its speed changes (0 < tau <= duration):
// x + iy moves by exp(i theta) (v0 tau f(w tau) + a tau^2 g(w tau)), a the change per second.
PlanarPose advanceChanging(const PlanarPose& pose, const PathSegment& seg, double tau) {
  const double a = (seg.endSpeed() - seg.speed_mps) / seg.duration_s;
  const double phi = seg.yaw_rate_rad_s * tau;
  const std::complex<double> move = std::polar(1.0, pose.theta) *
                                    (seg.speed_mps * tau * arcF(phi) + a * tau * tau * arcG(phi));
  PlanarPose out = pose;
  out.x += move.real();
  out.y += move.imag();
  out.theta += phi;
  return out;
}

// The pose after moving for tau seconds along `seg` from `pose`: the exact arc. A speed that
// changes does so within the segment; past its end (the last one's), the end speed holds.
PlanarPose advance(const PlanarPose& pose, const PathSegment& seg, double tau) {
  if (seg.endSpeed() != seg.speed_mps && tau > 0.0) {
    const PlanarPose end = advanceChanging(pose, seg, std::min(tau, seg.duration_s));
    if (tau <= seg.duration_s) return end;
    PathSegment after = seg;
    after.speed_mps = seg.endSpeed();
    after.end_speed_mps = -1.0;
    return advance(end, after, tau - seg.duration_s);
  }
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

double speedAlong(const std::vector<PathSegment>& segments, double t) {
  const Located at = locate(segments, t);
  const PathSegment& seg = segments[at.index];
  const double tau = std::clamp(t - at.start_s, 0.0, seg.duration_s);
  return seg.speed_mps + (seg.endSpeed() - seg.speed_mps) * tau / seg.duration_s;
}

const PathSegment& segmentAt(const std::vector<PathSegment>& segments, double t) {
  return segments[locate(segments, t).index];
}

}  // namespace sim
}  // namespace icanc
