// icanc_sim_bag: renders a scenario file (config/scenarios/*.yaml) into a rosbag with the LiDAR
// clouds (sensor frame), /tf_static (vehicle -> sensor mount), /tf (odom -> vehicle), /odom
// (nav_msgs/Odometry: the vehicle's pose in odom, its twist in the vehicle frame), /vehicle/twist
// (geometry_msgs/TwistStamped at 50 Hz, as a vehicle's CAN bus gives it: sim::canTwist, the wheel
// speed and the yaw rate with their errors; what the LiDAR odometry takes where the scene fixes no
// motion), /planned_path (nav_msgs/Path in the vehicle frame at each cloud's stamp: the scripted
// path from 1 s behind to 6 s ahead, as a planner that the vehicle follows gives it, seen from the
// vehicle, so it holds whatever the ego motion source's odom; what the predictive model's
// ~predictive/path_topic takes) and
// /ground_truth (icanc/GroundTruthArray, same stamp as each cloud, vehicle frame): every scene
// object's true box, velocity relative to the vehicle, returns inside the box and its danger
// label from the scripted motion (docs/design.md, "Ground truth for dangerous"). The corridor
// comes from the vehicle profile named by the scenario's `profile` key (config/<name>.yaml) or
// --profile. Prints, per object, when it is truly dangerous.
//
//   icanc_sim_bag SCENARIO.yaml OUT.bag [--topic /points] [--start-time 1000]
//                 [--profile PROFILE.yaml] [--truth-topic /ground_truth] [--odom-topic /odom]
//                 [--twist-topic /vehicle/twist] [--path-topic /planned_path]
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <map>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include <pcl_conversions/pcl_conversions.h>
#include <rosbag/bag.h>
#include <geometry_msgs/TwistStamped.h>
#include <nav_msgs/Odometry.h>
#include <nav_msgs/Path.h>
#include <sensor_msgs/PointCloud2.h>
#include <tf2_eigen/tf2_eigen.h>
#include <tf2_msgs/TFMessage.h>

#include "icanc/ros/bag_static_tf.hpp"
#include "icanc/ros/conversions.hpp"
#include "icanc/core/common/yaml_params.hpp"
#include "icanc/ros/truth_msgs.hpp"
#include "icanc/sim/lidar_sim.hpp"
#include "icanc/sim/scenario.hpp"
#include "icanc/sim/scenario_truth.hpp"
#include "tool_help.hpp"

