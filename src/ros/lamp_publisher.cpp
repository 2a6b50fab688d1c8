#include "icanc/ros/lamp_publisher.hpp"

#include <boost/make_shared.hpp>
#include <std_msgs/Bool.h>

#include "icanc/LampCommand.h"
#include "icanc/LightState.h"
#include "icanc/ros/nodelet_support.hpp"

namespace icanc {

void LampPublisher::advertise(ros::NodeHandle& nh, ros::NodeHandle& private_nh, bool markers,
                              const MarkerStyle& style) {
  marker_style_ = style;
  state_pub_.advertise<LightState>(nh, private_nh, "light_state", 10);
  lamp_pub_ = nh.advertise<std_msgs::Bool>("lamp_cmd", 10);
  if (markers) marker_pub_ = nh.advertise<visualization_msgs::MarkerArray>("markers", 5);
  command_pub_ = nh.advertise<LampCommand>("lamp_command", 10);
  if (markers) segment_marker_pub_ = private_nh.advertise<visualization_msgs::MarkerArray>("lamp_segments", 2);
}

void LampPublisher::onInput(const ObstacleArray& msg, bool triggered) {
  if (!msg.header.frame_id.empty()) marker_frame_ = msg.header.frame_id;
  input_stamp_ = msg.header.stamp;
  input_receive_time_ = msg.cloud_receive_time;
  if (triggered) {
    trigger_cloud_stamp_ = msg.header.stamp;
    trigger_receive_time_ = msg.cloud_receive_time;
    trigger_dangerous_ = msg.num_dangerous;
  }
}

void LampPublisher::publish(const ros::Time& now, LampControl* control,
                            const std::vector<float>& fault_levels, bool answers_input) {
  auto state = boost::make_shared<LightState>();
  auto command = boost::make_shared<LampCommand>();
  state->header.stamp = command->header.stamp = now;
  if (control) {
    const LightController& binary = control->binary();
    state->on = binary.on();
    state->reason = static_cast<std::uint8_t>(binary.reason());
    state->time_left = static_cast<float>(binary.timeLeft(now.toSec()));
    command->levels = control->segmented().levels();
    command->reason = static_cast<std::uint8_t>(control->segmented().reason());
    control->published(state->on);
  } else {
    state->on = true;
    state->reason = command->reason = static_cast<std::uint8_t>(LightReason::kFault);
    command->levels = fault_levels;
  }
  state->reason_text = toString(static_cast<LightReason>(state->reason));
  command->reason_text = toString(static_cast<LightReason>(command->reason));
  state->dangerous_objects = trigger_dangerous_;
  state->cloud_stamp = trigger_cloud_stamp_;
  state->cloud_receive_time = trigger_receive_time_;
  state->input_stamp = command->input_stamp = input_stamp_;
  if (answers_input && !input_receive_time_.isZero())
    state->input_latency_ms = command->input_latency_ms = static_cast<float>(
        (ros::WallTime::now().toSec() - input_receive_time_.toSec()) * 1e3);
  last_publish_ = now;
  // The levels before the binary lamp, so a board that follows both does not see the new ON
  // with the previous levels (the sketch also lights every segment for ON with all levels 0).
  command_pub_.publish(LampCommand::ConstPtr(command));
  state_pub_.publish(LightState::ConstPtr(state));
  publishBool(lamp_pub_, state->on);
  if (marker_pub_.getNumSubscribers() > 0) marker_pub_.publish(lampMarkers(*state, marker_frame_, marker_style_));
  if (control && segment_marker_pub_.getNumSubscribers() > 0)
    segment_marker_pub_.publish(segmentMarkers(*command, control->segmented().segments(),
                                               control->segmented().lamp().lamp_position_m,
                                               marker_frame_, 20.0, marker_style_));
}

}  // namespace icanc
