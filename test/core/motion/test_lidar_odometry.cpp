// LidarOdometry: simulated scans of a street (buildings with gaps, parked cars, poles)
// taken from a vehicle on a known path, straight then turning, are registered and the recovered
// trajectory is compared with the true one; a featureless corridor does not diverge; time going
// backwards resets; empty, tiny and NaN input; a scene that no longer matches the map falls back to
// the motion prior; parameter checks and the profile's section.
#include "icanc/core/motion/lidar_odometry.hpp"

#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "icanc/core/common/yaml_params.hpp"
#include "icanc/core/perception/cloud_decode.hpp"
#include "icanc/sim/lidar_sim.hpp"
#include "icanc/sim/scenario.hpp"
#include "lidar_odometry_scene.hpp"

namespace icanc {
namespace {

using namespace lio_scene;

std::string configDir() {  // as test_energy: next to this file's test/core/
  const std::string here = __FILE__;
  return here.substr(0, here.rfind("/test/core/")) + "/config/";
}

double yawOf(const Eigen::Isometry3d& pose) { return std::atan2(pose(1, 0), pose(0, 0)); }

LidarOdometryParams testParams() {
  LidarOdometryParams p;  // the library defaults but the range of the VLP-16 street
  p.max_range_m = 50.0;
  p.min_range_m = 2.0;
  p.ground_max_z_m = 0.3;  // base_link on the road
  p.max_registration_points = 600;  // the synthetic street's walls are thin: more of them
  return p;
}

// The frame's voxel set (a dense grid of z-masks around the sensor, a hash beyond it) answers
// "new voxel?" exactly as a hash of every voxel does: inside the grid, on its edges, beyond it in
// x, y and z (the hash part), across clear(), and with no grid at all.
TEST(ColumnVoxelSet, AnswersAsAHashOfTheSameVoxels) {
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> ij(-14, 13), k(-40, 40);
  for (const int half : {10, 0}) {
    ColumnVoxelSet set;
    set.reset(half);
    VoxelIndex reference;
    int news = 0, repeats = 0, hash_only = 0;
    for (int frame = 0; frame < 3; ++frame) {
      set.clear();
      reference.clear();
      for (int n = 0; n < 4000; ++n) {
        const std::int32_t i = ij(rng), j = ij(rng), z = k(rng);
        const std::uint64_t key = (std::uint64_t(std::uint32_t(i)) << 40) ^
                                  (std::uint64_t(std::uint32_t(j)) << 20) ^ std::uint32_t(z + 64);
        // A point the caller does not keep (out of range) is never new and sets nothing.
        const std::int32_t oi = ij(rng), oj = ij(rng), oz = k(rng);
        ASSERT_FALSE(set.insert({oi, oj, oz, (std::uint64_t(std::uint32_t(oi)) << 40) ^ 1u}, false));
        bool inserted;
        reference.findOrInsert(key, 0, inserted);
        ASSERT_EQ(set.insert({i, j, z, key}), inserted) << half << ": " << i << " " << j << " " << z;
        news += inserted;
        repeats += !inserted;
        hash_only += inserted && (std::abs(i + 0.5) > half || std::abs(j + 0.5) > half ||
                                  z < -32 || z >= 32);
      }
    }
    EXPECT_GT(news, 3000) << half;      // both answers occur,
    EXPECT_GT(repeats, 100) << half;
    EXPECT_GT(hash_only, 1000) << half;  // and many voxels lie beyond the grid
  }
}

// The packed search finds the match the plain loop over Eigen vectors finds, bit for bit: the
// first of the nearest (duplicates and equal distances included), none at or beyond the limit,
// whatever the count's remainder of 4 and with nothing to search.
TEST(NearestPacked, FindsThePointTheLoopFinds) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> coord(-2.0f, 2.0f);
  constexpr std::size_t kStride = 32;
  int found = 0, none = 0, ties = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    const int count = trial % 33;
    std::vector<Eigen::Vector3f> points;
    for (int j = 0; j < count; ++j) {
      // Points on a 0.25 m lattice a quarter of the time: equal distances occur.
      Eigen::Vector3f q(coord(rng), coord(rng), coord(rng));
      if (trial % 4 == 0) q = (q * 4.0f).array().round() / 4.0f;
      if (j > 0 && trial % 7 == 0) q = points[rng() % j];  // a duplicate
      points.push_back(q);
    }
    std::vector<float> xs(3 * kStride, std::numeric_limits<float>::infinity());
    for (int j = 0; j < count; ++j)
      for (int a = 0; a < 3; ++a) xs[a * kStride + j] = points[j][a];
    Eigen::Vector3f s(coord(rng), coord(rng), coord(rng));
    if (trial % 4 == 0) s = (s * 4.0f).array().round() / 4.0f;
    const float limit = trial % 3 == 0 ? 0.5f : 100.0f;
    float expected_best = limit;
    int expected = -1, equal = 0;
    for (int j = 0; j < count; ++j) {
      const float d2 = (points[j] - s).squaredNorm();
      equal += d2 == expected_best;
      if (d2 < expected_best) {
        expected_best = d2;
        expected = j;
        equal = 0;
      }
    }
    float best = limit;
    const int k = nearestPacked(xs.data(), count, kStride, s, best);
    ASSERT_EQ(k, expected) << "trial " << trial;
    ASSERT_EQ(best, expected_best) << "trial " << trial;
    found += k >= 0;
    none += k < 0;
    ties += k >= 0 && equal > 0;
  }
  EXPECT_GT(found, 5000);  // every case occurs
  EXPECT_GT(none, 1000);
  EXPECT_GT(ties, 100);
}

