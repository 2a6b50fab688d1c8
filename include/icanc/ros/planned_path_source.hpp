// Where the DangerDetector nodelet gets the planner's path (~predictive/path_topic, a
// nav_msgs/Path in any frame tf can bring into the vehicle frame, e.g. move_base's plan in odom or
// map): the newest path, put into the vehicle frame at the obstacles' stamp and cut to the part
// ahead of the vehicle (icanc::EgoPath). Glue only. Whatever cannot be used (no path yet, one
// older than max_age_s, unstamped, a transform tf does not have, a path the vehicle is not on)
// gives no path: the predictive model then predicts along the twist, as without a planner, and
// the reason is counted and warned about (throttled).
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <string>

#include <diagnostic_updater/DiagnosticStatusWrapper.h>
#include <nav_msgs/Path.h>
#include <ros/node_handle.h>
#include <ros/subscriber.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>

#include "icanc/core/motion/ego_path.hpp"

namespace icanc {

class PlannedPathSource {
 public:
  struct Params {
    std::string topic;             // "" = no planner: not subscribed
    double max_age_s = 1.0;        // a path stamped farther than this from the obstacles is stale
    double max_offset_m = 2.0;     // the vehicle farther than this from the path: not on it
    double max_heading_offset_rad = 1.5707963267948966;  // the path leads sideways or back
  };
  // "" when valid, else why.
  static std::string validate(const Params& params);

  PlannedPathSource(ros::NodeHandle& nh, const Params& params, const std::string& name);

  // The path in vehicle_frame at `stamp`, or null (and the reason counted) when none is usable.
  std::shared_ptr<const EgoPath> at(const ros::Time& stamp, const std::string& vehicle_frame);

  void addTo(diagnostic_updater::DiagnosticStatusWrapper& stat);

 private:
  void onPath(const nav_msgs::Path::ConstPtr& msg);
  void refuse(const std::string& why);

  Params params_;
  std::string name_;
  tf2_ros::Buffer tf_;
  std::unique_ptr<tf2_ros::TransformListener> listener_;
  ros::Subscriber sub_;
  std::mutex mutex_;
  nav_msgs::Path::ConstPtr path_;
  std::uint64_t along_path_ = 0;
  std::map<std::string, std::uint64_t> refused_;  // by reason
  std::string last_refusal_;
};

}  // namespace icanc