namespace {

geometry_msgs::TransformStamped toTransform(const Eigen::Isometry3f& pose, const std::string& parent,
                                           const std::string& child, const ros::Time& stamp) {
  geometry_msgs::TransformStamped t = tf2::eigenToTransform(pose.cast<double>());
  t.header.stamp = stamp;
  t.header.frame_id = parent;
  t.child_frame_id = child;
  return t;
}

// The simulator's odometry at t: exact, as wheel odometry fused with an IMU would report it (pose
// of the vehicle in odom, REP-105; twist in the vehicle frame, as nav_msgs/Odometry specifies).
// Covariances stay zero: the motion is known exactly.
nav_msgs::Odometry toOdometry(const icanc::sim::Scenario& s, double t, const ros::Time& stamp) {
  nav_msgs::Odometry odom;
  odom.header.stamp = stamp;
  odom.header.frame_id = "odom";
  odom.child_frame_id = s.vehicle_frame;
  odom.pose.pose = tf2::toMsg(s.vehiclePose(t).cast<double>());
  const icanc::sim::EgoTwist twist = s.vehicleTwist(t);
  odom.twist.twist.linear.x = twist.linear.x();
  odom.twist.twist.linear.y = twist.linear.y();
  odom.twist.twist.linear.z = twist.linear.z();
  odom.twist.twist.angular.z = twist.yaw_rate;
  return odom;
}

geometry_msgs::TwistStamped toTwistStamped(const icanc::MeasuredTwist& m, const std::string& frame,
                                           const ros::Time& stamp) {
  geometry_msgs::TwistStamped twist;
  twist.header.stamp = stamp;
  twist.header.frame_id = frame;
  twist.twist.linear.x = m.forward_mps;
  twist.twist.angular.z = m.yaw_rate_rad_s;
  return twist;
}

int usage(bool asked = false) {
  return icanc::tools::printUsage(
      "usage: icanc_sim_bag SCENARIO.yaml OUT.bag [--topic /points] [--start-time SEC]\n"
      "                     [--profile PROFILE.yaml] [--truth-topic /ground_truth]\n"
      "                     [--odom-topic /odom] [--twist-topic /vehicle/twist]\n"
      "                     [--path-topic /planned_path]\n",
      asked);
}

// Dangerous stretches of one object, for the printout: "7.0-9.0 s (21 frames)".
struct Episodes {
  std::string type;
  std::vector<std::pair<double, double>> spans;
  std::size_t frames = 0, in_corridor = 0;
  double last_t = -1.0;
  void add(double t, bool dangerous, bool in_corridor_now, double frame_dt) {
    in_corridor += in_corridor_now;
    if (!dangerous) return;
    ++frames;
    if (!spans.empty() && t - last_t < 1.5 * frame_dt) spans.back().second = t;
    else spans.emplace_back(t, t);
    last_t = t;
  }
};

// The path the vehicle drives, as a planner it follows would publish it at t: the scripted poses
// from 1 s behind (not before the scenario's start) to 6 s ahead, every 0.2 s, in the vehicle
// frame at t.
nav_msgs::Path toPlannedPath(const icanc::sim::Scenario& s, double t, const ros::Time& stamp) {
  constexpr int kBehind = 5, kAhead = 30;  // steps of kStepS
  constexpr double kStepS = 0.2;
  std_msgs::Header header;
  header.stamp = stamp;
  header.frame_id = s.vehicle_frame;
  std::vector<Eigen::Isometry3d> poses;
  for (int i = -kBehind; i <= kAhead; ++i)
    if (t + i * kStepS >= -1e-9) poses.push_back(s.vehiclePose(t + i * kStepS).cast<double>());
  return icanc::toRelativePath(header, s.vehiclePose(t).cast<double>(), poses);
}

}  // namespace

