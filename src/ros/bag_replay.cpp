#include "icanc/ros/bag_replay.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <tuple>
#include <vector>

#include <geometry_msgs/TwistStamped.h>
#include <nav_msgs/Odometry.h>
#include <nav_msgs/Path.h>
#include <ros/names.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <rosgraph_msgs/Clock.h>
#include <sensor_msgs/PointCloud2.h>
#include <tf2_eigen/tf2_eigen.h>
#include <tf2_msgs/TFMessage.h>
#include <tf2_ros/static_transform_broadcaster.h>

#include "icanc/GroundTruthArray.h"
#include "icanc/LightState.h"
#include "icanc/ObstacleArray.h"
#include "icanc/ros/param_reader.hpp"
#include "icanc/ros/planned_path_source.hpp"

namespace icanc {
namespace {

template <class Pred>
bool waitFor(Pred pred, double timeout) {
  const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(timeout);
  while (ros::ok() && !pred()) {
    if (ros::WallTime::now() > end) return false;
    ros::WallDuration(0.0005).sleep();
  }
  return pred();
}

std::vector<TruthObject> toTruth(const GroundTruthArray& gt) {
  std::vector<TruthObject> out;
  for (const auto& o : gt.objects) {
    TruthObject t;
    t.id = o.id;
    t.type = o.type;
    t.center = Eigen::Vector2d(o.pose.position.x, o.pose.position.y);
    t.size = Eigen::Vector2d(o.dimensions.x, o.dimensions.y);
    t.yaw = 2.0 * std::atan2(o.pose.orientation.z, o.pose.orientation.w);
    t.velocity = Eigen::Vector2d(o.velocity.x, o.velocity.y);
    t.num_points = o.num_points;
    t.dangerous = o.dangerous;
    t.time_to_corridor = o.time_to_corridor;
    t.horizon_cut = o.horizon_cut;
    out.push_back(t);
  }
  return out;
}

std::vector<DetectedObject> toDetections(const ObstacleArray& array) {
  std::vector<DetectedObject> out;
  for (const auto& o : array.obstacles) {
    DetectedObject d;
    d.id = o.id;
    d.center = Eigen::Vector2d(o.pose.position.x, o.pose.position.y);
    d.velocity = Eigen::Vector2d(o.velocity.x, o.velocity.y);
    d.velocity_over_ground = Eigen::Vector2d(o.velocity_over_ground.x, o.velocity_over_ground.y);
    d.motion = o.motion_state <= static_cast<std::uint8_t>(MotionState::kMoving)
                   ? static_cast<MotionState>(o.motion_state)
                   : MotionState::kUnknown;
    d.dangerous = o.dangerous;
    d.age = o.age;
    d.has_aabb = true;
    d.aabb_min = Eigen::Vector2d(o.aabb_min.x, o.aabb_min.y);
    d.aabb_max = Eigen::Vector2d(o.aabb_max.x, o.aabb_max.y);
    d.velocity_std = Eigen::Vector2d(o.velocity_std_axes.x, o.velocity_std_axes.y);
    out.push_back(d);
  }
  return out;
}

// The bag's planned path (the one the graph's DangerDetector takes) in the ground truth's frame at
// each cloud's stamp, for the danger model on perfect tracks: the path with that stamp, placed by
// the bag's own /tf when it is in another frame (a recorded planner's path in odom; icanc_sim_bag
// and icanc_kitti2bag write theirs in the vehicle frame). Null when there is none.
class BagPaths {
 public:
  // params: the DangerDetector's (topic "": no path).
  BagPaths(rosbag::Bag& bag, const PlannedPathSource::Params& params) : params_(params) {
    if (params_.topic.empty()) return;
    for (const rosbag::MessageInstance& m : rosbag::View(bag, rosbag::TopicQuery({params_.topic, "/tf"}))) {
      if (auto path = m.instantiate<nav_msgs::Path>()) paths_[path->header.stamp] = path;
      else if (auto tf = m.instantiate<tf2_msgs::TFMessage>())
        for (const auto& t : tf->transforms)
          poses_[{t.header.frame_id, t.child_frame_id, t.header.stamp.toNSec()}] = tf2::transformToEigen(t);
    }
  }