TEST(LidarOdometry, RecoversAStraightThenTurningPath) {
  const sim::Scene scene = street();
  LidarOdometry odometry(testParams());
  std::mt19937_64 rng(7);
  double worst_position = 0.0, worst_yaw = 0.0;
  for (int f = 0; f <= 65; ++f) {  // 6.5 s: 3 s straight, a 57 deg turn, 1.5 s straight
    const double t = 0.1 * f;
    const Eigen::Isometry3d truth = truePose(t);
    const Eigen::Isometry3d estimate = odometry.registerFrame(t, scanAt(scene, t, truth, rng));
    worst_position =
        std::max(worst_position, (estimate.translation() - truth.translation()).norm());
    worst_yaw = std::max(worst_yaw, std::fabs(yawOf(estimate) - yawOf(truth)));
    // Registered; the first frames of the pull-away (2 and 8 cm from the start) may be within
    // what the scan tells from no motion.
    if (f > 2) {
      EXPECT_EQ(odometry.lastStats().result, LidarOdometryStats::Result::kRegistered)
          << "frame " << f;
    }
  }
  // 44 m driven, 1 rad turned. Measured: worst 0.82 m, 0.036 rad (the simulator's exact planes
  // and scan pattern are harder than KITTI's real street, docs/lidar_odometry.md); a registration
  // that sticks or slips is off by metres.
  EXPECT_NEAR(yawOf(odometry.pose()), 1.0, 0.06);
  EXPECT_LT(worst_position, 1.2);
  EXPECT_LT(worst_yaw, 0.06);
  // Twist of the last frames (straight again, 8 m/s).
  EXPECT_NEAR(odometry.linearVelocity().x(), 8.0, 0.8);
  EXPECT_NEAR(odometry.linearVelocity().y(), 0.0, 0.8);
  EXPECT_NEAR(odometry.angularVelocity().z(), 0.0, 0.1);
  EXPECT_EQ(odometry.counters().degenerate, 0u);
  EXPECT_GT(odometry.mapPoints(), 1000u);
}

// The same drive seen by CARLA's 128-channel unit (0.72 deg between columns): a wall is sampled
// in vertical columns at fixed azimuths, which travel with the vehicle. Point-to-point ICP is
// pulled onto the previous scan's columns, toward "not moving"; point-to-plane slides along the
// wall and follows the drive.
TEST(LidarOdometry, PointToPlaneFollowsAStreetSampledInSparseColumns) {
  const sim::Scene scene = street();
  const auto worstError = [&](bool point_to_plane) {
    LidarOdometryParams params = testParams();
    params.point_to_plane = point_to_plane;
    params.input_stride = 2;  // as the CARLA profile
    params.max_registration_points = 400;
    LidarOdometry odometry(params);
    std::mt19937_64 rng(17);
    double worst = 0.0;
    for (int f = 0; f <= 65; ++f) {
      const double t = 0.1 * f;
      const Eigen::Isometry3d truth = truePose(t);
      const Eigen::Isometry3d estimate = odometry.registerFrame(
          t, scanAt(scene, t, truth, rng, 0.02f, sim::LidarModel::carla128()));
      worst = std::max(worst, (estimate.translation() - truth.translation()).norm());
    }
    return worst;
  };
  const double point_to_point = worstError(false), point_to_plane = worstError(true);
  std::printf("44 m driven, carla128: worst position error point-to-point %.2f m, "
              "point-to-plane %.2f m\n", point_to_point, point_to_plane);
  EXPECT_LT(point_to_plane, 1.0);
  EXPECT_GT(point_to_point, 3.0 * point_to_plane);
}

