#include "icanc/core/tracking/tracker.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "icanc/core/common/planar_geometry.hpp"

namespace icanc {
namespace {

// A detection at least this long (its oriented box's length) sets the track's face axes to its own
// sides [m]. Shorter ones (a car's rear alone, a walker, a partial view) have a noisy minimum-area
// rectangle: measured on KITTI 0000 and the simulated parked cars (docs/evaluation.md), taking
// every detection's own yaw, or the first one's, gave false alarms on young tracks.
constexpr float kOwnAxesMinLengthM = 3.0f;

bool finiteCenter(const Box3D& box) { return box.center.allFinite(); }

// A track this old whose speed is this high (and three sigmas) has measured its motion.
constexpr int kSettledHits = 10;
constexpr double kSettledSpeedMps = 2.0;

// True when p's (x, y) lies inside the box's footprint grown by margin_m.
bool planarContains(const Box3D& box, const Eigen::Vector3f& p, double margin_m) {
  const Eigen::Vector3d c = box.center.cast<double>();
  return orientedBoxContains(c, box.size.cast<double>(), box.yaw,
                             Eigen::Vector3d(p.x(), p.y(), c.z()), margin_m);
}

// Moves the box (centre, axis-aligned bounds, footprint and hull) by delta.
void translateBox(Box3D& box, const Eigen::Vector3f& delta) {
  box.center += delta;
  box.min += delta;
  box.max += delta;
  for (FootprintCell& cell : box.footprint) {
    cell.min += delta.head<2>();
    cell.max += delta.head<2>();
  }
  for (Eigen::Vector2f& p : box.hull) p += delta.head<2>();
}

// Re-expresses the box in another frame (the vehicle moved): the centre and the hull move exactly,
// the bounds become the hull's (without a hull: the axis-aligned bounds of the rotated corners),
// the footprint parts the axis-aligned bounds of their rotated corners, the yaw turns by `turn`
// (the motion's heading change).
void changeBoxFrame(Box3D& box, const Eigen::Isometry3d& motion, float turn) {
  const Eigen::Isometry3f m = motion.cast<float>();
  const auto planarBounds = [&m](Eigen::Vector2f& min, Eigen::Vector2f& max, float z) {
    Eigen::Vector2f lo = Eigen::Vector2f::Constant(std::numeric_limits<float>::infinity());
    Eigen::Vector2f hi = -lo;
    for (int corner = 0; corner < 4; ++corner) {
      const Eigen::Vector3f p(corner & 1 ? max.x() : min.x(), corner & 2 ? max.y() : min.y(), z);
      const Eigen::Vector2f q = (m * p).head<2>();
      lo = lo.cwiseMin(q);
      hi = hi.cwiseMax(q);
    }
    min = lo;
    max = hi;
  };
  const float z_mid = 0.5f * (box.min.z() + box.max.z());
  for (FootprintCell& cell : box.footprint) planarBounds(cell.min, cell.max, z_mid);
  Eigen::Vector2f min = box.min.head<2>(), max = box.max.head<2>();
  if (box.hull.empty()) {
    planarBounds(min, max, z_mid);
  } else {
    min.setConstant(std::numeric_limits<float>::infinity());
    max = -min;
    for (Eigen::Vector2f& p : box.hull) {
      p = (m * Eigen::Vector3f(p.x(), p.y(), z_mid)).head<2>();
      min = min.cwiseMin(p);
      max = max.cwiseMax(p);
    }
  }
  const float dz = (m * Eigen::Vector3f(box.center.x(), box.center.y(), z_mid)).z() - z_mid;
  box.min << min, box.min.z() + dz;
  box.max << max, box.max.z() + dz;
  box.center = m * box.center;
  box.yaw += turn;
}

// A box's bounds along a track's face axes (rows of `axes`: the axes' directions in the vehicle
// frame), and the outline points (vehicle frame) where each bound is reached.
struct AxesBounds {
  Eigen::Vector2f lo, hi;
  Eigen::Vector2f lo_at[2], hi_at[2];
};

// Calls f with each point of the box's planar outline: its hull, or without one the corners of its
// axis-aligned bounds.
template <class F>
void forEachOutlinePoint(const Box3D& box, F&& f) {
  if (box.hull.empty()) {
    for (int corner = 0; corner < 4; ++corner)
      f(Eigen::Vector2f(corner & 1 ? box.max.x() : box.min.x(),
                        corner & 2 ? box.max.y() : box.min.y()));
  } else {
    for (const Eigen::Vector2f& p : box.hull) f(p);
  }
}

AxesBounds boundsAlong(const Box3D& box, const Eigen::Matrix2f& axes) {
  AxesBounds b;
  b.lo.setConstant(std::numeric_limits<float>::infinity());
  b.hi = -b.lo;
  forEachOutlinePoint(box, [&](const Eigen::Vector2f& p) {
    const Eigen::Vector2f q = axes * p;
    for (int a = 0; a < 2; ++a) {
      if (q[a] < b.lo[a]) b.lo[a] = q[a], b.lo_at[a] = p;
      if (q[a] > b.hi[a]) b.hi[a] = q[a], b.hi_at[a] = p;
    }
  });
  return b;
}

float wrapAngle(float a) { return std::remainder(a, 2.0f * static_cast<float>(M_PI)); }

// A detection nearer than the face's end by at least this hides what lies behind it [m]: two
// pieces of one wall either side of a shadow are at the same range and do not hide each other.
constexpr float kOcclusionDepthM = 0.5f;
// A direction this close to a line (cos of 60 deg) runs along it.
constexpr float kFacingCos = 0.5f;
// A face whose points (those within kFaceDepthM of its bound) lie more than kEndSpreadM across
// the line of sight from its end is a side seen along its length (a parked car's flank): the
// view may end at its end, but not at the face itself [m].
constexpr float kFaceDepthM = 0.15f;
constexpr float kEndSpreadM = 0.2f;

// What occludedAt needs of one box and its frame (occlusion_gap_deg > 0): the nearer detections
// beside it as seen from the sensor.
struct ViewEnds {
  const TrackerView& view;
  const std::vector<Box3D>& detections;   // this frame's
  const std::vector<BearingSpan>& spans;  // ... as seen from the sensor
  const Box3D& box;
  BearingSpan own;                        // the box's own
  int skip = -1;                          // the detection the box is (or is matched to)
  float gap_rad = 0.0f;                   // 0: no occlusion test
};

// The range at which the ray from `origin` along the unit direction u first meets the box's
// outline (+inf when it misses).
float rangeAlong(const Box3D& box, const Eigen::Vector2f& origin, const Eigen::Vector2f& u) {
  float nearest = std::numeric_limits<float>::infinity();
  bool first = true;
  Eigen::Vector2f start, previous;
  const auto edge = [&](const Eigen::Vector2f& a, const Eigen::Vector2f& b) {
    // origin + t u = a + s (b - a): Cramer's rule on [u, a - b] [t s]^T = a - origin.
    const Eigen::Vector2f ab = a - b, ao = a - origin;
    const float det = u.x() * ab.y() - u.y() * ab.x();
    if (std::abs(det) < 1e-9f) return;
    const float t = (ao.x() * ab.y() - ao.y() * ab.x()) / det;
    const float s = (u.x() * ao.y() - u.y() * ao.x()) / det;
    if (t > 0.0f && s >= 0.0f && s <= 1.0f) nearest = std::min(nearest, t);
  };
  if (box.hull.size() == 1) return (box.hull[0] - origin).norm();
  const auto visit = [&](const Eigen::Vector2f& q) {
    if (first) {
      start = q;
      first = false;
    } else {
      edge(previous, q);
    }
    previous = q;
  };
  if (box.hull.empty()) {  // the axis-aligned bounds, in order around
    visit(box.min.head<2>());
    visit(Eigen::Vector2f(box.max.x(), box.min.y()));
    visit(box.max.head<2>());
    visit(Eigen::Vector2f(box.min.x(), box.max.y()));
  } else {
    for (const Eigen::Vector2f& q : box.hull) visit(q);
  }
  if (!first) edge(previous, start);
  return nearest;
}

// True when the outline point p, the box's end toward `dir` seen from the sensor (dir runs across
// the line of sight, within 60 deg; no part of the box lies beyond p's bearing that way by more
// than the gap; the face's points lie within kEndSpreadM of p across the line of sight: an end
// seen end-on, not a flank), borders on a detection whose bearings start within the gap beyond
// p's and which is nearer there by kOcclusionDepthM: the object may go on behind it.
bool occludedAt(const Eigen::Vector2f& p, const Eigen::Vector2f& dir, const ViewEnds& ends) {
  const Eigen::Vector2f d = p - ends.view.origin;
  const float range = d.norm();
  if (!ends.own.valid || !(range > 1e-3f)) return false;
  const float across = dir.dot(Eigen::Vector2f(-d.y(), d.x())) / range;  // toward larger bearing
  if (std::abs(across) < kFacingCos) return false;
  const float side = across > 0.0f ? 1.0f : -1.0f;
  const float bearing = std::atan2(d.y(), d.x());
  const float gap = ends.gap_rad;
  // The span's bearings relative to p's, turned so that `side` is positive: [lo, hi].
  const auto relative = [&](const BearingSpan& s, float& lo, float& hi) {
    const float shift = wrapAngle(s.bearing - bearing);
    lo = side > 0.0f ? shift + s.lo : -(shift + s.hi);
    hi = side > 0.0f ? shift + s.hi : -(shift + s.lo);
  };
  float lo, hi;
  relative(ends.own, lo, hi);
  if (hi > gap) return false;  // the box itself goes on beyond p that way: p is no end of it
  const float bound = dir.dot(p);
  bool flank = false;
  forEachOutlinePoint(ends.box, [&](const Eigen::Vector2f& q) {
    if (flank || dir.dot(q) < bound - kFaceDepthM) return;
    const Eigen::Vector2f e = q - ends.view.origin;
    const float back = -side * wrapAngle(std::atan2(e.y(), e.x()) - bearing);  // short of p's
    flank = back * e.norm() > kEndSpreadM;
  });
  if (flank) return false;
  for (std::size_t k = 0; k < ends.spans.size(); ++k) {
    const BearingSpan& s = ends.spans[k];
    if (static_cast<int>(k) == ends.skip || !s.valid) continue;
    if (!(s.near_range <= range - kOcclusionDepthM)) continue;
    relative(s, lo, hi);
    if (!(lo <= gap && hi > 0.0f)) continue;
    // Nearer where it borders on p (a long wall along the road is near at one end and behind a
    // parked car at the car's bearing): its range just beyond p's bearing, or at it.
    const float at = bearing + side * std::min(std::max(lo, 0.0f) + 1e-4f, hi);
    const Eigen::Vector2f u(std::cos(at), std::sin(at));
    if (rangeAlong(ends.detections[k], ends.view.origin, u) <= range - kOcclusionDepthM)
      return true;
  }
  return false;
}

// True when the outline point p, extreme along direction `dir` (vehicle frame), lies on an edge of
// the region of interest that faces that way (outward normal within 60 deg of dir): the bound
// there is where the view ends. Along the vehicle's axes: the edge of the same axis only.
bool atRegionEdge(const Eigen::Vector2f& p, const Eigen::Vector2f& dir, const TrackerView& view) {
  for (int k = 0; k < 2; ++k) {
    if (-dir[k] > kFacingCos && p[k] <= view.region_min[k] + view.region_tolerance_m) return true;
    if (dir[k] > kFacingCos && p[k] >= view.region_max[k] - view.region_tolerance_m) return true;
  }
  return false;
}

// True when the box, seen from the sensor, lies wholly behind the detection of span s: each of
// its bearings within s's, and the detection at least kOcclusionDepthM nearer there (at the
// box's two ends, a tenth of its span inward, and its middle).
bool hiddenBehind(const BearingSpan& own, const BearingSpan& s, const Box3D& detection,
                  const Eigen::Vector2f& origin) {
  if (!own.valid || !s.valid || !(s.near_range <= own.near_range - kOcclusionDepthM)) return false;
  const float shift = wrapAngle(s.bearing - own.bearing);
  if (!(shift + s.lo <= own.lo && shift + s.hi >= own.hi)) return false;
  const float inward = 0.1f * (own.hi - own.lo);
  for (const float rel : {own.lo + inward, 0.5f * (own.lo + own.hi), own.hi - inward}) {
    const float at = own.bearing + rel;
    const Eigen::Vector2f u(std::cos(at), std::sin(at));
    if (!(rangeAlong(detection, origin, u) <= own.near_range - kOcclusionDepthM)) return false;
  }
  return true;
}

// A detection where a held track is predicted: its box, grown by margin_m, holds the predicted
// centre, or its centre lies in the predicted box grown by as much.
bool nearPrediction(const Box3D& predicted, const Box3D& detection, double margin_m) {
  return planarContains(detection, predicted.center, margin_m) ||
         planarContains(predicted, detection.center, margin_m);
}

// Which part of the box the filter follows along one axis. kSteadier: of the two faces, the one
// that moved less against the prediction (a face hidden by a nearer object on one side: its
// shadow's edge moves with that object, and the other side may be hidden by the object itself).
enum class Face : std::uint8_t { kMiddle, kMin, kMax, kSteadier };

float faceValue(const AxesBounds& b, int axis, Face face) {
  switch (face) {
    case Face::kMin: return b.lo[axis];
    case Face::kMax: return b.hi[axis];
    case Face::kMiddle:
    case Face::kSteadier: break;
  }
  return 0.5f * (b.lo[axis] + b.hi[axis]);
}

// TrackAnchor::kNearestFace along one face axis of a box: the face toward the sensor (`sensor`:
// its coordinates along the axes) where the sensor lies beyond the box, the middle where it lies
// within the box's span. A face at the region of interest's edge is where the view ends, not the
// object: the other face instead (the middle when both are cut). Where the face that would be
// followed ends beside a nearer object that hides the rest: the steadier of the two (kSteadier).
Face nearestFace(const AxesBounds& b, int axis, const Eigen::Matrix2f& axes,
                 const Eigen::Vector2f& sensor, const ViewEnds& ends) {
  const Eigen::Vector2f dir = axes.row(axis).transpose();
  // Occlusion is tested only for the face that would be followed (each test runs over the
  // frame's detections).
  const auto hidden_lo = [&] {
    return ends.gap_rad > 0.0f && occludedAt(b.lo_at[axis], -dir, ends);
  };
  const auto hidden_hi = [&] {
    return ends.gap_rad > 0.0f && occludedAt(b.hi_at[axis], dir, ends);
  };
  const bool edge_lo = atRegionEdge(b.lo_at[axis], -dir, ends.view);
  const bool edge_hi = atRegionEdge(b.hi_at[axis], dir, ends.view);
  if (edge_lo && edge_hi) return Face::kMiddle;
  // One face at the region's edge: the other, unless a nearer object hides that one too.
  if (edge_lo) return hidden_hi() ? Face::kSteadier : Face::kMax;
  if (edge_hi) return hidden_lo() ? Face::kSteadier : Face::kMin;
  // The face toward the sensor, unless a nearer object hides it: the far face is then often
  // hidden by the object itself (a parked car behind the one before it), so neither is sure.
  // A hidden far face changes nothing: the near one is seen.
  if (sensor[axis] < b.lo[axis]) return hidden_lo() ? Face::kSteadier : Face::kMin;
  if (sensor[axis] > b.hi[axis]) return hidden_hi() ? Face::kSteadier : Face::kMax;
  return hidden_lo() || hidden_hi() ? Face::kSteadier : Face::kMiddle;
}

// The least extent jump read as a merge of an object whose faces are followed: a thin wall's
// measured depth is a few centimetres, its face's noise between frames about a tenth of a metre.
constexpr float kMinDepthJumpM = 0.15f;

// The position the filter measures for `detection` against the track's predicted box: the
// filter's predicted reference point moved by as much as the anchor faces moved from the predicted
// box to the detection (z: the middles). The same faces of both boxes are compared, so a change
// of the visible extent on the other side moves nothing, and a switch to other faces is smooth.
// The faces are taken along the track's face axes (fixed to the ground), from the boxes' hulls, so
// a parked car's do not move while the vehicle turns. An object whose footprint is shorter than
// params.face_min_extent_m both ways in both boxes is seen whole (a pedestrian, a bin): its
// middles, two faces' noise averaged. With params.face_jump_m, along an axis where the extent
// jumps by more than that (or by more than a thin or small object's own extent), the face that
// moved less against the prediction; with
// params.occlusion_gap_deg, the same along an axis where a face of the detection ends beside a
// nearer object. `detections` are the frame's, `spans` the same seen from the sensor, `matched`
// the index of `detection` among them.
Eigen::Vector3d anchoredMeasurement(const Box3D& detection, const Box3D& predicted,
                                    const Eigen::Vector3d& predicted_reference,
                                    float face_axes_yaw, const TrackerParams& params,
                                    const TrackerView& view,
                                    const std::vector<Box3D>& detections,
                                    const std::vector<BearingSpan>& spans, int matched) {
  const float c = std::cos(face_axes_yaw), s = std::sin(face_axes_yaw);
  Eigen::Matrix2f axes;
  axes << c, s, -s, c;
  const AxesBounds det = boundsAlong(detection, axes), pred = boundsAlong(predicted, axes);
  const float gap = params.occlusion_gap_deg * static_cast<float>(M_PI / 180.0);
  const ViewEnds det_ends{view,      detections, spans, detection,
                          spans[static_cast<std::size_t>(matched)], matched, gap};
  const Eigen::Vector2f extent = (det.hi - det.lo).cwiseMax(pred.hi - pred.lo);
  const bool faces = params.anchor == TrackAnchor::kNearestFace &&
                     !(extent.maxCoeff() < params.face_min_extent_m);
  const Eigen::Vector2f sensor = axes * view.origin;
  Eigen::Vector2f moved;
  for (int axis = 0; axis < 2; ++axis) {
    Face face = Face::kMiddle;
    if (faces) {
      // Passing alongside, the detection spans the sensor and both its faces are seen; the
      // predicted box's far face was not: keep the face it was followed by.
      face = nearestFace(det, axis, axes, sensor, det_ends);
      if (face == Face::kMiddle) {
        const ViewEnds pred_ends{view, detections, spans, predicted,
                                 gap > 0.0f ? bearingSpan(predicted, view.origin) : BearingSpan(),
                                 matched, gap};
        face = nearestFace(pred, axis, axes, sensor, pred_ends);
      }
    }
    // Each face's innovation against the prediction, and the smaller one: the face that stayed.
    const float lo = det.lo[axis] - pred.lo[axis], hi = det.hi[axis] - pred.hi[axis];
    const float steadier = std::abs(lo) < std::abs(hi) ? lo : hi;
    moved[axis] = face == Face::kSteadier
                      ? steadier
                      : faceValue(det, axis, face) - faceValue(pred, axis, face);
    if (params.anchor == TrackAnchor::kNearestFace && params.face_jump_m > 0.0f) {
      // The extent jumped (a merge or a split with what stands close): the face that stayed, when
      // neither box has it at the region's edge. A jump is face_jump_m, or less for a thin or small
      // object (its extent along the axis without what joined it or before it came apart, the
      // thinner of the two boxes): more than that depth (at least kMinDepthJumpM) where its faces
      // are followed (a wall taking in the walker beside it), more than half of it where it is
      // seen whole (a pedestrian taking in the post beside it).
      const Eigen::Vector2f dir = axes.row(axis).transpose();
      const float thinner = std::min(det.hi[axis] - det.lo[axis], pred.hi[axis] - pred.lo[axis]);
      const float jump = std::min(params.face_jump_m,
                                  faces ? std::max(kMinDepthJumpM, thinner) : 0.5f * thinner);
      if (std::abs(hi - lo) > jump && !atRegionEdge(det.lo_at[axis], -dir, view) &&
          !atRegionEdge(pred.lo_at[axis], -dir, view) &&
          !atRegionEdge(det.hi_at[axis], dir, view) && !atRegionEdge(pred.hi_at[axis], dir, view))
        moved[axis] = steadier;
    }
  }
  Eigen::Vector3d z = predicted_reference;
  z.head<2>() += (axes.transpose() * moved).cast<double>();
  z.z() += 0.5 * (double(detection.min.z()) + double(detection.max.z())) -
           0.5 * (double(predicted.min.z()) + double(predicted.max.z()));
  return z;
}

}  // namespace

BearingSpan bearingSpan(const Box3D& box, const Eigen::Vector2f& origin) {
  BearingSpan span;
  bool first = true, inside = false;
  forEachOutlinePoint(box, [&](const Eigen::Vector2f& p) {
    const Eigen::Vector2f d = p - origin;
    const float range = d.norm();
    if (!(range > 1e-3f)) inside = true;
    const float bearing = std::atan2(d.y(), d.x());
    if (first) {
      span.bearing = bearing;
      span.near_range = range;
      first = false;
      return;
    }
    const float rel = wrapAngle(bearing - span.bearing);
    span.lo = std::min(span.lo, rel);
    span.hi = std::max(span.hi, rel);
    span.near_range = std::min(span.near_range, range);
  });
  // Seen from outside a convex outline, its bearings span less than half a turn; from inside
  // (or from one of its points), they wrap.
  span.valid = !first && !inside && span.hi - span.lo < static_cast<float>(M_PI) &&
               std::isfinite(span.bearing) && std::isfinite(span.near_range);
  return span;
}

const char* toString(TrackAnchor anchor) {
  switch (anchor) {
    case TrackAnchor::kCentre: return "centre";
    case TrackAnchor::kNearestFace: return "nearest_face";
    case TrackAnchor::kInvalid: break;
  }
  return "invalid";
}

TrackAnchor parseTrackAnchor(const std::string& name) {
  if (name == "centre") return TrackAnchor::kCentre;
  if (name == "nearest_face") return TrackAnchor::kNearestFace;
  return TrackAnchor::kInvalid;
}

std::string validate(const TrackerParams& p) {
  std::ostringstream why;
  if (!(p.gate_distance_m > 0.0f) || !std::isfinite(p.gate_distance_m)) {
    why << "tracker.gate_distance_m must be > 0 (got " << p.gate_distance_m << ")";
  } else if (!(p.iou_weight >= 0.0f) || !std::isfinite(p.iou_weight)) {
    why << "tracker.iou_weight must be >= 0 (got " << p.iou_weight << ")";
  } else if (p.min_hits_to_confirm < 1) {
    why << "tracker.min_hits_to_confirm must be >= 1 (got " << p.min_hits_to_confirm << ")";
  } else if (p.min_birth_points < 0) {
    why << "tracker.min_birth_points must be >= 0 (got " << p.min_birth_points << ")";
  } else if (p.max_missed_frames < 0) {
    why << "tracker.max_missed_frames must be >= 0 (got " << p.max_missed_frames << ")";
  } else if (!(p.accel_std >= 0.0) || !std::isfinite(p.accel_std)) {
    why << "tracker.accel_std must be >= 0 (got " << p.accel_std << ")";
  } else if (!(p.steady_accel_std >= 0.0) || !std::isfinite(p.steady_accel_std)) {
    why << "tracker.steady_accel_std must be >= 0 (got " << p.steady_accel_std << ")";
  } else if (!(p.mode_switch_rate_per_s > 0.0) || !std::isfinite(p.mode_switch_rate_per_s)) {
    why << "tracker.mode_switch_rate_per_s must be > 0 (got " << p.mode_switch_rate_per_s << ")";
  } else if (!(p.measurement_std_m > 0.0) || !std::isfinite(p.measurement_std_m)) {
    why << "tracker.measurement_std_m must be > 0 (got " << p.measurement_std_m << ")";
  } else if (!(p.initial_velocity_std > 0.0) || !std::isfinite(p.initial_velocity_std)) {
    why << "tracker.initial_velocity_std must be > 0 (got " << p.initial_velocity_std << ")";
  } else if (!(p.max_dt_s > 0.0) || !std::isfinite(p.max_dt_s)) {
    why << "tracker.max_dt_s must be > 0 (got " << p.max_dt_s << ")";
  } else if (!(p.face_min_extent_m >= 0.0f) || !std::isfinite(p.face_min_extent_m)) {
    why << "tracker.face_min_extent_m must be >= 0 (got " << p.face_min_extent_m << ")";
  } else if (!(p.face_jump_m >= 0.0f) || !std::isfinite(p.face_jump_m)) {
    why << "tracker.face_jump_m must be >= 0 (got " << p.face_jump_m << ")";
  } else if (!(p.occlusion_gap_deg >= 0.0f) || !(p.occlusion_gap_deg < 90.0f)) {
    why << "tracker.occlusion_gap_deg must be >= 0 and < 90 (got " << p.occlusion_gap_deg << ")";
  } else if (!(p.merge_hold_m >= 0.0f) || !std::isfinite(p.merge_hold_m)) {
    why << "tracker.merge_hold_m must be >= 0 (got " << p.merge_hold_m << ")";
  } else if (p.merge_hold_frames < 0) {
    why << "tracker.merge_hold_frames must be >= 0 (got " << p.merge_hold_frames << ")";
  } else if (p.hidden_hold_frames < 0) {
    why << "tracker.hidden_hold_frames must be >= 0 (got " << p.hidden_hold_frames << ")";
  } else if (!(p.robust_sigma >= 0.0) || !std::isfinite(p.robust_sigma)) {
    why << "tracker.robust_sigma must be >= 0 (got " << p.robust_sigma << ")";
  } else if (p.anchor != TrackAnchor::kCentre && p.anchor != TrackAnchor::kNearestFace) {
    why << "tracker.anchor must be \"centre\" or \"nearest_face\"";
  }
  return why.str();
}

bool updateMotionState(Track& track, const MotionEvidence& evidence) {
  track.evidence = evidence;
  const MotionState reading = evidence.state();
  if (reading == MotionState::kMoving) {
    ++track.moving_in_row;
    track.static_in_row = 0;
  } else if (reading == MotionState::kStatic) {
    ++track.static_in_row;
    track.moving_in_row = 0;
  } else {
    return false;  // nothing new: the state stands
  }
  const MotionState before = track.motion;
  if (reading == MotionState::kMoving) {
    if (track.motion != MotionState::kStatic || track.moving_in_row >= 2) track.motion = MotionState::kMoving;
  } else {
    const double speed = track.filter.velocity().head<2>().norm();
    const auto& P = track.filter.covariance();
    const bool settled_motion = track.hits >= kSettledHits && speed > kSettledSpeedMps &&
                                speed > 3.0 * std::sqrt(P(3, 3) + P(4, 4));
    if (track.motion == MotionState::kUnknown && !settled_motion) track.motion = MotionState::kStatic;
    else if (track.motion == MotionState::kMoving && track.static_in_row >= 3 && !settled_motion)
      track.motion = MotionState::kStatic;
  }
  return track.motion != before;
}

Eigen::Vector3d Track::velocity() const {
  return motion == MotionState::kStatic ? Eigen::Vector3d::Zero() : filter.velocity();
}

double Track::velocityStd() const {
  if (motion == MotionState::kStatic) return std::sqrt(2.0) * kStaticVelocityStd;
  const auto& P = filter.covariance();
  return std::sqrt(P(3, 3) + P(4, 4));
}

Eigen::Vector2d Track::velocityStdXY() const {
  if (motion == MotionState::kStatic) return Eigen::Vector2d::Constant(kStaticVelocityStd);
  const auto& P = filter.covariance();
  return Eigen::Vector2d(std::sqrt(P(3, 3)), std::sqrt(P(4, 4)));
}

MultiObjectTracker::MultiObjectTracker(const TrackerParams& params) : params_(params) {}

void MultiObjectTracker::reset() {
  tracks_.clear();
  has_stamp_ = false;
}

double MultiObjectTracker::holdMargin(const Track& track) const {
  // Plus three standard deviations of where the filter predicts it: a young track, its velocity
  // still unknown, is not held to a place it does not know (a walker entering a counter's box).
  const auto& P = track.filter.covariance();
  return params_.merge_hold_m + 3.0 * std::sqrt(std::max(P(0, 0), P(1, 1)));
}

void MultiObjectTracker::holdTracksInsideDetections(const std::vector<Box3D>& detections) {
  const int num_tracks = static_cast<int>(tracks_.size());
  const int num_detections = static_cast<int>(detections.size());
  const auto inside = [&](int i, int j) {
    return cost_(i, j) < kForbiddenCost &&
           planarContains(detections[j], tracks_[i].box.center, 0.0);
  };
  // Of the tracks inside a detection, the one it fits best (the lowest cost).
  best_inside_.assign(num_detections, -1);
  track_held_.assign(num_tracks, 0);
  for (int i = 0; i < num_tracks; ++i) {
    for (int j = 0; j < num_detections; ++j) {
      if (!inside(i, j)) continue;
      track_held_[i] = 1;
      int& best = best_inside_[j];
      if (best < 0 || cost_(i, j) < cost_(best, j)) best = i;
    }
  }
  for (int i = 0; i < num_tracks; ++i) {
    if (!track_held_[i]) continue;
    const Box3D& predicted = tracks_[i].box;
    const double margin = holdMargin(tracks_[i]);
    for (int j = 0; j < num_detections; ++j) {
      if (cost_(i, j) >= kForbiddenCost) continue;
      // A box that holds several tracks (a merge) goes to the one it fits best; the others coast
      // inside it. Else the assignment, which pairs as many as it can, gave it to the smaller
      // track and the bigger one a sliver beside it (a pedestrian's and a parked car's tracks).
      const bool taken_by_another = best_inside_[j] >= 0 && best_inside_[j] != i && inside(i, j);
      if (taken_by_another || !nearPrediction(predicted, detections[j], margin))
        cost_(i, j) = kForbiddenCost;
    }
  }
}

void MultiObjectTracker::holdHiddenTracks(const std::vector<Box3D>& detections,
                                          const TrackerView& view) {
  const int num_tracks = static_cast<int>(tracks_.size());
  const int num_detections = static_cast<int>(detections.size());
  track_hidden_.assign(num_tracks, 0);
  for (int i = 0; i < num_tracks; ++i) {
    const BearingSpan own = bearingSpan(tracks_[i].box, view.origin);
    for (int j = 0; j < num_detections && !track_hidden_[i]; ++j)
      track_hidden_[i] = hiddenBehind(own, spans_[j], detections[j], view.origin);
    if (!track_hidden_[i]) continue;
    // What is seen where it is predicted is still its own (a box's outline overstates the bearings
    // a near object hides: a walker 1 m away "hid" the bin 5 m behind it and beside it).
    const double margin = holdMargin(tracks_[i]);
    for (int j = 0; j < num_detections; ++j)
      if (!nearPrediction(tracks_[i].box, detections[j], margin)) cost_(i, j) = kForbiddenCost;
  }
}

MultiObjectTracker::UpdateResult MultiObjectTracker::update(double stamp_s,
                                                            const std::vector<Box3D>& detections,
                                                            const TrackerView& view,
                                                            const Eigen::Isometry3d& motion) {
  UpdateResult result = UpdateResult::kOk;
  double dt = 0.0;
  if (has_stamp_) {
    dt = stamp_s - last_stamp_s_;
    if (dt < 0.0) {
      reset();
      result = UpdateResult::kResetTimeBackwards;
    } else if (!(dt <= params_.max_dt_s)) {  // also a non-finite stamp
      reset();
      result = UpdateResult::kResetGap;
    }
    if (result != UpdateResult::kOk) dt = 0.0;
  }
  last_stamp_s_ = stamp_s;
  has_stamp_ = true;

  // The vehicle moved since the last frame: every track re-expressed in this frame's vehicle
  // frame, so the filter's velocity is over ground and a parked car keeps standing still.
  if (result == UpdateResult::kOk && !motion.isApprox(Eigen::Isometry3d::Identity())) {
    const float turn = static_cast<float>(yawOf(motion.linear()));
    for (Track& track : tracks_) {
      track.filter.changeFrame(motion);
      changeBoxFrame(track.box, motion, turn);
      const float turned = track.face_axes_yaw + turn;
      track.face_axes_yaw = std::atan2(std::sin(turned), std::cos(turned));
    }
  }

  // Predict: the filter, and the box moves as its reference point does.
  const ImmModels models{params_.steady_accel_std, params_.accel_std,
                         params_.mode_switch_rate_per_s};
  for (Track& track : tracks_) {
    const Eigen::Vector3d before = track.filter.position();
    track.filter.predict(dt, models);
    translateBox(track.box, (track.filter.position() - before).cast<float>());
  }

  // Cost matrix tracks x detections: planar centre distance / gate + weight * (1 - BEV IoU).
  const int num_tracks = static_cast<int>(tracks_.size());
  const int num_detections = static_cast<int>(detections.size());
  if (cost_.rows() < num_tracks || cost_.cols() < num_detections) {
    cost_.resize(std::max<Eigen::Index>(num_tracks, cost_.rows()),
                 std::max<Eigen::Index>(num_detections, cost_.cols()));
  }
  const double gate = params_.gate_distance_m;
  for (int j = 0; j < num_detections; ++j) {
    const Box3D& detection = detections[j];
    if (!finiteCenter(detection)) {
      cost_.col(j).head(num_tracks).setConstant(kForbiddenCost);
      continue;
    }
    for (int i = 0; i < num_tracks; ++i) {
      const Box3D& predicted = tracks_[i].box;
      const double dx = predicted.center.x() - detection.center.x();
      const double dy = predicted.center.y() - detection.center.y();
      const double d2 = dx * dx + dy * dy;  // gate on the square: most pairs are far apart
      cost_(i, j) = d2 > gate * gate
                        ? kForbiddenCost
                        : std::sqrt(d2) / gate +
                              params_.iou_weight * (1.0 - bevIoU(predicted, detection));
    }
  }
  // The detections seen from the sensor: which faces end where a nearer object hides the rest,
  // and which tracks it hides whole.
  const bool hold_hidden = params_.hidden_hold_frames > 0;
  spans_.clear();
  if (params_.occlusion_gap_deg > 0.0f || hold_hidden) {
    for (const Box3D& detection : detections) spans_.push_back(bearingSpan(detection, view.origin));
  } else {
    spans_.resize(detections.size());  // invalid: never read
  }
  const bool hold_merges = params_.merge_hold_m > 0.0f;
  if (hold_merges) holdTracksInsideDetections(detections);
  if (hold_hidden) holdHiddenTracks(detections, view);
  solveAssignmentByComponents(cost_.topLeftCorner(num_tracks, num_detections),
                              assignment_workspace_, track_to_detection_);

  // Update matched tracks, age every track, drop the ones missed too often.
  const double measurement_variance = params_.measurement_std_m * params_.measurement_std_m;
  detection_used_.assign(num_detections, 0);
  for (int i = 0; i < num_tracks; ++i) {
    Track& track = tracks_[i];
    const int j = track_to_detection_[i];
    if (j >= 0) {
      const Box3D& detection = detections[j];
      detection_used_[j] = 1;
      // A detection this long has a well-defined long side (a car seen along it): its faces are
      // then measured along the object's own sides, which stay put whatever part of them is seen.
      if (detection.size.x() >= kOwnAxesMinLengthM) track.face_axes_yaw = detection.yaw;
      const Eigen::Vector3d z = anchoredMeasurement(detection, track.box, track.filter.position(),
                                                    track.face_axes_yaw, params_, view,
                                                    detections, spans_, j);
      track.filter.update(z, measurement_variance, params_.robust_sigma);
      updateMotionState(track, detection.motion);
      track.box = detection;
      translateBox(track.box, (track.filter.position() - z).cast<float>());
      ++track.hits;
      track.missed = 0;
      track.held = 0;
    } else if (hold_merges && track_held_[i] && track.held < params_.merge_hold_frames) {
      ++track.held;  // inside a detection another track took: merged, not gone
    } else if (hold_hidden && track_hidden_[i] && track.held < params_.hidden_hold_frames) {
      ++track.held;  // behind a nearer object: hidden, not gone
    } else {
      ++track.missed;
    }
    ++track.age;
    track.confirmed = track.confirmed || track.hits >= params_.min_hits_to_confirm;
  }
  tracks_.erase(std::remove_if(tracks_.begin(), tracks_.end(),
                               [this](const Track& track) {
                                 return track.missed > params_.max_missed_frames;
                               }),
                tracks_.end());

  // Birth: one tentative track per unassigned detection with the points to start one.
  const double velocity_variance = params_.initial_velocity_std * params_.initial_velocity_std;
  for (int j = 0; j < num_detections; ++j) {
    if (detection_used_[j] || !finiteCenter(detections[j]) ||
        detections[j].num_points < params_.min_birth_points)
      continue;
    tracks_.emplace_back();
    Track& track = tracks_.back();
    track.id = next_id_++;
    track.box = detections[j];
    track.filter.init(detections[j].center.cast<double>(), measurement_variance,
                      velocity_variance);
    track.age = 1;
    track.hits = 1;
    track.missed = 0;
    track.confirmed = track.hits >= params_.min_hits_to_confirm;
    updateMotionState(track, detections[j].motion);
  }
  return result;
}

}  // namespace icanc
