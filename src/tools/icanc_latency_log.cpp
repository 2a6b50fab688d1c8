// icanc_latency_log: per-frame and per-trigger latency of a running graph, to CSV (used by
// scripts/utilisation). Wall clock throughout: the nodelets stamp cloud_receive_time with the wall
// clock when the ObstacleDetector received the cloud.
//
//   icanc_latency_log FRAMES.csv LIGHT.csv [LEVELS.csv] obstacles_danger:=/icanc/obstacles_danger
//                     light_state:=/icanc/light_state lamp_command:=/icanc/lamp_command
//
// FRAMES.csv, one row per icanc/ObstacleArray on obstacles_danger:
//   frame, stamp_s (cloud stamp), wall_s (since the first row), detector_ms (the detector's own
//   processing_ms), cloud_to_danger_ms (cloud received -> danger-marked array received here),
//   obstacles, dangerous
// LIGHT.csv, one row per icanc/LightState that carries a new trigger (a dangerous cloud that
// (re)started the lamp timer; the paper's "point cloud received -> light command" latency):
//   trigger, stamp_s, wall_s, cloud_to_light_ms, on, reason, dangerous_objects
// LEVELS.csv (optional), one row per input the LightController answered: the binary
// lamp's and the segment levels' latency, each measured in the nodelet when it published
// (LightState and LampCommand input_latency_ms, cloud received -> published; no hop):
//   input, input_stamp_s, cloud_to_light_state_ms, cloud_to_levels_ms, lit_segments, segments, reason
// This node is a separate process, so both latencies include one serialised hop to it (inside
// the manager the nodelets pass pointers).
#include <algorithm>
#include <cstdio>
#include <iterator>
#include <map>
#include <mutex>
#include <string>
#include <vector>

#include <ros/ros.h>

#include "icanc/LampCommand.h"
#include "icanc/LightState.h"
#include "icanc/ObstacleArray.h"
#include "tool_help.hpp"

namespace {

class LatencyLog {
 public:
  LatencyLog(ros::NodeHandle& nh, std::FILE* frames, std::FILE* light, std::FILE* levels)
      : frames_(frames), light_(light), levels_(levels) {
    std::fprintf(frames_, "frame,stamp_s,wall_s,detector_ms,cloud_to_danger_ms,obstacles,dangerous\n");
    std::fprintf(light_, "trigger,stamp_s,wall_s,cloud_to_light_ms,on,reason,dangerous_objects\n");
    std::fflush(frames_);
    std::fflush(light_);
    obstacles_sub_ = nh.subscribe("obstacles_danger", 50, &LatencyLog::onObstacles, this,
                                  ros::TransportHints().tcpNoDelay());
    light_sub_ = nh.subscribe("light_state", 50, &LatencyLog::onLight, this,
                              ros::TransportHints().tcpNoDelay());
    if (levels_) {
      std::fprintf(levels_, "input,input_stamp_s,cloud_to_light_state_ms,cloud_to_levels_ms,lit_segments,"
                   "segments,reason\n");
      std::fflush(levels_);
      levels_sub_ = nh.subscribe("lamp_command", 50, &LatencyLog::onLevels, this,
                                 ros::TransportHints().tcpNoDelay());
    }
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
    if (levels_ && msg->input_latency_ms > 0.0f) {
      pending_[msg->input_stamp].state_ms = msg->input_latency_ms;
      writeInput(msg->input_stamp);
    }
    if (msg->cloud_receive_time.isZero() || msg->cloud_stamp == last_trigger_) return;
    last_trigger_ = msg->cloud_stamp;
    std::fprintf(light_, "%zu,%.6f,%.6f,%.3f,%d,%u,%u\n", triggers_++, msg->header.stamp.toSec(),
                 wall - start_wall_, (wall - msg->cloud_receive_time.toSec()) * 1e3, int(msg->on),
                 unsigned(msg->reason), msg->dangerous_objects);
    std::fflush(light_);
  }

  // LightState and LampCommand answering the same input are paired by its stamp.
  void onLevels(const icanc::LampCommand::ConstPtr& msg) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (msg->input_latency_ms <= 0.0f) return;  // a timer publication
    pending_[msg->input_stamp].command = msg;
    writeInput(msg->input_stamp);
  }

  // With mutex_ held.
  void writeInput(const ros::Time& stamp) {
    const auto it = pending_.find(stamp);
    if (it == pending_.end() || !it->second.command || it->second.state_ms < 0.0f) return;
    const icanc::LampCommand& c = *it->second.command;
    const auto lit = std::count_if(c.levels.begin(), c.levels.end(), [](float l) { return l > 0.0f; });
    std::fprintf(levels_, "%zu,%.6f,%.3f,%.3f,%ld,%zu,%u\n", inputs_++, stamp.toSec(), it->second.state_ms,
                 c.input_latency_ms, long(lit), c.levels.size(), unsigned(c.reason));
    std::fflush(levels_);
    pending_.erase(pending_.begin(), std::next(it));  // older unpaired ones will not pair any more
  }

 private:
  std::mutex mutex_;
  std::FILE* frames_;
  std::FILE* light_;
  std::FILE* levels_;
  ros::Subscriber obstacles_sub_, light_sub_, levels_sub_;
  double start_wall_ = -1.0;
  std::size_t frames_seen_ = 0, triggers_ = 0, inputs_ = 0;
  ros::Time last_trigger_;
  struct Pending {
    float state_ms = -1.0f;
    icanc::LampCommand::ConstPtr command;
  };
  std::map<ros::Time, Pending> pending_;
};

}  // namespace

int main(int argc, char** argv) {
  // The arguments are checked before ros::init and the master: --help and bad usage answer at once.
  const char* const usage = "usage: icanc_latency_log FRAMES.csv LIGHT.csv [LEVELS.csv] [remaps]\n";
  if (icanc::tools::wantsHelp(argc, argv)) return icanc::tools::printUsage(usage, true);
  std::vector<std::string> args;  // without the remaps
  ros::removeROSArgs(argc, argv, args);
  if (args.size() != 3 && args.size() != 4) return icanc::tools::printUsage(usage, false);
  std::FILE* frames = std::fopen(args[1].c_str(), "w");
  std::FILE* light = std::fopen(args[2].c_str(), "w");
  std::FILE* levels = args.size() == 4 ? std::fopen(args[3].c_str(), "w") : nullptr;
  if (!frames || !light || (args.size() == 4 && !levels)) {
    std::fprintf(stderr, "icanc_latency_log: cannot write %s\n", !frames ? args[1].c_str()
                 : !light ? args[2].c_str() : args[3].c_str());
    return 1;
  }
  ros::init(argc, argv, "icanc_latency_log", ros::init_options::AnonymousName);
  ros::NodeHandle nh;
  LatencyLog log(nh, frames, light, levels);
  ros::spin();
  std::fclose(frames);
  std::fclose(light);
  if (levels) std::fclose(levels);
  return 0;
}