// A driver's organized cloud read at the source as the nodelet reads it (every input_stride-th
// point of each row): its columns stand at the same azimuths every frame. With the same columns
// kept frame after frame, the registration locked onto them where night_town_street turns left
// (carla128, the CARLA profile's stride 2: 8.4 m off, the yaw 0.27 rad behind); with the phase
// turning with every frame it follows the drive (0.08 m).
TEST(LidarOdometry, ColumnsReadAtTheSourceTurnWithEveryFrame) {
  const std::string scenario = configDir() + "scenarios/night_town_street.yaml";
  const sim::Scenario s = sim::loadScenario(scenario);
  const Profile profile = loadProfile(sim::profilePath(scenario, s.profile));
  ASSERT_EQ(profile.lidar_odometry.input_stride, 2);
  const sim::LidarModel model = sim::LidarModel::byName(s.lidar);
  const Eigen::Isometry3d start_inv = s.vehiclePose(0.0).cast<double>().inverse();
  const Eigen::Affine3f mount(s.sensor_mount.matrix());
  const auto worstError = [&](bool turning_phase) {
    LidarOdometry odometry(profile.lidar_odometry);
    std::mt19937_64 rng(s.seed);
    double worst = 0.0;
    for (std::size_t f = 0; f < s.frames(); ++f) {
      const double t = double(f) / s.rate_hz;
      Cloud scan;
      sim::renderScan(s.scene, t, s.sensorPose(t), model, s.noise, rng, scan);
      const RawCloud raw = rawView(scan);  // as the nodelet reads the driver's organized cloud
      DecodePlan plan;
      EXPECT_EQ(planDecode(raw, scan.size(), plan), DecodeError::kNone);
      const DecodePlan thinned = everyNthPoint(plan, 2, turning_phase ? odometry.sourcePhase() : 0);
      const Eigen::Isometry3d estimate = odometry.registerFrom(
          t, [&](auto&& sink) { forEachXYZ(raw, thinned, mount, sink); },
          LidarOdometry::Thinning::kBySource);
      const Eigen::Isometry3d truth = start_inv * s.vehiclePose(t).cast<double>();
      worst = std::max(worst, (estimate.translation() - truth.translation()).norm());
    }
    return worst;
  };
  const double fixed = worstError(false), turning = worstError(true);
  std::printf("night_town_street (78 m, a 90 deg turn), carla128 read at the source every 2nd "
              "column: worst position error same columns %.2f m, turning phase %.2f m\n",
              fixed, turning);
  EXPECT_LT(turning, 0.5);
  EXPECT_GT(fixed, 2.0);
}

TEST(LidarOdometry, MeasuresTheYawRateInTheTurn) {
  const sim::Scene scene = street();
  LidarOdometry odometry(testParams());
  std::mt19937_64 rng(8);
  for (int f = 0; f <= 42; ++f) {
    const double t = 0.1 * f;
    odometry.registerFrame(t, scanAt(scene, t, truePose(t), rng));
  }
  EXPECT_NEAR(odometry.angularVelocity().z(), 0.5, 0.05);
  // One frame's speed: a 4 cm registration error in the turn is 0.4 m/s.
  EXPECT_NEAR(odometry.linearVelocity().norm(), 8.0, 0.4);
}

TEST(LidarOdometry, StraightCorridorDoesNotDiverge) {
  // Two long smooth walls and the road: along the corridor nothing is observable. The estimate
  // must stay finite, on the corridor's axis and level, and never run ahead of the vehicle or
  // backwards. (It does not keep the speed: in the simulator's exact scan pattern the walls' scan
  // lines hold it back, a known limit, docs/lidar_odometry.md.)
  const sim::Scene corridor = lio_scene::corridor();
  LidarOdometry odometry(testParams());
  std::mt19937_64 rng(9);
  for (int f = 0; f <= 40; ++f) {
    const double t = 0.1 * f;
    const Eigen::Isometry3d truth = truePose(t, 8.0, false);
    const Eigen::Isometry3d estimate = odometry.registerFrame(t, scanAt(corridor, t, truth, rng));
    ASSERT_TRUE(estimate.matrix().allFinite());
    EXPECT_NEAR(estimate.translation().y(), 0.0, 0.15) << "frame " << f;
    EXPECT_NEAR(estimate.translation().z(), 0.0, 0.15) << "frame " << f;
    EXPECT_NEAR(yawOf(estimate), 0.0, 0.01) << "frame " << f;
    EXPECT_GT(estimate.translation().x(), -0.5) << "frame " << f;
    EXPECT_LT(estimate.translation().x(), truth.translation().x() + 1.0) << "frame " << f;
  }
  EXPECT_GT(odometry.linearVelocity().x(), -1.0);
  EXPECT_LT(odometry.linearVelocity().x(), 1.5 * 8.0);
  // And it says so: nothing faces along the corridor, every registration is degenerate.
  EXPECT_LT(odometry.lastStats().horizontal_observability, 0.05);
  EXPECT_EQ(odometry.counters().registered, 0u);
  EXPECT_EQ(odometry.counters().degenerate, 40u);
}

// The vehicle's speed at frame time t of truePose (pulling away at 4 m/s2 up to `speed`).
double trueSpeed(double t, double speed = 8.0) { return std::min(speed, 4.0 * t); }


