// The ObstacleDetector's throttled warnings for each frame and the counters of its diagnostics,
// from what DetectorPipeline and CloudTransformQueue report and the nodelet's own counts: ROS glue
// over their counters.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

#include <diagnostic_updater/DiagnosticStatusWrapper.h>

#include "icanc/core/common/status_report.hpp"
#include "icanc/core/perception/detector_pipeline.hpp"
#include "icanc/ros/cloud_transform_queue.hpp"

namespace icanc {

class DetectorStatus {
 public:
  DetectorStatus(const std::string& log_name = "", const std::string& target_frame = "",
                 const std::string& fixed_frame = "")
      : log_name_(log_name), target_frame_(target_frame), fixed_frame_(fixed_frame) {}

  // Warns (throttled) about a missing transform or pose, a reset of the tracks, a rejected ground.
  void logFrame(const DetectorPipeline& pipeline, const DetectorPipelineResult& r,
                const CloudTransformQueue::Transforms& t, const std::string& cloud_frame,
                double stamp_s);

  // The nodelet's own counts: a cloud arrived, ground or obstacle points were published for a
  // frame, an ObstacleArray was published (its obstacles, its processing time and the stages').
  void onReceived() { ++received_; }
  void onDebugFrame() { ++debug_frames_; }
  void onPublished(std::size_t obstacles, double processing_ms, const StageTimes& times);

  // WARN naming the first kind of fault that grew since the last report (invalid clouds,
  // transforms missing or late, ego motion, ground), else OK; then the counters, the pipeline's
  // and the nodelet's.
  void addTo(diagnostic_updater::DiagnosticStatusWrapper& stat, const DetectorPipelineCounters& c,
             EgoMotionSource source, const CloudTransformQueue::Stats& waits);

 private:
  void logGround(const ObstacleDetector& detector, const std::string& frame);

  std::string log_name_, target_frame_, fixed_frame_;
  FaultGrowth faults_;  // the fault kinds counted at the last report
  std::uint64_t received_ = 0, published_ = 0, debug_frames_ = 0;
  std::size_t last_obstacles_ = 0;
  double last_processing_ms_ = 0.0;
  StageTimes last_times_;
};

}  // namespace icanc
