#include "icanc/core/perception/detector_pipeline.hpp"

namespace icanc {

DetectorPipeline::DetectorPipeline(const ObstacleDetectorParams& params, const EgoMotionParams& ego,
                                   std::size_t max_points)
    : detector_(params), ego_(ego), max_points_(max_points) {}

DecodeError DetectorPipeline::plan(const RawCloud& raw, DecodePlan& plan) {
  const DecodeError error = planDecode(raw, max_points_, plan);
  if (error != DecodeError::kNone) ++counters_.invalid[error];
  return error;
}

DetectorPipelineResult DetectorPipeline::process(const DetectorPipelineInput& in) {
  DetectorPipelineResult result;
  if (!last_frame_.empty() && in.frame != last_frame_) {
    ++counters_.frame_changes;
    result.previous_frame = last_frame_;
    detector_.reset();
  }
  last_frame_ = in.frame;

  result.ego = egoStep(in.stamp_s, in.fixed_T_vehicle);
  detector_.setFrameMotion(result.ego.motion, result.ego.status != EgoStep::Status::kNone &&
                                                  result.ego.status != EgoStep::Status::kLost);
  detector_.setCollectMovingPoints(in.collect_moving_points);
  detector_.setSensorOrigin(in.to_frame.translation());  // the cloud frame's origin

  DecodeStats stats;
  // Each point the detector reads, as the message has it, for the blind-sensor check.
  ReturnCounter* const returns = in.returns;
  const auto count = [returns](float x, float y, float z) {
    if (returns != nullptr) returns->add(x, y, z);
  };
  if (detector_.fast()) {
    result.tracker = detector_.processFrom(
        in.stamp_s,
        [&](auto&& sink) { stats = forEachXYZ(*in.raw, *in.plan, in.to_frame, sink, count); },
        &result.times);
  } else {
    if (returns != nullptr) forEachXYZ(*in.raw, *in.plan, Eigen::Affine3f::Identity(), count);
    decodeXYZ(*in.raw, in.to_frame, max_points_, cloud_, &stats);
    result.tracker = detector_.process(in.stamp_s, cloud_, &result.times);
    result.ground_fault = countGround();
  }
  counters_.dropped_points += stats.dropped_nonfinite + stats.dropped_zero;
  if (result.tracker == MultiObjectTracker::UpdateResult::kResetTimeBackwards) ++counters_.time_resets;
  if (result.tracker == MultiObjectTracker::UpdateResult::kResetGap) ++counters_.gap_resets;
  ++counters_.frames;
  return result;
}

EgoStep DetectorPipeline::egoStep(double stamp_s, const Eigen::Isometry3d* pose) {
  if (ego_.params().source == EgoMotionSource::kNone) return EgoStep();
  const EgoStep step = ego_.update(stamp_s, pose);
  ++counters_.ego[step.status];
  const bool over_ground = step.status != EgoStep::Status::kNone &&
                           step.status != EgoStep::Status::kLost;
  if (ego_frames_ > 0 && over_ground != over_ground_) {  // the first frame starts, not restarts
    detector_.reset();
    ++counters_.ego_restarts;
  }
  over_ground_ = over_ground;
  ++ego_frames_;
  return step;
}

// A wrong ground plane is never silent: a plane rejected as the road and a frame without any
// plausible road (every point kept) are counted; the caller warns.
bool DetectorPipeline::countGround() {
  const GroundResult& ground = detector_.ground();
  if (ground.status == GroundStatus::kNoPlane) {
    ++counters_.ground_absent;
    return true;
  }
  if (ground.rejection == GroundRejection::kNone) return false;
  counters_.last_rejected_height_m = ground.rejected_height_m;
  if (ground.status == GroundStatus::kFoundOnRetry)
    ++counters_.ground_retried;
  else
    ++counters_.ground_rejected;
  return true;
}

}  // namespace icanc
