// rviz markers (visualization_msgs/MarkerArray) of what the nodelets see: a box per obstacle (red
// dangerous, green not), a label with its id and speed, its velocity as an arrow, the boundaries
// of the paper's three sections (y = +-half_width) and the lamp state. Markers have stable ids
// (the track id, per namespace) and a lifetime, so those of a vanished track disappear by
// themselves and two publishers (DangerDetector, LightController) can share one topic.
#pragma once

#include <string>

#include <visualization_msgs/MarkerArray.h>

#include "icanc/LampCommand.h"
#include "icanc/LightState.h"
#include "icanc/ObstacleArray.h"
#include "icanc/core/danger/danger.hpp"
#include "icanc/core/light/lamp_segments.hpp"

namespace icanc {

struct MarkerStyle {
  double lifetime_s = 0.5;         // a marker not refreshed for this long disappears
  double section_length_m = 30.0;  // section boundaries drawn from x = 0 to this
  double arrow_time_s = 1.0;       // the velocity arrow is the displacement over this time
};

// Marker namespaces, one per kind.
constexpr const char* kBoxesNs = "obstacles";
constexpr const char* kLabelsNs = "labels";
constexpr const char* kVelocityNs = "velocity";
constexpr const char* kSectionsNs = "sections";
constexpr const char* kLampNs = "lamp";
constexpr const char* kSegmentsNs = "lamp_segments";

// Boxes (CUBE), labels (TEXT_VIEW_FACING "#id  s.s m/s") and velocity arrows (ARROW) for every
// obstacle, in the array's frame and stamp, plus the two section boundaries (LINE_STRIP at
// y = +-params.half_width_m, ids 0 and 1) and the sections' names (TEXT, ids 2..4).
visualization_msgs::MarkerArray dangerMarkers(const ObstacleArray& array, const DangerParams& params,
                                              const MarkerStyle& style = MarkerStyle());

// The lamp above the vehicle origin in `frame`: a SPHERE (id 0, yellow on, dark grey off) and a
// TEXT_VIEW_FACING (id 1) "lamp ON: danger 2.4 s".
visualization_msgs::MarkerArray lampMarkers(const LightState& state, const std::string& frame,
                                            const MarkerStyle& style = MarkerStyle());

// The segmented lamp seen from above in `frame`: a flat wedge (TRIANGLE_LIST, id = segment index)
// per segment from the lamp out to `range_m` over its azimuth range, yellow with the opacity of
// its level while lit, faint grey while off.
visualization_msgs::MarkerArray segmentMarkers(const LampCommand& command,
                                               const std::vector<LampSegment>& segments,
                                               const Eigen::Vector3f& lamp_position,
                                               const std::string& frame, double range_m = 20.0,
                                               const MarkerStyle& style = MarkerStyle());

}  // namespace icanc