TEST(LidarOdometry, MeasuredSpeedCarriesItAlongACorridor) {
  // The corridor of StraightCorridorDoesNotDiverge, with the vehicle's wheel speed seeded as a
  // CAN bus gives it: 1 % over (tyre radius) and 0.05 m/s noise. Every frame is still degenerate
  // (the scene cannot say how far it went); the pose now follows the measured speed.
  const sim::Scene corridor = lio_scene::corridor();
  LidarOdometry seeded(testParams()), alone(testParams());
  std::mt19937_64 rng(9), wheel(3);
  std::normal_distribution<double> noise(0.0, 0.05);
  double worst_seeded = 0.0, worst_alone = 0.0;
  for (int f = 0; f <= 40; ++f) {
    const double t = 0.1 * f;
    const Eigen::Isometry3d truth = truePose(t, 8.0, false);
    const std::vector<Eigen::Vector3f> scan = scanAt(corridor, t, truth, rng);
    seeded.seedTwist(measuredTwist(1.01 * trueSpeed(t) + noise(wheel)));
    const Eigen::Isometry3d with = seeded.registerFrame(t, scan);
    const Eigen::Isometry3d without = alone.registerFrame(t, scan);
    ASSERT_TRUE(with.matrix().allFinite());
    EXPECT_NEAR(with.translation().y(), 0.0, 0.15) << "frame " << f;
    EXPECT_NEAR(yawOf(with), 0.0, 0.01) << "frame " << f;
    worst_seeded = std::max(worst_seeded, (with.translation() - truth.translation()).norm());
    worst_alone = std::max(worst_alone, (without.translation() - truth.translation()).norm());
    if (f > 0) {
      EXPECT_TRUE(seeded.lastStats().speed_seeded) << "frame " << f;
    }
  }
  std::printf("[ MEASURE ] corridor, 24 m at up to 8 m/s: worst error %.2f m with the wheel speed "
              "(1 %% over), %.2f m without\n", worst_seeded, worst_alone);
  EXPECT_LT(worst_seeded, 0.5);   // 1 % of 24 m and the noise
  EXPECT_GT(worst_alone, 5.0);    // without it, "not moving" for a good part of the way
  EXPECT_NEAR(seeded.linearVelocity().x(), 8.08, 0.3);
  EXPECT_EQ(seeded.counters().degenerate, 40u);  // the scene still fixes nothing along it
  EXPECT_EQ(seeded.counters().speed_seeded, 40u);
  // A seed holds for one frame: the next frame without one is the constant-velocity prior.
  seeded.registerFrame(4.1, scanAt(corridor, 4.1, truePose(4.1, 8.0, false), rng));
  EXPECT_FALSE(seeded.lastStats().speed_seeded);
  EXPECT_EQ(seeded.counters().speed_seeded, 40u);
}

TEST(LidarOdometry, MeasuredYawRateTurnsItOnAnOpenRoad) {
  // Nothing but the road: the drive of RecoversAStraightThenTurningPath (1 rad turned at 3-5 s)
  // with the wheel speed, and with the gyro's yaw rate too (0.003 rad/s bias). With the speed
  // alone the degenerate frames' pose goes straight on through the turn.
  const sim::Scene road;
  LidarOdometry twist(testParams()), speed_only(testParams());
  std::mt19937_64 rng(5);
  double worst_twist = 0.0, worst_speed = 0.0;
  for (int f = 0; f <= 65; ++f) {
    const double t = 0.1 * f;
    const Eigen::Isometry3d truth = truePose(t);
    const double yaw_rate = t >= 3.0 && t < 5.0 ? 0.5 : 0.0;  // truePose's, at the frame
    const std::vector<Eigen::Vector3f> scan = scanAt(road, t, truth, rng);
    twist.seedTwist(measuredTwist(trueSpeed(t), yaw_rate + 0.003));
    speed_only.seedTwist(measuredTwist(trueSpeed(t)));
    const Eigen::Isometry3d a = twist.registerFrame(t, scan), b = speed_only.registerFrame(t, scan);
    worst_twist = std::max(worst_twist, (a.translation() - truth.translation()).norm());
    worst_speed = std::max(worst_speed, (b.translation() - truth.translation()).norm());
  }
  std::printf("[ MEASURE ] open road, 1 rad turn: worst error %.2f m with speed and yaw rate, %.2f m "
              "with the speed alone\n", worst_twist, worst_speed);
  EXPECT_EQ(twist.counters().registered, 0u);
  EXPECT_NEAR(yawOf(twist.pose()), 1.0 + 0.003 * 6.5, 0.06);
  EXPECT_LT(worst_twist, 1.0);
  EXPECT_NEAR(yawOf(speed_only.pose()), 0.0, 0.06);
  EXPECT_GT(worst_speed, 5.0);
}

TEST(LidarOdometry, WallsGiveTheTurnWhereOnlyTheSpeedIsMeasured) {
  // A road between walls that turns 1 rad, and a speed-only source (no gyro): the motion along the
  // walls is unobserved in every frame, the turn and the position across them are. Registered with
  // the along-track translation held at the measured speed's (Result::kHeld), the pose follows
  // the bend; the prior alone would go straight on (the open road's 19 m above).
  const sim::Scene scene = bendingCorridor();
  LidarOdometry odometry(testParams());
  std::mt19937_64 rng(13);
  double worst = 0.0, worst_yaw = 0.0;
  for (int f = 0; f <= 65; ++f) {
    const double t = 0.1 * f;
    const Eigen::Isometry3d truth = truePose(t);
    odometry.seedTwist(measuredTwist(1.01 * trueSpeed(t)));
    const Eigen::Isometry3d estimate = odometry.registerFrame(t, scanAt(scene, t, truth, rng));
    worst = std::max(worst, (estimate.translation() - truth.translation()).norm());
    worst_yaw = std::max(worst_yaw, std::fabs(yawOf(estimate) - yawOf(truth)));
  }
  std::printf("[ MEASURE ] bending corridor, speed only: worst error %.2f m, yaw %.3f rad; %llu of "
              "65 frames held, %llu registered\n", worst, worst_yaw,
              static_cast<unsigned long long>(odometry.counters().held),
              static_cast<unsigned long long>(odometry.counters().registered));
  EXPECT_GT(odometry.counters().held, 30u);
  EXPECT_NEAR(yawOf(odometry.pose()), 1.0, 0.06);
  EXPECT_LT(worst, 1.5);
}

