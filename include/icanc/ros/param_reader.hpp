// Reads a nodelet's private parameters into the core's parameter structs, remembering every key
// it read so that unknown keys (typos in a YAML profile) can be reported. A value of the wrong type
// (a string for a number, 2.5 for an integer, a list for a number) is refused, not replaced by the
// default in silence: the value stays as it was, and the problem, naming the key and the type
// found, is collected in errors() (the nodelet then refuses to start, see checkParams).
#pragma once

#include <set>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <ros/node_handle.h>

#include "icanc/core/danger/danger.hpp"
#include "icanc/core/camera/illumination.hpp"
#include "icanc/core/light/lamp_segments.hpp"
#include "icanc/core/light/light_controller.hpp"
#include "icanc/core/perception/obstacle_detector.hpp"

namespace icanc {

class ParamReader {
 public:
  explicit ParamReader(const ros::NodeHandle& private_nh) : nh_(private_nh) {}

  // The struct's default stays when the key is absent or its value has the wrong type.
  void read(const std::string& key, double& value);
  void read(const std::string& key, int& value);
  void read(const std::string& key, bool& value);
  void read(const std::string& key, std::string& value);
  void read(const std::string& key, float& value);
  void read(const std::string& key, Eigen::Vector3f& value);  // a list of three numbers
  // A list of dictionaries of numbers (light_controller/segments).
  void read(const std::string& key, std::vector<LampSegment>& value);
  // The visitParams reader interface (icanc/core/common/param_keys.hpp).
  template <class T>
  void operator()(const std::string& key, T& value) {
    read(key, value);
  }

  // Marks `key` as known without reading it (a key another component owns).
  void accept(const std::string& key) { keys_.insert(key); }

  // Problems met while reading (wrong type, wrong list length), "" when none: all of them,
  // "; "-separated, each naming its key.
  const std::string& error() const { return error_; }
  const std::vector<std::string>& errors() const { return errors_; }
  // Keys present under the private namespace that nothing read.
  std::vector<std::string> unknownKeys() const;

 private:
  ros::NodeHandle nh_;
  std::set<std::string> keys_;
  // The value under `key` when present (false when absent).
  bool fetch(const std::string& key, XmlRpc::XmlRpcValue& value);
  void addError(const std::string& key, const std::string& why);

  std::string error_;
  std::vector<std::string> errors_;
};

void readParams(ParamReader& reader, ObstacleDetectorParams& params);
void readParams(ParamReader& reader, DangerParams& params);
void readParams(ParamReader& reader, LightControllerParams& params);
void readParams(ParamReader& reader, SegmentLampParams& params);
void readParams(ParamReader& reader, IlluminationParams& params);

}  // namespace icanc
