// icanc_sim_bag: renders a scenario file (config/scenarios/*.yaml) into a rosbag with the LiDAR
// clouds (sensor frame), /tf_static (vehicle -> sensor mount) and /tf (odom -> vehicle).
//
//   icanc_sim_bag SCENARIO.yaml OUT.bag [--topic /points] [--start-time 1000]
#include <cstdlib>
#include <iostream>
#include <random>
#include <string>

#include <pcl_conversions/pcl_conversions.h>
#include <rosbag/bag.h>
#include <sensor_msgs/PointCloud2.h>
#include <tf2_eigen/tf2_eigen.h>
#include <tf2_msgs/TFMessage.h>

#include "icanc/sim/lidar_sim.hpp"
#include "icanc/sim/scenario.hpp"

namespace {

geometry_msgs::TransformStamped toTransform(const Eigen::Isometry3f& pose, const std::string& parent,
                                           const std::string& child, const ros::Time& stamp) {
  geometry_msgs::TransformStamped t = tf2::eigenToTransform(pose.cast<double>());
  t.header.stamp = stamp;
  t.header.frame_id = parent;
  t.child_frame_id = child;
  return t;
}

int usage() {
  std::cerr << "usage: icanc_sim_bag SCENARIO.yaml OUT.bag [--topic /points] [--start-time SEC]\n";
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) return usage();
  const std::string scenario_path = argv[1], bag_path = argv[2];
  std::string topic = "/points";
  double start_time = 1000.0;
  for (int i = 3; i + 1 < argc; i += 2) {
    const std::string flag = argv[i];
    if (flag == "--topic") topic = argv[i + 1];
    else if (flag == "--start-time") start_time = std::atof(argv[i + 1]);
    else return usage();
  }
  ros::Time::init();
  try {
    const icanc::sim::Scenario s = icanc::sim::loadScenario(scenario_path);
    const icanc::sim::LidarModel model = icanc::sim::LidarModel::byName(s.lidar);
    std::mt19937_64 rng(s.seed);
    const ros::Time t0(start_time);

    rosbag::Bag bag(bag_path, rosbag::bagmode::Write);
    bag.setCompression(rosbag::compression::LZ4);

    tf2_msgs::TFMessage mount;
    mount.transforms.push_back(toTransform(s.sensor_mount, s.vehicle_frame, s.sensor_frame, t0));
    auto latched = boost::make_shared<ros::M_string>();
    // A connection header given to rosbag must be complete, as a recorded one is.
    (*latched)["type"] = ros::message_traits::datatype<tf2_msgs::TFMessage>();
    (*latched)["md5sum"] = ros::message_traits::md5sum<tf2_msgs::TFMessage>();
    (*latched)["message_definition"] = ros::message_traits::definition<tf2_msgs::TFMessage>();
    (*latched)["latching"] = "1";
    (*latched)["callerid"] = "/icanc_sim_bag";
    bag.write("/tf_static", t0, mount, latched);

    icanc::Cloud scan;
    std::size_t points = 0;
    for (std::size_t k = 0; k < s.frames(); ++k) {
      const double t = static_cast<double>(k) / s.rate_hz;
      const ros::Time stamp = t0 + ros::Duration(t);
      icanc::sim::renderScan(s.scene, t, s.sensorPose(t), model, s.noise, rng, scan);
      sensor_msgs::PointCloud2 cloud;
      pcl::toROSMsg(scan, cloud);
      cloud.header.stamp = stamp;
      cloud.header.frame_id = s.sensor_frame;
      points += scan.size();

      tf2_msgs::TFMessage odom;
      odom.transforms.push_back(toTransform(s.vehiclePose(t), "odom", s.vehicle_frame, stamp));
      bag.write("/tf", stamp, odom);
      bag.write(topic, stamp, cloud);
    }
    bag.close();
    std::cout << "wrote " << bag_path << ": scenario '" << s.name << "', " << s.frames()
              << " frames of " << model.name << " (" << points / s.frames() << " rays per frame) on "
              << topic << ", " << s.duration_s << " s\n";
  } catch (const std::exception& e) {
    std::cerr << "icanc_sim_bag: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
