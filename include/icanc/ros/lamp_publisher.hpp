// The LightController's lamp on every topic: icanc/LightState on `light_state` (zero-copy),
// std_msgs/Bool on `lamp_cmd`, icanc/LampCommand on `lamp_command`, and while someone listens the
// lamp as rviz markers on `markers` and the segments' wedges on `~lamp_segments`. Besides the
// lamp, the messages carry the input that last started the timer and the latest input's stamps,
// kept here. ROS glue over icanc::LampControl; not thread-safe (the nodelet's lock covers it).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <ros/node_handle.h>
#include <ros/publisher.h>
#include <ros/time.h>

#include "icanc/ObstacleArray.h"
#include "icanc/core/light/lamp_control.hpp"
#include "icanc/ros/markers.hpp"
#include "icanc/ros/zero_copy.hpp"

namespace icanc {

class LampPublisher {
 public:
  // The lamp's topics; with `markers` (not on the fault path) the two marker topics too.
  void advertise(ros::NodeHandle& nh, ros::NodeHandle& private_nh, bool markers,
                 const MarkerStyle& style = MarkerStyle());

  // A DangerDetector output: its frame for the markers, its stamps for the next messages and,
  // when it `triggered` the timer, the lamp's cause.
  void onInput(const ObstacleArray& msg, bool triggered);

  // The lamp at `now` on every topic: `control`'s (told what was published), or without one (the
  // fault path) every segment ON at `fault_levels` for REASON_FAULT. `answers_input`: the message
  // answers an input, its latency since the cloud arrived is filled in.
  void publish(const ros::Time& now, LampControl* control, const std::vector<float>& fault_levels,
               bool answers_input);
  const ros::Time& lastPublished() const { return last_publish_; }

 private:
  ZeroCopyPublisher state_pub_;
  ros::Publisher lamp_pub_, marker_pub_, command_pub_, segment_marker_pub_;
  MarkerStyle marker_style_;
  std::string marker_frame_ = "base_link";  // the input's frame once it flows
  ros::Time last_publish_;
  ros::Time trigger_cloud_stamp_;
  ros::Time trigger_receive_time_;
  ros::Time input_stamp_, input_receive_time_;
  std::uint32_t trigger_dangerous_ = 0;
};

}  // namespace icanc
