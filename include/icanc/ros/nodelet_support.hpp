// What every icanc nodelet does the same way: finish reading parameters (report list errors,
// unknown keys and invalid values) and run its diagnostic_updater on a timer.
#pragma once

#include <memory>
#include <string>

#include <diagnostic_updater/diagnostic_updater.h>
#include <ros/node_handle.h>
#include <ros/timer.h>

#include "icanc/ros/param_reader.hpp"

namespace icanc {

// Logs every problem with the parameters read by `reader` plus `validation` (the core's
// validate() result) under `name`. Returns false when the nodelet must not start.
bool checkParams(const std::string& name, const ParamReader& reader, const std::string& validation);

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

}  // namespace icanc
