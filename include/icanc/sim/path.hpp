// Planar paths made of segments of constant speed and constant turn rate (straight lines and
// circular arcs, as a vehicle drives a road): the simulated ego vehicle's motion and scene objects
// that follow a road. Integrated exactly, not stepped. ROS-free.
#pragma once

#include <vector>

namespace icanc {
namespace sim {

// One stretch of a path: constant speed along the heading and constant yaw rate (a straight line
// when yaw_rate_rad_s = 0, else an arc of radius speed / yaw rate).
struct PathSegment {
  double duration_s = 0.0;
  double speed_mps = 0.0;       // along the heading
  double yaw_rate_rad_s = 0.0;  // + turns left (counter-clockwise seen from above, REP-103)
};

struct PlanarPose {
  double x = 0.0, y = 0.0;  // [m]
  double theta = 0.0;       // heading [rad], not wrapped
};

// Where the path has got to after t seconds, starting at the origin facing +x. The pose is
// continuous at the joins; the last segment's motion continues past its end, and t < 0 runs the
// first segment backwards. `segments` must not be empty (std::invalid_argument).
PlanarPose poseAlong(const std::vector<PathSegment>& segments, double t);

// The segment in effect at t (at a join: the later one; the first before 0, the last past the
// end). `segments` must not be empty (std::invalid_argument).
const PathSegment& segmentAt(const std::vector<PathSegment>& segments, double t);

}  // namespace sim
}  // namespace icanc
