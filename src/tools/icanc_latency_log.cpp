// icanc_latency_log: per-frame and per-trigger latency of a running graph, to CSV (used by
// scripts/utilisation). Wall clock throughout: the nodelets stamp cloud_receive_time with the wall
// clock when the ObstacleDetector received the cloud.
//
//   icanc_latency_log FRAMES.csv LIGHT.csv obstacles_danger:=/icanc/obstacles_danger
//                     light_state:=/icanc/light_state
//
// FRAMES.csv, one row per icanc/ObstacleArray on obstacles_danger:
//   frame, stamp_s (cloud stamp), wall_s (since the first row), detector_ms (the detector's own
//   processing_ms), cloud_to_danger_ms (cloud received -> danger-marked array received here),
//   obstacles, dangerous
// LIGHT.csv, one row per icanc/LightState that carries a new trigger (a dangerous cloud that
// (re)started the lamp timer; the paper's "point cloud received -> light command" latency):
//   trigger, stamp_s, wall_s, cloud_to_light_ms, on, reason, dangerous_objects
// This node is a separate process, so both latencies include one serialised hop to it (inside
// the manager the nodelets pass pointers).
#include <cstdio>
#include <mutex>
#include <string>
#include <vector>

#include <ros/ros.h>

#include "icanc/LightState.h"
#include "icanc/ObstacleArray.h"
#include "tool_help.hpp"

namespace {

class LatencyLog {
 public:
  LatencyLog(ros::NodeHandle& nh, std::FILE* frames, std::FILE* light) : frames_(frames), light_(light) {
    std::fprintf(frames_, "frame,stamp_s,wall_s,detector_ms,cloud_to_danger_ms,obstacles,dangerous\n");
    std::fprintf(light_, "trigger,stamp_s,wall_s,cloud_to_light_ms,on,reason,dangerous_objects\n");
    std::fflush(frames_);
    std::fflush(light_);
    obstacles_sub_ = nh.subscribe("obstacles_danger", 50, &LatencyLog::onObstacles, this,
                                  ros::TransportHints().tcpNoDelay());
    light_sub_ = nh.subscribe("light_state", 50, &LatencyLog::onLight, this,
                              ros::TransportHints().tcpNoDelay());
  }

  void onObstacles(const icanc::ObstacleArray::ConstPtr& msg) {
    const double wall = ros::WallTime::now().toSec();
    std::lock_guard<std::mutex> lock(mutex_);
    if (start_wall_ < 0.0) start_wall_ = wall;
    const double latency_ms =
        msg->cloud_receive_time.isZero() ? -1.0 : (wall - msg->cloud_receive_time.toSec()) * 1e3;
    std::fprintf(frames_, "%zu,%.6f,%.6f,%.3f,%.3f,%zu,%u\n", frames_seen_++, msg->header.stamp.toSec(),
                 wall - start_wall_, msg->processing_ms, latency_ms, msg->obstacles.size(),
                 msg->num_dangerous);
    std::fflush(frames_);
  }

  void onLight(const icanc::LightState::ConstPtr& msg) {
    const double wall = ros::WallTime::now().toSec();
    std::lock_guard<std::mutex> lock(mutex_);
    if (start_wall_ < 0.0) start_wall_ = wall;
    if (msg->cloud_receive_time.isZero() || msg->cloud_stamp == last_trigger_) return;
    last_trigger_ = msg->cloud_stamp;
    std::fprintf(light_, "%zu,%.6f,%.6f,%.3f,%d,%u,%u\n", triggers_++, msg->header.stamp.toSec(),
                 wall - start_wall_, (wall - msg->cloud_receive_time.toSec()) * 1e3, int(msg->on),
                 unsigned(msg->reason), msg->dangerous_objects);
    std::fflush(light_);
  }

 private:
  std::mutex mutex_;
  std::FILE* frames_;
  std::FILE* light_;
  ros::Subscriber obstacles_sub_, light_sub_;
  double start_wall_ = -1.0;
  std::size_t frames_seen_ = 0, triggers_ = 0;
  ros::Time last_trigger_;
};

}  // namespace

int main(int argc, char** argv) {
  // The arguments are checked before ros::init and the master: --help and bad usage answer at once.
  const char* const usage = "usage: icanc_latency_log FRAMES.csv LIGHT.csv [remaps]\n";
  if (icanc::tools::wantsHelp(argc, argv)) return icanc::tools::printUsage(usage, true);
  std::vector<std::string> args;  // without the remaps
  ros::removeROSArgs(argc, argv, args);
  if (args.size() != 3) return icanc::tools::printUsage(usage, false);
  std::FILE* frames = std::fopen(args[1].c_str(), "w");
  std::FILE* light = std::fopen(args[2].c_str(), "w");
  if (!frames || !light) {
    std::fprintf(stderr, "icanc_latency_log: cannot write %s or %s\n", args[1].c_str(),
                 args[2].c_str());
    return 1;
  }
  ros::init(argc, argv, "icanc_latency_log", ros::init_options::AnonymousName);
  ros::NodeHandle nh;
  LatencyLog log(nh, frames, light);
  ros::spin();
  std::fclose(frames);
  std::fclose(light);
  return 0;
}
