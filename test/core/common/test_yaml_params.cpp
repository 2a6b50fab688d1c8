// The shipped vehicle profiles load and validate, carry the paper's values, and a bad value is
// reported with its file and key.
#include <cstdio>
#include <fstream>
#include <stdexcept>

#include <iterator>
#include <map>
#include <set>
#include <sstream>

#include <gtest/gtest.h>
#include <unistd.h>
#include <yaml-cpp/yaml.h>

#include "icanc/core/common/param_keys.hpp"
#include "icanc/core/common/yaml_params.hpp"

namespace icanc {
namespace {


std::string configDir() {
  // The source tree's config/ (tests run from the build tree; the macro points next to it).
  const std::string here = __FILE__;
  return here.substr(0, here.rfind("/test/core/")) + "/config/";
}

TEST(Profiles, ShippedProfilesCarryThePapersValues) {
  const Profile zebra = loadProfile(configDir() + "zebra.yaml");
  EXPECT_DOUBLE_EQ(zebra.danger.half_width_m, 0.7);
  EXPECT_DOUBLE_EQ(zebra.danger.reaction_time_s, 3.0);
  EXPECT_DOUBLE_EQ(zebra.light.tau_s, 3.0);
  EXPECT_FLOAT_EQ(zebra.detector.prep.voxel_leaf_m, 0.2f);
  EXPECT_EQ(zebra.detector.ground.max_iterations, 30);
  EXPECT_FLOAT_EQ(zebra.detector.ground.distance_threshold_m, 0.3f);
  EXPECT_FLOAT_EQ(zebra.detector.cluster.tolerance_m, 0.6f);
  EXPECT_EQ(zebra.detector.cluster.min_points, 10);
  EXPECT_EQ(zebra.detector.cluster.max_points, 5000);
  EXPECT_EQ(zebra.detector.tracker.anchor, TrackAnchor::kNearestFace);
  EXPECT_FLOAT_EQ(zebra.detector.prep.roi_max.x(), 30.0f);
  EXPECT_FALSE(zebra.light.illumination_enabled);  // the paper unless launched with a camera
  EXPECT_DOUBLE_EQ(zebra.light.illumination_stale_timeout_s, 1.0);
  EXPECT_DOUBLE_EQ(zebra.illumination.dark_at, 0.15);
  EXPECT_DOUBLE_EQ(zebra.illumination.bright_at, 0.30);
  EXPECT_DOUBLE_EQ(zebra.illumination.min_dwell_s, 2.0);

  const Profile carla = loadProfile(configDir() + "carla_model3.yaml");
  EXPECT_DOUBLE_EQ(carla.danger.half_width_m, 1.2);
  EXPECT_DOUBLE_EQ(carla.danger.reaction_time_s, 2.0);
  EXPECT_DOUBLE_EQ(carla.light.tau_s, 2.0);

  const Profile kitti = loadProfile(configDir() + "kitti_hdl64e.yaml");
  // The footprint margin is each profile's measured box bias (README: Predictive danger model):
  // KITTI's labelled boxes reach 0.19-0.25 m beyond what the HDL-64E sees (the cyclist's sides
  // 0.28-0.35 m: docs/evaluation.md), the simulator's 0-0.07.
  EXPECT_DOUBLE_EQ(kitti.danger.footprint_margin_m, 0.3);
  EXPECT_DOUBLE_EQ(zebra.danger.footprint_margin_m, 0.0);
  EXPECT_DOUBLE_EQ(carla.danger.footprint_margin_m, 0.05);
  // Where each profile's target frame has the road: base_link on it, KITTI's
  // velodyne frame 1.73 m above it.
  EXPECT_FLOAT_EQ(zebra.detector.ground.expected_height_m, 0.0f);
  EXPECT_FLOAT_EQ(carla.detector.ground.expected_height_m, 0.0f);
  EXPECT_FLOAT_EQ(kitti.detector.ground.expected_height_m, -1.73f);
  for (const Profile* p : {&zebra, &carla, &kitti}) {
    // The paper's single lamp (segments [] = one segment, every direction).
    EXPECT_TRUE(p->lamp.segments.empty());
    EXPECT_EQ(effectiveSegments(p->lamp).size(), 1u);
    EXPECT_DOUBLE_EQ(p->lamp.segment_margin_deg, 2.0);
    EXPECT_DOUBLE_EQ(p->lamp.low_beam_below_m, 15.0);
    EXPECT_DOUBLE_EQ(p->lamp.full_power_range_m, 0.0);  // no dimming: the paper's on / off lamp
    EXPECT_DOUBLE_EQ(p->lamp.min_level, 0.05);
    // The headlight at the vehicle's front, one centred unit (not at base_link's origin).
    EXPECT_FLOAT_EQ(p->lamp.lamp_position_m.x(), float(p->corridor.vehicle_front_m));
    EXPECT_FLOAT_EQ(p->lamp.lamp_position_m.y(), 0.0f);
    EXPECT_DOUBLE_EQ(p->danger.vehicle_front_m, p->corridor.vehicle_front_m);
    EXPECT_FLOAT_EQ(p->detector.ground.max_height_error_m, 0.5f);
    EXPECT_FLOAT_EQ(p->detector.footprint_cell_m, 1.0f);
    EXPECT_DOUBLE_EQ(p->detector.tracker.accel_std, 3.0);
    EXPECT_DOUBLE_EQ(p->detector.tracker.steady_accel_std, 0.05);
  }
}

// Writes `yaml` to `path` and expects loadProfile to refuse it with a message holding `key`.
void expectRefused(const std::string& path, const std::string& yaml, const std::string& key,
                   const char* what) {
  std::ofstream(path) << yaml;
  try {
    loadProfile(path);
    ADD_FAILURE() << what << " was accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(key), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
  }
}

TEST(Profiles, BadValueNamesFileAndKey) {
  const std::string path = ::testing::TempDir() + "icanc_bad_profile_" + std::to_string(::getpid()) + ".yaml";
  expectRefused(path, "danger_detector:\n  half_width_m: -1.0\n", "half_width_m", "a negative half width");
  expectRefused(path, "obstacle_detector:\n  prep:\n    roi_min: [1, 2]\n", "prep/roi_min",
                "a two-element roi_min");
  expectRefused(path, "obstacle_detector:\n  tracker:\n    anchor: middle\n", "tracker.anchor",
                "an unknown tracker anchor");
  expectRefused(path,
                "light_controller:\n  segments:\n    - {azimuth_min_deg: -10, azimuth_max_deg: 10, watts: 3}\n"
                "    - {azimuth_min_deg: 10, azimuth_max_deg: 30, wats: 3}\n",
                "segments[1]: unknown key 'wats'", "a misspelt segment key");
  expectRefused(path, "light_controller:\n  segments:\n    - {azimuth_min_deg: 10, azimuth_max_deg: -10, watts: 3}\n",
                "segments[0].azimuth_min_deg", "a segment with min > max");
  std::ofstream(path) << "light_controller:\n  segments:\n"
                         "    - {azimuth_min_deg: -90, azimuth_max_deg: 0, watts: 3, low_watts: 2}\n"
                         "    - {azimuth_min_deg: 0, azimuth_max_deg: 90, watts: 3}\n";
  const Profile two = loadProfile(path);
  ASSERT_EQ(two.lamp.segments.size(), 2u);
  EXPECT_DOUBLE_EQ(two.lamp.segments[0].low_watts, 2.0);
  EXPECT_DOUBLE_EQ(two.lamp.segments[1].azimuth_max_deg, 90.0);
  // A lamp with a low beam cannot also dim by distance.
  expectRefused(path, "light_controller:\n  full_power_range_m: 20\n  segments:\n"
                "    - {azimuth_min_deg: -10, azimuth_max_deg: 10, watts: 3, low_watts: 2}\n",
                "segments[0].low_watts", "a low beam with dimming");
  expectRefused(path, "light_controller:\n  min_level: 0\n", "min_level", "a zero dimming floor");
  std::remove(path.c_str());
}

// Every value loadProfile reads, as text, by "section/key" (the visitParams keys).
class ProfileDump {
 public:
  explicit ProfileDump(Profile p) {
    section_ = "obstacle_detector/";
    visitParams(*this, p.detector);
    section_ = "danger_detector/";
    visitParams(*this, p.danger);
    section_ = "light_controller/";
    visitParams(*this, p.light);
    visitParams(*this, p.lamp);
    section_ = "ground_truth/";
    visitParams(*this, p.corridor);
    section_ = "illumination_monitor/";
    visitParams(*this, p.illumination);
    section_ = "lidar_odometry/";
    visitParams(*this, p.lidar_odometry);
  }
  template <class T>
  void operator()(const std::string& key, T& value) {
    std::ostringstream text;
    text << value;
    values_[section_ + key] = text.str();
  }
  void operator()(const std::string& key, Eigen::Vector3f& v) {
    (*this)(key + "/x", v.x());
    (*this)(key + "/y", v.y());
    (*this)(key + "/z", v.z());
  }
  void operator()(const std::string& key, std::vector<LampSegment>& segments) {
    values_[section_ + key] = std::to_string(segments.size()) + " segments";
  }
  const std::map<std::string, std::string>& values() const { return values_; }
  bool hasKey(const std::string& key) const {
    return values_.count(key) || values_.count(key + "/x");
  }

