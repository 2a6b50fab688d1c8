// Planar paths made of segments of constant turn rate and a speed constant or changing evenly
// (straight lines and circular arcs, as a vehicle drives a road, brakes and stops): the simulated
// ego vehicle's motion and scene objects that follow a road. Integrated exactly, not stepped.
// ROS-free.
#pragma once

#include <vector>

namespace icanc {
namespace sim {

// One stretch of a path: constant yaw rate, and a speed along the heading that goes evenly from
// speed_mps at its start to end_speed_mps at its end (constant when they are equal: a straight
// line when yaw_rate_rad_s = 0, else an arc of radius speed / yaw rate).
struct PathSegment {
  double duration_s = 0.0;
  double speed_mps = 0.0;       // along the heading, at the start
  double yaw_rate_rad_s = 0.0;  // + turns left (counter-clockwise seen from above, REP-103)
  double end_speed_mps = -1.0;  // at the end; < 0: speed_mps (constant speed)
  double endSpeed() const { return end_speed_mps < 0.0 ? speed_mps : end_speed_mps; }
};

struct PlanarPose {
  double x = 0.0, y = 0.0;  // [m]
  double theta = 0.0;       // heading [rad], not wrapped
};

// Where the path has got to after t seconds, starting at the origin facing +x. The pose is
// continuous at the joins; the last segment's motion continues past its end, and t < 0 runs the
// first segment backwards. `segments` must not be empty (std::invalid_argument).
PlanarPose poseAlong(const std::vector<PathSegment>& segments, double t);

// The speed along the heading at t (past the last segment's end: its end speed; before 0: the
// first segment's start speed). `segments` must not be empty (std::invalid_argument).
double speedAlong(const std::vector<PathSegment>& segments, double t);

// The segment in effect at t (at a join: the later one; the first before 0, the last past the
// end). `segments` must not be empty (std::invalid_argument).
const PathSegment& segmentAt(const std::vector<PathSegment>& segments, double t);

}  // namespace sim
}  // namespace icanc
