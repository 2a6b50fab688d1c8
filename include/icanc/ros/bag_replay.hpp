// Replays a bag through the running icanc graph in lockstep on sim time (publishing /clock),
// one cloud at a time, and collects what the graph answered for each frame together with the
// bag's ground truth: the input of icanc::evaluate. Used by icanc_eval and the regression
// rostests, so both score exactly the same way.
#pragma once

#include <string>
#include <vector>

#include <ros/node_handle.h>

#include "icanc/core/evaluation/evaluation.hpp"
#include "icanc/core/light/lamp_segments.hpp"

namespace icanc {

struct ReplayOptions {
  std::string bag;
  std::string points_topic = "/points";
  std::string truth_topic = "/ground_truth";
  std::string ns = "/icanc";      // namespace of the icanc graph
  double rate = 0.0;              // 0: as fast as possible (lockstep); 1: recorded speed
  double frame_timeout_s = 5.0;   // wall time to wait for the graph's answer to a frame
  double graph_timeout_s = 30.0;  // wall time to wait for the graph to come up
  std::size_t max_frames = 0;     // 0: all
  // The bag's /tf (the vehicle's odom -> base_link) and odometry are published before each cloud,
  // up to its stamp, for the ego_motion sources tf and odometry; never when the graph's
  // ego_motion/source is lidar (the LidarOdometry nodelet publishes that transform itself); then
  // the vehicle's measured speed is, on the graph's lidar_odometry/twist_topic when it has one.
  bool publish_tf = true;
  std::string odom_topic = "/odom";  // nav_msgs/Odometry in the bag, if any
};

// Throws std::runtime_error when the bag cannot be read or the graph does not come up.
std::vector<EvalFrame> replayBag(ros::NodeHandle& nh, const ReplayOptions& options);

// What the evaluation takes from the graph's parameters under `ns`: the light controller's timer
// (EvalParams::lamp_tau_s, lamp_recheck_below_s), the danger detector's parameters
// (EvalParams::danger) and the obstacle detector's region of interest (EvalParams::roi).
// Throws std::runtime_error when those parameters are invalid.
void readGraphParams(const std::string& ns, EvalParams& params);

// Where the graph's profile puts the segmented lamp (`ns`/light_controller: lamp_position_m,
// segment_margin_deg, low_beam_below_m) into `lamp`, keeping its segments. Throws
// std::runtime_error when a key is malformed or the profile's lamp is invalid.
void readLampPlacement(const std::string& ns, SegmentLampParams& lamp);

}  // namespace icanc