TEST(LidarOdometry, MeasuredSpeedLeavesRegisteredFramesAlone) {
  // Where the scene fixes the motion (the street and its turn, registered in every frame), the
  // poses are exactly those without a seed.
  const sim::Scene scene = street();
  LidarOdometry seeded(testParams()), alone(testParams());
  std::mt19937_64 rng(7);
  for (int f = 0; f <= 65; ++f) {
    const double t = 0.1 * f;
    const std::vector<Eigen::Vector3f> scan = scanAt(scene, t, truePose(t), rng);
    seeded.seedTwist(measuredTwist(1.01 * trueSpeed(t), 0.0));
    const Eigen::Isometry3d with = seeded.registerFrame(t, scan);
    const Eigen::Isometry3d without = alone.registerFrame(t, scan);
    ASSERT_TRUE(with.isApprox(without, 1e-12)) << "frame " << f;
  }
  EXPECT_EQ(seeded.counters().registered + seeded.counters().at_rest, 65u);
  EXPECT_EQ(seeded.counters().speed_seeded, 0u);
}

// A corridor (walls along the road) with a car waiting in the lane 8 m ahead of where the vehicle
// stops: the car's back is all that faces along the road.
sim::Scene corridorBehindACar(double stop_x) {
  sim::Scene scene = lio_scene::corridor();
  scene.objects.push_back(box(static_cast<float>(stop_x + 8.0 + 2.35), 0.0f, 4.7f, 1.9f, 1.5f));
  return scene;
}

// The vehicle at `speed` until `stop_s`, standing from then on (a hard stop: the prior's motion is
// a whole frame's).
Eigen::Isometry3d stopAt(double t, double speed, double stop_s) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation().x() = speed * std::min(t, stop_s);
  return pose;
}

TEST(LidarOdometry, StandsStillWhereTheSceneIsDegenerate) {
  // Along the corridor at 3 m/s with the wheel speed (the scene says nothing along the road but
  // the waiting car's back), then standing, the wheel speed gone silent: the motion prior still
  // says 3 m/s. The scan fits "no motion" and rules the prior out: the pose holds, the twist is
  // zero. Measured drift without the at-rest test: the prior's 0.3 m per frame.
  const double stop_s = 1.0, speed = 3.0;
  const sim::Scene scene = corridorBehindACar(speed * stop_s);
  LidarOdometry odometry(testParams());
  std::mt19937_64 rng(21);
  for (int f = 0; f <= 40; ++f) {
    const double t = 0.1 * f;
    const Eigen::Isometry3d truth = stopAt(t, speed, stop_s);
    if (t < stop_s - 1e-9) odometry.seedTwist(measuredTwist(speed));
    const Eigen::Isometry3d estimate = odometry.registerFrame(t, scanAt(scene, t, truth, rng));
    ASSERT_TRUE(estimate.matrix().allFinite());
    if (f > 0 && t < stop_s - 1e-9) {  // moving: never at rest
      EXPECT_NE(odometry.lastStats().result, LidarOdometryStats::Result::kAtRest) << "frame " << f;
    }
    if (t > stop_s + 0.15) {  // standing (the first frame after the stop may still move)
      EXPECT_EQ(odometry.lastStats().result, LidarOdometryStats::Result::kAtRest) << "frame " << f;
      EXPECT_EQ(odometry.linearVelocity().norm(), 0.0) << "frame " << f;
      EXPECT_EQ(odometry.angularVelocity().norm(), 0.0) << "frame " << f;
      EXPECT_NEAR(estimate.translation().x(), truth.translation().x(), 0.3) << "frame " << f;
    }
  }
  std::printf("[ MEASURE ] corridor behind a car: %llu frames at rest, %llu degenerate, last F %.2f "
              "over %zu residuals, observability %.3f\n",
              static_cast<unsigned long long>(odometry.counters().at_rest),
              static_cast<unsigned long long>(odometry.counters().degenerate),
              odometry.lastStats().rest_f, odometry.lastStats().rest_residuals,
              odometry.lastStats().horizontal_observability);
  EXPECT_GE(odometry.counters().at_rest, 28u);
}

TEST(LidarOdometry, StandsStillWhereTheWheelsStand) {
  // The same corridor and car with the wheel speed throughout: 3 m/s, then exactly 0 once the
  // wheels stand (and a gyro's bias). From the second standing frame on, every frame is at rest
  // with no motion at all, however the registration would have jittered.
  const double stop_s = 1.0, speed = 3.0;
  const sim::Scene scene = corridorBehindACar(speed * stop_s);
  LidarOdometry odometry(testParams());
  std::mt19937_64 rng(24);
  Eigen::Isometry3d held = Eigen::Isometry3d::Identity();
  for (int f = 0; f <= 30; ++f) {
    const double t = 0.1 * f;
    const Eigen::Isometry3d truth = stopAt(t, speed, stop_s);
    odometry.seedTwist(measuredTwist(t < stop_s - 1e-9 ? speed : 0.0, 0.003));
    const Eigen::Isometry3d estimate = odometry.registerFrame(t, scanAt(scene, t, truth, rng));
    if (f > 0 && t < stop_s - 1e-9) {
      EXPECT_NE(odometry.lastStats().result, LidarOdometryStats::Result::kAtRest) << "frame " << f;
    }
    if (t > stop_s + 0.15) {
      EXPECT_EQ(odometry.lastStats().result, LidarOdometryStats::Result::kAtRest) << "frame " << f;
      EXPECT_EQ(odometry.linearVelocity().norm(), 0.0) << "frame " << f;
      EXPECT_TRUE(estimate.isApprox(held, 0.0)) << "frame " << f << ": the pose moved";
    }
    held = estimate;
  }
}

