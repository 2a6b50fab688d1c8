#include "icanc/ros/nodelet_support.hpp"

#include <ros/console.h>

namespace icanc {

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

}  // namespace icanc
