// The ObstacleDetector's input checks beyond the message layout, as ROS glue over the
// core's StampCheck and SensorHealth: parameters (stamp_check/*, sensor_health/*), throttled logs
// per kind, and counters and levels in the nodelet's diagnostics. A rejected stamp makes the frame
// invalid input (dropped: the LightController's watchdog lights the lamp when they keep coming); a
// blind frame is processed and flagged (ObstacleArray sensor_blind: the lamp comes on).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include <diagnostic_updater/DiagnosticStatusWrapper.h>
#include <ros/time.h>

#include "icanc/core/input/sensor_health.hpp"
#include "icanc/core/input/stamp_check.hpp"
#include "icanc/ros/nodelet_support.hpp"
#include "icanc/ros/param_reader.hpp"

namespace icanc {

class CloudInputChecks {
 public:
  explicit CloudInputChecks(const std::string& log_name = "") : log_name_(log_name) {}

  // Reads stamp_check/* and sensor_health/*; "" or why they are invalid (naming the key).
  std::string load(ParamReader& reader);

  // False (counted, warned about, `input` told) when the frame's stamp is not valid input.
  bool stampValid(const ros::Time& stamp, InputMonitor& input);

  // Starts counting a frame's returns: the DetectorPipeline counts them in its pass over the cloud
  // (DetectorPipelineInput::returns).
  ReturnCounter& beginCount() {
    returns_.begin(health_.params());
    return returns_;
  }
  // Updates the sensor's health with the returns counted since beginCount() in a cloud of
  // `points` points (error while blind, throttled). Returns the valid count; blind() tells the
  // verdict.
  std::size_t checkHealth(std::size_t points);
  bool blind() const { return health_.blind(); }

  // Counters, and ERROR while blind / WARN when stamps were rejected since the last report
  // (merged into the status's level and message).
  void addTo(diagnostic_updater::DiagnosticStatusWrapper& stat);

 private:
  std::string log_name_;
  StampCheck stamps_;
  SensorHealth health_;
  ReturnCounter returns_;  // this frame's returns, per azimuth sector
  ros::WallTime logged_[kStampVerdicts];
  std::uint64_t reported_rejected_ = 0;
};

}  // namespace icanc