TEST(LidarOdometry, MovingIsNotAtRest) {
  // The same corridor and car, driven toward at 3 m/s without a wheel speed, and the street at up
  // to 8 m/s: the scan never fits "no motion" (the street's first frame, 2 cm from the start, may).
  const sim::Scene scene = corridorBehindACar(12.0);
  LidarOdometry corridor(testParams());
  std::mt19937_64 rng(22);
  for (int f = 0; f <= 30; ++f) {
    const double t = 0.1 * f;
    corridor.registerFrame(t, scanAt(scene, t, stopAt(t, 3.0, 100.0), rng));
  }
  EXPECT_EQ(corridor.counters().at_rest, 0u);
  LidarOdometry street_odometry(testParams());
  const sim::Scene town = street();
  for (int f = 0; f <= 30; ++f) {
    const double t = 0.1 * f;
    street_odometry.registerFrame(t, scanAt(town, t, truePose(t), rng));
    if (f >= 3) {
      EXPECT_NE(street_odometry.lastStats().result, LidarOdometryStats::Result::kAtRest) << "frame " << f;
    }
  }
  EXPECT_LE(street_odometry.counters().at_rest, 2u);
}

TEST(LidarOdometry, StandsStillOnAStreet) {
  // Where the scene fixes the motion, a vehicle that stopped is registered at no motion: the pose
  // is held exactly rather than jittering with each registration.
  const sim::Scene scene = street();
  LidarOdometry odometry(testParams());
  std::mt19937_64 rng(23);
  Eigen::Isometry3d held = Eigen::Isometry3d::Identity();
  for (int f = 0; f <= 30; ++f) {
    const double t = 0.1 * f;
    const Eigen::Isometry3d truth = stopAt(t, 4.0, 1.5);
    const Eigen::Isometry3d estimate = odometry.registerFrame(t, scanAt(scene, t, truth, rng));
    if (t > 1.65) {
      EXPECT_EQ(odometry.lastStats().result, LidarOdometryStats::Result::kAtRest) << "frame " << f;
      EXPECT_TRUE(estimate.isApprox(held, 1e-12)) << "frame " << f;
      EXPECT_NEAR(estimate.translation().x(), 6.0, 0.2) << "frame " << f;
    }
    held = estimate;
  }
}

TEST(LidarOdometry, ObservabilityTellsAStreetFromACorridor) {
  // The street (buildings with gaps, parked cars, poles across it) constrains both horizontal
  // directions; its observability stays above the default threshold in every frame.
  const sim::Scene scene = street();
  LidarOdometry odometry(testParams());
  std::mt19937_64 rng(11);
  double lowest = 1.0;
  for (int f = 0; f <= 30; ++f) {
    const double t = 0.1 * f;
    odometry.registerFrame(t, scanAt(scene, t, truePose(t), rng));
    if (f > 0) lowest = std::min(lowest, odometry.lastStats().horizontal_observability);
  }
  EXPECT_GT(lowest, LidarOdometryParams().min_horizontal_observability);
  EXPECT_EQ(odometry.counters().degenerate, 0u);
  // Switched off, the corridor registers (and slides) as before.
  const sim::Scene corridor = lio_scene::corridor();
  LidarOdometryParams unchecked = testParams();
  unchecked.min_horizontal_observability = 0.0;
  LidarOdometry sliding(unchecked);
  for (int f = 0; f <= 10; ++f) {
    const double t = 0.1 * f;
    sliding.registerFrame(t, scanAt(corridor, t, truePose(t, 8.0, false), rng));
  }
  EXPECT_EQ(sliding.counters().degenerate, 0u);
}

