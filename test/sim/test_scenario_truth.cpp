// Pins the scenarios' ground truth (what icanc_sim_bag writes on /ground_truth): when each shipped
// scenario's objects are truly dangerous, relative velocities, points inside the true boxes, and
// that the trajectories come from the scripted motion, finer than the frames and past the end.
#include <map>
#include <random>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

#include "icanc/core/common/yaml_params.hpp"
#include "icanc/sim/lidar_sim.hpp"
#include "icanc/sim/scenario.hpp"
#include "icanc/sim/scenario_truth.hpp"

namespace icanc {
namespace sim {
namespace {

std::string repoPath(const std::string& rel) {
  const std::string here = __FILE__;
  return here.substr(0, here.rfind("/test/sim/")) + "/" + rel;
}

struct Danger {
  std::size_t frames = 0;
  double first = -1.0, last = -1.0;
};

struct Summary {
  std::size_t frames = 0;
  std::string profile;
  std::map<std::uint32_t, Danger> dangerous;  // only ids that are dangerous in some frame
  std::size_t total() const {
    std::size_t n = 0;
    for (const auto& d : dangerous) n += d.second.frames;
    return n;
  }
};

Summary summarise(const std::string& name) {
  const std::string path = repoPath("config/scenarios/" + name + ".yaml");
  const Scenario s = loadScenario(path);
  const ScenarioTruth truth(s, loadProfile(profilePath(path, s.profile)).corridor);
  Summary out;
  out.frames = s.frames();
  out.profile = s.profile;
  for (std::size_t k = 0; k < s.frames(); ++k) {
    const FrameTruth f = truth.frame(static_cast<double>(k) / s.rate_hz);
    for (std::size_t i = 0; i < f.boxes.size(); ++i) {
      if (f.labels[i].in_corridor) {
        EXPECT_TRUE(f.labels[i].dangerous) << name << " t " << f.t;
      }
      if (!f.labels[i].dangerous) continue;
      Danger& d = out.dangerous[f.boxes[i].id];
      if (d.frames++ == 0) d.first = f.t;
      d.last = f.t;
    }
  }
  return out;
}

void expectDanger(const Summary& s, std::uint32_t id, std::size_t frames, double first, double last) {
  ASSERT_EQ(s.dangerous.count(id), 1u) << "id " << id << " never dangerous";
  const Danger& d = s.dangerous.at(id);
  EXPECT_EQ(d.frames, frames) << "id " << id;
  EXPECT_NEAR(d.first, first, 1e-6) << "id " << id;
  EXPECT_NEAR(d.last, last, 1e-6) << "id " << id;
}

// The times below are the ones each scenario file's comment states.
TEST(ScenarioTruth, PedestrianNearTowardIsDangerousFromThreeSecondsBeforeTheCorridor) {
  const Summary s = summarise("pedestrian_near_toward");
  EXPECT_EQ(s.profile, "zebra");
  EXPECT_EQ(s.frames, 101u);
  EXPECT_EQ(s.dangerous.size(), 1u);  // the pedestrian only: bin, chair and wall never
  expectDanger(s, 1, 88, 1.3, 10.0);
}

TEST(ScenarioTruth, PedestriansMovingAwayOrCrossingFarAreNeverDangerous) {
  for (const char* name : {"pedestrian_far_away", "pedestrian_near_away",
                           "pedestrian_far_perpendicular", "pedestrian_approach"}) {
    const Summary s = summarise(name);
    EXPECT_EQ(s.total(), 0u) << name;
  }
}

TEST(ScenarioTruth, ZebraScenariosWithDanger) {
  Summary s = summarise("pedestrian_far_toward");
  EXPECT_EQ(s.dangerous.size(), 1u);
  expectDanger(s, 1, 64, 7.7, 14.0);
  s = summarise("pedestrian_near_perpendicular");
  EXPECT_EQ(s.dangerous.size(), 1u);
  expectDanger(s, 1, 51, 0.3, 5.3);
  s = summarise("indoor_cluttered_course");
  EXPECT_EQ(s.dangerous.size(), 2u);  // the weaving pedestrian and the table in the path
  expectDanger(s, 1, 46, 1.5, 6.0);
  expectDanger(s, 20, 38, 12.3, 16.0);
}

TEST(ScenarioTruth, NightRoadScenarios) {
  Summary s = summarise("night_oncoming_car");
  EXPECT_EQ(s.profile, "carla_model3");
  EXPECT_EQ(s.total(), 0u);
  s = summarise("night_pull_out");
  EXPECT_EQ(s.dangerous.size(), 1u);
  expectDanger(s, 1, 21, 5.5, 7.5);
  s = summarise("night_pedestrian_crossing");
  EXPECT_EQ(s.dangerous.size(), 1u);
  expectDanger(s, 1, 27, 1.8, 4.4);
  s = summarise("night_parked_cars");
  EXPECT_EQ(s.dangerous.size(), 1u);  // only the car sticking out into the path
  expectDanger(s, 1, 32, 9.1, 12.2);
}

// The turning scenarios: the truth follows the vehicle along its path.
TEST(ScenarioTruth, TurningRoadScenarios) {
  Summary s = summarise("night_bend_parked_cars");
  EXPECT_EQ(s.profile, "carla_model3");
  EXPECT_EQ(s.frames, 141u);
  EXPECT_EQ(s.total(), 0u);  // the parked cars and posts on the outside of the bend: never
  s = summarise("night_junction_turn_pedestrian");
  EXPECT_EQ(s.dangerous.size(), 1u);  // the pedestrian on the crossing of the side road only
  expectDanger(s, 1, 31, 5.4, 8.4);
  s = summarise("night_s_bend_oncoming");
  EXPECT_EQ(s.dangerous.size(), 1u);  // the broken-down car only, never the oncoming traffic
  expectDanger(s, 5, 32, 10.3, 13.4);
  s = summarise("night_town_street");  // façades, posts, trees, parked cars: never
  EXPECT_EQ(s.frames, 131u);
  EXPECT_EQ(s.dangerous.size(), 1u);  // the pedestrian stepping out between parked cars only
  expectDanger(s, 1, 24, 2.8, 5.1);
}

TEST(ScenarioTruth, RenderedFrameCountsPointsInTheTrueBoxesInTheVehicleFrame) {
  const std::string path = repoPath("config/scenarios/indoor_cluttered_course.yaml");
  const Scenario s = loadScenario(path);
  const ScenarioTruth truth(s, loadProfile(profilePath(path, s.profile)).corridor);
  const LidarModel model = LidarModel::byName(s.lidar);
  std::mt19937_64 rng(s.seed);
  Cloud scan;
  std::map<std::uint32_t, std::size_t> index;
  for (std::size_t i = 0; i < s.scene.objects.size(); ++i) index[s.scene.objects[i].id] = i;

  renderScan(s.scene, 5.0, s.sensorPose(5.0), model, s.noise, rng, scan);
  FrameTruth f = truth.frame(5.0, &scan);
  const TruthBox& walker = f.boxes[index[1]];
  EXPECT_NEAR(walker.center.x(), 5.0 - 0.4 * 3.0 - 0.5 * 5.0, 1e-4);  // relative to the Zebra
  EXPECT_NEAR(walker.center.z(), 0.85, 1e-4);
  EXPECT_NEAR(walker.velocity.x(), -0.4 - 0.5, 1e-5);  // world velocity minus the Zebra's
  EXPECT_NEAR(walker.velocity.y(), -0.9, 1e-5);
  EXPECT_GT(f.num_points[index[1]], 1000u);           // 1.3 m ahead
  EXPECT_TRUE(f.labels[index[1]].in_corridor);
  EXPECT_EQ(f.num_points[index[14]], 0u);             // the bin behind it is in its shadow
  EXPECT_NEAR(f.boxes[index[14]].velocity.x(), -0.5, 1e-6);  // static: minus the Zebra's speed

  renderScan(s.scene, 0.0, s.sensorPose(0.0), model, s.noise, rng, scan);
  f = truth.frame(0.0, &scan);
  EXPECT_GT(f.num_points[index[14]], 20u);            // the same bin, 11 m ahead, in view
  EXPECT_GT(f.num_points[index[1]], 100u);
  const FrameTruth no_scan = truth.frame(0.0);
  EXPECT_EQ(no_scan.num_points, std::vector<std::uint32_t>(s.scene.objects.size(), 0u));

  renderScan(s.scene, 14.0, s.sensorPose(14.0), model, s.noise, rng, scan);
  f = truth.frame(14.0, &scan);
  EXPECT_NEAR(f.boxes[index[1]].center.x(), -4.0, 1e-4);  // behind the forward-only M1
  EXPECT_EQ(f.num_points[index[1]], 0u);
}

// A scripted scene built in code: frames at 1 Hz for 2 s.
Scenario twoSecondScene() {
  Scenario s;
  s.duration_s = 2.0;
  s.rate_hz = 1.0;
  SceneObject fast;  // crosses x = 1.5 at 10 m/s in y between 0.3 s and 0.95 s, in no frame
  fast.id = 1;
  fast.type = "pedestrian";
  fast.shape = Shape::kCylinder;
  fast.position = Eigen::Vector3f(1.5f, 5.0f, 0.0f);
  fast.velocity = Eigen::Vector3f(0.0f, -10.0f, 0.0f);
  fast.start_s = 0.3;
  fast.stop_s = 0.95;  // ends at y = -1.5: out of the corridor
  s.scene.objects.push_back(fast);
  SceneObject late;  // approaches at 2 m/s from x = 10: enters after the last frame
  late.id = 2;
  late.type = "pedestrian";
  late.shape = Shape::kCylinder;
  late.position = Eigen::Vector3f(10.0f, 0.0f, 0.0f);
  late.velocity = Eigen::Vector3f(-2.0f, 0.0f, 0.0f);
  s.scene.objects.push_back(late);
  return s;
}

TEST(ScenarioTruth, TrajectoriesAreSampledFinerThanFramesAndPastTheEnd) {
  const Scenario s = twoSecondScene();
  CorridorParams c;  // |y| <= 1.0, 0 <= x <= 2.5, 3 s
  const ScenarioTruth truth(s, c);
  const FrameTruth f0 = truth.frame(0.0), f1 = truth.frame(1.0), f2 = truth.frame(2.0);
  // The fast walker's centre reaches y = 1.25 at 0.675 s: sample 0.68 s. Labelling from the
  // frames alone (y = 5, -1.5, -1.5) would miss it.
  EXPECT_TRUE(f0.labels[0].dangerous);
  EXPECT_NEAR(f0.labels[0].time_to_corridor, 0.68, 1e-6);
  EXPECT_FALSE(f1.labels[0].dangerous);
  std::vector<TruthBox> frames_only = {f0.boxes[0], f1.boxes[0], f2.boxes[0]};
  EXPECT_FALSE(labelTruths(frames_only, c)[0].dangerous);
  // The late walker enters when its centre reaches x = 2.75 at 3.625 s (sample 3.64 s), after the
  // 2 s scenario: the last frames are labelled from the scripted motion past the end.
  EXPECT_FALSE(f0.labels[1].dangerous);
  EXPECT_NEAR(f1.labels[1].time_to_corridor, 2.64, 1e-6);
  EXPECT_NEAR(f2.labels[1].time_to_corridor, 1.64, 1e-6);
  EXPECT_THROW((ScenarioTruth{s, c, 0.0}), std::invalid_argument);
  c.horizon_s = 0.0;
  EXPECT_THROW((ScenarioTruth{s, c}), std::invalid_argument);
}

// A vehicle on a left circle (10 m/s, 18 deg/s: R = 31.83 m about (0, R)) and two small static
// posts: one on its path 3 s ahead, one straight ahead of its start 25 m away.
Scenario turningScene() {
  Scenario s;
  s.duration_s = 4.0;
  s.rate_hz = 10.0;
  s.ego_segments.push_back({4.0, 10.0, M_PI / 10.0});
  const double r = 10.0 / (M_PI / 10.0), phi = 3.0 * M_PI / 10.0;
  SceneObject on_path;
  on_path.id = 1;
  on_path.type = "pole";
  on_path.shape = Shape::kCylinder;
  on_path.size = Eigen::Vector3f(0.1f, 0.1f, 1.0f);
  on_path.position =
      Eigen::Vector3f(float(r * std::sin(phi)), float(r * (1.0 - std::cos(phi))), 0.0f);
  s.scene.objects.push_back(on_path);
  SceneObject straight_ahead = on_path;
  straight_ahead.id = 2;
  straight_ahead.position = Eigen::Vector3f(25.0f, 0.0f, 0.0f);
  s.scene.objects.push_back(straight_ahead);
  return s;
}

TEST(ScenarioTruth, TurningVehicleIsJudgedAlongItsPath) {
  const Scenario s = turningScene();
  CorridorParams c;  // |y| <= 1.0, 0 <= x <= 2.5, 3 s
  const ScenarioTruth truth(s, c);
  const double r = 10.0 / (M_PI / 10.0);
  // The post on the path is 13 m to the side of the start heading, yet dangerous: the vehicle
  // reaches it at 3 s. It enters the corridor when its chord is 2.5 m + its half size, i.e. at
  // 3 s - R asin(2.55 / R) / 10 m/s (within a sample, 0.02 s).
  const FrameTruth f0 = truth.frame(0.0);
  EXPECT_GT(f0.boxes[0].center.y(), 13.0);
  EXPECT_TRUE(f0.labels[0].dangerous);
  EXPECT_NEAR(f0.labels[0].time_to_corridor, 3.0 - r * std::asin(2.55 / r) / 10.0, 0.025);
  // Straight ahead at 25 m: a straight-driving vehicle would reach it in 2.2 s, the turning one
  // passes 8 m beside it.
  for (std::size_t k = 0; k < s.frames(); ++k) {
    const FrameTruth f = truth.frame(static_cast<double>(k) / s.rate_hz);
    EXPECT_FALSE(f.labels[1].dangerous) << f.t;
  }
  // Boxes at t are in the vehicle frame at t: after a quarter circle (5 s: heading +y, at (R, R))
  // the straight-ahead post is behind-left and the posts' velocity is minus the vehicle's, in its
  // own axes, minus yaw rate x r (the frame turns).
  const std::vector<TruthBox> quarter = truthBoxes(s, 5.0);
  EXPECT_NEAR(quarter[1].center.x(), -r, 1e-3);
  EXPECT_NEAR(quarter[1].center.y(), -(25.0 - r), 1e-3);
  EXPECT_NEAR(quarter[1].yaw, -M_PI / 2.0, 1e-5);
  const double w = M_PI / 10.0;
  EXPECT_NEAR(quarter[1].velocity.x(), -10.0 + w * quarter[1].center.y(), 1e-3);
  EXPECT_NEAR(quarter[1].velocity.y(), -w * quarter[1].center.x(), 1e-3);
}

TEST(ScenarioTruth, ProfileResolvesBesideTheScenarioDirectory) {
  EXPECT_EQ(profilePath("config/scenarios/a.yaml", "zebra"), "config/scenarios/../zebra.yaml");
  EXPECT_EQ(profilePath("a.yaml", "carla_model3"), "./../carla_model3.yaml");
  EXPECT_EQ(profilePath("/x/s/a.yaml", "mine.yaml"), "/x/s/mine.yaml");
  EXPECT_EQ(profilePath("/x/s/a.yaml", "/p/q.yaml"), "/p/q.yaml");
  EXPECT_EQ(Scenario().profile, "zebra");
}

}  // namespace
}  // namespace sim
}  // namespace icanc
