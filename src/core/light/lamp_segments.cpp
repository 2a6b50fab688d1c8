#include "icanc/core/light/lamp_segments.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace icanc {

std::string setSegmentKey(LampSegment& segment, const std::string& key, double value) {
  if (key == "azimuth_min_deg") segment.azimuth_min_deg = value;
  else if (key == "azimuth_max_deg") segment.azimuth_max_deg = value;
  else if (key == "watts") segment.watts = value;
  else if (key == "low_watts") segment.low_watts = value;
  else return "unknown key '" + key + "' (azimuth_min_deg, azimuth_max_deg, watts, low_watts)";
  return "";
}

std::string validate(const SegmentLampParams& params) {
  std::ostringstream why;
  if (params.segments.size() > kMaxLampSegments) {
    why << "light.segments has " << params.segments.size() << " segments, at most "
        << kMaxLampSegments;
    return why.str();
  }
  for (std::size_t i = 0; i < params.segments.size(); ++i) {
    const LampSegment& s = params.segments[i];
    why << "light.segments[" << i << "].";
    if (!(s.azimuth_min_deg >= -180.0 && s.azimuth_max_deg <= 180.0 &&
          s.azimuth_min_deg < s.azimuth_max_deg))
      why << "azimuth_min_deg < azimuth_max_deg, both in [-180, 180], are required (got "
          << s.azimuth_min_deg << ", " << s.azimuth_max_deg << ")";
    else if (!(s.watts > 0.0 && std::isfinite(s.watts)))
      why << "watts must be > 0 (got " << s.watts << ")";
    else if (!(s.low_watts >= 0.0 && s.low_watts <= s.watts))
      why << "low_watts must be in [0, watts = " << s.watts << "], 0 = no low beam (got "
          << s.low_watts << ")";
    else
      why.str("");
    if (!why.str().empty()) return why.str();
  }
  if (!params.lamp_position_m.allFinite() || params.lamp_position_m.cwiseAbs().maxCoeff() > 10.0)
    why << "light.lamp_position_m must be finite, within 10 m of base_link";
  else if (!(params.segment_margin_deg >= 0.0 && params.segment_margin_deg <= 90.0))
    why << "light.segment_margin_deg must be in [0, 90] (got " << params.segment_margin_deg << ")";
  else if (!(params.low_beam_below_m >= 0.0 && std::isfinite(params.low_beam_below_m)))
    why << "light.low_beam_below_m must be >= 0 (got " << params.low_beam_below_m << ")";
  else if (!(params.full_power_range_m >= 0.0 && params.full_power_range_m <= 1000.0))
    why << "light.full_power_range_m must be in [0, 1000], 0 = no dimming (got "
        << params.full_power_range_m << ")";
  else if (!(params.min_level > 0.0 && params.min_level <= 1.0))
    why << "light.min_level must be in (0, 1] (got " << params.min_level << ")";
  if (!why.str().empty() || !(params.full_power_range_m > 0.0)) return why.str();
  for (std::size_t i = 0; i < params.segments.size(); ++i)
    if (params.segments[i].low_watts > 0.0) {
      why << "light.segments[" << i << "].low_watts: a lamp dimmed by distance (full_power_range_m "
          << params.full_power_range_m << ") has no separate low beam; set low_watts 0 or "
          << "full_power_range_m 0";
      break;
    }
  return why.str();
}

std::vector<LampSegment> effectiveSegments(const SegmentLampParams& params) {
  if (!params.segments.empty()) return params.segments;
  LampSegment paper;
  paper.azimuth_min_deg = -180.0;
  paper.azimuth_max_deg = 180.0;
  paper.watts = kPaperLampWatts;
  return {paper};
}

double requiredLevel(const SegmentLampParams& params, const LampSegment& segment, double distance_m) {
  if (!(distance_m >= 0.0)) return 1.0;  // NaN: unknown place, full power
  if (params.full_power_range_m > 0.0) {
    const double ratio = distance_m / params.full_power_range_m;
    return std::clamp(ratio * ratio, params.min_level, 1.0);
  }
  if (segment.low_watts > 0.0 && distance_m < params.low_beam_below_m) return segment.low_watts / segment.watts;
  return 1.0;
}

AzimuthRange azimuthRange(const Eigen::AlignedBox2d& box, const Eigen::Vector2d& lamp) {
  if (box.isEmpty() || box.contains(lamp)) return AzimuthRange{};
  // Corners as offsets from the direction of the centre: a box not holding the lamp is seen
  // under less than 180 deg, so the offsets do not wrap.
  const Eigen::Vector2d c = box.center() - lamp;
  const double centre = std::atan2(c.y(), c.x());
  double lo = 0.0, hi = 0.0;
  for (const auto corner : {Eigen::AlignedBox2d::BottomLeft, Eigen::AlignedBox2d::BottomRight,
                            Eigen::AlignedBox2d::TopLeft, Eigen::AlignedBox2d::TopRight}) {
    const Eigen::Vector2d d = box.corner(corner) - lamp;
    const double offset = std::remainder(std::atan2(d.y(), d.x()) - centre, 2.0 * M_PI);
    lo = std::min(lo, offset);
    hi = std::max(hi, offset);
  }
  const double deg = 180.0 / M_PI;
  return AzimuthRange{(centre + lo) * deg, (centre + hi) * deg};
}

bool covers(const LampSegment& segment, const AzimuthRange& range, double margin_deg) {
  for (const double turn : {-360.0, 0.0, 360.0})
    if (range.lo_deg - margin_deg + turn <= segment.azimuth_max_deg &&
        range.hi_deg + margin_deg + turn >= segment.azimuth_min_deg)
      return true;
  return false;
}

}  // namespace icanc