TEST(LidarOdometry, ThinningAtTheSourceRegistersTheSamePoints) {
  // The nodelet decodes only every input_stride-th point (everyNthPoint); the odometry counting
  // them itself over the whole cloud must give the very same poses.
  const sim::Scene scene = street();
  LidarOdometryParams params = testParams();
  params.input_stride = 3;
  LidarOdometry counting(params), at_source(params);
  std::mt19937_64 rng(13);
  for (int f = 0; f <= 20; ++f) {
    const double t = 0.1 * f;
    const std::vector<Eigen::Vector3f> scan = scanAt(scene, t, truePose(t), rng);
    RawCloud raw;  // the scan as an unorganized PointCloud2 of x, y, z float32
    raw.width = static_cast<std::uint32_t>(scan.size());
    raw.height = 1;
    raw.point_step = sizeof(Eigen::Vector3f);
    raw.row_step = raw.width * raw.point_step;
    raw.fields = {{"x", 0, 7, 1}, {"y", 4, 7, 1}, {"z", 8, 7, 1}};
    raw.data = reinterpret_cast<const std::uint8_t*>(scan.data());
    raw.data_size = scan.size() * sizeof(Eigen::Vector3f);
    DecodePlan plan;
    ASSERT_EQ(planDecode(raw, 1000000, plan), DecodeError::kNone);
    const Eigen::Affine3f identity = Eigen::Affine3f::Identity();
    const Eigen::Isometry3d a = counting.registerFrom(
        t, [&](auto&& sink) { forEachXYZ(raw, plan, identity, sink); });
    // The phase turns with every frame (0, 1, 2, 0, ...), at the source as when counting.
    EXPECT_EQ(at_source.sourcePhase(), static_cast<std::size_t>(f % 3));
    const DecodePlan thinned = everyNthPoint(plan, 3, at_source.sourcePhase());
    const std::size_t expected_points = (scan.size() - at_source.sourcePhase() + 2) / 3;
    const Eigen::Isometry3d b = at_source.registerFrom(
        t, [&](auto&& sink) { forEachXYZ(raw, thinned, identity, sink); },
        LidarOdometry::Thinning::kBySource);
    ASSERT_TRUE(a.isApprox(b, 1e-12)) << "frame " << f;
    EXPECT_EQ(counting.lastStats().registration_points, at_source.lastStats().registration_points);
    EXPECT_EQ(counting.lastStats().input_points, scan.size());
    EXPECT_EQ(at_source.lastStats().input_points, expected_points);
  }
  EXPECT_EQ(at_source.counters().registered + at_source.counters().at_rest, 20u);
}

TEST(LidarOdometry, TimeGoingBackwardsResets) {
  const sim::Scene scene = street();
  LidarOdometry odometry(testParams());
  std::mt19937_64 rng(10);
  for (int f = 0; f <= 10; ++f)
    odometry.registerFrame(0.1 * f, scanAt(scene, 0.1 * f, truePose(0.1 * f), rng));
  ASSERT_GT(odometry.pose().translation().x(), 1.0);
  const std::size_t map_before = odometry.mapPoints();
  // A bag loop: back to t = 0.
  const Eigen::Isometry3d pose =
      odometry.registerFrame(0.0, scanAt(scene, 0.0, truePose(0.0), rng));
  EXPECT_EQ(odometry.lastStats().result, LidarOdometryStats::Result::kReset);
  EXPECT_EQ(odometry.counters().resets, 1u);
  EXPECT_TRUE(pose.isApprox(Eigen::Isometry3d::Identity()));
  EXPECT_EQ(odometry.linearVelocity().norm(), 0.0);
  EXPECT_LT(odometry.mapPoints(), map_before);  // one scan's worth again
  // And it runs on from there.
  for (int f = 1; f <= 10; ++f)
    odometry.registerFrame(0.1 * f, scanAt(scene, 0.1 * f, truePose(0.1 * f), rng));
  EXPECT_NEAR(odometry.pose().translation().x(), truePose(1.0).translation().x(), 0.2);

  odometry.reset();  // explicit reset: pose and map forgotten, counters kept
  EXPECT_TRUE(odometry.pose().isApprox(Eigen::Isometry3d::Identity()));
  EXPECT_EQ(odometry.mapPoints(), 0u);
  EXPECT_EQ(odometry.counters().resets, 1u);
}

TEST(LidarOdometry, EmptyTinyAndNaNInput) {
  const sim::Scene scene = street();
  LidarOdometry odometry(testParams());
  std::mt19937_64 rng(11);
  // Empty before anything: identity, counted, nothing started.
  EXPECT_TRUE(odometry.registerFrame(0.0, {}).isApprox(Eigen::Isometry3d::Identity()));
  EXPECT_EQ(odometry.lastStats().result, LidarOdometryStats::Result::kExtrapolated);
  EXPECT_EQ(odometry.counters().extrapolated, 1u);
  for (int f = 1; f <= 10; ++f) {
    std::vector<Eigen::Vector3f> points = scanAt(scene, 0.1 * f, truePose(0.1 * f), rng);
    const float nan = std::numeric_limits<float>::quiet_NaN();
    points.insert(points.begin() + points.size() / 2, Eigen::Vector3f(nan, 1.0f, 1.0f));
    points.emplace_back(std::numeric_limits<float>::infinity(), 0.0f, 0.0f);
    odometry.registerFrame(0.1 * f, points);
  }
  EXPECT_EQ(odometry.counters().nonfinite_points, 20u);
  EXPECT_NEAR(odometry.pose().translation().x(), truePose(1.0).translation().x(), 0.2);
  // A tiny cloud (a few points) and an empty one: the pose carries on with the motion prior.
  const std::vector<Eigen::Vector3f> tiny = {{5.0f, 0.0f, 0.0f}, {6.0f, 1.0f, 0.0f}};
  odometry.registerFrame(1.1, tiny);
  EXPECT_EQ(odometry.lastStats().result, LidarOdometryStats::Result::kExtrapolated);
  EXPECT_NEAR(odometry.pose().translation().x(), truePose(1.1).translation().x(), 0.2);
  odometry.registerFrame(1.2, {});
  EXPECT_NEAR(odometry.pose().translation().x(), truePose(1.2).translation().x(), 0.25);
  EXPECT_EQ(odometry.counters().extrapolated, 3u);
  // And registration resumes.
  odometry.registerFrame(1.3, scanAt(scene, 1.3, truePose(1.3), rng));
  EXPECT_EQ(odometry.lastStats().result, LidarOdometryStats::Result::kRegistered);
  EXPECT_NEAR(odometry.pose().translation().x(), truePose(1.3).translation().x(), 0.2);
}