int main(int argc, char** argv) {
  if (icanc::tools::wantsHelp(argc, argv)) return usage(true);
  if (argc < 3) return usage();
  const std::string scenario_path = argv[1], bag_path = argv[2];
  std::string topic = "/points", truth_topic = "/ground_truth", odom_topic = "/odom",
              twist_topic = "/vehicle/twist", path_topic = "/planned_path", profile_override;
  double start_time = 1000.0;
  for (int i = 3; i < argc; i += 2) {
    if (i + 1 >= argc) return usage();
    const std::string flag = argv[i];
    if (flag == "--topic") topic = argv[i + 1];
    else if (flag == "--start-time") start_time = std::atof(argv[i + 1]);
    else if (flag == "--profile") profile_override = argv[i + 1];
    else if (flag == "--truth-topic") truth_topic = argv[i + 1];
    else if (flag == "--odom-topic") odom_topic = argv[i + 1];
    else if (flag == "--twist-topic") twist_topic = argv[i + 1];
    else if (flag == "--path-topic") path_topic = argv[i + 1];
    else return usage();
  }
  ros::Time::init();
  try {
    const icanc::sim::Scenario s = icanc::sim::loadScenario(scenario_path);
    const icanc::sim::LidarModel model = icanc::sim::LidarModel::byName(s.lidar);
    const std::string profile_path = profile_override.empty()
                                         ? icanc::sim::profilePath(scenario_path, s.profile)
                                         : profile_override;
    icanc::CorridorParams corridor;
    try {
      corridor = icanc::loadProfile(profile_path).corridor;
    } catch (const std::exception& e) {
      throw std::runtime_error("vehicle profile '" + s.profile + "' for the ground truth: " +
                               e.what() + " (give --profile PATH)");
    }
    const icanc::sim::ScenarioTruth truth(s, corridor);
    std::mt19937_64 rng(s.seed);
    std::mt19937_64 wheel_rng(s.seed + 1);  // its own: the clouds stay those of the seed
    const ros::Time t0(start_time);

    rosbag::Bag bag(bag_path, rosbag::bagmode::Write);
    bag.setCompression(rosbag::compression::LZ4);

    tf2_msgs::TFMessage mount;
    mount.transforms.push_back(toTransform(s.sensor_mount, s.vehicle_frame, s.sensor_frame, t0));
    icanc::writeStaticTransforms(bag, t0, mount, "/icanc_sim_bag");

    icanc::Cloud scan;
    std::size_t points = 0, dangerous = 0, dangerous_frames = 0;
    std::map<std::uint32_t, Episodes> episodes;
    const double frame_dt = 1.0 / s.rate_hz;
    for (std::size_t k = 0; k < s.frames(); ++k) {
      const double t = static_cast<double>(k) / s.rate_hz;
      const ros::Time stamp = t0 + ros::Duration(t);
      icanc::sim::renderScan(s.scene, t, s.sensorPose(t), model, s.noise, rng, scan);
      sensor_msgs::PointCloud2 cloud;
      pcl::toROSMsg(scan, cloud);
      cloud.header.stamp = stamp;
      cloud.header.frame_id = s.sensor_frame;
      points += scan.size();

      const icanc::sim::FrameTruth f = truth.frame(t, &scan);
      bool any = false;
      for (std::size_t i = 0; i < f.boxes.size(); ++i) {
        Episodes& e = episodes[f.boxes[i].id];
        e.type = f.boxes[i].type;
        e.add(t, f.labels[i].dangerous, f.labels[i].in_corridor, frame_dt);
        dangerous += f.labels[i].dangerous;
        any = any || f.labels[i].dangerous;
      }
      dangerous_frames += any;

      tf2_msgs::TFMessage odom;
      odom.transforms.push_back(toTransform(s.vehiclePose(t), "odom", s.vehicle_frame, stamp));
      bag.write("/tf", stamp, odom);
      bag.write(odom_topic, stamp, toOdometry(s, t, stamp));
      for (int j = 0; j < static_cast<int>(icanc::sim::kCanTwistHz * frame_dt + 0.5); ++j) {
        const double dt = j / icanc::sim::kCanTwistHz;
        bag.write(twist_topic, stamp + ros::Duration(dt),
                  toTwistStamped(icanc::sim::canTwist(s, t + dt, wheel_rng), s.vehicle_frame,
                                 stamp + ros::Duration(dt)));
      }
      bag.write(path_topic, stamp, toPlannedPath(s, t, stamp));
      bag.write(topic, stamp, cloud);
      bag.write(truth_topic, stamp,
                icanc::toGroundTruthArray(f.boxes, f.labels, f.num_points, corridor, stamp,
                                          s.vehicle_frame));
    }
    bag.close();
    std::cout << "wrote " << bag_path << ": scenario '" << s.name << "', " << s.frames()
              << " frames of " << model.name << " (" << points / s.frames() << " rays per frame) on "
              << topic << ", " << s.duration_s << " s\n";
    std::printf("ground truth on %s (profile %s): corridor |y| <= %.2f m, 0 <= x <= %.2f m, horizon "
                "%.1f s; %zu dangerous object-frames in %zu of %zu frames\n",
                truth_topic.c_str(), profile_path.c_str(), corridor.halfWidth(), corridor.length(),
                corridor.horizon_s, dangerous, dangerous_frames, s.frames());
    for (const auto& entry : episodes) {
      const Episodes& e = entry.second;
      if (e.frames == 0) continue;
      std::printf("  id %u %s: dangerous %zu frames (in corridor %zu):", entry.first,
                  e.type.c_str(), e.frames, e.in_corridor);
      for (const auto& span : e.spans) std::printf(" %.1f-%.1f s", span.first, span.second);
      std::printf("\n");
    }
  } catch (const std::exception& e) {
    std::cerr << "icanc_sim_bag: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