  std::shared_ptr<const EgoPath> at(const ros::Time& stamp, const std::string& frame) const {
    const auto it = paths_.find(stamp);
    if (it == paths_.end()) return nullptr;
    const nav_msgs::Path& msg = *it->second;
    Eigen::Isometry3d frame_T_path = Eigen::Isometry3d::Identity();
    if (msg.header.frame_id != frame) {
      const auto pose = poses_.find({msg.header.frame_id, frame, stamp.toNSec()});
      if (pose == poses_.end()) return nullptr;
      frame_T_path = pose->second.inverse();
    }
    std::vector<Eigen::Vector2d> points;
    for (const geometry_msgs::PoseStamped& p : msg.poses)
      points.push_back((frame_T_path * Eigen::Vector3d(p.pose.position.x, p.pose.position.y, 0.0)).head<2>());
    auto path = std::make_shared<EgoPath>();
    if (path->set(points, params_.max_offset_m, params_.max_heading_offset_rad) != EgoPath::Refused::kNone)
      return nullptr;
    return path;
  }

 private:
  PlannedPathSource::Params params_;
  std::map<ros::Time, nav_msgs::Path::ConstPtr> paths_;
  std::map<std::tuple<std::string, std::string, std::uint64_t>, Eigen::Isometry3d> poses_;  // parent, child, stamp
};

// What a nodelet of the graph would refuse at load, as an exception naming `section`: the
// reader's first error (a malformed key), else `validation` (validate() of what was read).
void throwIfRefused(const std::string& section, const ParamReader& reader,
                    const std::string& validation) {
  const std::string& why = reader.error().empty() ? validation : reader.error();
  if (!why.empty()) throw std::runtime_error(section + ": " + why);
}

}  // namespace

std::vector<EvalFrame> replayBag(ros::NodeHandle& nh, const ReplayOptions& opt) {
  rosbag::Bag bag;
  try {
    bag.open(opt.bag, rosbag::bagmode::Read);
  } catch (const rosbag::BagException& e) {
    throw std::runtime_error(opt.bag + ": " + e.what());
  }

  // Ground truth by stamp, static transforms.
  std::map<ros::Time, std::vector<TruthObject>> truth;
  std::string truth_frame;
  tf2_ros::StaticTransformBroadcaster static_tf;
  for (const rosbag::MessageInstance& m : rosbag::View(bag, rosbag::TopicQuery({opt.truth_topic, "/tf_static"}))) {
    if (auto gt = m.instantiate<GroundTruthArray>()) {
      truth[gt->header.stamp] = toTruth(*gt);
      truth_frame = gt->header.frame_id;
    }
    if (auto tf = m.instantiate<tf2_msgs::TFMessage>()) static_tf.sendTransform(tf->transforms);
  }

  std::mutex mutex;
  std::map<ros::Time, ObstacleArray::ConstPtr> arrays;
  std::map<ros::Time, LightState::ConstPtr> answers;
  ros::Subscriber array_sub = nh.subscribe<ObstacleArray>(opt.ns + "/obstacles_danger", 50,
      [&](const ObstacleArray::ConstPtr& m) { std::lock_guard<std::mutex> l(mutex); arrays[m->header.stamp] = m; });
  ros::Subscriber state_sub = nh.subscribe<LightState>(opt.ns + "/light_state", 200,
      [&](const LightState::ConstPtr& m) { std::lock_guard<std::mutex> l(mutex); answers[m->input_stamp] = m; });
  ros::Publisher clock_pub = nh.advertise<rosgraph_msgs::Clock>("/clock", 10);
  ros::Publisher cloud_pub = nh.advertise<sensor_msgs::PointCloud2>(opt.points_topic, 2);

  // The vehicle's motion, published ahead of each cloud (header stamps up to the cloud's).
  // Not when the graph makes it itself (LidarOdometry): two sources of one transform would fight.
  std::string ego_source;
  ros::param::get(opt.ns + "/ego_motion/source", ego_source);
  std::vector<rosbag::MessageInstance> motion;
  // Its measured speed (icanc_sim_bag's /vehicle/twist), when the graph's LidarOdometry takes one.
  std::string twist_topic;
  if (ego_source == "lidar") ros::param::get(opt.ns + "/lidar_odometry/twist_topic", twist_topic);
  if (!twist_topic.empty()) twist_topic = ros::names::resolve(opt.ns, twist_topic);
  // The planner's path (icanc_sim_bag's /planned_path), when the graph's DangerDetector takes one.
  PlannedPathSource::Params path_params;
  ros::param::get(opt.ns + "/danger_detector/predictive/path_topic", path_params.topic);
  if (!path_params.topic.empty()) path_params.topic = ros::names::resolve(opt.ns, path_params.topic);
  ros::param::get(opt.ns + "/danger_detector/predictive/path_max_offset_m", path_params.max_offset_m);
  const BagPaths perfect_paths(bag, path_params);
  const std::string& path_topic = path_params.topic;
  std::vector<std::string> motion_topics;
  if (opt.publish_tf && ego_source != "lidar") motion_topics = {"/tf", opt.odom_topic};
  if (!twist_topic.empty()) motion_topics.push_back(twist_topic);
  if (!path_topic.empty()) motion_topics.push_back(path_topic);
  if (!motion_topics.empty())
    for (const rosbag::MessageInstance& m : rosbag::View(bag, rosbag::TopicQuery(motion_topics)))
      motion.push_back(m);
  const bool has_tf = std::any_of(motion.begin(), motion.end(),
                                  [](const rosbag::MessageInstance& m) { return m.getTopic() == "/tf"; });
  const bool has_speed = std::any_of(motion.begin(), motion.end(), [&](const rosbag::MessageInstance& m) {
    return m.getTopic() == twist_topic;
  });
  ros::Publisher tf_pub = nh.advertise<tf2_msgs::TFMessage>("/tf", 100);
  ros::Publisher odom_pub = nh.advertise<nav_msgs::Odometry>(opt.odom_topic, 100);
  const bool has_path = std::any_of(motion.begin(), motion.end(), [&](const rosbag::MessageInstance& m) {
    return m.getTopic() == path_topic;
  });
  ros::Publisher speed_pub, path_pub;
  if (has_speed) speed_pub = nh.advertise<geometry_msgs::TwistStamped>(twist_topic, 100);
  if (has_path) path_pub = nh.advertise<nav_msgs::Path>(path_topic, 10);
  // The measured twist goes 0.15 s ahead of each cloud (the samples the odometry interpolates at
  // its stamp left a frame earlier): two subscriptions of the manager are served in no set order,
  // and a sample published just before the cloud might come after it.
  const ros::Duration motion_ahead(has_speed ? 0.15 : 0.0);
  std::size_t next_motion = 0;
  const auto publishMotionUpTo = [&](const ros::Time& stamp) {
    for (; next_motion < motion.size() && motion[next_motion].getTime() <= stamp; ++next_motion) {
      if (auto tf = motion[next_motion].instantiate<tf2_msgs::TFMessage>()) tf_pub.publish(tf);
      else if (auto odom = motion[next_motion].instantiate<nav_msgs::Odometry>()) odom_pub.publish(odom);
      else if (auto speed = motion[next_motion].instantiate<geometry_msgs::TwistStamped>()) speed_pub.publish(speed);
      else if (auto path = motion[next_motion].instantiate<nav_msgs::Path>()) path_pub.publish(path);
    }
  };

  rosbag::View clouds(bag, rosbag::TopicQuery(opt.points_topic));
  if (clouds.size() == 0) throw std::runtime_error(opt.bag + ": no messages on " + opt.points_topic);
  rosgraph_msgs::Clock clock;
  clock.clock = clouds.getBeginTime() - ros::Duration(0.5);
  const bool up = waitFor([&] {
    clock_pub.publish(clock);  // the graph's timers need a clock to come up
    return cloud_pub.getNumSubscribers() > 0 && array_sub.getNumPublishers() > 0 &&
           state_sub.getNumPublishers() > 0 && (!has_tf || tf_pub.getNumSubscribers() > 0) &&
           (!has_speed || speed_pub.getNumSubscribers() > 0) &&
           (!has_path || path_pub.getNumSubscribers() > 0);
  }, opt.graph_timeout_s);
  if (!up) throw std::runtime_error("the icanc graph in " + opt.ns + " did not come up");
  // The first cloud's motion goes out before the settling pause: a later cloud's samples left with
  // the cloud before it, a processed frame ago; without this the first cloud could overtake its
  // own (the LiDAR odometry then ran that frame without the measured twist, and the run's counts
  // moved from one replay to the next).
  publishMotionUpTo(clouds.begin()->getTime() + motion_ahead);
  ros::WallDuration(0.3).sleep();  // let the connections settle

  std::vector<EvalFrame> frames;
  const ros::WallTime wall_start = ros::WallTime::now();
  const ros::Time bag_start = clouds.getBeginTime();
  for (const rosbag::MessageInstance& m : clouds) {
    auto cloud = m.instantiate<sensor_msgs::PointCloud2>();
    if (!cloud) continue;
    if (opt.max_frames && frames.size() >= opt.max_frames) break;
    const ros::Time stamp = cloud->header.stamp;
    if (opt.rate > 0.0) {
      const ros::WallTime due = wall_start + ros::WallDuration((stamp - bag_start).toSec() / opt.rate);
      const ros::WallTime now = ros::WallTime::now();
      if (due > now) (due - now).sleep();
    }
    // Advance the clock in 20 ms steps so the controller's timer runs between frames.
    while (clock.clock + ros::Duration(0.02) < stamp) {
      clock.clock += ros::Duration(0.02);
      clock_pub.publish(clock);
    }
    clock.clock = stamp;
    clock_pub.publish(clock);
    publishMotionUpTo(m.getTime() + motion_ahead);
    cloud_pub.publish(cloud);

    EvalFrame f;
    f.t = stamp.toSec();
    f.processed = waitFor([&] {
      std::lock_guard<std::mutex> l(mutex);
      return arrays.count(stamp) && answers.count(stamp);
    }, opt.frame_timeout_s);
    if (f.processed) {
      std::lock_guard<std::mutex> l(mutex);
      f.detections = toDetections(*arrays[stamp]);
      f.ego_velocity = Eigen::Vector2d(arrays[stamp]->ego_twist.linear.x, arrays[stamp]->ego_twist.linear.y);
      f.ego_yaw_rate = arrays[stamp]->ego_twist.angular.z;
      const std::string& ego = arrays[stamp]->ego_motion_status;
      f.ego_motion = ego == "measured" || ego == "extrapolated" || ego == "jump";
      f.ego_motion_fault = ego == "extrapolated" || ego == "jump" || ego == "lost";
      f.lamp_on = answers[stamp]->on;
      f.latency_ms = answers[stamp]->input_latency_ms;
      arrays.erase(arrays.begin(), arrays.upper_bound(stamp));
    }
    auto it = truth.find(stamp);
    if (it != truth.end()) f.truth = it->second;
    f.ego_path = perfect_paths.at(stamp, truth_frame);
    frames.push_back(std::move(f));
    if (!ros::ok()) break;
  }
  return frames;
}

void readGraphParams(const std::string& ns, EvalParams& params) {
  const ros::NodeHandle lamp(ns + "/light_controller");
  lamp.param("tau_s", params.lamp_tau_s, params.lamp_tau_s);
  lamp.param("recheck_below_s", params.lamp_recheck_below_s, params.lamp_recheck_below_s);
  ParamReader danger(ros::NodeHandle(ns + "/danger_detector"));
  readParams(danger, params.danger);
  throwIfRefused(ns + "/danger_detector", danger, validate(params.danger));
  // The detector's region of interest (EvalReport::detection_roi), in its target frame, the truth's.
  ParamReader detector(ros::NodeHandle(ns + "/obstacle_detector"));
  ObstacleDetectorParams obstacle;
  readParams(detector, obstacle);
  throwIfRefused(ns + "/obstacle_detector", detector, validate(obstacle.prep));
  params.roi = Eigen::AlignedBox2d(obstacle.prep.roi_min.head<2>().cast<double>(),
                                   obstacle.prep.roi_max.head<2>().cast<double>());
}

void readLampPlacement(const std::string& ns, SegmentLampParams& lamp) {
  ParamReader reader(ros::NodeHandle(ns + "/light_controller"));
  SegmentLampParams profile;
  readParams(reader, profile);
  throwIfRefused(ns + "/light_controller", reader, validate(profile));
  lamp.lamp_position_m = profile.lamp_position_m;
  lamp.segment_margin_deg = profile.segment_margin_deg;
  lamp.low_beam_below_m = profile.low_beam_below_m;
  lamp.full_power_range_m = profile.full_power_range_m;
  lamp.min_level = profile.min_level;
}

}  // namespace icanc
