// The LidarOdometry nodelet's logic, without ROS: its own parameters, the vehicle's twist
// (validated, kept in a TwistHistory and seeded into LidarOdometry at each cloud's stamp), the
// counts of invalid clouds, missing transforms and twists, what each frame's result says in the
// log, the covariances published with the pose and the diagnostics report. Two clocks, both
// arguments: stamps (the cloud's, the twist's) and `now`, the ROS time that paces log lines.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "icanc/core/common/log_line.hpp"
#include "icanc/core/common/status_report.hpp"
#include "icanc/core/motion/lidar_odometry.hpp"
#include "icanc/core/motion/measured_twist.hpp"
#include "icanc/core/perception/cloud_decode.hpp"

namespace icanc {

// The nodelet's parameters beside LidarOdometryParams.
struct OdometryFeedParams {
  std::string base_frame = "base_link";
  std::string odom_frame = "odom";
  int max_points = 2000000;
  std::string twist_topic;         // "": no vehicle speed
  double twist_max_age_s = 0.2;    // a speed this far from the cloud's stamp is not used [s]
  bool twist_yaw_rate = false;     // twist.angular.z is the vehicle's yaw rate (a gyro)
};

// "" when valid, else the first problem naming its key.
std::string validate(const OdometryFeedParams& params);

// Diagonal variances of the published pose and twist: the registered ones centimetre-level, those
// from the motion prior a metre and 0.1 rad, so a fusing filter trusts them little.
struct OdometryVariances {
  double position, rotation, velocity, rate;
};
OdometryVariances odometryVariances(LidarOdometryStats::Result result);

class OdometryFeed {
 public:
  // `twist_topic`: the twist's resolved name, for the log ("" without one).
  OdometryFeed(const LidarOdometryParams& odometry, const OdometryFeedParams& params,
               const std::string& twist_topic);

  LidarOdometry& odometry() { return odometry_; }
  const OdometryFeedParams& params() const { return params_; }

  // The vehicle's twist measured at `stamp` (0: unstamped, refused).
  void onTwist(double stamp, double forward_mps, double yaw_rate_rad_s, double now, std::vector<LogLine>& logs);

  void onCloud() { ++received_; }
  void onInvalidCloud(DecodeError error, const std::string& frame, std::uint32_t width, std::uint32_t height,
                      std::size_t bytes, double now, std::vector<LogLine>& logs);
  void onTransformFailure(const std::string& frame, const std::string& what, double now, std::vector<LogLine>& logs);
  // The measured twist at the cloud's stamp to the odometry, before it registers the cloud.
  void seedTwist(double stamp, double now, std::vector<LogLine>& logs);
  // After the registration: what its result says.
  void onRegistered(double now, std::vector<LogLine>& logs);
  void onPublished() { ++published_; }

  // WARN while a count grew since the previous report.
  StatusReport report(double last_ms);

 private:
  LidarOdometry odometry_;
  OdometryFeedParams params_;
  std::string twist_topic_;
  TwistHistory speeds_;
  std::map<DecodeError, std::uint64_t> invalid_;
  std::uint64_t received_ = 0, published_ = 0, tf_failures_ = 0;
  FaultGrowth faults_;  // the fault kinds counted at the last report
  std::uint64_t invalid_speeds_ = 0, speed_missing_ = 0, speed_restarts_ = 0;
  LogThrottle invalid_twist_log_{1.0}, restart_log_{1.0}, missing_log_{5.0}, invalid_cloud_log_{1.0};
  LogThrottle tf_log_{5.0}, reset_log_{1.0}, seeded_log_{10.0}, degenerate_log_{1.0}, extrapolated_log_{1.0};
};

}  // namespace icanc
