// The device side of the rosserial protocol, behaving like ros_lib's NodeHandle (the library an
// Arduino sketch is built with): it answers "request topics" with a time request and the
// TopicInfo of its publishers (id 0) and subscribers (id 1), requests the time every sync period
// once configured, drops its configuration on TX stop or when no time reply came for the sync
// timeout, and hands user frames to its subscribers even before it is configured (as ros_lib
// does). Used by the emulated headlight (tests, bench) with the same framing code as the host.
// Time is an argument (milliseconds, like Arduino's millis()).
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "icanc/core/bridge/rosserial_protocol.hpp"

namespace icanc {
namespace rosserial {

struct DeviceConfig {
  int max_subscribers = 25;             // publisher ids start at 100 + max_subscribers
  std::size_t input_size = 512;         // receive buffer: larger frames are rejected
  std::size_t output_size = 512;        // announced in the publishers' TopicInfo
  std::uint32_t sync_period_ms = 2500;  // ros_lib: SYNC_SECONDS * 500
  std::uint32_t sync_timeout_ms = 11000;  // ros_lib: SYNC_SECONDS * 2200, then not connected
  std::uint32_t frame_timeout_ms = 20;  // ros_lib: SERIAL_MSG_TIMEOUT
};

class RosserialDevice {
 public:
  using Callback = std::function<void(const std::uint8_t* data, std::size_t size)>;

  explicit RosserialDevice(const DeviceConfig& config = DeviceConfig());

  // Registration, as at the top of a sketch (returns the topic id).
  std::uint16_t advertise(const std::string& name, const std::string& type, const std::string& md5);
  std::uint16_t subscribe(const std::string& name, const std::string& type, const std::string& md5,
                          Callback callback);

  // Bytes from the host at `now_ms`; frames to the host are appended to `tx`.
  void receive(const std::uint8_t* data, std::size_t size, std::uint32_t now_ms, std::vector<std::uint8_t>& tx);
  // The rest of spinOnce(): sync timeout and the periodic time request.
  void spinOnce(std::uint32_t now_ms, std::vector<std::uint8_t>& tx);
  // A user-topic publication; dropped (false) while not configured, as ros_lib does.
  bool publish(std::uint16_t id, const std::vector<std::uint8_t>& payload, std::vector<std::uint8_t>& tx);
  void log(std::uint8_t level, const std::string& text, std::vector<std::uint8_t>& tx);
  // A reset: configuration and partial input are lost, registrations stay (the sketch's globals).
  void powerCycle();

  bool connected() const { return configured_; }
  bool timeSynced() const { return time_synced_; }
  const Stamp& lastTime() const { return last_time_; }
  const ParserCounters& parserCounters() const { return parser_.counters(); }
  std::uint64_t topicRequests() const { return topic_requests_; }
  std::uint64_t txStops() const { return tx_stops_; }

 private:
  struct Endpoint {
    TopicInfo info;
    Callback callback;
  };
  void dispatch(const std::vector<Frame>& frames, std::uint32_t now_ms, std::vector<std::uint8_t>& tx);
  void requestSyncTime(std::uint32_t now_ms, std::vector<std::uint8_t>& tx);
  void negotiateTopics(std::vector<std::uint8_t>& tx);

  DeviceConfig config_;
  FrameParser parser_;
  std::vector<Endpoint> publishers_, subscribers_;
  bool configured_ = false;
  bool time_synced_ = false;
  Stamp last_time_;
  std::uint32_t last_sync_time_ms_ = 0;
  std::uint32_t last_sync_receive_ms_ = 0;
  std::uint64_t topic_requests_ = 0, tx_stops_ = 0;
};

}  // namespace rosserial
}  // namespace icanc
