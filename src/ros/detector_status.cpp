#include "icanc/ros/detector_status.hpp"

#include <algorithm>
#include <cstdio>
#include <map>

#include <ros/console.h>

namespace icanc {

void DetectorStatus::logFrame(const DetectorPipeline& pipeline, const DetectorPipelineResult& r,
                              const CloudTransformQueue::Transforms& t,
                              const std::string& cloud_frame, double stamp_s) {
  const char* name = log_name_.c_str();
  const char* frame = t.frame.c_str();
  if (t.mount_missing)
    ROS_WARN_THROTTLE_NAMED(5.0, log_name_, "[%s] no transform %s -> %s at %.3f after waiting %.2f s "
                            "(%s): publishing boxes in %s", name, cloud_frame.c_str(),
                            target_frame_.c_str(), stamp_s, t.waited_s,
                            t.mount_why.c_str(), frame);
  if (!r.previous_frame.empty())
    ROS_WARN_NAMED(log_name_, "[%s] output frame changed from '%s' to '%s': tracker reset", name,
                   r.previous_frame.c_str(), frame);
  if (r.tracker == MultiObjectTracker::UpdateResult::kResetTimeBackwards)
    ROS_WARN_THROTTLE_NAMED(1.0, log_name_, "[%s] cloud stamp went backwards (bag loop?): tracker reset", name);
  else if (r.tracker == MultiObjectTracker::UpdateResult::kResetGap)
    ROS_WARN_THROTTLE_NAMED(1.0, log_name_, "[%s] gap between clouds above tracker/max_dt_s: tracker reset", name);
  if (r.ground_fault) logGround(pipeline.detector(), t.frame);
  const char* fixed = fixed_frame_.c_str();
  const char* why = t.pose_why.c_str();
  switch (r.ego.status) {
    case EgoStep::Status::kExtrapolated:
      ROS_WARN_THROTTLE_NAMED(1.0, log_name_, "[%s] no pose of %s in %s at %.3f after waiting %.2f s "
                              "(%s): ego motion extrapolated", name, frame, fixed, stamp_s,
                              t.waited_s, why);
      break;
    case EgoStep::Status::kJump:
      ROS_WARN_THROTTLE_NAMED(1.0, log_name_, "[%s] the pose of %s in %s jumped at %.3f (odometry "
                              "reset?): re-based on it", name, frame, fixed, stamp_s);
      break;
    case EgoStep::Status::kLost:
      ROS_ERROR_THROTTLE_NAMED(1.0, log_name_, "[%s] no pose of %s in %s for more than %.2f s (%s): "
                               "velocities are relative to the vehicle until it comes back", name,
                               frame, fixed, pipeline.egoParams().max_extrapolation_s, why);
      break;
    case EgoStep::Status::kNone:
      if (pipeline.egoParams().source != EgoMotionSource::kNone)
        ROS_WARN_THROTTLE_NAMED(5.0, log_name_, "[%s] no pose of %s in %s yet (%s): velocities "
                                "relative to the vehicle", name, frame, fixed, why);
      break;
    case EgoStep::Status::kFirst:
    case EgoStep::Status::kMeasured: break;
  }
}

// A wrong ground plane is never silent (classic path): what was rejected, and what was done.
void DetectorStatus::logGround(const ObstacleDetector& detector, const std::string& frame) {
  const GroundResult& ground = detector.ground();
  const GroundParams& params = detector.params().ground;
  if (ground.status == GroundStatus::kNoPlane) {
    ROS_WARN_THROTTLE_NAMED(1.0, log_name_, "[%s] no ground plane within %.1f deg of horizontal in "
                            "%s: every point kept as obstacle", log_name_.c_str(),
                            params.max_slope_deg, frame.c_str());
    return;
  }
  char what[160];
  if (ground.status == GroundStatus::kFoundOnRetry)
    std::snprintf(what, sizeof(what), "road found on retry at %.2f m", ground.height_m);
  else
    std::snprintf(what, sizeof(what), "no plausible road near %.2f m either (%s), every point "
                  "kept as obstacle", params.expected_height_m,
                  ground.retry_rejection == GroundRejection::kNone ? "no plane there"
                                                                   : toString(ground.retry_rejection));
  ROS_WARN_THROTTLE_NAMED(1.0, log_name_, "[%s] ground plane at %.2f m in %s rejected, %s (road "
                          "expected at %.2f +- %.2f m; %zu points on it, %zu under it): %s",
                          log_name_.c_str(), ground.rejected_height_m, frame.c_str(),
                          toString(ground.rejection), params.expected_height_m,
                          params.max_height_error_m, ground.rejected_inliers,
                          ground.rejected_points_below, what);
}

void DetectorStatus::onPublished(std::size_t obstacles, double processing_ms, const StageTimes& times) {
  ++published_;
  last_obstacles_ = obstacles;
  last_processing_ms_ = processing_ms;
  last_times_ = times;
}

void DetectorStatus::addTo(diagnostic_updater::DiagnosticStatusWrapper& stat,
                           const DetectorPipelineCounters& c, EgoMotionSource source,
                           const CloudTransformQueue::Stats& waits) {
  const std::uint64_t invalid = addCountsByKind(stat, "invalid clouds: ", c.invalid);
  const auto ego = [&](EgoStep::Status s) {
    const auto it = c.ego.find(s);
    return it == c.ego.end() ? std::uint64_t{0} : it->second;
  };
  const char* const what[4] = {"invalid clouds dropped", "transform to target frame missing or late",
                               "ego motion extrapolated, jumped or lost",
                               "ground plane rejected or absent"};
  const int grown = faults_.firstGrown(
      {invalid, waits.mount_missing + waits.timed_out,
       ego(EgoStep::Status::kExtrapolated) + ego(EgoStep::Status::kJump) + ego(EgoStep::Status::kLost),
       c.ground_retried + c.ground_rejected + c.ground_absent});
  if (grown < 0)
    stat.summary(diagnostic_msgs::DiagnosticStatus::OK, "ok");
  else
    stat.summary(diagnostic_msgs::DiagnosticStatus::WARN, what[grown]);
  stat.add("ego motion source", toString(source));
  std::map<EgoStep::Status, std::uint64_t> frames = c.ego;  // the faults listed even at zero
  for (const auto s : {EgoStep::Status::kExtrapolated, EgoStep::Status::kJump, EgoStep::Status::kLost})
    frames[s] += 0;
  addCountsByKind(stat, "ego motion frames: ", frames);
  stat.add("ego motion restarts of the tracks", c.ego_restarts);
  stat.add("invalid clouds", invalid);
  stat.add("points dropped (NaN/Inf/zero)", c.dropped_points);
  stat.add("transform failures", waits.mount_missing);
  stat.add("transform waits timed out", waits.timed_out);
  stat.add("clouds sent on early: transform queue full", waits.pushed_out);
  stat.add("clouds waiting for transforms", waits.waiting);
  stat.add("transform wait ms (max since last report)", waits.max_wait_ms);
  stat.add("tracker resets: time backwards", c.time_resets);
  stat.add("tracker resets: gap", c.gap_resets);
  stat.add("output frame changes", c.frame_changes);
  stat.add("ground planes rejected, road found on retry", c.ground_retried);
  stat.add("ground planes rejected, every point kept", c.ground_rejected);
  stat.add("frames without a ground plane, every point kept", c.ground_absent);
  stat.add("last rejected ground plane height m", c.last_rejected_height_m);
  stat.add("clouds received", received_);
  stat.add("obstacle arrays published", published_);
  stat.add("obstacles (last frame)", last_obstacles_);
  stat.add("frames with ground/obstacle points published", debug_frames_);
  stat.add("processing ms (last frame)", last_processing_ms_);
  stat.add("prep ms", last_times_.prep_ms);
  stat.add("ground ms", last_times_.ground_ms);
  stat.add("cluster ms", last_times_.cluster_ms);
  stat.add("motion ms", last_times_.motion_ms);
  stat.add("track ms", last_times_.track_ms);
}

}  // namespace icanc
