// Live tuning: a dynamic_reconfigure server over one of the core's parameter structs. The .cfg
// (cfg/*.cfg) names are the visitParams keys (icanc/core/common/param_keys.hpp) with '/' written '_', so
// the conversion walks the same key list as the YAML and rosparam readers, and keys the .cfg does
// not declare (the ROI boxes) stay as loaded. The server starts from the values the nodelet
// loaded; a change is validated with the core's validate() (invalid: throttled error, the old
// values stay and are sent back to the client) and handed to the nodelet's frame callback through
// take(), so it takes effect on the next frame. The reconfigure and frame callbacks may run on
// different threads.
#pragma once

#include <cstdint>
#include <mutex>
#include <set>
#include <string>

#include <boost/thread/recursive_mutex.hpp>
#include <dynamic_reconfigure/Config.h>
#include <diagnostic_updater/DiagnosticStatusWrapper.h>
#include <dynamic_reconfigure/server.h>
#include <ros/console.h>

#include "icanc/core/common/param_keys.hpp"
#include "icanc/ros/param_reader.hpp"

namespace icanc {

// "prep/voxel_leaf_m" -> "prep_voxel_leaf_m".
std::string reconfigureName(const std::string& key);

// Writes every value of the struct whose name `msg` already holds (msg: a Config's
// __toMessage__, i.e. the .cfg's parameters); returns the names written.
class ConfigMessageWriter {
 public:
  explicit ConfigMessageWriter(dynamic_reconfigure::Config& msg) : msg_(msg) {}
  void operator()(const std::string& key, double& v);
  void operator()(const std::string& key, float& v);
  void operator()(const std::string& key, int& v);
  void operator()(const std::string& key, bool& v);
  void operator()(const std::string& key, std::string& v);
  void operator()(const std::string& key, Eigen::Vector3f& v) {}  // not live
  const std::set<std::string>& written() const { return written_; }

 private:
  dynamic_reconfigure::Config& msg_;
  std::set<std::string> written_;
};

// Reads every value of the struct that `msg` holds; the others keep their value.
class ConfigMessageReader {
 public:
  explicit ConfigMessageReader(const dynamic_reconfigure::Config& msg) : msg_(msg) {}
  void operator()(const std::string& key, double& v);
  void operator()(const std::string& key, float& v);
  void operator()(const std::string& key, int& v);
  void operator()(const std::string& key, bool& v);
  void operator()(const std::string& key, std::string& v);
  void operator()(const std::string& key, Eigen::Vector3f& v) {}

 private:
  const dynamic_reconfigure::Config& msg_;
};

template <class ConfigT, class Params>
ConfigT toConfig(Params params) {
  ConfigT config = ConfigT::__getDefault__();
  dynamic_reconfigure::Config msg;
  config.__toMessage__(msg);
  ConfigMessageWriter writer(msg);
  visitParams(writer, params);
  config.__fromMessage__(msg);
  return config;
}

template <class ConfigT, class Params>
Params fromConfig(const ConfigT& config, Params params) {
  dynamic_reconfigure::Config msg;
  config.__toMessage__(msg);
  ConfigMessageReader reader(msg);
  visitParams(reader, params);
  return params;
}

// The .cfg names dynamic_reconfigure also stores as private parameters: known keys for `reader`,
// so a restarted nodelet does not call them unknown.
template <class ConfigT>
void acceptReconfigureKeys(ParamReader& reader) {
  for (const auto& p : ConfigT::__getParamDescriptions__()) reader.accept(p->name);
}

template <class ConfigT, class Params>
class LiveParams {
 public:
  LiveParams(const ros::NodeHandle& private_nh, const Params& loaded, const std::string& log_name)
      : current_(loaded), log_name_(log_name), server_(server_mutex_, private_nh) {
    {
      boost::recursive_mutex::scoped_lock lock(server_mutex_);
      server_.updateConfig(toConfig<ConfigT>(loaded));
    }
    server_.setCallback([this](ConfigT& config, std::uint32_t) { onReconfigure(config); });
  }

  // The change accepted since the last call, if any (call at the start of each frame).
  bool take(Params& params) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!pending_) return false;
    params = current_;
    pending_ = false;
    return true;
  }

  // Counters for the nodelet's diagnostics.
  void addTo(diagnostic_updater::DiagnosticStatusWrapper& stat) const {
    std::lock_guard<std::mutex> lock(mutex_);
    stat.add("reconfigurations accepted", accepted_);
    stat.add("reconfigurations rejected", rejected_);
    stat.add("last rejection", last_rejection_);
  }

  std::uint64_t accepted() const { std::lock_guard<std::mutex> l(mutex_); return accepted_; }
  std::uint64_t rejected() const { std::lock_guard<std::mutex> l(mutex_); return rejected_; }
  std::string lastRejection() const { std::lock_guard<std::mutex> l(mutex_); return last_rejection_; }

 private:
  void onReconfigure(ConfigT& config) {
    std::lock_guard<std::mutex> lock(mutex_);
    const Params candidate = fromConfig(config, current_);
    const std::string why = validate(candidate);
    if (!why.empty()) {
      ++rejected_;
      last_rejection_ = why;
      ROS_ERROR_STREAM_THROTTLE_NAMED(1.0, log_name_, "[" << log_name_ << "] reconfigure rejected, "
                                      "keeping the current parameters: " << why);
      config = toConfig<ConfigT>(current_);  // the client sees what is in force
      return;
    }
    if (first_call_) {  // setCallback's initial call: the loaded values, nothing new
      first_call_ = false;
      return;
    }
    ++accepted_;
    current_ = candidate;
    pending_ = true;
    ROS_INFO_STREAM_NAMED(log_name_, "[" << log_name_ << "] reconfigured: applied from the next frame");
  }

  mutable std::mutex mutex_;
  Params current_;
  bool pending_ = false;
  bool first_call_ = true;
  std::uint64_t accepted_ = 0, rejected_ = 0;
  std::string last_rejection_;
  std::string log_name_;
  boost::recursive_mutex server_mutex_;
  dynamic_reconfigure::Server<ConfigT> server_;
};

}  // namespace icanc
