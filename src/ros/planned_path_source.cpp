#include "icanc/ros/planned_path_source.hpp"

#include <cmath>
#include <vector>

#include <ros/console.h>
#include <tf2_eigen/tf2_eigen.h>

#include "icanc/ros/nodelet_support.hpp"

namespace icanc {

std::string PlannedPathSource::validate(const Params& p) {
  if (!(p.max_age_s > 0.0 && p.max_age_s <= 10.0)) return "predictive/path_max_age_s must be in (0, 10]";
  if (!(p.max_offset_m > 0.0 && p.max_offset_m <= 10.0))
    return "predictive/path_max_offset_m must be in (0, 10]";
  return "";
}

PlannedPathSource::PlannedPathSource(ros::NodeHandle& nh, const Params& params, const std::string& name)
    : params_(params), name_(name) {
  if (params_.topic.empty()) return;
  // /tf on the obstacles' callback queue: its transforms come in order with them, and no thread
  // polls for them.
  listener_.reset(new tf2_ros::TransformListener(tf_, nh, /*spin_thread=*/false));
  sub_ = nh.subscribe(params_.topic, 2, &PlannedPathSource::onPath, this);
}

void PlannedPathSource::onPath(const nav_msgs::Path::ConstPtr& msg) {
  std::lock_guard<std::mutex> lock(mutex_);
  path_ = msg;
}

void PlannedPathSource::refuse(const std::string& why) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    ++refused_[why];
    last_refusal_ = why;
  }
  ROS_WARN_STREAM_THROTTLE_NAMED(5.0, name_, name_ << ": planned path on " << params_.topic << " not used ("
                                                  << why << "): the vehicle predicted along its twist");
}

std::shared_ptr<const EgoPath> PlannedPathSource::at(const ros::Time& stamp, const std::string& vehicle_frame) {
  if (params_.topic.empty()) return nullptr;
  nav_msgs::Path::ConstPtr msg;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    msg = path_;
  }
  if (!msg) {
    refuse("no path received");
    return nullptr;
  }
  if (msg->header.stamp.isZero()) {
    refuse("path unstamped (header.stamp 0)");
    return nullptr;
  }
  if (std::abs((stamp - msg->header.stamp).toSec()) > params_.max_age_s) {
    refuse("path stamp farther than path_max_age_s from the obstacles'");
    return nullptr;
  }
  // The transform at the obstacles' stamp, without waiting: this listener runs on the same
  // callback queue as the obstacles, so the transform the ObstacleDetector used (it came before
  // them) is here already; one that is not is refused for this frame and counted.
  const std::string frame = bareFrame(msg->header.frame_id), vehicle = bareFrame(vehicle_frame);
  if (!tf_.canTransform(vehicle, frame, stamp)) {
    refuse("no transform " + frame + " -> " + vehicle + " at the stamp");
    return nullptr;
  }
  Eigen::Isometry3d vehicle_T_path;
  try {
    vehicle_T_path = tf2::transformToEigen(tf_.lookupTransform(vehicle, frame, stamp));
  } catch (const tf2::TransformException& e) {
    refuse("no transform " + frame + " -> " + vehicle + " at the stamp");
    return nullptr;
  }
  std::vector<Eigen::Vector2d> points;
  points.reserve(msg->poses.size());
  for (const geometry_msgs::PoseStamped& p : msg->poses) {
    const Eigen::Vector3d in_path(p.pose.position.x, p.pose.position.y, p.pose.position.z);
    points.push_back((vehicle_T_path * in_path).head<2>());
  }
  auto path = std::make_shared<EgoPath>();
  const EgoPath::Refused why = path->set(points, params_.max_offset_m, params_.max_heading_offset_rad);
  if (why != EgoPath::Refused::kNone) {
    refuse(std::string("path refused: ") + toString(why));
    return nullptr;
  }
  std::lock_guard<std::mutex> lock(mutex_);
  ++along_path_;
  return path;
}

void PlannedPathSource::addTo(diagnostic_updater::DiagnosticStatusWrapper& stat) {
  std::lock_guard<std::mutex> lock(mutex_);
  stat.add("path topic", params_.topic.empty() ? std::string("none (the twist)") : params_.topic);
  if (params_.topic.empty()) return;
  stat.add("arrays along the planned path", along_path_);
  std::uint64_t refused = 0;
  for (const auto& r : refused_) refused += r.second;
  stat.add("arrays along the twist (no usable path)", refused);
  for (const auto& r : refused_) stat.add("no usable path: " + r.first, r.second);
  stat.add("last path refusal", last_refusal_);
}

}  // namespace icanc
