// FreeSpaceMotion: returns where earlier rays passed through read moving, returns on surfaces seen
// before read static, on a small ray-cast scene seen from a vehicle that drives or stands.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "icanc/core/motion/free_space.hpp"

namespace icanc {
namespace {

struct WorldBox {
  Eigen::Vector3f min, max;  // in the world frame [m]
};

// The scene: the road 1.7 m below the sensor, a wall along y = -6 and the boxes; the sensor at
// the vehicle frame's origin, the vehicle at (x, 0) in the world looking along +x.
struct Scene {
  std::vector<WorldBox> boxes;
  float wall_y = -6.0f;

  // Every return of a sweep (azimuth +-90 deg every 0.2, elevation -16..4 every 0.4), in the
  // vehicle frame.
  template <class Sink>
  void sweep(float vehicle_x, Sink&& sink) const {
    for (float az = -90.0f; az <= 90.0f; az += 0.2f) {
      for (float el = -16.0f; el <= 4.0f; el += 0.4f) {
        const float a = az * static_cast<float>(M_PI) / 180.0f;
        const float e = el * static_cast<float>(M_PI) / 180.0f;
        const Eigen::Vector3f dir(std::cos(e) * std::cos(a), std::cos(e) * std::sin(a), std::sin(e));
        const Eigen::Vector3f origin(vehicle_x, 0.0f, 0.0f);
        float t = std::numeric_limits<float>::infinity();
        if (dir.z() < 0.0f) t = std::min(t, -1.7f / dir.z());
        if (dir.y() < 0.0f) t = std::min(t, (wall_y - origin.y()) / dir.y());
        for (const WorldBox& b : boxes) t = std::min(t, hit(origin, dir, b));
        if (t > 80.0f) continue;
        const Eigen::Vector3f p = origin + t * dir;
        sink(p.x() - vehicle_x, p.y(), p.z());
      }
    }
  }

