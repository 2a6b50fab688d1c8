// What every icanc nodelet does the same way: finish reading parameters (report list errors,
// unknown keys and invalid values), run its diagnostic_updater on a timer and report its main
// input (rate, processing time, invalid and dropped frames) in one status.
#pragma once

#include <cstdint>
#include <memory>
#include <mutex>
#include <string>

#include <diagnostic_updater/diagnostic_updater.h>
#include <diagnostic_updater/publisher.h>
#include <geometry_msgs/TransformStamped.h>
#include <ros/node_handle.h>
#include <ros/publisher.h>
#include <ros/timer.h>
#include <tf2_ros/buffer.h>

#include "icanc/core/common/log_line.hpp"
#include "icanc/core/common/status_report.hpp"
#include "icanc/ros/param_reader.hpp"

namespace icanc {

// Logs every problem with the parameters read by `reader` plus `validation` (the core's
// validate() result) under `name`. Returns false when the nodelet must not start.
bool checkParams(const std::string& name, const ParamReader& reader, const std::string& validation);

// A core class's report (icanc/core/common/status_report.hpp) into a diagnostic status: its
// summary and its values.
void report(diagnostic_updater::DiagnosticStatusWrapper& stat, const StatusReport& report);

// A core class's log line under the nodelet's name (as NODELET_INFO and the like write it).
void log(const std::string& name, const LogLine& line);

// A std_msgs/Bool with `value`, published as a shared pointer (no copy within a nodelet manager).
void publishBool(const ros::Publisher& pub, bool value);

// A frame id as tf2 names it: tf2 frame ids carry no leading '/', tf1-era ones may.
inline std::string bareFrame(const std::string& frame) {
  return !frame.empty() && frame[0] == '/' ? frame.substr(1) : frame;
}

// target <- source at `stamp`, else the latest one (a static mount sent once, long before the
// cloud). Throws tf2::TransformException when there is none.
geometry_msgs::TransformStamped lookupAtStampOrLatest(const tf2_ros::Buffer& buffer,
                                                      const std::string& target,
                                                      const std::string& source,
                                                      const ros::Time& stamp);

// A diagnostic_updater whose update() runs from a 1 Hz timer of `nh`.
class Diagnostics {
 public:
  Diagnostics(ros::NodeHandle& nh, ros::NodeHandle& private_nh, const std::string& node_name,
              const std::string& hardware_id);
  diagnostic_updater::Updater& updater() { return *updater_; }

 private:
  std::unique_ptr<diagnostic_updater::Updater> updater_;
  ros::Timer timer_;
};

// Reads ~expected_rate_hz (the input rate the nodelet expects, default 10 Hz); "" or a problem.
std::string readExpectedRate(ParamReader& reader, double& expected_rate_hz);

// The status "<node>: input topic status" of a nodelet's main input: its rate
// (diagnostic_updater::FrequencyStatus over 10 updates, WARN "Frequency too low." below 80 % of
// expected_rate_hz, no upper bound: replays may run faster), processing time (last, mean and max
// since the previous report), and invalid and dropped frames (WARN while they grow). Dropped
// frames are missing stamps at the expected rate (icanc/core/input/frame_gaps.hpp). Thread-safe.
class InputMonitor {
 public:
  InputMonitor(diagnostic_updater::Updater& updater, const std::string& topic, double expected_rate_hz);

  void received();                // a message without a stamp arrived
  void received(double stamp_s);  // a stamped message arrived (counts stamp gaps as dropped)
  void processed(double ms);      // it was processed in `ms` wall milliseconds
  void invalid();                 // it was rejected as invalid

 private:
  void diagnose(diagnostic_updater::DiagnosticStatusWrapper& stat);

  std::string topic_;
  double expected_rate_hz_;
  double min_rate_hz_, max_rate_hz_;
  diagnostic_updater::HeaderlessTopicDiagnostic rate_;
  diagnostic_updater::FunctionDiagnosticTask frames_;

  std::mutex mutex_;
  std::uint64_t received_ = 0, processed_ = 0, invalid_ = 0, dropped_ = 0;
  std::uint64_t reported_invalid_ = 0, reported_dropped_ = 0;
  bool has_stamp_ = false;
  double last_stamp_s_ = 0.0;
  double last_ms_ = 0.0, sum_ms_ = 0.0, max_ms_ = 0.0;
  std::uint64_t window_count_ = 0;
};

}  // namespace icanc
