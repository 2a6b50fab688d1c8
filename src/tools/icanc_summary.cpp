// icanc_summary: a readable account of a run. Prints each lamp transition with the obstacle that
// caused it, then at shutdown: frames, obstacles per frame, lamp on-time and duty cycle (ROS time),
// processing time and end-to-end latency (cloud received -> light state, wall clock).
// The lamp is timed on the LightController's clock (its states' stamps) from the first frame to
// the last, so a replay on the wall clock (replay.launch sim_time:=false), whose clouds keep their
// recorded stamps, still gets a duty cycle within [0, 100] %.
//
// Subscribes to obstacles_danger (icanc/ObstacleArray) and light_state (icanc/LightState); remap
// them, e.g. obstacles_danger:=/icanc/obstacles_danger light_state:=/icanc/light_state.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <mutex>
#include <stdexcept>
#include <utility>
#include <string>
#include <vector>

#include <ros/ros.h>

#include "icanc/LightState.h"
#include "icanc/ObstacleArray.h"
#include "icanc/core/common/percentile.hpp"
#include "icanc/core/evaluation/energy.hpp"
#include "tool_help.hpp"

namespace {

using icanc::percentile;

class Summary {
 public:
  explicit Summary(ros::NodeHandle& nh) {
    obstacles_sub_ = nh.subscribe("obstacles_danger", 20, &Summary::onObstacles, this);
    light_sub_ = nh.subscribe("light_state", 50, &Summary::onLight, this);
  }

  void onObstacles(const icanc::ObstacleArray::ConstPtr& msg) {
    std::lock_guard<std::mutex> lock(mutex_);
    // The lamp's window, on the LightController's clock (sim or wall, as this node's).
    const ros::Time now = ros::Time::now();
    if (frames_ == 0) lamp_from_ = lamp_to_ = now;
    settle(now);
    if (frames_ == 0) first_stamp_ = msg->header.stamp;
    last_stamp_ = msg->header.stamp;
    ++frames_;
    obstacles_ += msg->obstacles.size();
    dangerous_ += msg->num_dangerous;
    processing_ms_.push_back(msg->processing_ms);
    last_array_ = msg;
  }

  void onLight(const icanc::LightState::ConstPtr& msg) {
    std::lock_guard<std::mutex> lock(mutex_);
    const ros::WallTime wall = ros::WallTime::now();
    if (msg->cloud_stamp != last_trigger_ && !msg->cloud_receive_time.isZero()) {
      last_trigger_ = msg->cloud_stamp;
      latency_ms_.push_back((wall.toSec() - msg->cloud_receive_time.toSec()) * 1e3);
    }
    states_.emplace_back(msg->header.stamp, msg->on);
    if (!have_state_ || msg->on != on_ || msg->reason != reason_) describe(*msg);
    have_state_ = true;
    on_ = msg->on;
    reason_ = msg->reason;
  }

  // Adds the lamp's on-time from the last frame to `t` (integrateOnTime: each state holds until
  // the next one) and forgets the states before `t` but the one in force then (bounded memory).
  void settle(const ros::Time& t) {
    std::size_t in_force = 0;
    window_.clear();
    for (std::size_t i = 0; i < states_.size() && states_[i].first <= t; ++i) {
      in_force = i;
      window_.push_back({std::max(states_[i].first, lamp_to_).toSec(), states_[i].second, 0});
    }
    try {
      on_seconds_ += icanc::integrateOnTime(window_, t.toSec()).on_s;
    } catch (const std::invalid_argument& e) {  // the clock went backwards (a looped bag)
      ROS_WARN_THROTTLE(5.0, "icanc_summary: lamp time not counted: %s", e.what());
    }
    states_.erase(states_.begin(), states_.begin() + in_force);
    lamp_to_ = std::max(lamp_to_, t);
  }

