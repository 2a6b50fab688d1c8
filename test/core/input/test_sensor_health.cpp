// SensorHealth: a LiDAR that returns NaN, (0, 0, 0), points on its own window or nothing in range
// is blind (lamp on), per frame and over a window, and healthy again when the returns come back;
// a sector under a cover, or whose returns vanish, is blind while the rest of the frame is fine.
#include <cmath>
#include <limits>
#include <functional>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "icanc/core/input/sensor_health.hpp"

namespace icanc {
namespace {

// An unorganized FLOAT32 x/y/z cloud of `points`.
struct Cloud3 {
  std::vector<float> xyz;
  RawCloud raw;
  DecodePlan plan;
  explicit Cloud3(const std::vector<Eigen::Vector3f>& points) {
    for (const auto& p : points) xyz.insert(xyz.end(), {p.x(), p.y(), p.z()});
    raw.width = points.size();
    raw.height = 1;
    raw.point_step = 12;
    raw.row_step = 12 * raw.width;
    raw.fields = {{"x", 0, 7, 1}, {"y", 4, 7, 1}, {"z", 8, 7, 1}};
    raw.data = reinterpret_cast<const std::uint8_t*>(xyz.data());
    raw.data_size = xyz.size() * sizeof(float);
    EXPECT_EQ(planDecode(raw, 1000000, plan), DecodeError::kNone);
  }
};

std::vector<Eigen::Vector3f> filled(std::size_t n, const Eigen::Vector3f& p) {
  return std::vector<Eigen::Vector3f>(n, p);
}

TEST(SensorHealth, CountsOnlyFiniteNonZeroReturnsInRange) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const SensorHealthParams params;  // 1 .. 250 m
  std::vector<Eigen::Vector3f> points = {
      {10.0f, 0.0f, 0.0f},   // valid
      {0.0f, 5.0f, -1.0f},   // valid
      {nan, 1.0f, 1.0f},     // NaN
      {0.0f, 0.0f, 0.0f},    // no return
      {0.05f, 0.0f, 0.0f},   // on the window
      {300.0f, 0.0f, 0.0f},  // beyond max range
      {1e30f, 0.0f, 0.0f},   // absurd
  };
  Cloud3 cloud(points);
  EXPECT_EQ(countValidReturns(cloud.raw, cloud.plan, params), 2u);
}

TEST(SensorHealth, AllNanAllZeroAllOutOfRangeAreBlindFrames) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const SensorHealthParams params;
  for (const Eigen::Vector3f& p : {Eigen::Vector3f(nan, nan, nan), Eigen::Vector3f(0, 0, 0),
                                   Eigen::Vector3f(0.01f, 0.02f, 0.0f), Eigen::Vector3f(900, 0, 0)}) {
    Cloud3 cloud(filled(1000, p));
    SensorHealth health(params);
    const std::size_t valid = countValidReturns(cloud.raw, cloud.plan, params);
    EXPECT_EQ(valid, 0u);
    EXPECT_TRUE(health.update(valid, 1000)) << p.transpose();
    EXPECT_EQ(health.frameShare(), 0.0);
  }
}

TEST(SensorHealth, HealthyFramesAreNotBlind) {
  SensorHealth health;
  for (int i = 0; i < 30; ++i) EXPECT_FALSE(health.update(900, 1000));
  EXPECT_NEAR(health.windowShare(), 0.9, 1e-12);
  EXPECT_EQ(health.blindFrames(), 0u);
}

TEST(SensorHealth, OneBlindFrameIsBlindAndTheNextGoodFrameIsNot) {
  SensorHealthParams params;
  params.window_frames = 10;
  SensorHealth health(params);
  for (int i = 0; i < 10; ++i) health.update(1000, 1000);
  EXPECT_TRUE(health.update(0, 1000));   // per frame: 0 < 5 %
  EXPECT_FALSE(health.update(1000, 1000));  // window mean 0.9
  EXPECT_EQ(health.blindEpisodes(), 1u);
}

