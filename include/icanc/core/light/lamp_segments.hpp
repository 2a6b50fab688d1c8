// A segmented (matrix) headlight: a list of segments across the field of view, each an
// azimuth range seen from the lamp, in base_link (REP-103: x forward, y left; degrees,
// counter-clockwise positive, 0 = straight ahead, +90 = left). The paper's single lamp is one
// segment covering every direction, and the default (an absent or empty `segments` list).
//
// Profile keys, in the light_controller section (config/*.yaml):
//   segments: [{azimuth_min_deg: -15, azimuth_max_deg: 0, watts: 3.125, low_watts: 1.875}, ...]
//   lamp_position_m: [x, y, z]   # the lamp in base_link (z unused)
//   segment_margin_deg: 2.0      # an object's azimuth range is widened by this on both sides
//   low_beam_below_m: 15.0       # objects nearer than this (from the lamp) need only the low beam
//   full_power_range_m: 0.0      # > 0: dim a segment to (d / this)^2 of its watts for an object d
//                                #   away (the same illuminance E = I / d^2 on it as at this range)
//   min_level: 0.05              #   ... but never below this level (PWM floor)
#pragma once

#include <cstddef>
#include <limits>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace icanc {

struct LampSegment {
  // Required in a profile: NaN until given, so a missing key fails validate().
  double azimuth_min_deg = std::numeric_limits<double>::quiet_NaN();
  double azimuth_max_deg = std::numeric_limits<double>::quiet_NaN();
  double watts = std::numeric_limits<double>::quiet_NaN();  // high beam [W], > 0
  double low_watts = 0.0;  // low beam [W], in (0, watts]; 0 = no low beam (always high)
};

constexpr std::size_t kMaxLampSegments = 32;
constexpr double kPaperLampWatts = 25.0;  // the paper's LED (high beam), for the default segment

struct SegmentLampParams {
  std::vector<LampSegment> segments;  // empty: one segment, every direction (the paper)
  Eigen::Vector3f lamp_position_m = Eigen::Vector3f::Zero();
  double segment_margin_deg = 2.0;
  double low_beam_below_m = 15.0;
  // Dimming by distance (PWM per segment), instead of the low beam: 0 = off. An object d metres
  // from the lamp gets the same illuminance from (d / full_power_range_m)^2 of a segment's power as
  // an object at full_power_range_m from all of it (inverse-square law); the level is clamped to
  // [min_level, 1]. A segment's lamp with a low beam (low_watts > 0) cannot dim as well.
  double full_power_range_m = 0.0;
  double min_level = 0.05;
};

// The level (0..1 of a segment's high-beam watts) an object `distance_m` from the lamp needs from
// a segment: dimmed by distance when full_power_range_m > 0; else low_watts / watts when the
// segment has a low beam and the object is nearer than low_beam_below_m; else 1. NaN: 1.
double requiredLevel(const SegmentLampParams& params, const LampSegment& segment, double distance_m);

// Sets one key of a segment entry (a profile's `segments` list); "" or why the key is refused.
std::string setSegmentKey(LampSegment& segment, const std::string& key, double value);

// "" or the first problem, naming segments[i] and its key. Overlapping segments are allowed.
std::string validate(const SegmentLampParams& params);

// The segments in force: params.segments, or the paper's one segment [-180, 180] deg, 25 W.
std::vector<LampSegment> effectiveSegments(const SegmentLampParams& params);

// Azimuth range [lo, hi] (degrees, lo <= hi, possibly beyond +-180 around the rear) under which a
// box is seen from `lamp`; a box holding the lamp is every direction (hi - lo = 360).
struct AzimuthRange {
  double lo_deg = -180.0;
  double hi_deg = 180.0;
};
AzimuthRange azimuthRange(const Eigen::AlignedBox2d& box, const Eigen::Vector2d& lamp);

// Whether `range`, widened by margin_deg on both sides, meets the segment (360-deg wrap included).
bool covers(const LampSegment& segment, const AzimuthRange& range, double margin_deg);

}  // namespace icanc
