#include "icanc/ros/param_reader.hpp"

#include <sstream>

#include "icanc/core/common/param_keys.hpp"

namespace icanc {

namespace {

const char* typeName(const XmlRpc::XmlRpcValue& v) {
  switch (v.getType()) {
    case XmlRpc::XmlRpcValue::TypeBoolean: return "a boolean";
    case XmlRpc::XmlRpcValue::TypeInt: return "an integer";
    case XmlRpc::XmlRpcValue::TypeDouble: return "a floating-point number";
    case XmlRpc::XmlRpcValue::TypeString: return "a string";
    case XmlRpc::XmlRpcValue::TypeArray: return "a list";
    case XmlRpc::XmlRpcValue::TypeStruct: return "a dictionary";
    default: return "of another type";
  }
}

}  // namespace

bool ParamReader::fetch(const std::string& key, XmlRpc::XmlRpcValue& value) {
  keys_.insert(key);
  return nh_.getParam(key, value);
}

void ParamReader::addError(const std::string& key, const std::string& why) {
  errors_.push_back(nh_.resolveName(key) + " " + why);
  error_ = error_.empty() ? errors_.back() : error_ + "; " + errors_.back();
}

void ParamReader::read(const std::string& key, double& value) {
  XmlRpc::XmlRpcValue v;
  if (!fetch(key, v)) return;
  if (v.getType() == XmlRpc::XmlRpcValue::TypeDouble)
    value = static_cast<double>(v);
  else if (v.getType() == XmlRpc::XmlRpcValue::TypeInt)
    value = static_cast<int>(v);
  else
    addError(key, std::string("must be a number (got ") + typeName(v) + "): refused");
}

void ParamReader::read(const std::string& key, int& value) {
  XmlRpc::XmlRpcValue v;
  if (!fetch(key, v)) return;
  if (v.getType() == XmlRpc::XmlRpcValue::TypeInt)
    value = static_cast<int>(v);
  else
    addError(key, std::string("must be an integer (got ") + typeName(v) + "): refused");
}

void ParamReader::read(const std::string& key, bool& value) {
  XmlRpc::XmlRpcValue v;
  if (!fetch(key, v)) return;
  if (v.getType() == XmlRpc::XmlRpcValue::TypeBoolean)
    value = static_cast<bool>(v);
  else
    addError(key, std::string("must be true or false (got ") + typeName(v) + "): refused");
}

void ParamReader::read(const std::string& key, std::string& value) {
  XmlRpc::XmlRpcValue v;
  if (!fetch(key, v)) return;
  if (v.getType() == XmlRpc::XmlRpcValue::TypeString)
    value = static_cast<std::string>(v);
  else
    addError(key, std::string("must be a string (got ") + typeName(v) + "): refused");
}

void ParamReader::read(const std::string& key, float& value) {
  double v = value;
  read(key, v);
  value = static_cast<float>(v);
}

void ParamReader::read(const std::string& key, Eigen::Vector3f& value) {
  XmlRpc::XmlRpcValue v;
  if (!fetch(key, v)) return;
  bool numbers = v.getType() == XmlRpc::XmlRpcValue::TypeArray && v.size() == 3;
  for (int i = 0; numbers && i < 3; ++i)
    numbers = v[i].getType() == XmlRpc::XmlRpcValue::TypeDouble ||
              v[i].getType() == XmlRpc::XmlRpcValue::TypeInt;
  if (!numbers) {
    std::ostringstream why;
    why << "must be a list of 3 numbers (got ";
    if (v.getType() == XmlRpc::XmlRpcValue::TypeArray)
      why << "a list of " << v.size() << (v.size() == 3 ? " with a non-number" : "") << ")";
    else
      why << typeName(v) << ")";
    addError(key, why.str());
    return;
  }
  double xyz[3];
  for (int i = 0; i < 3; ++i)
    xyz[i] = v[i].getType() == XmlRpc::XmlRpcValue::TypeInt ? static_cast<double>(static_cast<int>(v[i]))
                                                           : static_cast<double>(v[i]);
  value = Eigen::Vector3f(xyz[0], xyz[1], xyz[2]);
}

void ParamReader::read(const std::string& key, std::vector<LampSegment>& value) {
  XmlRpc::XmlRpcValue v;
  if (!fetch(key, v)) return;
  if (v.getType() != XmlRpc::XmlRpcValue::TypeArray) {
    addError(key, std::string("must be a list of segments (got ") + typeName(v) + ")");
    return;
  }
  std::vector<LampSegment> segments(v.size());
  for (int i = 0; i < v.size(); ++i) {
    const std::string entry = key + "[" + std::to_string(i) + "]";
    if (v[i].getType() != XmlRpc::XmlRpcValue::TypeStruct) {
      addError(entry, std::string("must be a dictionary of numbers (got ") + typeName(v[i]) + ")");
      return;
    }
    for (auto& kv : v[i]) {
      XmlRpc::XmlRpcValue& x = kv.second;
      std::string why;
      if (x.getType() == XmlRpc::XmlRpcValue::TypeDouble)
        why = setSegmentKey(segments[i], kv.first, static_cast<double>(x));
      else if (x.getType() == XmlRpc::XmlRpcValue::TypeInt)
        why = setSegmentKey(segments[i], kv.first, static_cast<int>(x));
      else
        why = kv.first + " must be a number (got " + typeName(x) + ")";
      if (!why.empty()) {
        addError(entry, why);
        return;
      }
    }
  }
  value = segments;
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
void readParams(ParamReader& r, SegmentLampParams& p) { visitParams(r, p); }
void readParams(ParamReader& r, IlluminationParams& p) { visitParams(r, p); }

}  // namespace icanc
