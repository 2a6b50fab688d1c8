#include "icanc/ros/cloud_input_checks.hpp"

#include <limits>
#include <sstream>

#include <ros/console.h>

namespace icanc {

std::string CloudInputChecks::load(ParamReader& reader) {
  StampCheckParams stamp_params;
  SensorHealthParams health_params;
  visitParams(reader, stamp_params);
  visitParams(reader, health_params);
  stamps_.setParams(stamp_params);
  health_.setParams(health_params);
  const std::string why = validate(stamp_params);
  return why.empty() ? validate(health_params) : why;
}

bool CloudInputChecks::stampValid(const ros::Time& stamp, InputMonitor& input) {
  const double previous = stamps_.previousStamp();
  // The receipt clock for the stamps' rate: ROS time on a vehicle; on sim time (a replay) the
  // clock is the bag's own, so the rate is not judged there.
  const double receipt = ros::Time::isSimTime() ? std::numeric_limits<double>::quiet_NaN()
                                                : ros::Time::now().toSec();
  const StampVerdict verdict = stamps_.check(stamp.toSec(), receipt);
  if (verdict == StampVerdict::kOk) return true;
  input.invalid();
  if (verdict == StampVerdict::kRate) {
    ROS_ERROR_THROTTLE_NAMED(1.0, log_name_, "[%s] dropping cloud stamped %.6f: its stamps advance "
                             "%.2f times the receipt clock over %.1f s (allowed %.2f to %.2f): the "
                             "sensor's clock runs fast or slow, speeds would be wrong; lamp on",
                             log_name_.c_str(), stamp.toSec(), stamps_.rateRatio(), kStampRateWindowS,
                             1.0 / kMaxStampRate, kMaxStampRate);
    return false;
  }
  // Throttled per kind: a burst of one kind does not hide the first of another.
  const ros::WallTime now = ros::WallTime::now();
  ros::WallTime& last = logged_[static_cast<int>(verdict)];
  if (last.isZero() || (now - last).toSec() >= 1.0) {
    last = now;
    ROS_WARN_NAMED(log_name_, "[%s] dropping cloud stamped %.6f: %s (previous %.6f); not valid "
                   "input, the lamp fails safe if this goes on", log_name_.c_str(), stamp.toSec(),
                   toString(verdict), previous);
  }
  return false;
}

std::size_t CloudInputChecks::checkHealth(std::size_t points) {
  const std::size_t valid = returns_.valid();
  const bool was_blind = health_.blind();
  if (health_.update(valid, points, returns_.sectors())) {
    if (health_.blindSector() >= 0) {
      const double width = 360.0 / health_.params().sectors;
      ROS_ERROR_THROTTLE_NAMED(1.0, log_name_, "[%s] sensor blind in azimuth %.0f..%.0f deg: %.1f %% "
                               "of the returns it delivered when it saw the scene: lamp on",
                               log_name_.c_str(), health_.blindSector() * width,
                               (health_.blindSector() + 1) * width,
                               100.0 * health_.blindSectorShare());
    } else {
      ROS_ERROR_THROTTLE_NAMED(1.0, log_name_, "[%s] sensor blind: %zu valid returns of %zu points "
                               "(%.1f %% this frame, %.1f %% over the window): lamp on",
                               log_name_.c_str(), valid, points, 100.0 * health_.frameShare(),
                               100.0 * health_.windowShare());
    }
  } else if (was_blind) {
    ROS_INFO_NAMED(log_name_, "[%s] sensor returns are back (%.1f %% this frame): not blind",
                   log_name_.c_str(), 100.0 * health_.frameShare());
  }
  return valid;
}

void CloudInputChecks::addTo(diagnostic_updater::DiagnosticStatusWrapper& stat) {
  if (health_.blind())
    stat.mergeSummary(diagnostic_msgs::DiagnosticStatus::ERROR,
                      health_.blindSector() >= 0 ? "sensor blind in a sector (lamp on)"
                                                 : "sensor blind (lamp on)");
  if (stamps_.rejected() > reported_rejected_)
    stat.mergeSummary(diagnostic_msgs::DiagnosticStatus::WARN, "cloud stamps rejected");
  reported_rejected_ = stamps_.rejected();
  for (int v = 1; v < kStampVerdicts; ++v) {
    const auto verdict = static_cast<StampVerdict>(v);
    stat.add(std::string("stamps rejected: ") + toString(verdict), stamps_.count(verdict));
  }
  stat.add("repeated stamps", stamps_.count(StampVerdict::kRepeated));
  stat.add("stamp rate over receipt clock", stamps_.rateRatio());
  stat.add("sensor blind", health_.blind());
  stat.add("sensor blind frames", health_.blindFrames());
  stat.add("sensor blind episodes", health_.blindEpisodes());
  stat.add("valid return share (last frame)", health_.frameShare());
  stat.add("valid return share (window)", health_.windowShare());
  stat.add("sensor blind sector frames", health_.blindSectorFrames());
  if (health_.blindSector() >= 0) {
    const double width = 360.0 / health_.params().sectors;
    std::ostringstream sector;
    sector << health_.blindSector() * width << ".." << (health_.blindSector() + 1) * width << " deg";
    stat.add("blind sector (azimuth)", sector.str());
    stat.add("blind sector's share of its returns", health_.blindSectorShare());
  }
}

}  // namespace icanc