 private:
  std::string section_;
  std::map<std::string, std::string> values_;
};

// The leaves of a YAML map as "a/b/c" paths.
void leaves(const YAML::Node& node, const std::string& prefix, std::vector<std::string>& out) {
  for (const auto& kv : node) {
    const std::string path = prefix + kv.first.as<std::string>();
    if (kv.second.IsMap())
      leaves(kv.second, path + "/", out);
    else
      out.push_back(path);
  }
}

// The profile's YAML without one leaf, written to `path`.
void writeWithout(const std::string& profile, const std::string& leaf, const std::string& path) {
  YAML::Node root = YAML::LoadFile(profile);
  std::istringstream parts(leaf);
  std::vector<std::string> names;
  for (std::string part; std::getline(parts, part, '/');) names.push_back(part);
  std::vector<YAML::Node> chain{root};
  for (std::size_t i = 0; i + 1 < names.size(); ++i) chain.push_back(chain.back()[names[i]]);
  chain.back().remove(names.back());
  std::ofstream(path) << root;
}

// A profile holds what a vehicle must set and what differs from the code's defaults, nothing
// else: every key loadProfile reads that a profile sets changes what it loads (the detector and
// the danger model are named as choices either way), and each profile stays within 40 keys (the
// frames and the ego-motion source read by the nodelets included).
TEST(Profiles, ShippedProfilesSetOnlyWhatDiffersFromTheDefaults) {
  const ProfileDump defaults{Profile()};
  const std::string scratch =
      ::testing::TempDir() + "icanc_profile_without_" + std::to_string(::getpid()) + ".yaml";
  for (const char* name : {"zebra.yaml", "carla_model3.yaml", "kitti_hdl64e.yaml"}) {
    const std::string path = configDir() + name;
    const ProfileDump full{loadProfile(path)};
    std::vector<std::string> keys;
    leaves(YAML::LoadFile(path), "", keys);
    EXPECT_LE(keys.size(), 40u) << name;
    int read_by_load = 0;
    for (const std::string& key : keys) {
      if (!defaults.hasKey(key)) continue;  // a nodelet's own key (frames, topics, ego_motion)
      if (key == "obstacle_detector/method" || key == "danger_detector/model") continue;  // choices
      ++read_by_load;
      writeWithout(path, key, scratch);
      EXPECT_NE(ProfileDump(loadProfile(scratch)).values(), full.values())
          << name << ": " << key << " is the code's default, leave it out";
    }
    EXPECT_GT(read_by_load, 10) << name;
  }
  std::remove(scratch.c_str());
}

// docs/parameters.md (the LiDAR odometry's in docs/lidar_odometry.md) names every key.
TEST(Profiles, TheParameterReferenceNamesEveryKey) {
  const std::string docs = configDir() + "../docs/";
  std::string text;
  for (const char* file : {"parameters.md", "lidar_odometry.md"}) {
    std::ifstream in(docs + file);
    ASSERT_TRUE(in) << docs + file;
    text += std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  std::set<std::string> missing;
  const ProfileDump defaults{Profile()};
  for (const auto& kv : defaults.values()) {
    std::string key = kv.first.substr(kv.first.find('/') + 1);
    for (const char* axis : {"/x", "/y", "/z"})
      if (key.size() > 2 && key.compare(key.size() - 2, 2, axis) == 0) key.resize(key.size() - 2);
    const std::string leaf = key.substr(key.rfind('/') + 1);
    const std::string full = kv.first.substr(0, kv.first.find('/') + 1) + key;
    if (text.find("`" + full + "`") == std::string::npos && text.find("`" + key + "`") == std::string::npos &&
        text.find("`" + leaf + "`") == std::string::npos)
      missing.insert(kv.first);
  }
  EXPECT_TRUE(missing.empty()) << "not in docs/parameters.md: " << ::testing::PrintToString(missing);
}

}  // namespace
}  // namespace icanc
