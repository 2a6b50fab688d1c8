#include "icanc/ros/markers.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace icanc {

namespace {

std_msgs::ColorRGBA rgba(float r, float g, float b, float a) {
  std_msgs::ColorRGBA c;
  c.r = r;
  c.g = g;
  c.b = b;
  c.a = a;
  return c;
}

geometry_msgs::Point point(double x, double y, double z) {
  geometry_msgs::Point p;
  p.x = x;
  p.y = y;
  p.z = z;
  return p;
}

visualization_msgs::Marker marker(const std_msgs::Header& header, const char* ns, int id, int type,
                                  const MarkerStyle& style) {
  visualization_msgs::Marker m;
  m.header = header;
  m.ns = ns;
  m.id = id;
  m.type = type;
  m.action = visualization_msgs::Marker::ADD;
  m.pose.orientation.w = 1.0;
  m.scale.x = m.scale.y = m.scale.z = 1.0;
  m.lifetime = ros::Duration(style.lifetime_s);
  return m;
}

visualization_msgs::Marker text(const std_msgs::Header& header, const char* ns, int id,
                                const geometry_msgs::Point& at, const std::string& s,
                                const MarkerStyle& style) {
  visualization_msgs::Marker m = marker(header, ns, id, visualization_msgs::Marker::TEXT_VIEW_FACING, style);
  m.pose.position = at;
  m.scale.z = 0.4;  // text height [m]
  m.color = rgba(1.0f, 1.0f, 1.0f, 1.0f);
  m.text = s;
  return m;
}

}  // namespace

visualization_msgs::MarkerArray dangerMarkers(const ObstacleArray& array, const DangerParams& params,
                                              const MarkerStyle& style) {
  using visualization_msgs::Marker;
  visualization_msgs::MarkerArray out;
  const std_msgs::Header& h = array.header;
  for (const Obstacle& o : array.obstacles) {
    const int id = static_cast<int>(o.id);
    Marker box = marker(h, kBoxesNs, id, Marker::CUBE, style);
    box.pose = o.pose;
    box.scale.x = o.dimensions.x;
    box.scale.y = o.dimensions.y;
    box.scale.z = o.dimensions.z;
    box.color = o.dangerous ? rgba(1.0f, 0.0f, 0.0f, 0.6f) : rgba(0.0f, 0.8f, 0.0f, 0.4f);
    out.markers.push_back(box);

    char label[64];
    std::snprintf(label, sizeof(label), "#%u  %.1f m/s", o.id, o.speed);
    geometry_msgs::Point above = o.pose.position;
    above.z += 0.5 * o.dimensions.z + 0.4;
    out.markers.push_back(text(h, kLabelsNs, id, above, label, style));

    Marker arrow = marker(h, kVelocityNs, id, Marker::ARROW, style);
    arrow.scale.x = 0.08;  // shaft diameter
    arrow.scale.y = 0.2;   // head diameter
    arrow.scale.z = 0.2;   // head length
    arrow.color = box.color;
    arrow.color.a = 1.0f;
    const geometry_msgs::Point& c = o.pose.position;
    arrow.points.push_back(c);
    arrow.points.push_back(point(c.x + o.velocity.x * style.arrow_time_s,
                                 c.y + o.velocity.y * style.arrow_time_s,
                                 c.z + o.velocity.z * style.arrow_time_s));
    out.markers.push_back(arrow);
  }

  // Sections (icanc::getSection): left y >= w, front -w < y < w, right y <= -w.
  const double w = params.half_width_m, len = style.section_length_m;
  for (int side = 0; side < 2; ++side) {
    Marker line = marker(h, kSectionsNs, side, Marker::LINE_STRIP, style);
    line.scale.x = 0.05;  // line width
    line.color = rgba(1.0f, 1.0f, 0.0f, 0.8f);
    const double y = side == 0 ? w : -w;
    line.points.push_back(point(0.0, y, 0.0));
    line.points.push_back(point(len, y, 0.0));
    out.markers.push_back(line);
  }
  const double label_x = std::min(len, 5.0);
  out.markers.push_back(text(h, kSectionsNs, 2, point(label_x, w + 1.0, 0.0), "1 left", style));
  out.markers.push_back(text(h, kSectionsNs, 3, point(label_x, 0.0, 0.0), "2 front", style));
  out.markers.push_back(text(h, kSectionsNs, 4, point(label_x, -w - 1.0, 0.0), "3 right", style));
  return out;
}

visualization_msgs::MarkerArray lampMarkers(const LightState& state, const std::string& frame,
                                            const MarkerStyle& style) {
  using visualization_msgs::Marker;
  visualization_msgs::MarkerArray out;
  std_msgs::Header h = state.header;
  h.frame_id = frame;
  Marker lamp = marker(h, kLampNs, 0, Marker::SPHERE, style);
  lamp.pose.position = point(0.0, 0.0, 2.0);
  lamp.scale.x = lamp.scale.y = lamp.scale.z = 0.5;
  lamp.color = state.on ? rgba(1.0f, 0.9f, 0.2f, 1.0f) : rgba(0.3f, 0.3f, 0.3f, 0.8f);
  out.markers.push_back(lamp);
  char label[96];
  if (state.on && state.reason == LightState::REASON_DANGER)
    std::snprintf(label, sizeof(label), "lamp ON: %s, %.1f s left", state.reason_text.c_str(), state.time_left);
  else if (state.on)
    std::snprintf(label, sizeof(label), "lamp ON: %s", state.reason_text.c_str());
  else
    std::snprintf(label, sizeof(label), "lamp off");
  out.markers.push_back(text(h, kLampNs, 1, point(0.0, 0.0, 2.6), label, style));
  return out;
}

visualization_msgs::MarkerArray segmentMarkers(const LampCommand& command,
                                               const std::vector<LampSegment>& segments,
                                               const Eigen::Vector3f& lamp_position,
                                               const std::string& frame, double range_m,
                                               const MarkerStyle& style) {
  using visualization_msgs::Marker;
  visualization_msgs::MarkerArray out;
  std_msgs::Header h = command.header;
  h.frame_id = frame;
  constexpr double kStepDeg = 5.0;  // arc resolution
  for (std::size_t i = 0; i < segments.size(); ++i) {
    const float level = i < command.levels.size() ? command.levels[i] : 1.0f;
    Marker m = marker(h, kSegmentsNs, int(i), Marker::TRIANGLE_LIST, style);
    m.pose.position = point(lamp_position.x(), lamp_position.y(), 0.05);
    m.color = level > 0.0f ? rgba(1.0f, 0.9f, 0.2f, 0.15f + 0.45f * std::min(level, 1.0f))
                           : rgba(0.5f, 0.5f, 0.5f, 0.08f);
    const double lo = segments[i].azimuth_min_deg, hi = segments[i].azimuth_max_deg;
    const int steps = std::max(1, int(std::ceil((hi - lo) / kStepDeg)));
    for (int k = 0; k < steps; ++k) {
      const double a0 = (lo + (hi - lo) * k / steps) * M_PI / 180.0;
      const double a1 = (lo + (hi - lo) * (k + 1) / steps) * M_PI / 180.0;
      m.points.push_back(point(0.0, 0.0, 0.0));
      m.points.push_back(point(range_m * std::cos(a0), range_m * std::sin(a0), 0.0));
      m.points.push_back(point(range_m * std::cos(a1), range_m * std::sin(a1), 0.0));
    }
    out.markers.push_back(m);
  }
  return out;
}

}  // namespace icanc
