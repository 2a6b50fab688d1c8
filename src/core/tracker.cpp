#include "icanc/core/tracker.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace icanc {
namespace {

bool finiteCenter(const Box3D& box) { return box.center.allFinite(); }

// Moves the box (centre and axis-aligned bounds) so that its centre is `center`.
void moveBoxTo(Box3D& box, const Eigen::Vector3f& center) {
  const Eigen::Vector3f delta = center - box.center;
  box.center = center;
  box.min += delta;
  box.max += delta;
}

}  // namespace

std::string validate(const TrackerParams& p) {
  std::ostringstream why;
  if (!(p.gate_distance_m > 0.0f) || !std::isfinite(p.gate_distance_m)) {
    why << "tracker.gate_distance_m must be > 0 (got " << p.gate_distance_m << ")";
  } else if (!(p.iou_weight >= 0.0f) || !std::isfinite(p.iou_weight)) {
    why << "tracker.iou_weight must be >= 0 (got " << p.iou_weight << ")";
  } else if (p.min_hits_to_confirm < 1) {
    why << "tracker.min_hits_to_confirm must be >= 1 (got " << p.min_hits_to_confirm << ")";
  } else if (p.max_missed_frames < 0) {
    why << "tracker.max_missed_frames must be >= 0 (got " << p.max_missed_frames << ")";
  } else if (!(p.accel_std >= 0.0) || !std::isfinite(p.accel_std)) {
    why << "tracker.accel_std must be >= 0 (got " << p.accel_std << ")";
  } else if (!(p.measurement_std_m > 0.0) || !std::isfinite(p.measurement_std_m)) {
    why << "tracker.measurement_std_m must be > 0 (got " << p.measurement_std_m << ")";
  } else if (!(p.initial_velocity_std > 0.0) || !std::isfinite(p.initial_velocity_std)) {
    why << "tracker.initial_velocity_std must be > 0 (got " << p.initial_velocity_std << ")";
  } else if (!(p.max_dt_s > 0.0) || !std::isfinite(p.max_dt_s)) {
    why << "tracker.max_dt_s must be > 0 (got " << p.max_dt_s << ")";
  }
  return why.str();
}

double Track::velocityStd() const {
  const auto& P = filter.covariance();
  return std::sqrt(P(3, 3) + P(4, 4));
}

Eigen::Vector2d Track::velocityStdXY() const {
  const auto& P = filter.covariance();
  return Eigen::Vector2d(std::sqrt(P(3, 3)), std::sqrt(P(4, 4)));
}

MultiObjectTracker::MultiObjectTracker(const TrackerParams& params) : params_(params) {}

void MultiObjectTracker::reset() {
  tracks_.clear();
  has_stamp_ = false;
}

MultiObjectTracker::UpdateResult MultiObjectTracker::update(double stamp_s,
                                                            const std::vector<Box3D>& detections) {
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

  // Predict: the filter, and the box follows the predicted centre.
  for (Track& track : tracks_) {
    track.filter.predict(dt, params_.accel_std);
    moveBoxTo(track.box, track.filter.position().cast<float>());
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
      track.filter.update(detection.center.cast<double>(), measurement_variance);
      track.box = detection;
      track.box.center = track.filter.position().cast<float>();
      ++track.hits;
      track.missed = 0;
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

  // Birth: one tentative track per unassigned detection.
  const double velocity_variance = params_.initial_velocity_std * params_.initial_velocity_std;
  for (int j = 0; j < num_detections; ++j) {
    if (detection_used_[j] || !finiteCenter(detections[j])) continue;
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
  }
  return result;
}

}  // namespace icanc
