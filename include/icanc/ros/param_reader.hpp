// Reads a nodelet's private parameters into the core's parameter structs, remembering every key
// it read so that unknown keys (typos in a YAML profile) can be reported.
#pragma once

#include <set>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <ros/node_handle.h>

#include "icanc/core/danger.hpp"
#include "icanc/core/illumination.hpp"
#include "icanc/core/light_controller.hpp"
#include "icanc/core/obstacle_detector.hpp"

namespace icanc {

class ParamReader {
 public:
  explicit ParamReader(const ros::NodeHandle& private_nh) : nh_(private_nh) {}

  template <class T>
  void read(const std::string& key, T& value) {
    keys_.insert(key);
    nh_.param(key, value, value);  // the struct's default stays when the key is absent
  }
  void read(const std::string& key, float& value);
  void read(const std::string& key, Eigen::Vector3f& value);  // a list of three numbers
  // The visitParams reader interface (icanc/core/param_keys.hpp).
  template <class T>
  void operator()(const std::string& key, T& value) {
    read(key, value);
  }

  // Marks `key` as known without reading it (a key another component owns).
  void accept(const std::string& key) { keys_.insert(key); }

  // Problems met while reading (wrong list length), "" when none.
  const std::string& error() const { return error_; }
  // Keys present under the private namespace that nothing read.
  std::vector<std::string> unknownKeys() const;

 private:
  ros::NodeHandle nh_;
  std::set<std::string> keys_;
  std::string error_;
};

void readParams(ParamReader& reader, ObstacleDetectorParams& params);
void readParams(ParamReader& reader, DangerParams& params);
void readParams(ParamReader& reader, LightControllerParams& params);
void readParams(ParamReader& reader, IlluminationParams& params);

}  // namespace icanc
