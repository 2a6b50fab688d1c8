// Plays a bag's sensor and localisation topics into ROS on the wall clock from a thread of its
// own, as a LiDAR driver replaying a capture does inside its nodelet manager (velodyne_driver
// reading a pcap): every sensor_msgs/PointCloud2 topic, /tf, /tf_static (one latched message with
// every static transform) and every nav_msgs/Odometry, geometry_msgs/TwistStamped and
// nav_msgs/Path topic, at the recorded pace. Other topics (ground truth, images) are not played.
//
// Each message is read and deserialized in the player's thread and published as the shared
// pointer it was read into: subscribers in the same process (nodelets of the same manager) get
// that object, no copy and no serialization. Like a driver, the player stamps with the host's
// clock: with `restamp`, every header stamp (clouds, transforms, odometry, twist, paths and their
// poses) is shifted by one offset so that the first message played is stamped now; intervals,
// and so the transforms at each cloud's stamp, stay as recorded. Without it the recorded stamps
// are kept (as rosbag play does). Wall clock only: on sim time there is no clock to stamp with.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <string>
#include <thread>

#include <ros/node_handle.h>
#include <ros/publisher.h>

namespace icanc {

struct BagPlayerOptions {
  std::string bag;
  double rate = 1.0;     // times the recorded pace (1: as the sensor ran)
  double delay_s = 1.0;  // wall time from start() to the first message [s]
  bool restamp = true;   // stamps shifted so that the first message played is stamped now
  std::string thread_name = "bag_player";  // as /proc/PID/task/TID/comm shows it (<= 15 chars)
};

// "" or why the options are invalid (naming the parameter).
std::string validate(const BagPlayerOptions& options);

class BagPlayer {
 public:
  // Topics are advertised on `nh` under their recorded names (a nodelet's node handle: its
  // remappings apply); ~finished on `private_nh`, and ~publish_trace with the address of every
  // cloud when ~trace_publications is true (icanc/zero_copy.hpp). When the bag has played,
  // ~finished (std_msgs/UInt32, latched) carries the number of clouds published.
  BagPlayer(const ros::NodeHandle& nh, const ros::NodeHandle& private_nh, const BagPlayerOptions& options);
  // Stops the thread (between two messages) and joins it. After the bag the thread waits, idle,
  // for this, so that its CPU time stays readable in /proc/PID/task.
  ~BagPlayer();

  BagPlayer(const BagPlayer&) = delete;
  BagPlayer& operator=(const BagPlayer&) = delete;

  void start();
  bool finished() const { return finished_; }
  std::uint64_t cloudsPublished() const { return clouds_; }

 private:
  void run();
  // Plays the bag; throws what rosbag throws on a damaged bag.
  void play();
  // Sleeps until `deadline` (steady clock) or stop; false when stopped.
  bool sleepUntil(std::chrono::steady_clock::time_point deadline);

  ros::NodeHandle nh_, private_nh_;
  BagPlayerOptions options_;
  std::mutex mutex_;
  std::condition_variable wake_;
  bool stop_ = false;
  std::atomic<bool> finished_{false};
  std::atomic<std::uint64_t> clouds_{0};
  ros::Publisher finished_pub_;  // the thread's; kept after it ends (the message is latched)
  std::thread thread_;
};

}  // namespace icanc
