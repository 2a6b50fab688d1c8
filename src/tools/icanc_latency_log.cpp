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

#include <ros/ros.h>

#include "icanc/LightState.h"
#include "icanc/ObstacleArray.h"

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
  ros::init(argc, argv, "icanc_latency_log", ros::init_options::AnonymousName);
  if (argc != 3) {  // remaps are removed by ros::init
    std::fprintf(stderr, "usage: icanc_latency_log FRAMES.csv LIGHT.csv [remaps]\n");
    return 2;
  }
  std::FILE* frames = std::fopen(argv[1], "w");
  std::FILE* light = std::fopen(argv[2], "w");
  if (!frames || !light) {
    std::fprintf(stderr, "icanc_latency_log: cannot write %s or %s\n", argv[1], argv[2]);
    return 1;
  }
  ros::NodeHandle nh;
  LatencyLog log(nh, frames, light);
  ros::spin();
  std::fclose(frames);
  std::fclose(light);
  return 0;
}
