// icanc_headlight: the lamp end of icanc/LightBridge (paper Section IV-A: a flashlight switched by
// an Arduino). Built with rosserial_arduino's ros_lib (Arduino IDE: Sketch > Include Library >
// Rosserial Arduino Library; any ros_lib of the 0xFE protocol revision, ROS Hydro or later).
//
//   subscribes  lamp_cmd    std_msgs/Bool   the host's command, repeated at its heartbeat rate
//   publishes   lamp_state  std_msgs/Bool   the pin's actual state, on change and every 100 ms
//   subscribes  lamp_levels std_msgs/UInt8MultiArray   segment levels 0..255, for a
//               segmented lamp: the bridge's ~device_levels_topic; one PWM pin per segment
//               (SEGMENT_PINS, in the profile's segment order), full ON unless the link is up, the
//               Bool command fresh and levels came within COMMAND_TIMEOUT_MS (headlight_logic.h)
//
// Fail-safe (headlight_logic.h): the lamp is ON at power-up until the host speaks, whenever the
// node handle is not connected, and when no command came for COMMAND_TIMEOUT_MS.
//
// Wiring: LAMP_PIN drives a logic-level MOSFET gate or a relay module input. Between reset and
// setup() (bootloader, ~0.5-2 s) the pin floats: pull the gate to the level that means ON (a
// 10 kOhm resistor to 5 V with LAMP_ACTIVE_HIGH) so that the lamp is ON then too.
//
// The topic names must match the bridge's ~device_cmd_topic and ~device_state_topic; the baud
// rate its ~baud (57600 default, 115200 supported).
#include <ros.h>
#include <std_msgs/Bool.h>
#include <std_msgs/UInt8MultiArray.h>

#include "headlight_logic.h"

const uint8_t LAMP_PIN = 7;
const bool LAMP_ACTIVE_HIGH = true;
const uint32_t COMMAND_TIMEOUT_MS = 500;  // > 2 heartbeat periods of the bridge (10 Hz)
const uint32_t STATE_PERIOD_MS = 100;     // the bridge's link_timeout_s watches this
const long BAUD = 57600;
// PWM pins of the segments (an Uno has six: 3, 5, 6, 9, 10, 11; a Mega more, up to
// SegmentLevels::kMaxSegments). SEGMENT_COUNT 0: the paper's binary lamp alone (lamp_levels is
// then not subscribed).
const uint8_t SEGMENT_PINS[] = {3, 5, 6, 9, 10, 11};
const uint8_t SEGMENT_COUNT = sizeof(SEGMENT_PINS);

ros::NodeHandle nh;
icanc_fw::HeadlightLogic logic(COMMAND_TIMEOUT_MS);

std_msgs::Bool state_msg;
ros::Publisher state_pub("lamp_state", &state_msg);

void onCommand(const std_msgs::Bool& msg) { logic.onCommand(msg.data, millis()); }
ros::Subscriber<std_msgs::Bool> cmd_sub("lamp_cmd", &onCommand);

icanc_fw::SegmentLevels segments(COMMAND_TIMEOUT_MS);
void onLevels(const std_msgs::UInt8MultiArray& msg) { segments.onLevels(msg.data, msg.data_length, millis()); }
ros::Subscriber<std_msgs::UInt8MultiArray> levels_sub("lamp_levels", &onLevels);

bool lamp_on = true;
uint32_t last_state_ms = 0;
icanc_fw::HeadlightReason last_reason = icanc_fw::kNoCommandYet;

void writeLamp(bool on) { digitalWrite(LAMP_PIN, on == LAMP_ACTIVE_HIGH ? HIGH : LOW); }
void writeSegment(uint8_t i, uint8_t duty) { analogWrite(SEGMENT_PINS[i], LAMP_ACTIVE_HIGH ? duty : 255 - duty); }

void setup() {
  writeLamp(true);  // set the level before the pin becomes an output: no OFF glitch
  pinMode(LAMP_PIN, OUTPUT);
  writeLamp(true);
  for (uint8_t i = 0; i < SEGMENT_COUNT; ++i) {  // every segment ON from the start, no glitch
    digitalWrite(SEGMENT_PINS[i], LAMP_ACTIVE_HIGH ? HIGH : LOW);
    pinMode(SEGMENT_PINS[i], OUTPUT);
  }
  nh.getHardware()->setBaud(BAUD);
  nh.initNode();
  nh.advertise(state_pub);
  nh.subscribe(cmd_sub);
  if (SEGMENT_COUNT > 0) nh.subscribe(levels_sub);
}

void loop() {
  nh.spinOnce();
  const uint32_t now = millis();
  const bool on = logic.update(nh.connected(), now);
  if (on != lamp_on) writeLamp(on);
  if (!nh.connected()) segments.onDisconnect();
  for (uint8_t i = 0; i < SEGMENT_COUNT; ++i) writeSegment(i, segments.duty(i, logic, now));
  if (on != lamp_on || now - last_state_ms >= STATE_PERIOD_MS) {
    state_msg.data = on;
    state_pub.publish(&state_msg);  // ros_lib drops it while not connected
    last_state_ms = now;
  }
  if (logic.reason() != last_reason && nh.connected()) {
    if (logic.reason() == icanc_fw::kCommandTimeout) nh.logwarn("no lamp command: lamp ON (fail-safe)");
    last_reason = logic.reason();
  }
  lamp_on = on;
}