  void describe(const icanc::LightState& s) {
    const double t = frames_ ? std::max(0.0, (s.header.stamp - lamp_from_).toSec()) : 0.0;
    std::printf("[%7.2f s] lamp %-3s (%s)", t, s.on ? "ON" : "off", s.reason_text.c_str());
    if (s.reason == icanc::LightState::REASON_DANGER && last_array_) {
      for (const auto& o : last_array_->obstacles) {
        if (!o.dangerous) continue;
        // The message's heading [rad, (-pi, pi]] as the paper's rule reads it: [0, 360) deg.
        std::printf("  id %u at %.2f m, %.2f m/s, heading %.0f deg", o.id, o.closest_distance,
                    o.speed, std::fmod(o.heading * 180.0 / M_PI + 360.0, 360.0));
      }
    }
    std::printf("\n");
    std::fflush(stdout);
  }

  void print() {
    std::lock_guard<std::mutex> lock(mutex_);
    const double span = frames_ > 1 ? (last_stamp_ - first_stamp_).toSec() : 0.0;
    const double lamp_span = frames_ > 0 ? std::max(0.0, (lamp_to_ - lamp_from_).toSec()) : 0.0;
    std::printf("\n==== icanc run summary ====\n");
    std::printf("frames processed         %zu over %.1f s of data\n", frames_, span);
    std::printf("obstacles per frame      %.2f (dangerous object-frames: %zu)\n",
                frames_ ? double(obstacles_) / frames_ : 0.0, dangerous_);
    std::printf("lamp on                  %.1f s of %.1f s (duty cycle %.1f %%)\n", on_seconds_,
                lamp_span, lamp_span > 0 ? 100.0 * on_seconds_ / lamp_span : 0.0);
    std::printf("detector processing ms   p50 %.2f  p99 %.2f  max %.2f\n",
                percentile(processing_ms_, 0.5), percentile(processing_ms_, 0.99),
                percentile(processing_ms_, 1.0));
    std::printf("cloud -> lamp latency ms p50 %.2f  p99 %.2f (n = %zu timer starts)\n",
                percentile(latency_ms_, 0.5), percentile(latency_ms_, 0.99), latency_ms_.size());
    std::fflush(stdout);
  }

 private:
  std::mutex mutex_;
  icanc::ObstacleArray::ConstPtr last_array_;
  std::size_t frames_ = 0, obstacles_ = 0, dangerous_ = 0;
  ros::Time first_stamp_, last_stamp_, last_trigger_;
  ros::Time lamp_from_, lamp_to_;  // first and last frame's arrival, on the LightController's clock
  double on_seconds_ = 0.0;        // lamp on within [lamp_from_, lamp_to_]
  std::vector<std::pair<ros::Time, bool>> states_;  // LightStates (stamp, on) since the last frame
  std::vector<icanc::LampSample> window_;           // reused by settle()
  bool have_state_ = false, on_ = false;
  std::uint8_t reason_ = 0;
  std::vector<double> processing_ms_, latency_ms_;
  // Declared last, so destroyed first: no callback runs into the members above as they go.
  ros::Subscriber obstacles_sub_, light_sub_;
};

}  // namespace

int main(int argc, char** argv) {
  // The arguments are checked before ros::init and the master: --help and bad usage answer at once.
  const char* const usage =
      "usage: icanc_summary [obstacles_danger:=/icanc/obstacles_danger] "
      "[light_state:=/icanc/light_state]\n"
      "Prints each lamp switch with its reason while a graph runs, and a summary at shutdown.\n";
  if (icanc::tools::wantsHelp(argc, argv)) return icanc::tools::printUsage(usage, true);
  std::vector<std::string> args;  // without the remaps
  ros::removeROSArgs(argc, argv, args);
  if (args.size() != 1) return icanc::tools::printUsage(usage, false);
  ros::init(argc, argv, "icanc_summary");
  ros::NodeHandle nh;
  Summary summary(nh);
  ros::spin();
  summary.print();
  return 0;
}
