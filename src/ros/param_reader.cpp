#include "icanc/ros/param_reader.hpp"

#include <sstream>

#include "icanc/core/param_keys.hpp"

namespace icanc {

void ParamReader::read(const std::string& key, float& value) {
  double v = value;
  read(key, v);
  value = static_cast<float>(v);
}

void ParamReader::read(const std::string& key, Eigen::Vector3f& value) {
  keys_.insert(key);
  std::vector<double> list;
  if (!nh_.getParam(key, list)) return;
  if (list.size() != 3) {
    std::ostringstream why;
    why << nh_.resolveName(key) << " must be a list of 3 numbers (got " << list.size() << ")";
    if (error_.empty()) error_ = why.str();
    return;
  }
  value = Eigen::Vector3f(list[0], list[1], list[2]);
}

std::vector<std::string> ParamReader::unknownKeys() const {
  std::vector<std::string> names, unknown;
  ros::NodeHandle root;
  if (!root.getParamNames(names)) return unknown;
  const std::string prefix = nh_.getNamespace() + "/";
  for (const std::string& name : names) {
    if (name.compare(0, prefix.size(), prefix) != 0) continue;
    const std::string key = name.substr(prefix.size());
    if (!keys_.count(key)) unknown.push_back(name);
  }
  return unknown;
}

void readParams(ParamReader& r, ObstacleDetectorParams& p) { visitParams(r, p); }
void readParams(ParamReader& r, DangerParams& p) { visitParams(r, p); }
void readParams(ParamReader& r, LightControllerParams& p) { visitParams(r, p); }
void readParams(ParamReader& r, IlluminationParams& p) { visitParams(r, p); }

}  // namespace icanc
