// SensorHealth: a LiDAR that returns NaN, (0, 0, 0), points on its own window or nothing in range
// is blind (lamp on), per frame and over a window, and healthy again when the returns come back.
#include <cmath>
#include <limits>
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
  const SensorHealthParams params;  // 0.2 .. 250 m
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
}

}  // namespace
}  // namespace icanc