  static float hit(const Eigen::Vector3f& o, const Eigen::Vector3f& d, const WorldBox& b) {
    float t0 = 0.0f, t1 = std::numeric_limits<float>::infinity();
    for (int i = 0; i < 3; ++i) {
      if (std::abs(d[i]) < 1e-9f) {
        if (o[i] < b.min[i] || o[i] > b.max[i]) return std::numeric_limits<float>::infinity();
        continue;
      }
      float a = (b.min[i] - o[i]) / d[i], c = (b.max[i] - o[i]) / d[i];
      if (a > c) std::swap(a, c);
      t0 = std::max(t0, a);
      t1 = std::min(t1, c);
    }
    return t0 <= t1 ? t0 : std::numeric_limits<float>::infinity();
  }
};

Box3D boxAt(const WorldBox& b, float vehicle_x) {
  Box3D box;
  box.min = b.min - Eigen::Vector3f(vehicle_x, 0.0f, 0.0f);
  box.max = b.max - Eigen::Vector3f(vehicle_x, 0.0f, 0.0f);
  box.center = 0.5f * (box.min + box.max);
  box.size = box.max - box.min;
  return box;
}

// Runs frames at 10 Hz with the vehicle at speed_mps along +x; each frame the scene is built by
// `at(k)` and its boxes evaluated; returns the evidence of box `which` on each frame.
template <class SceneAt>
std::vector<MotionEvidence> run(int frames, float speed_mps, SceneAt&& at, std::size_t which = 0) {
  FreeSpaceMotion motion;
  std::vector<MotionEvidence> out;
  for (int k = 0; k < frames; ++k) {
    const float x = speed_mps * 0.1f * k;
    const Scene scene = at(k);
    Eigen::Isometry3d step = Eigen::Isometry3d::Identity();
    step.translation() = Eigen::Vector3d(-speed_mps * 0.1, 0.0, 0.0);  // p_now = step * p_prev
    motion.beginFrame(0.1 * k, k == 0 ? Eigen::Isometry3d::Identity() : step, Eigen::Vector3f::Zero());
    scene.sweep(x, [&](float px, float py, float pz) { motion.addPoint(px, py, pz); });
    std::vector<Box3D> boxes;
    for (const WorldBox& b : scene.boxes) boxes.push_back(boxAt(b, x));
    motion.evaluate(boxes);
    motion.endFrame();
    out.push_back(boxes.at(which).motion);
  }
  return out;
}

const WorldBox kParked{{15.0f, -4.0f, -1.6f}, {19.5f, -2.2f, -0.2f}};

TEST(FreeSpaceMotion, NoHistoryNoEvidence) {
  const auto e = run(1, 0.0f, [](int) { Scene s; s.boxes = {kParked}; return s; });
  EXPECT_EQ(e[0].tested, 0);
  EXPECT_EQ(e[0].state(), MotionState::kUnknown);
}

TEST(FreeSpaceMotion, ParkedCarStandsWhileTheVehicleDrives) {
  const auto e = run(10, 10.0f, [](int) { Scene s; s.boxes = {kParked}; return s; });
  for (int k = 2; k < 10; ++k) {
    EXPECT_EQ(e[k].state(), MotionState::kStatic) << "frame " << k;
    EXPECT_EQ(e[k].free, 0) << "frame " << k;
    EXPECT_GT(e[k].tested, 20) << "frame " << k;
  }
}

TEST(FreeSpaceMotion, WalkerCrossingReadsMoving) {
  // A pedestrian 12 m ahead walking across at 1.4 m/s while the vehicle drives at 5 m/s.
  const auto at = [](int k) {
    Scene s;
    const float y = -3.0f + 0.14f * k;
    s.boxes = {{{12.0f, y - 0.25f, -1.7f}, {12.4f, y + 0.25f, 0.0f}}};
    return s;
  };
  const auto e = run(8, 5.0f, at);
  for (int k = 2; k < 8; ++k) EXPECT_EQ(e[k].state(), MotionState::kMoving) << "frame " << k;
}

TEST(FreeSpaceMotion, WalkerComingTowardTheSensorReadsMoving) {
  const auto at = [](int k) {
    Scene s;
    const float x = 14.0f - 0.15f * k;
    s.boxes = {{{x, -0.3f, -1.7f}, {x + 0.4f, 0.3f, 0.0f}}};
    return s;
  };
  // Along its own rays it must have come nearer than the tolerance (0.3 m plus two pixels' width
  // at its range): from the fourth frame on, against the image 0.4 s old.
  const auto e = run(8, 0.0f, at);
  for (int k = 4; k < 8; ++k) EXPECT_EQ(e[k].state(), MotionState::kMoving) << "frame " << k;
}

TEST(FreeSpaceMotion, CarDrivingAwayAheadIsNotStatic) {
  // A car ahead keeping its distance: its rear lies behind where the rays ended before, which
  // says nothing; it must not read static (the swept-path rule would flag it).
  const auto at = [](int k) {
    Scene s;
    const float x = 15.0f + 1.0f * k;  // 10 m/s, as the vehicle
    s.boxes = {{{x, -0.9f, -1.7f}, {x + 4.5f, 0.9f, -0.2f}}};
    return s;
  };
  const auto e = run(8, 10.0f, at);
  for (int k = 2; k < 8; ++k) {
    EXPECT_NE(e[k].state(), MotionState::kStatic) << "frame " << k;
    EXPECT_EQ(e[k].free, 0) << "frame " << k;
  }
}

TEST(FreeSpaceMotion, EgoBoxAndNonFiniteReturnsAreSkipped) {
  FreeSpaceMotion motion;
  motion.setEgoBox(Eigen::Vector3f(-2.0f, -1.0f, -2.0f), Eigen::Vector3f(2.0f, 1.0f, 0.5f));
  for (int k = 0; k < 4; ++k) {
    motion.beginFrame(0.1 * k, Eigen::Isometry3d::Identity(), Eigen::Vector3f::Zero());
    // The vehicle's own body, right in front of the box's rays, then NaN: neither hides the box.
    if (k == 3) {
      motion.addPoint(1.0f, 0.0f, 0.0f);
      motion.addPoint(std::numeric_limits<float>::quiet_NaN(), 0.0f, 0.0f);
    }
    Scene s;
    s.boxes = {{{8.0f, -0.3f, -1.7f}, {8.4f, 0.3f, 0.0f}}};
    s.sweep(0.0f, [&](float x, float y, float z) { motion.addPoint(x, y, z); });
    std::vector<Box3D> boxes{boxAt(s.boxes[0], 0.0f)};
    motion.setCollectFree(true);
    motion.evaluate(boxes);
    motion.endFrame();
    if (k == 3) {
      EXPECT_EQ(boxes[0].motion.state(), MotionState::kStatic);
      EXPECT_TRUE(motion.freePoints().empty());
    }
  }
}

TEST(FreeSpaceMotion, TimeGoingBackwardsForgetsTheImages) {
  FreeSpaceMotion motion;
  Scene s;
  s.boxes = {kParked};
  const auto frame = [&](double t) {
    motion.beginFrame(t, Eigen::Isometry3d::Identity(), Eigen::Vector3f::Zero());
    s.sweep(0.0f, [&](float x, float y, float z) { motion.addPoint(x, y, z); });
    std::vector<Box3D> boxes{boxAt(kParked, 0.0f)};
    motion.evaluate(boxes);
    motion.endFrame();
    return boxes[0].motion;
  };
  for (int k = 0; k < 4; ++k) frame(10.0 + 0.1 * k);
  EXPECT_GT(frame(10.4).tested, 0);
  EXPECT_EQ(frame(0.0).tested, 0);  // a replay restarted: nothing to compare with
}

TEST(MotionEvidence, StateFromCounts) {
  EXPECT_EQ((MotionEvidence{40, 2, 30}).state(), MotionState::kStatic);
  EXPECT_EQ((MotionEvidence{40, 8, 20}).state(), MotionState::kMoving);
  EXPECT_EQ((MotionEvidence{40, 4, 10}).state(), MotionState::kUnknown);  // neither
  EXPECT_EQ((MotionEvidence{10, 2, 8}).state(), MotionState::kUnknown);   // two free: sampling
  EXPECT_EQ((MotionEvidence{0, 0, 0}).state(), MotionState::kUnknown);
}

TEST(FreeSpaceParams, Validate) {
  EXPECT_EQ(validate(FreeSpaceParams()), "");
  FreeSpaceParams p;
  p.azimuth_step_deg = 0.0f;
  EXPECT_NE(validate(p).find("azimuth_step_deg"), std::string::npos);
  p = FreeSpaceParams();
  p.tolerance_m = 0.0f;
  EXPECT_NE(validate(p).find("tolerance_m"), std::string::npos);
}

}  // namespace
}  // namespace icanc
