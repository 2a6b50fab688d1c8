#include "icanc/ros/live_params.hpp"

#include <algorithm>

namespace icanc {

std::string reconfigureName(const std::string& key) {
  std::string name = key;
  std::replace(name.begin(), name.end(), '/', '_');
  return name;
}

namespace {

template <class Vec, class T>
bool set(Vec& params, const std::string& name, const T& value) {
  for (auto& p : params)
    if (p.name == name) {
      p.value = value;
      return true;
    }
  return false;
}

template <class Vec, class T>
bool get(const Vec& params, const std::string& name, T& value) {
  for (const auto& p : params)
    if (p.name == name) {
      value = p.value;
      return true;
    }
  return false;
}

}  // namespace

void ConfigMessageWriter::operator()(const std::string& key, double& v) {
  if (set(msg_.doubles, reconfigureName(key), v)) written_.insert(reconfigureName(key));
}
void ConfigMessageWriter::operator()(const std::string& key, float& v) {
  double d = v;
  (*this)(key, d);
}
void ConfigMessageWriter::operator()(const std::string& key, int& v) {
  if (set(msg_.ints, reconfigureName(key), v)) written_.insert(reconfigureName(key));
}
void ConfigMessageWriter::operator()(const std::string& key, bool& v) {
  if (set(msg_.bools, reconfigureName(key), v)) written_.insert(reconfigureName(key));
}
void ConfigMessageWriter::operator()(const std::string& key, std::string& v) {
  if (set(msg_.strs, reconfigureName(key), v)) written_.insert(reconfigureName(key));
}

void ConfigMessageReader::operator()(const std::string& key, double& v) { get(msg_.doubles, reconfigureName(key), v); }
void ConfigMessageReader::operator()(const std::string& key, float& v) {
  double d = v;
  if (get(msg_.doubles, reconfigureName(key), d)) v = static_cast<float>(d);
}
void ConfigMessageReader::operator()(const std::string& key, int& v) { get(msg_.ints, reconfigureName(key), v); }
void ConfigMessageReader::operator()(const std::string& key, bool& v) { get(msg_.bools, reconfigureName(key), v); }
void ConfigMessageReader::operator()(const std::string& key, std::string& v) { get(msg_.strs, reconfigureName(key), v); }

}  // namespace icanc
