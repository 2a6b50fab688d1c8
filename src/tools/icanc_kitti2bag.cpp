// icanc_kitti2bag: converts a KITTI tracking sequence into a rosbag the nodelets can replay and
// icanc_eval can score:
//   /points        sensor_msgs/PointCloud2, frame "velodyne", every point of the scan including
//                  a trailing all-zero point when the file has one (the detector drops it)
//   /tf_static     base_link -> velodyne identity: KITTI gives no vehicle frame, the velodyne
//                  frame is the vehicle frame (the kitti_hdl64e profile's target_frame); the
//                  identity only lets a profile whose target_frame is base_link replay the bag
//   /ground_truth  icanc/GroundTruthArray, frame "velodyne", same stamp as the cloud: every
//                  labelled object (DontCare skipped) with its box (kitti::toVelodyne), velocity
//                  relative to the vehicle by central difference of the same track id's
//                  positions in the neighbouring frames (0.1 s apart; one-sided at a track's
//                  ends, 0 for a track seen once), returns inside the box (kitti::contains) and
//                  the danger label from the labelled positions of the same track id
//                  (docs/design.md, "Ground truth for dangerous"; no interpolation between the
//                  0.1 s frames, no extrapolation past a track's last label). In the
//                  sequence's last horizon_s, an object that does not enter the corridor
//                  before the labels end is horizon_cut: its danger is unknown, not scored.
// KITTI labels exist only in the front camera's field of view (about 90 degrees ahead): objects
// beside or behind the car are in the clouds but not in the ground truth, and a track whose
// object leaves that field of view is labelled only from the frames it has.
//   /planned_path  nav_msgs/Path, frame "velodyne", same stamp as the cloud: the path the car
//                  drove from 1 s behind to 6 s ahead (to the last frame converted), as the
//                  profile's LiDAR odometry measures it over those frames: what a planner the car
//                  followed would have given (the predictive model's ~predictive/path_topic).
//                  The labels' danger comes from the labelled positions of later frames, i.e.
//                  along the path truly driven.
// Stamps: 1000.0 s + 0.1 s per frame (the tracking data has no timestamps).
//
//   icanc_kitti2bag SEQUENCE_DIR OUT.bag [--profile config/kitti_hdl64e.yaml] [--frames N]
//                   [--topic /points] [--sequence 0000] [--path-topic /planned_path]
// SEQUENCE_DIR holds velodyne/, label_02/ and calib/ (e.g. ../shared/data/kitti_tracking_0000).
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

#include <pcl_conversions/pcl_conversions.h>
#include <rosbag/bag.h>
#include <nav_msgs/Path.h>
#include <sensor_msgs/PointCloud2.h>
#include <tf2_eigen/tf2_eigen.h>
#include <tf2_msgs/TFMessage.h>

#include "icanc/ros/bag_static_tf.hpp"
#include "icanc/ros/conversions.hpp"
#include "icanc/core/evaluation/kitti.hpp"
#include "icanc/core/evaluation/truth_labels.hpp"
#include "icanc/core/common/yaml_params.hpp"
#include "icanc/core/motion/lidar_odometry.hpp"
#include "icanc/ros/truth_msgs.hpp"
#include "tool_help.hpp"

namespace {

constexpr double kFramePeriodS = 0.1;
constexpr double kStartTimeS = 1000.0;
const char* const kFrame = "velodyne";

int usage(bool asked = false) {
  return icanc::tools::printUsage(
      "usage: icanc_kitti2bag SEQUENCE_DIR OUT.bag [--profile config/kitti_hdl64e.yaml]\n"
      "                       [--frames N] [--topic /points] [--sequence 0000]\n"
      "                       [--path-topic /planned_path]\n",
      asked);
}

// The poses of the vehicle over the sequence (odom_T_vehicle per frame), by the profile's LiDAR
// odometry.
std::vector<Eigen::Isometry3d> drivenPoses(const std::string& dir, int max_frames,
                                           const icanc::LidarOdometryParams& params) {
  icanc::LidarOdometry odometry(params);
  std::vector<Eigen::Isometry3d> poses;
  icanc::Cloud scan;
  for (int f = 0; f < max_frames; ++f) {
    const std::string path = icanc::kitti::velodynePath(dir, f);
    if (!std::ifstream(path).good()) break;
    icanc::kitti::readVelodyne(path, scan);
    poses.push_back(odometry.registerFrom(kFramePeriodS * f, [&](auto&& sink) {
      for (const auto& p : scan) sink(p.x, p.y, p.z);
    }));
  }
  return poses;
}

// The driven path seen from frame f: the poses from 1 s behind to 6 s ahead in its vehicle frame.
nav_msgs::Path plannedPath(const std::vector<Eigen::Isometry3d>& poses, int f, const ros::Time& stamp) {
  constexpr int kBehind = 10, kAhead = 60;  // frames
  std_msgs::Header header;
  header.stamp = stamp;
  header.frame_id = kFrame;
  const int last = static_cast<int>(poses.size()) - 1;
  const std::vector<Eigen::Isometry3d> window(poses.begin() + std::max(0, f - kBehind),
                                              poses.begin() + std::min(last, f + kAhead) + 1);
  return icanc::toRelativePath(header, poses[static_cast<std::size_t>(f)], window);
}

}  // namespace

