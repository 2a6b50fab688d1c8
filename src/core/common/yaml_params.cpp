#include "icanc/core/common/yaml_params.hpp"

#include <sstream>
#include <stdexcept>

#include <yaml-cpp/yaml.h>

#include "icanc/core/common/param_keys.hpp"

namespace icanc {
namespace {

// visitParams reader over one YAML section; "a/b" keys walk nested maps.
class YamlReader {
 public:
  YamlReader(const YAML::Node& section, std::string where) : section_(section), where_(std::move(where)) {}

  template <class T>
  void operator()(const std::string& key, T& value) {
    const YAML::Node node = find(key);
    if (!node) return;
    try {
      value = node.as<T>();
    } catch (const YAML::Exception& e) {
      fail(key, e.what());
    }
  }
  void operator()(const std::string& key, Eigen::Vector3f& value) {
    const YAML::Node node = find(key);
    if (!node) return;
    if (!node.IsSequence() || node.size() != 3) fail(key, "must be a list of 3 numbers");
    try {
      for (int i = 0; i < 3; ++i) value[i] = node[i].as<float>();
    } catch (const YAML::Exception& e) {
      fail(key, e.what());
    }
  }
  void operator()(const std::string& key, std::vector<LampSegment>& value) {
    const YAML::Node node = find(key);
    if (!node) return;
    if (!node.IsSequence()) fail(key, "must be a list of segments");
    value.assign(node.size(), LampSegment());
    for (std::size_t i = 0; i < node.size(); ++i) {
      const std::string entry = key + "[" + std::to_string(i) + "]";
      if (!node[i].IsMap()) fail(entry, "must be a dictionary of numbers");
      for (const auto& kv : node[i]) {
        std::string why;
        try {
          why = setSegmentKey(value[i], kv.first.as<std::string>(), kv.second.as<double>());
        } catch (const YAML::Exception& e) {
          why = e.what();
        }
        if (!why.empty()) fail(entry, why);
      }
    }
  }

 private:
  YAML::Node find(const std::string& key) const {
    YAML::Node node;
    node.reset(section_);  // rebinding, never assignment: assignment would edit the tree
    std::istringstream parts(key);
    for (std::string part; std::getline(parts, part, '/');) {
      if (!node.IsMap() || !node[part]) return YAML::Node(YAML::NodeType::Undefined);
      node.reset(node[part]);
    }
    return node;
  }
  [[noreturn]] void fail(const std::string& key, const std::string& why) const {
    throw std::runtime_error(where_ + "/" + key + ": " + why);
  }

  YAML::Node section_;
  std::string where_;
};

template <class Params>
void readSection(const YAML::Node& root, const std::string& path, const std::string& name, Params& p) {
  if (!root[name]) return;
  YamlReader reader(root[name], path + ": " + name);
  visitParams(reader, p);
  const std::string why = validate(p);
  if (!why.empty()) throw std::runtime_error(path + ": " + why);
}

}  // namespace

Profile loadProfile(const std::string& path) {
  YAML::Node root;
  try {
    root = YAML::LoadFile(path);
  } catch (const YAML::Exception& e) {
    throw std::runtime_error(path + ": " + e.what());
  }
  Profile p;
  readSection(root, path, "obstacle_detector", p.detector);
  readSection(root, path, "danger_detector", p.danger);
  readSection(root, path, "light_controller", p.light);
  readSection(root, path, "light_controller", p.lamp);
  // The truth's corridor is the danger detector's unless the ground_truth section says otherwise.
  p.corridor.half_width_m = p.danger.half_width_m;
  p.corridor.horizon_s = p.danger.reaction_time_s;
  p.corridor.margin_m = p.danger.margin_m;
  p.corridor.vehicle_front_m = p.danger.vehicle_front_m;
  p.corridor.stopping_margin_m = p.danger.stopping_margin_m;
  readSection(root, path, "ground_truth", p.corridor);
  readSection(root, path, "illumination_monitor", p.illumination);
  readSection(root, path, "lidar_odometry", p.lidar_odometry);
  return p;
}

}  // namespace icanc
