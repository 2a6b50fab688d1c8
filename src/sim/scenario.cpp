#include "icanc/sim/scenario.hpp"

#include <cmath>
#include <stdexcept>

#include <yaml-cpp/yaml.h>

namespace icanc {
namespace sim {
namespace {

struct Context {
  std::string path;
  [[noreturn]] void fail(const std::string& key, const std::string& why) const {
    throw std::runtime_error(path + ": " + key + ": " + why);
  }
};

template <class T>
T get(const YAML::Node& node, const std::string& key, const T& fallback, const Context& ctx) {
  const YAML::Node value = node[key];
  if (!value) return fallback;
  try {
    return value.as<T>();
  } catch (const YAML::Exception& e) {
    ctx.fail(key, std::string("cannot read value: ") + e.what());
  }
}

Eigen::Vector3f getVector(const YAML::Node& node, const std::string& key,
                          const Eigen::Vector3f& fallback, const Context& ctx) {
  const YAML::Node value = node[key];
  if (!value) return fallback;
  if (!value.IsSequence() || value.size() != 3) ctx.fail(key, "must be a list of 3 numbers");
  Eigen::Vector3f v;
  try {
    for (int i = 0; i < 3; ++i) v[i] = value[i].as<float>();
  } catch (const YAML::Exception& e) {
    ctx.fail(key, std::string("must be a list of 3 numbers: ") + e.what());
  }
  return v;
}

constexpr double kDegToRad = M_PI / 180.0;

// Limits of the path keys (ego and objects; they also keep the pose integration finite).
constexpr double kMaxSpeedMps = 100.0;
constexpr double kMaxYawRateDegS = 360.0;
constexpr std::size_t kMaxPathSegments = 10000;

// Reads a number and checks lo <= value <= hi (and finite).
double getBounded(const YAML::Node& node, const std::string& key, const std::string& name,
                  double fallback, double lo, double hi, const Context& ctx) {
  const double value = get<double>(node, key, fallback, ctx);
  if (!std::isfinite(value) || value < lo || value > hi)
    ctx.fail(name, "must be in [" + std::to_string(lo) + ", " + std::to_string(hi) + "], got " +
                       std::to_string(value));
  return value;
}

void rejectUnknownKeys(const YAML::Node& node, const std::vector<std::string>& known,
                       const std::string& name, const Context& ctx) {
  for (const auto& entry : node) {
    if (!entry.first.IsScalar()) ctx.fail(name, "keys must be names");
    const std::string key = entry.first.Scalar();
    bool found = false;
    for (const std::string& k : known) found = found || k == key;
    if (!found) {
      std::string list;
      for (const std::string& k : known) list += (list.empty() ? "" : ", ") + k;
      ctx.fail(name + "." + key, "unknown key (known: " + list + ")");
    }
  }
}

// A path: a non-empty list of {duration_s, speed_mps, yaw_rate_deg_s (default 0), end_speed_mps
// (default speed_mps: the speed changes evenly to it over the segment)}.
std::vector<PathSegment> readSegments(const YAML::Node& segments, const std::string& name,
                                      const Context& ctx) {
  if (!segments.IsSequence() || segments.size() == 0)
    ctx.fail(name, "must be a non-empty list of {duration_s, speed_mps, yaw_rate_deg_s}");
  if (segments.size() > kMaxPathSegments)
    ctx.fail(name, "at most " + std::to_string(kMaxPathSegments) + " segments");
  std::vector<PathSegment> out;
  for (std::size_t i = 0; i < segments.size(); ++i) {
    const YAML::Node seg = segments[i];
    const std::string at = name + "[" + std::to_string(i) + "]";
    if (!seg.IsMap()) ctx.fail(at, "must be a mapping {duration_s, speed_mps, yaw_rate_deg_s}");
    rejectUnknownKeys(seg, {"duration_s", "speed_mps", "yaw_rate_deg_s", "end_speed_mps"}, at, ctx);
    for (const char* required : {"duration_s", "speed_mps"})
      if (!seg[required]) ctx.fail(at + "." + required, "missing");
    PathSegment e;
    e.duration_s = getBounded(seg, "duration_s", at + ".duration_s", 0.0, 0.0, 86400.0, ctx);
    if (!(e.duration_s > 0.0)) ctx.fail(at + ".duration_s", "must be > 0");
    e.speed_mps = getBounded(seg, "speed_mps", at + ".speed_mps", 0.0, 0.0, kMaxSpeedMps, ctx);
    e.yaw_rate_rad_s = kDegToRad * getBounded(seg, "yaw_rate_deg_s", at + ".yaw_rate_deg_s", 0.0,
                                              -kMaxYawRateDegS, kMaxYawRateDegS, ctx);
    e.end_speed_mps = getBounded(seg, "end_speed_mps", at + ".end_speed_mps", e.speed_mps, 0.0,
                                 kMaxSpeedMps, ctx);
    out.push_back(e);
  }
  return out;
}

SceneObject readObject(const YAML::Node& node, std::uint32_t default_id, const Context& ctx) {
  SceneObject o;
  o.id = get<std::uint32_t>(node, "id", default_id, ctx);
  o.type = get<std::string>(node, "type", "object", ctx);
  const std::string shape = get<std::string>(node, "shape", "box", ctx);
  if (shape == "box") o.shape = Shape::kBox;
  else if (shape == "cylinder") o.shape = Shape::kCylinder;
  else ctx.fail("objects[" + std::to_string(default_id) + "].shape", "box or cylinder, got " + shape);
  o.size = getVector(node, "size", o.size, ctx);
  o.yaw = get<float>(node, "yaw_deg", 0.0f, ctx) * static_cast<float>(M_PI / 180.0);
  o.position = getVector(node, "position", o.position, ctx);
  o.velocity = getVector(node, "velocity", o.velocity, ctx);
  if (const YAML::Node path = node["path"]) {
    const std::string name = "objects[" + std::to_string(default_id) + "].path";
    if (node["velocity"]) ctx.fail(name, "give either velocity or path, not both");
    o.path = readSegments(path, name, ctx);
  }
  o.start_s = get<double>(node, "start_s", o.start_s, ctx);
  o.stop_s = get<double>(node, "stop_s", o.stop_s, ctx);
  if ((o.size.array() <= 0.0f).any())
    ctx.fail("objects[" + std::to_string(default_id) + "].size", "every side must be > 0");
  if (o.stop_s < o.start_s)
    ctx.fail("objects[" + std::to_string(default_id) + "].stop_s", "must be >= start_s");
  return o;
}

// The ego block: `velocity` (constant, any direction), or `speed_mps` + `yaw_rate_deg_s` (one
// arc for the whole scenario), or `segments` (a list of them with durations). One of the three.
void readEgo(const YAML::Node& ego, Scenario& s, const Context& ctx) {
  if (!ego.IsMap()) ctx.fail("ego", "must be a mapping");
  rejectUnknownKeys(ego, {"frame", "velocity", "speed_mps", "yaw_rate_deg_s", "segments"}, "ego",
                    ctx);
  s.vehicle_frame = get<std::string>(ego, "frame", s.vehicle_frame, ctx);
  const int forms =
      (ego["velocity"] ? 1 : 0) + (ego["speed_mps"] ? 1 : 0) + (ego["segments"] ? 1 : 0);
  if (forms > 1)
    ctx.fail("ego", "give one of velocity, speed_mps (with yaw_rate_deg_s) or segments");
  if (ego["yaw_rate_deg_s"] && !ego["speed_mps"])
    ctx.fail("ego.yaw_rate_deg_s", "needs ego.speed_mps (or use ego.segments)");
  s.ego_velocity = getVector(ego, "velocity", s.ego_velocity, ctx);
  if (ego["speed_mps"]) {
    PathSegment one;
    one.duration_s = s.duration_s;  // the last segment continues anyway
    one.speed_mps = getBounded(ego, "speed_mps", "ego.speed_mps", 0.0, 0.0, kMaxSpeedMps, ctx);
    one.yaw_rate_rad_s = kDegToRad * getBounded(ego, "yaw_rate_deg_s", "ego.yaw_rate_deg_s", 0.0,
                                                -kMaxYawRateDegS, kMaxYawRateDegS, ctx);
    s.ego_segments.push_back(one);
  }
  if (const YAML::Node segments = ego["segments"])
    s.ego_segments = readSegments(segments, "ego.segments", ctx);
}

}  // namespace

Eigen::Isometry3f Scenario::vehiclePose(double t) const {
  Eigen::Isometry3f pose = Eigen::Isometry3f::Identity();
  if (ego_segments.empty()) {
    pose.translation() = ego_velocity * static_cast<float>(t);
    return pose;
  }
  const PlanarPose p = poseAlong(ego_segments, t);
  pose.linear() = Eigen::AngleAxisf(static_cast<float>(p.theta), Eigen::Vector3f::UnitZ()).matrix();
  pose.translation() = Eigen::Vector3f(static_cast<float>(p.x), static_cast<float>(p.y), 0.0f);
  return pose;
}

EgoTwist Scenario::vehicleTwist(double t) const {
  EgoTwist twist;
  if (ego_segments.empty()) {
    twist.linear = ego_velocity;  // the vehicle never turns: its axes are the world's
    return twist;
  }
  const PathSegment& seg = segmentAt(ego_segments, t);
  twist.linear = Eigen::Vector3f(static_cast<float>(speedAlong(ego_segments, t)), 0.0f, 0.0f);
  twist.yaw_rate = static_cast<float>(seg.yaw_rate_rad_s);
  return twist;
}

MeasuredTwist canTwist(const Scenario& s, double t, std::mt19937_64& rng) {
  constexpr double kScale = 1.01, kSpeedNoiseMps = 0.05, kGyroBiasRadS = 0.003, kGyroNoiseRadS = 0.01;
  std::normal_distribution<double> noise(0.0, 1.0);
  const EgoTwist truth = s.vehicleTwist(t);
  const double speed_noise = noise(rng), gyro_noise = noise(rng);
  // Wheels that stand still turn no encoder: the wheel speed reads exactly zero at rest.
  const double speed =
      truth.linear.x() == 0.0f ? 0.0 : kScale * truth.linear.x() + kSpeedNoiseMps * speed_noise;
  return measuredTwist(speed, truth.yaw_rate + kGyroBiasRadS + kGyroNoiseRadS * gyro_noise);
}

Eigen::Vector3f Scenario::vehicleVelocity(double t) const {
  return vehiclePose(t).linear() * vehicleTwist(t).linear;
}

std::size_t Scenario::frames() const {
  return static_cast<std::size_t>(std::floor(duration_s * rate_hz + 1e-9)) + 1;
}

Scenario loadScenario(const std::string& path) {
  const Context ctx{path};
  YAML::Node root;
  try {
    root = YAML::LoadFile(path);
  } catch (const YAML::Exception& e) {
    throw std::runtime_error(path + ": " + e.what());
  }
  if (!root.IsMap()) throw std::runtime_error(path + ": not a YAML mapping");

  Scenario s;
  s.name = get<std::string>(root, "name", path, ctx);
  s.description = get<std::string>(root, "description", "", ctx);
  s.duration_s = get<double>(root, "duration_s", s.duration_s, ctx);
  s.rate_hz = get<double>(root, "rate_hz", s.rate_hz, ctx);
  s.seed = get<std::uint64_t>(root, "seed", s.seed, ctx);
  s.profile = get<std::string>(root, "profile", s.profile, ctx);
  if (s.profile.empty()) ctx.fail("profile", "must name a vehicle profile (e.g. zebra)");
  // Bounded (found by test/fuzz/scenario_fuzzer.cpp): an infinite or huge duration made frames()
  // convert an out-of-range double to size_t (undefined behaviour) and the renderers loop forever.
  if (!(s.duration_s > 0.0 && s.duration_s <= 86400.0)) ctx.fail("duration_s", "must be in (0, 86400] s");
  if (!(s.rate_hz > 0.0 && s.rate_hz <= 100.0)) ctx.fail("rate_hz", "must be in (0, 100]");

  if (const YAML::Node sensor = root["sensor"]) {
    s.lidar = get<std::string>(sensor, "model", s.lidar, ctx);
    s.sensor_frame = get<std::string>(sensor, "frame", s.sensor_frame, ctx);
    const Eigen::Vector3f xyz = getVector(sensor, "mount_xyz", Eigen::Vector3f::Zero(), ctx);
    const Eigen::Vector3f rpy =
        getVector(sensor, "mount_rpy_deg", Eigen::Vector3f::Zero(), ctx) * static_cast<float>(M_PI / 180.0);
    s.sensor_mount = Eigen::Translation3f(xyz) *
                     Eigen::AngleAxisf(rpy.z(), Eigen::Vector3f::UnitZ()) *
                     Eigen::AngleAxisf(rpy.y(), Eigen::Vector3f::UnitY()) *
                     Eigen::AngleAxisf(rpy.x(), Eigen::Vector3f::UnitX());
  }
  try {
    LidarModel::byName(s.lidar);
  } catch (const std::exception& e) {
    ctx.fail("sensor.model", e.what());
  }
  if (const YAML::Node ego = root["ego"]) readEgo(ego, s, ctx);
  if (const YAML::Node noise = root["noise"]) {
    s.noise.range_std_m = get<float>(noise, "range_std_m", 0.0f, ctx);
    s.noise.dropout_prob = get<float>(noise, "dropout_prob", 0.0f, ctx);
    s.noise.spurious_prob = get<float>(noise, "spurious_prob", 0.0f, ctx);
    if (s.noise.range_std_m < 0.0f) ctx.fail("noise.range_std_m", "must be >= 0");
    for (float p : {s.noise.dropout_prob, s.noise.spurious_prob})
      if (p < 0.0f || p > 1.0f) ctx.fail("noise", "probabilities must be in [0, 1]");
  }
  s.scene.has_ground = get<bool>(root, "ground", true, ctx);
  if (const YAML::Node objects = root["objects"]) {
    if (!objects.IsSequence()) ctx.fail("objects", "must be a list");
    for (std::size_t i = 0; i < objects.size(); ++i)
      s.scene.objects.push_back(readObject(objects[i], static_cast<std::uint32_t>(i + 1), ctx));
  }
  return s;
}

std::string profilePath(const std::string& scenario_path, const std::string& profile) {
  const std::size_t slash = scenario_path.rfind('/');
  const std::string dir = slash == std::string::npos ? "." : scenario_path.substr(0, slash);
  const std::string suffix = ".yaml";
  const bool is_file = profile.size() > suffix.size() &&
                       profile.compare(profile.size() - suffix.size(), suffix.size(), suffix) == 0;
  if (!is_file) return dir + "/../" + profile + suffix;
  if (!profile.empty() && profile[0] == '/') return profile;
  return dir + "/" + profile;
}

}  // namespace sim
}  // namespace icanc