TEST(SensorHealth, SlowDegradationIsCaughtByTheWindowAndRecovers) {
  SensorHealthParams params;
  params.min_frame_share = 0.05;
  params.min_window_share = 0.2;
  params.window_frames = 5;
  SensorHealth health(params);
  // 10 % of the returns each frame: above the per-frame threshold, below the window's.
  EXPECT_TRUE(health.update(100, 1000));
  for (int i = 0; i < 5; ++i) EXPECT_TRUE(health.update(100, 1000));
  // Returns come back: healthy once the window mean is above 0.2 again.
  EXPECT_TRUE(health.update(150, 1000));
  EXPECT_FALSE(health.update(1000, 1000));  // (0.1 * 3 + 0.15 + 1) / 5 = 0.29
  EXPECT_FALSE(health.update(1000, 1000));
}

TEST(SensorHealth, ExpectedPointsFromTheProfile) {
  SensorHealthParams params;
  params.expected_points = 100000;  // a driver that drops the non-returns
  SensorHealth health(params);
  EXPECT_TRUE(health.update(300, 300));  // 300 points, all valid, but 0.3 % of a healthy frame
  EXPECT_NEAR(health.frameShare(), 0.003, 1e-12);
  EXPECT_FALSE(health.update(120000, 120000));  // more than expected: share 1
  EXPECT_EQ(health.frameShare(), 1.0);
}

TEST(SensorHealth, Validate) {
  EXPECT_EQ(validate(SensorHealthParams()), "");
  SensorHealthParams p;
  p.min_frame_share = 1.5;
  EXPECT_NE(validate(p).find("sensor_health/min_frame_share"), std::string::npos);
  // 0 would never call the sensor blind: refused, both shares.
  p = SensorHealthParams();
  p.min_frame_share = 0.0;
  EXPECT_NE(validate(p).find("sensor_health/min_frame_share"), std::string::npos);
  p = SensorHealthParams();
  p.min_window_share = 0.0;
  EXPECT_NE(validate(p).find("sensor_health/min_window_share"), std::string::npos);
  p = SensorHealthParams();
  p.window_frames = 0;
  EXPECT_NE(validate(p).find("sensor_health/window_frames"), std::string::npos);
  p = SensorHealthParams();
  p.max_range_m = 0.1;
  EXPECT_NE(validate(p).find("sensor_health/max_range_m"), std::string::npos);
  p = SensorHealthParams();
  p.expected_points = -1;
  EXPECT_NE(validate(p), "");
  for (int sectors : {0, 73}) {
    p = SensorHealthParams();
    p.sectors = sectors;
    EXPECT_NE(validate(p).find("sensor_health/sectors"), std::string::npos) << sectors;
  }
}

TEST(SensorHealth, AzimuthSectorAgreesWithAtan2AwayFromTheEdges) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> angle(-M_PI, M_PI), range(0.5f, 80.0f);
  for (int sectors : {2, 8, 12, 36, 72}) {
    const double width = 2.0 * M_PI / sectors;
    for (int i = 0; i < 1000; ++i) {  // each call builds the sector table afresh
      const float a = angle(rng), r = range(rng);
      double a0 = a < 0 ? a + 2.0 * M_PI : a;
      const double into = std::fmod(a0, width);
      if (into < 0.004 || width - into < 0.004) continue;  // within a quarter degree of an edge
      ASSERT_EQ(azimuthSector(r * std::cos(a), r * std::sin(a), sectors),
                static_cast<int>(a0 / width))
          << "sectors " << sectors << ", azimuth " << a0 * 180.0 / M_PI;
    }
  }
  EXPECT_EQ(azimuthSector(5.0f, 0.0f, 12), 0);     // straight ahead
  EXPECT_EQ(azimuthSector(0.0f, 5.0f, 12), 3);     // left: 90..120 deg
  EXPECT_EQ(azimuthSector(-5.0f, -0.1f, 12), 6);   // behind, just right of the axis: 180..210
  EXPECT_EQ(azimuthSector(5.0f, -0.01f, 12), 11);  // ahead, just right: 330..360
}

// A 360-degree scan seen from the sensor: `beams` rings of 1800 azimuths, the ground ahead at
// 5-40 m. `cover(azimuth_deg)` says what becomes of a ray: kept, NaN, on a cover 0.3 m away, or
// dropped from the message.
enum class Ray { kScene, kNan, kCover, kDropped };
std::vector<Eigen::Vector3f> scan(int beams, const std::function<Ray(double)>& cover) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  std::vector<Eigen::Vector3f> points;
  for (int b = 0; b < beams; ++b) {
    for (int i = 0; i < 1800; ++i) {
      const double deg = i * 0.2 + 0.1;
      const double a = deg * M_PI / 180.0;
      const Eigen::Vector3f dir(std::cos(a), std::sin(a), -0.05f * (b + 1));
      const float range = 5.0f + 35.0f * b / beams;
      switch (cover(deg)) {
        case Ray::kScene: points.push_back(range * dir); break;
        case Ray::kNan: points.emplace_back(nan, nan, nan); break;
        case Ray::kCover: points.push_back(0.3f * dir.normalized()); break;
        case Ray::kDropped: break;
      }
    }
  }
  return points;
}

