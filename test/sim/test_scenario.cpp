// Scenario files load with their motion and sensor mount; mistakes are reported by key.
#include <cstdio>
#include <fstream>
#include <stdexcept>

#include <gtest/gtest.h>

#include "icanc/sim/scenario.hpp"

namespace icanc {
namespace sim {
namespace {

std::string repoPath(const std::string& rel) {
  const std::string here = __FILE__;
  return here.substr(0, here.rfind("/test/sim/")) + "/" + rel;
}

std::string writeTemp(const std::string& text) {
  const std::string path = ::testing::TempDir() + "icanc_scenario_test.yaml";
  std::ofstream(path) << text;
  return path;
}

TEST(Scenario, ShippedPedestrianApproachLoads) {
  const Scenario s = loadScenario(repoPath("config/scenarios/pedestrian_approach.yaml"));
  EXPECT_EQ(s.lidar, "robosense_m1");
  EXPECT_EQ(s.frames(), 161u);  // 16 s at 10 Hz, both ends
  ASSERT_EQ(s.scene.objects.size(), 4u);
  const SceneObject& walker = s.scene.objects[0];
  EXPECT_EQ(walker.type, "pedestrian");
  EXPECT_EQ(walker.shape, Shape::kCylinder);
  EXPECT_NEAR(walker.positionAt(9.0).x(), 3.0, 1e-5);   // stops 3 m ahead
  EXPECT_NEAR(walker.positionAt(15.0).x(), 3.0, 1e-5);
  EXPECT_NEAR(s.sensorPose(0.0).translation().z(), 0.6, 1e-6);
  EXPECT_NEAR(s.scene.objects[2].yaw, 20.0 * M_PI / 180.0, 1e-6);
}

TEST(Scenario, EgoMotionMovesTheSensor) {
  const Scenario s = loadScenario(writeTemp(
      "duration_s: 2\nsensor: {model: vlp16, mount_xyz: [1, 0, 1.5]}\nego: {velocity: [10, 0, 0]}\n"));
  EXPECT_NEAR(s.sensorPose(1.5).translation().x(), 16.0, 1e-5);
  EXPECT_NEAR(s.sensorPose(1.5).translation().z(), 1.5, 1e-5);
}

TEST(Scenario, MistakesNameTheKey) {
  const auto error = [](const std::string& yaml) {
    try {
      loadScenario(writeTemp(yaml));
    } catch (const std::runtime_error& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_NE(error("sensor: {model: hdl65}\n").find("sensor.model"), std::string::npos);
  EXPECT_NE(error("duration_s: -1\n").find("duration_s"), std::string::npos);
  EXPECT_NE(error("objects:\n  - {shape: cone}\n").find("shape"), std::string::npos);
  EXPECT_NE(error("objects:\n  - {size: [1, 0, 1]}\n").find("size"), std::string::npos);
  EXPECT_NE(error("objects:\n  - {position: [1, 2]}\n").find("position"), std::string::npos);
  EXPECT_NE(error("noise: {dropout_prob: 2}\n").find("noise"), std::string::npos);
  EXPECT_NE(error("[1, 2]\n").find("mapping"), std::string::npos);
}

}  // namespace
}  // namespace sim
}  // namespace icanc
