#include "icanc/ros/nodelet_support.hpp"

#include <algorithm>
#include <limits>

#include <boost/make_shared.hpp>
#include <ros/console.h>
#include <std_msgs/Bool.h>

#include "icanc/core/input/frame_gaps.hpp"

namespace icanc {

geometry_msgs::TransformStamped lookupAtStampOrLatest(const tf2_ros::Buffer& buffer,
                                                      const std::string& target,
                                                      const std::string& source,
                                                      const ros::Time& stamp) {
  try {
    return buffer.lookupTransform(target, source, stamp);
  } catch (const tf2::ExtrapolationException&) {
    return buffer.lookupTransform(target, source, ros::Time(0));
  }
}

void publishBool(const ros::Publisher& pub, bool value) {
  auto msg = boost::make_shared<std_msgs::Bool>();
  msg->data = value;
  pub.publish(std_msgs::Bool::ConstPtr(msg));
}

void report(diagnostic_updater::DiagnosticStatusWrapper& stat, const StatusReport& report) {
  stat.summary(static_cast<unsigned char>(report.level), report.message);
  for (const auto& kv : report.values) stat.add(kv.first, kv.second);
}

void log(const std::string& name, const LogLine& line) {
  switch (line.severity) {
    case LogSeverity::kDebug: ROS_DEBUG_NAMED(name, "%s", line.text.c_str()); break;
    case LogSeverity::kInfo: ROS_INFO_NAMED(name, "%s", line.text.c_str()); break;
    case LogSeverity::kWarn: ROS_WARN_NAMED(name, "%s", line.text.c_str()); break;
    case LogSeverity::kError: ROS_ERROR_NAMED(name, "%s", line.text.c_str()); break;
    case LogSeverity::kFatal: ROS_FATAL_NAMED(name, "%s", line.text.c_str()); break;
  }
}

bool checkParams(const std::string& name, const ParamReader& reader, const std::string& validation) {
  for (const std::string& key : reader.unknownKeys()) {
    ROS_WARN_NAMED(name, "[%s] unknown parameter %s is ignored (typo?)", name.c_str(), key.c_str());
  }
  const std::string& why = reader.error().empty() ? validation : reader.error();
  if (!why.empty()) {
    ROS_FATAL_NAMED(name, "[%s] invalid parameters, not starting: %s", name.c_str(), why.c_str());
    return false;
  }
  return true;
}

Diagnostics::Diagnostics(ros::NodeHandle& nh, ros::NodeHandle& private_nh,
                         const std::string& node_name, const std::string& hardware_id)
    : updater_(new diagnostic_updater::Updater(nh, private_nh, node_name)) {
  updater_->setHardwareID(hardware_id);
  timer_ = nh.createTimer(ros::Duration(1.0), [this](const ros::TimerEvent&) { updater_->force_update(); });
}

std::string readExpectedRate(ParamReader& reader, double& expected_rate_hz) {
  reader.read("expected_rate_hz", expected_rate_hz);
  return expected_rate_hz > 0.0 ? "" : "expected_rate_hz must be > 0";
}

InputMonitor::InputMonitor(diagnostic_updater::Updater& updater, const std::string& topic,
                           double expected_rate_hz)
    : topic_(topic),
      expected_rate_hz_(expected_rate_hz),
      min_rate_hz_(0.8 * expected_rate_hz),
      max_rate_hz_(std::numeric_limits<double>::infinity()),
      rate_("input", updater, diagnostic_updater::FrequencyStatusParam(&min_rate_hz_, &max_rate_hz_, 0.0, 10)),
      frames_("frames", [this](diagnostic_updater::DiagnosticStatusWrapper& s) { diagnose(s); }) {
  rate_.addTask(&frames_);
}

void InputMonitor::received() {
  rate_.tick();
  std::lock_guard<std::mutex> lock(mutex_);
  ++received_;
}

void InputMonitor::received(double stamp_s) {
  rate_.tick();
  std::lock_guard<std::mutex> lock(mutex_);
  ++received_;
  if (has_stamp_) dropped_ += missedFrames(last_stamp_s_, stamp_s, expected_rate_hz_);
  has_stamp_ = true;
  last_stamp_s_ = stamp_s;
}

void InputMonitor::processed(double ms) {
  std::lock_guard<std::mutex> lock(mutex_);
  ++processed_;
  last_ms_ = ms;
  sum_ms_ += ms;
  max_ms_ = std::max(max_ms_, ms);
  ++window_count_;
}

void InputMonitor::invalid() {
  std::lock_guard<std::mutex> lock(mutex_);
  ++invalid_;
}

void InputMonitor::diagnose(diagnostic_updater::DiagnosticStatusWrapper& stat) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (invalid_ > reported_invalid_)
    stat.summary(diagnostic_msgs::DiagnosticStatus::WARN, "invalid frames rejected");
  else if (dropped_ > reported_dropped_)
    stat.summary(diagnostic_msgs::DiagnosticStatus::WARN, "frames dropped (stamp gaps)");
  else
    stat.summary(diagnostic_msgs::DiagnosticStatus::OK, "");
  reported_invalid_ = invalid_;
  reported_dropped_ = dropped_;
  stat.add("topic", topic_);
  stat.add("expected rate [Hz]", expected_rate_hz_);
  stat.add("frames received", received_);
  stat.add("frames processed", processed_);
  stat.add("invalid frames", invalid_);
  stat.add("dropped frames", dropped_);
  stat.add("processing ms (last)", last_ms_);
  stat.add("processing ms (mean since last report)", window_count_ ? sum_ms_ / window_count_ : 0.0);
  stat.add("processing ms (max since last report)", max_ms_);
  sum_ms_ = max_ms_ = 0.0;
  window_count_ = 0;
}

}  // namespace icanc