// Feeds `frames` frames of `points` to `health` (sector counts and all); returns the last verdict.
bool feed(SensorHealth& health, const std::vector<Eigen::Vector3f>& points, int frames) {
  Cloud3 cloud(points);
  SectorReturns sectors;
  bool blind = false;
  for (int i = 0; i < frames; ++i) {
    const std::size_t valid = countValidReturns(cloud.raw, cloud.plan, health.params(), &sectors);
    blind = health.update(valid, points.size(), sectors);
  }
  return blind;
}

TEST(SensorHealth, AHalfCoveredSensorIsBlindInItsSectors) {
  const std::vector<Eigen::Vector3f> healthy = scan(16, [](double) { return Ray::kScene; });
  for (Ray what : {Ray::kNan, Ray::kCover, Ray::kDropped}) {
    SCOPED_TRACE(static_cast<int>(what));
    // Left half (0..180 deg) covered: NaN, returns 0.3 m away on the cover, or not delivered.
    const std::vector<Eigen::Vector3f> covered =
        scan(16, [&](double deg) { return deg < 180.0 ? what : Ray::kScene; });
    SensorHealth health;
    EXPECT_FALSE(feed(health, healthy, 10));
    if (what == Ray::kCover) {
      // It returns (0.3 m away): a passer-by for a few frames, a cover once the window says so.
      EXPECT_FALSE(feed(health, covered, 3));
      EXPECT_TRUE(feed(health, covered, 6)) << "blind within the window (10 frames)";
    } else {
      EXPECT_TRUE(feed(health, covered, 1)) << "nothing returns: blind from the first frame";
    }
    EXPECT_GE(health.blindSector(), 0);
    EXPECT_LT(health.blindSector(), 6);
    EXPECT_EQ(health.blindSectorShare(), 0.0);
    EXPECT_GE(health.blindSectorFrames(), 1u);
    // Healthy again once the cover is gone and the window has recovered.
    EXPECT_FALSE(feed(health, healthy, 10));
    EXPECT_EQ(health.blindSector(), -1);

    // The same cover with the sectors switched off: the whole frame alone calls it healthy
    // (the NaN half reads 50 %; the other two read 100 %).
    SensorHealthParams whole;
    whole.sectors = 1;
    SensorHealth frame_only(whole);
    feed(frame_only, healthy, 10);
    EXPECT_FALSE(feed(frame_only, covered, 10));
  }
}

TEST(SensorHealth, ASceneWithFewerReturnsIsNotBlind) {
  // Half the beams return nothing (an open field under upper beams that see only sky): every
  // sector at half its reference, above both shares.
  const std::vector<Eigen::Vector3f> healthy = scan(16, [](double) { return Ray::kScene; });
  const std::vector<Eigen::Vector3f> open = scan(8, [](double) { return Ray::kScene; });
  SensorHealth health;
  EXPECT_FALSE(feed(health, healthy, 10));
  EXPECT_FALSE(feed(health, open, 20));
  EXPECT_EQ(health.blindSectorFrames(), 0u);
}

TEST(SensorHealth, SectorsOutsideTheFieldOfViewAreNotJudged) {
  // A forward sensor with 120 degrees: nothing ever comes from 60..300 deg.
  const auto fov = [](double deg) { return deg < 60.0 || deg > 300.0 ? Ray::kScene : Ray::kDropped; };
  SensorHealth health;
  EXPECT_FALSE(feed(health, scan(16, fov), 20));
  EXPECT_EQ(health.blindSectorFrames(), 0u);
  // Its right third covered: blind.
  EXPECT_TRUE(feed(health, scan(16, [&](double deg) {
                 return deg > 300.0 && deg < 340.0 ? Ray::kNan : fov(deg);
               }), 1));
  EXPECT_EQ(health.blindSector(), 10);
}

}  // namespace
}  // namespace icanc
