// Pins the LidarOdometry nodelet's logic around the registration: its parameters, the vehicle's
// twist (unstamped and impossible ones refused, a restart counted, seeded at a cloud's stamp or
// counted missing), invalid clouds and missing transforms counted, what a frame's result logs,
// the covariances and the report (WARN while a count grows, then OK).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "icanc/core/motion/odometry_feed.hpp"

namespace icanc {
namespace {

OdometryFeedParams withTwist() {
  OdometryFeedParams p;
  p.twist_topic = "vehicle/twist";
  return p;
}

std::string joined(const std::vector<LogLine>& logs) {
  std::string s;
  for (const LogLine& l : logs) s += l.text + "\n";
  return s;
}

TEST(OdometryFeed, ParametersAreValidated) {
  EXPECT_EQ(validate(OdometryFeedParams()), "");
  OdometryFeedParams p;
  p.max_points = 0;
  EXPECT_EQ(validate(p), "max_points must be > 0");
  p = OdometryFeedParams();
  p.odom_frame = "";
  EXPECT_EQ(validate(p), "base_frame and odom_frame must not be empty");
  p = OdometryFeedParams();
  p.odom_frame = p.base_frame;
  EXPECT_EQ(validate(p), "base_frame must differ from odom_frame");
  p = OdometryFeedParams();
  p.twist_max_age_s = 1.5;
  EXPECT_EQ(validate(p), "twist_max_age_s must be in (0, 1]");
}

TEST(OdometryFeed, MeasuredPosesAreTrustedPriorOnesLittle) {
  using Result = LidarOdometryStats::Result;
  EXPECT_DOUBLE_EQ(odometryVariances(Result::kRegistered).position, 0.05 * 0.05);
  EXPECT_DOUBLE_EQ(odometryVariances(Result::kAtRest).rate, 0.02 * 0.02);
  EXPECT_DOUBLE_EQ(odometryVariances(Result::kDegenerate).position, 1.0);
  EXPECT_DOUBLE_EQ(odometryVariances(Result::kExtrapolated).velocity, 4.0);
  EXPECT_DOUBLE_EQ(odometryVariances(Result::kExtrapolated).rotation, 0.01);
}

TEST(OdometryFeed, UnstampedAndImpossibleTwistsAreRefusedAndLoggedOnceASecond) {
  OdometryFeed feed(LidarOdometryParams(), withTwist(), "/vehicle/twist");
  std::vector<LogLine> logs;
  feed.onTwist(0.0, 5.0, 0.0, 100.0, logs);
  ASSERT_EQ(logs.size(), 1u);
  EXPECT_EQ(logs[0].severity, LogSeverity::kError);
  EXPECT_NE(logs[0].text.find("vehicle twist on /vehicle/twist dropped: header.stamp is 0"), std::string::npos);
  feed.onTwist(10.0, std::numeric_limits<double>::quiet_NaN(), 0.0, 100.5, logs);
  EXPECT_EQ(logs.size(), 1u) << "the same line's throttle: " << joined(logs);
  feed.onTwist(10.0, std::numeric_limits<double>::quiet_NaN(), 0.0, 101.0, logs);
  ASSERT_EQ(logs.size(), 2u);
  EXPECT_NE(logs[1].text.find("is no measurement"), std::string::npos);
  StatusReport r = feed.report(0.0);
  EXPECT_EQ(r.value("invalid vehicle speeds"), "3");
  EXPECT_EQ(r.level, StatusLevel::kWarn);
  EXPECT_EQ(r.message, "vehicle speed invalid or missing");
  r = feed.report(0.0);
  EXPECT_EQ(r.level, StatusLevel::kOk) << "WARN only while the count grows";
  EXPECT_EQ(r.message, "ok");
}

TEST(OdometryFeed, TwistIsSeededAtTheCloudsStampOrCountedMissing) {
  OdometryFeed feed(LidarOdometryParams(), withTwist(), "/vehicle/twist");
  std::vector<LogLine> logs;
  feed.onTwist(10.0, 5.0, 0.0, 100.0, logs);
  feed.onTwist(10.1, 5.0, 0.0, 100.0, logs);
  EXPECT_TRUE(logs.empty());
  feed.seedTwist(10.05, 100.0, logs);
  EXPECT_TRUE(logs.empty());
  feed.seedTwist(20.0, 100.0, logs);
  ASSERT_EQ(logs.size(), 1u);
  EXPECT_EQ(logs[0].text, "no vehicle speed on /vehicle/twist within 0.20 s of the cloud at 20.000: the LiDAR "
                          "alone for this frame");
  feed.onTwist(5.0, 5.0, 0.0, 100.0, logs);
  ASSERT_EQ(logs.size(), 2u);
  EXPECT_EQ(logs[1].text, "vehicle speed stamp went backwards on /vehicle/twist (bag loop?): history restarted");
  const StatusReport r = feed.report(0.0);
  EXPECT_EQ(r.value("clouds without a vehicle speed"), "1");
  EXPECT_EQ(r.value("vehicle speed restarts: time backwards"), "1");
  EXPECT_EQ(r.value("twist topic"), "/vehicle/twist");
}

TEST(OdometryFeed, WithoutATwistTopicNothingIsSeededOrMissing) {
  OdometryFeed feed(LidarOdometryParams(), OdometryFeedParams(), "");
  std::vector<LogLine> logs;
  feed.seedTwist(10.0, 100.0, logs);
  EXPECT_TRUE(logs.empty());
  EXPECT_EQ(feed.report(0.0).value("clouds without a vehicle speed"), "0");
  EXPECT_EQ(feed.report(0.0).value("twist topic"), "none");
}

TEST(OdometryFeed, InvalidCloudsAndMissingTransformsAreCountedByKind) {
  OdometryFeed feed(LidarOdometryParams(), OdometryFeedParams(), "");
  std::vector<LogLine> logs;
  feed.onCloud();
  feed.onInvalidCloud(DecodeError::kMissingXYZ, "velodyne", 10, 1, 0, 100.0, logs);
  ASSERT_EQ(logs.size(), 1u);
  EXPECT_EQ(logs[0].text, std::string("dropping cloud (frame 'velodyne', 10x1, 0 bytes): ") + toString(DecodeError::kMissingXYZ));
  StatusReport r = feed.report(1.5);
  EXPECT_EQ(r.message, "invalid clouds dropped");
  EXPECT_EQ(r.value(std::string("invalid clouds: ") + toString(DecodeError::kMissingXYZ)), "1");
  EXPECT_EQ(r.value("invalid clouds"), "1");
  EXPECT_EQ(r.value("clouds received"), "1");
  EXPECT_EQ(r.value("processing ms (last frame)"), "1.5");
  feed.onTransformFailure("velodyne", "no such frame", 100.0, logs);
  ASSERT_EQ(logs.size(), 2u);
  EXPECT_EQ(logs[1].text, "no transform velodyne -> base_link (no such frame): cloud skipped, no odometry");
  r = feed.report(0.0);
  EXPECT_EQ(r.message, "transform to base frame missing");
  EXPECT_EQ(r.value("transform failures"), "1");
}

TEST(OdometryFeed, AFrameFromThePriorIsLoggedAndReported) {
  OdometryFeed feed(LidarOdometryParams(), OdometryFeedParams(), "");
  std::vector<LogLine> logs;
  const std::vector<Eigen::Vector3f> none;
  feed.odometry().registerFrame(10.0, none);
  feed.onRegistered(100.0, logs);
  feed.odometry().registerFrame(10.1, none);
  feed.onRegistered(100.1, logs);
  ASSERT_EQ(feed.odometry().lastStats().result, LidarOdometryStats::Result::kExtrapolated);
  ASSERT_EQ(logs.size(), 1u) << joined(logs);
  EXPECT_EQ(logs[0].severity, LogSeverity::kWarn);
  EXPECT_NE(logs[0].text.find("cloud with 0 usable points"), std::string::npos);
  EXPECT_NE(logs[0].text.find("pose from the motion prior"), std::string::npos);
  feed.onPublished();
  const StatusReport r = feed.report(0.0);
  EXPECT_EQ(r.message, "poses from the motion prior");
  EXPECT_EQ(r.value("odometry published"), "1");
  EXPECT_EQ(r.value("last result"), toString(LidarOdometryStats::Result::kExtrapolated));
}

TEST(OdometryFeed, AStampGoingBackwardsIsLogged) {
  OdometryFeed feed(LidarOdometryParams(), OdometryFeedParams(), "");
  std::vector<Eigen::Vector3f> wall;
  for (int i = 0; i < 40; ++i)
    for (int j = 0; j < 10; ++j) {  // two walls and the ground between them
      wall.emplace_back(-20.0f + 1.5f * i, -8.0f + 0.2f * j, 1.5f * j);
      wall.emplace_back(15.0f, -20.0f + 1.0f * i, 1.5f * j);
      wall.emplace_back(-20.0f + 1.5f * i, -15.0f + 3.0f * j, -1.7f);
    }
  std::vector<LogLine> logs;
  feed.odometry().registerFrame(10.0, wall);
  feed.odometry().registerFrame(9.0, wall);
  ASSERT_EQ(feed.odometry().lastStats().result, LidarOdometryStats::Result::kReset);
  feed.onRegistered(100.0, logs);
  ASSERT_EQ(logs.size(), 1u);
  EXPECT_EQ(logs[0].text, "cloud stamp went backwards (bag loop?): odometry restarted at identity");
}

}  // namespace
}  // namespace icanc