int main(int argc, char** argv) {
  if (icanc::tools::wantsHelp(argc, argv)) return usage(true);
  if (argc < 3) return usage();
  const std::string dir = argv[1], bag_path = argv[2];
  std::string profile_path = "config/kitti_hdl64e.yaml", topic = "/points", sequence = "0000",
              path_topic = "/planned_path";
  int max_frames = 1 << 30;
  for (int i = 3; i < argc; i += 2) {
    if (i + 1 >= argc) return usage();
    const std::string flag = argv[i];
    if (flag == "--profile") profile_path = argv[i + 1];
    else if (flag == "--frames") max_frames = std::atoi(argv[i + 1]);
    else if (flag == "--topic") topic = argv[i + 1];
    else if (flag == "--sequence") sequence = argv[i + 1];
    else if (flag == "--path-topic") path_topic = argv[i + 1];
    else return usage();
  }
  ros::Time::init();
  try {
    const icanc::Profile profile = icanc::loadProfile(profile_path);
    const icanc::CorridorParams corridor = profile.corridor;
    const icanc::kitti::Calib calib = icanc::kitti::readCalib(dir + "/calib/" + sequence + ".txt");
    const std::vector<icanc::kitti::VeloBox> velo = icanc::kitti::toVelodyne(
        icanc::kitti::readLabels(dir + "/label_02/" + sequence + ".txt"), calib);

    // Every label of the sequence (also past --frames: the last frames' labels look ahead). The
    // sequence's last frame ends what the labels know: a label not dangerous within less than the
    // horizon before it is horizon_cut (not scored).
    int last_frame = 0;
    while (std::ifstream(icanc::kitti::velodynePath(dir, last_frame + 1)).good()) ++last_frame;
    for (const icanc::kitti::VeloBox& v : velo) last_frame = std::max(last_frame, v.frame);
    const std::vector<icanc::TruthBox> boxes = icanc::truthBoxesFromKitti(velo, kFramePeriodS);
    const std::vector<icanc::TruthLabel> labels =
        icanc::labelTruths(boxes, corridor, kFramePeriodS * last_frame);
    std::map<int, std::vector<std::size_t>> by_frame;
    for (std::size_t i = 0; i < velo.size(); ++i) by_frame[velo[i].frame].push_back(i);

    const ros::Time t0(kStartTimeS);
    rosbag::Bag bag(bag_path, rosbag::bagmode::Write);
    bag.setCompression(rosbag::compression::LZ4);

    tf2_msgs::TFMessage mount;
    geometry_msgs::TransformStamped identity;
    identity.header.stamp = t0;
    identity.header.frame_id = "base_link";
    identity.child_frame_id = kFrame;
    identity.transform.rotation.w = 1.0;
    mount.transforms.push_back(identity);
    icanc::writeStaticTransforms(bag, t0, mount, "/icanc_kitti2bag");

    const std::vector<Eigen::Isometry3d> driven = drivenPoses(dir, max_frames, profile.lidar_odometry);
    icanc::Cloud scan;
    int frames = 0;
    std::size_t points = 0, objects = 0, dangerous = 0, in_corridor = 0, dangerous_frames = 0,
                cut = 0;
    std::map<std::uint32_t, std::pair<std::string, std::size_t>> dangerous_per_track;
    for (int f = 0; f < max_frames; ++f) {
      const std::string path = icanc::kitti::velodynePath(dir, f);
      if (!std::ifstream(path).good()) break;
      icanc::kitti::readVelodyne(path, scan);
      const ros::Time stamp = t0 + ros::Duration(kFramePeriodS * f);
      sensor_msgs::PointCloud2 cloud;
      pcl::toROSMsg(scan, cloud);
      cloud.header.stamp = stamp;
      cloud.header.frame_id = kFrame;
      points += scan.size();

      std::vector<icanc::TruthBox> frame_boxes;
      std::vector<icanc::TruthLabel> frame_labels;
      std::vector<std::uint32_t> num_points;
      bool any = false;
      for (std::size_t i : by_frame[f]) {
        std::uint32_t n = 0;
        for (const icanc::Point& q : scan.points)
          n += icanc::kitti::contains(velo[i], Eigen::Vector3d(q.x, q.y, q.z));
        frame_boxes.push_back(boxes[i]);
        frame_labels.push_back(labels[i]);
        num_points.push_back(n);
        dangerous += labels[i].dangerous;
        in_corridor += labels[i].in_corridor;
        cut += labels[i].horizon_cut;
        any = any || labels[i].dangerous;
        if (labels[i].dangerous) {
          auto& entry = dangerous_per_track[boxes[i].id];
          entry.first = boxes[i].type;
          ++entry.second;
        }
      }
      objects += frame_boxes.size();
      dangerous_frames += any;
      bag.write(path_topic, stamp, plannedPath(driven, f, stamp));
      bag.write(topic, stamp, cloud);
      bag.write("/ground_truth", stamp,
                icanc::toGroundTruthArray(frame_boxes, frame_labels, num_points, corridor, stamp,
                                          kFrame));
      ++frames;
    }
    bag.close();
    if (frames == 0) throw std::runtime_error(dir + ": no velodyne/000000.bin[.xz]");
    std::printf("wrote %s: %d frames, %zu points per frame on %s; ground truth (profile %s): %zu "
                "labelled object-frames, %zu dangerous (%zu in the corridor) in %zu frames; %zu "
                "of unknown danger (the labels end within their horizon)\n",
                bag_path.c_str(), frames, points / frames, topic.c_str(), profile_path.c_str(),
                objects, dangerous, in_corridor, dangerous_frames, cut);
    for (const auto& entry : dangerous_per_track)
      std::printf("  track %u %s: dangerous in %zu frames\n", entry.first,
                  entry.second.first.c_str(), entry.second.second);
  } catch (const std::exception& e) {
    std::cerr << "icanc_kitti2bag: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
