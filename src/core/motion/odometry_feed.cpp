#include "icanc/core/motion/odometry_feed.hpp"

namespace icanc {

std::string validate(const OdometryFeedParams& p) {
  if (p.max_points <= 0) return "max_points must be > 0";
  if (p.base_frame.empty() || p.odom_frame.empty()) return "base_frame and odom_frame must not be empty";
  if (p.base_frame == p.odom_frame) return "base_frame must differ from odom_frame";
  if (!(p.twist_max_age_s > 0.0 && p.twist_max_age_s <= 1.0)) return "twist_max_age_s must be in (0, 1]";
  return "";
}

OdometryVariances odometryVariances(LidarOdometryStats::Result result) {
  using Result = LidarOdometryStats::Result;
  const bool measured = result == Result::kRegistered || result == Result::kHeld || result == Result::kAtRest ||
                        result == Result::kFirstFrame || result == Result::kReset;
  if (measured) return OdometryVariances{0.05 * 0.05, 0.01 * 0.01, 0.2 * 0.2, 0.02 * 0.02};
  return OdometryVariances{1.0, 0.01, 4.0, 0.04};
}

OdometryFeed::OdometryFeed(const LidarOdometryParams& odometry, const OdometryFeedParams& params,
                           const std::string& twist_topic)
    : odometry_(odometry), params_(params), twist_topic_(twist_topic) {}

void OdometryFeed::onTwist(double stamp, double forward_mps, double yaw_rate_rad_s, double now,
                           std::vector<LogLine>& logs) {
  if (stamp == 0.0) {  // an unstamped driver: nothing to match a cloud's stamp to
    ++invalid_speeds_;
    if (invalid_twist_log_.allow(now))
      logs.push_back({LogSeverity::kError,
                      formatText("vehicle twist on %s dropped: header.stamp is 0 (it is matched to each "
                                 "cloud's stamp; stamp it when measured)", twist_topic_.c_str())});
    return;
  }
  MeasuredTwist twist = measuredTwist(forward_mps);
  if (params_.twist_yaw_rate) twist.yaw_rate_rad_s = yaw_rate_rad_s;
  const TwistHistory::Added added = speeds_.add(stamp, twist);
  if (added == TwistHistory::Added::kInvalid) {
    ++invalid_speeds_;
    if (invalid_twist_log_.allow(now))
      logs.push_back({LogSeverity::kError,
                      formatText("vehicle twist on %s dropped: %g m/s, %g rad/s at stamp %.3f is no "
                                 "measurement", twist_topic_.c_str(), forward_mps, yaw_rate_rad_s, stamp)});
  } else if (added == TwistHistory::Added::kRestarted) {
    ++speed_restarts_;
    if (restart_log_.allow(now))
      logs.push_back({LogSeverity::kWarn, formatText("vehicle speed stamp went backwards on %s (bag loop?): "
                                                     "history restarted", twist_topic_.c_str())});
  }
}

void OdometryFeed::onInvalidCloud(DecodeError error, const std::string& frame, std::uint32_t width,
                                  std::uint32_t height, std::size_t bytes, double now, std::vector<LogLine>& logs) {
  ++invalid_[error];
  if (invalid_cloud_log_.allow(now))
    logs.push_back({LogSeverity::kError, formatText("dropping cloud (frame '%s', %ux%u, %zu bytes): %s",
                                                    frame.c_str(), width, height, bytes, toString(error))});
}

void OdometryFeed::onTransformFailure(const std::string& frame, const std::string& what, double now,
                                      std::vector<LogLine>& logs) {
  ++tf_failures_;
  if (tf_log_.allow(now))
    logs.push_back({LogSeverity::kWarn, formatText("no transform %s -> %s (%s): cloud skipped, no odometry",
                                                   frame.c_str(), params_.base_frame.c_str(), what.c_str())});
}

void OdometryFeed::seedTwist(double stamp, double now, std::vector<LogLine>& logs) {
  if (params_.twist_topic.empty()) return;
  MeasuredTwist twist;
  if (speeds_.at(stamp, params_.twist_max_age_s, twist)) {
    odometry_.seedTwist(twist);
    return;
  }
  ++speed_missing_;
  if (missing_log_.allow(now))
    logs.push_back({LogSeverity::kWarn,
                    formatText("no vehicle speed on %s within %.2f s of the cloud at %.3f: the LiDAR alone "
                               "for this frame", twist_topic_.c_str(), params_.twist_max_age_s, stamp)});
}

void OdometryFeed::onRegistered(double now, std::vector<LogLine>& logs) {
  const LidarOdometryStats& stats = odometry_.lastStats();
  const LidarOdometryParams& p = odometry_.params();
  using Result = LidarOdometryStats::Result;
  if (stats.result == Result::kReset) {
    if (reset_log_.allow(now))
      logs.push_back({LogSeverity::kWarn, "cloud stamp went backwards (bag loop?): odometry restarted at identity"});
  } else if (stats.result == Result::kDegenerate && stats.speed_seeded) {
    // Expected on a flat road or between walls; the vehicle's speed carries the pose.
    if (seeded_log_.allow(now))
      logs.push_back({LogSeverity::kInfo,
                      formatText("registration degenerate (horizontal observability %.3f, at least %.3f wanted): "
                                 "pose from the vehicle's measured motion",
                                 stats.horizontal_observability, p.min_horizontal_observability)});
  } else if (stats.result == Result::kDegenerate) {
    if (degenerate_log_.allow(now))
      logs.push_back({LogSeverity::kWarn,
                      formatText("registration degenerate (%zu of %zu points matched, horizontal observability "
                                 "%.3f, at least %.3f wanted): pose from the motion prior",
                                 stats.correspondences, stats.registration_points,
                                 stats.horizontal_observability, p.min_horizontal_observability)});
  } else if (stats.result == Result::kExtrapolated) {
    if (extrapolated_log_.allow(now))
      logs.push_back({LogSeverity::kWarn, formatText("cloud with %zu usable points (< %d): pose from the %s",
                                                     stats.registration_points, p.min_points,
                                                     stats.speed_seeded ? "vehicle's measured motion"
                                                                        : "motion prior")});
  }
}

StatusReport OdometryFeed::report(double last_ms) {
  StatusReport stat;
  const std::uint64_t invalid = addCountsByKind(stat, "invalid clouds: ", invalid_);
  const LidarOdometryCounters& c = odometry_.counters();
  const char* const what[4] = {"invalid clouds dropped", "transform to base frame missing",
                               "vehicle speed invalid or missing", "poses from the motion prior"};
  const int grown = faults_.firstGrown({invalid, tf_failures_, invalid_speeds_ + speed_missing_,
                                        c.degenerate + c.extrapolated});
  if (grown < 0)
    stat.summary(StatusLevel::kOk, "ok");
  else
    stat.summary(StatusLevel::kWarn, what[grown]);
  const LidarOdometryStats& s = odometry_.lastStats();
  stat.add("clouds received", received_);
  stat.add("odometry published", published_);
  stat.add("invalid clouds", invalid);
  stat.add("transform failures", tf_failures_);
  stat.add("frames", c.frames);
  stat.add("registered", c.registered);
  stat.add("at rest (the scan fits no motion)", c.at_rest);
  stat.add("degenerate (motion prior)", c.degenerate);
  stat.add("of those, registered along-track held (speed only)", c.held);
  stat.add("too few points (motion prior)", c.extrapolated);
  stat.add("resets: time backwards", c.resets);
  stat.add("gaps above max_dt_s", c.gaps);
  stat.add("non-finite points", c.nonfinite_points);
  stat.add("twist topic", params_.twist_topic.empty() ? std::string("none") : twist_topic_);
  stat.add("poses from the measured twist (scene degenerate)", c.speed_seeded);
  stat.add("clouds without a vehicle speed", speed_missing_);
  stat.add("invalid vehicle speeds", invalid_speeds_);
  stat.add("vehicle speed restarts: time backwards", speed_restarts_);
  stat.add("last result", std::string(toString(s.result)));
  stat.add("registration points", s.registration_points);
  stat.add("correspondences", s.correspondences);
  stat.add("iterations", s.iterations);
  stat.add("threshold m", s.threshold_m);
  stat.add("map points", s.map_points);
  stat.add("downsample ms", s.downsample_ms);
  stat.add("registration ms", s.register_ms);
  stat.add("map ms", s.map_ms);
  stat.add("processing ms (last frame)", last_ms);
  return stat;
}

}  // namespace icanc