TEST(LidarOdometry, UnmatchedSceneFallsBackToTheMotionPrior) {
  const sim::Scene scene = street();
  LidarOdometry odometry(testParams());
  std::mt19937_64 rng(12);
  for (int f = 0; f <= 10; ++f)
    odometry.registerFrame(0.1 * f, scanAt(scene, 0.1 * f, truePose(0.1 * f), rng));
  // Every point 20 m up: nothing in the map within reach (a corrupt or foreign cloud).
  std::vector<Eigen::Vector3f> foreign = scanAt(scene, 1.1, truePose(1.1), rng);
  for (auto& p : foreign) p.z() += 20.0f;
  const Eigen::Isometry3d pose = odometry.registerFrame(1.1, foreign);
  EXPECT_EQ(odometry.lastStats().result, LidarOdometryStats::Result::kDegenerate);
  EXPECT_EQ(odometry.counters().degenerate, 1u);
  EXPECT_NEAR(pose.translation().x(), truePose(1.1).translation().x(), 0.2);  // the prior
  EXPECT_NEAR(pose.translation().z(), 0.0, 0.05);
}

TEST(LidarOdometry, LongGapDropsThePrior) {
  const sim::Scene scene = street();
  LidarOdometry odometry(testParams());
  std::mt19937_64 rng(13);
  for (int f = 0; f <= 5; ++f)
    odometry.registerFrame(0.1 * f, scanAt(scene, 0.1 * f, truePose(0.1 * f), rng));
  // 2 s later, the vehicle stood still meanwhile (same place): with the prior kept the guess would
  // be 16 m ahead; dropped, registration starts from the last pose and finds it: no motion.
  odometry.registerFrame(2.5, scanAt(scene, 2.5, truePose(0.5), rng));
  EXPECT_EQ(odometry.counters().gaps, 1u);
  // (Or a correction of the last frame's pose by the map, when it is above what the scan's
  // residuals allow for no motion.)
  EXPECT_TRUE(odometry.lastStats().result == LidarOdometryStats::Result::kRegistered ||
              odometry.lastStats().result == LidarOdometryStats::Result::kAtRest);
  EXPECT_NEAR(odometry.pose().translation().x(), truePose(0.5).translation().x(), 0.2);
}

TEST(LidarOdometry, ParametersAreChecked) {
  EXPECT_EQ(validate(LidarOdometryParams()), "");
  const auto why = [](auto edit) {
    LidarOdometryParams p;
    edit(p);
    return validate(p);
  };
  EXPECT_NE(why([](LidarOdometryParams& p) { p.voxel_m = 0.0; }).find("voxel_m"),
            std::string::npos);
  EXPECT_NE(why([](LidarOdometryParams& p) { p.min_range_m = 100.0; }).find("min_range_m"),
            std::string::npos);
  EXPECT_NE(
      why([](LidarOdometryParams& p) { p.max_points_per_voxel = 0; }).find("max_points_per_voxel"),
      std::string::npos);
  EXPECT_NE(why([](LidarOdometryParams& p) {
              p.max_points_per_voxel = kMaxPointsPerVoxel + 1;
            }).find("max_points_per_voxel"),
            std::string::npos);
  EXPECT_NE(why([](LidarOdometryParams& p) { p.max_iterations = 0; }).find("max_iterations"),
            std::string::npos);
  EXPECT_NE(why([](LidarOdometryParams& p) { p.input_stride = 0; }).find("input_stride"),
            std::string::npos);
  EXPECT_NE(why([](LidarOdometryParams& p) { p.min_points = 3; }).find("min_points"),
            std::string::npos);
  EXPECT_NE(why([](LidarOdometryParams& p) {
              p.min_correspondence_ratio = 1.5;
            }).find("min_correspondence_ratio"),
            std::string::npos);
  EXPECT_NE(why([](LidarOdometryParams& p) { p.max_dt_s = std::nan(""); }).find("max_dt_s"),
            std::string::npos);
  EXPECT_NE(why([](LidarOdometryParams& p) {
              p.min_horizontal_observability = 0.6;
            }).find("min_horizontal_observability"),
            std::string::npos);
  LidarOdometryParams bad;
  bad.voxel_m = -1.0;
  EXPECT_THROW(LidarOdometry{bad}, std::invalid_argument);
}

TEST(LidarOdometry, ProfilesCarryAValidSection) {
  for (const char* name : {"kitti_hdl64e", "zebra", "carla_model3"}) {
    const Profile p = loadProfile(configDir() + name + ".yaml");
    EXPECT_EQ(validate(p.lidar_odometry), "") << name;
  }
  const Profile kitti = loadProfile(configDir() + "kitti_hdl64e.yaml");
  EXPECT_EQ(kitti.lidar_odometry.input_stride, 3);  // the section is read, not the defaults
}

}  // namespace
}  // namespace icanc
