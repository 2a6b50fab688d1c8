#include "icanc/core/bridge/rosserial_device.hpp"

namespace icanc {
namespace rosserial {

RosserialDevice::RosserialDevice(const DeviceConfig& config)
    : config_(config), parser_(config.input_size, config.frame_timeout_ms / 1000.0) {}

std::uint16_t RosserialDevice::advertise(const std::string& name, const std::string& type,
                                         const std::string& md5) {
  Endpoint e;
  e.info.topic_id = static_cast<std::uint16_t>(kFirstUserTopic + config_.max_subscribers + publishers_.size());
  e.info.topic_name = name;
  e.info.message_type = type;
  e.info.md5sum = md5;
  e.info.buffer_size = static_cast<std::int32_t>(config_.output_size);
  publishers_.push_back(e);
  return e.info.topic_id;
}

std::uint16_t RosserialDevice::subscribe(const std::string& name, const std::string& type,
                                         const std::string& md5, Callback callback) {
  Endpoint e;
  e.info.topic_id = static_cast<std::uint16_t>(kFirstUserTopic + subscribers_.size());
  e.info.topic_name = name;
  e.info.message_type = type;
  e.info.md5sum = md5;
  e.info.buffer_size = static_cast<std::int32_t>(config_.input_size);
  e.callback = std::move(callback);
  subscribers_.push_back(e);
  return e.info.topic_id;
}

void RosserialDevice::powerCycle() {
  configured_ = false;
  time_synced_ = false;
  parser_.reset();
}

void RosserialDevice::requestSyncTime(std::uint32_t now_ms, std::vector<std::uint8_t>& tx) {
  std::vector<std::uint8_t> payload;
  serialize(Stamp(), payload);
  appendFrame(kIdTime, payload.data(), payload.size(), tx);
  last_sync_time_ms_ = now_ms;
}

void RosserialDevice::negotiateTopics(std::vector<std::uint8_t>& tx) {
  std::vector<std::uint8_t> payload;
  for (const Endpoint& e : publishers_) {
    payload.clear();
    serialize(e.info, payload);
    appendFrame(kIdPublisher, payload.data(), payload.size(), tx);
  }
  for (const Endpoint& e : subscribers_) {
    payload.clear();
    serialize(e.info, payload);
    appendFrame(kIdSubscriber, payload.data(), payload.size(), tx);
  }
  configured_ = true;
}

void RosserialDevice::receive(const std::uint8_t* data, std::size_t size, std::uint32_t now_ms,
                              std::vector<std::uint8_t>& tx) {
  std::vector<Frame> frames;
  parser_.feed(data, size, now_ms / 1000.0, frames);
  dispatch(frames, now_ms, tx);
}

void RosserialDevice::dispatch(const std::vector<Frame>& frames, std::uint32_t now_ms,
                               std::vector<std::uint8_t>& tx) {
  for (const Frame& f : frames) {
    if (f.topic == kIdPublisher) {
      ++topic_requests_;
      requestSyncTime(now_ms, tx);
      negotiateTopics(tx);
      last_sync_receive_ms_ = now_ms;
    } else if (f.topic == kIdTime) {
      Stamp t;
      if (deserialize(f.payload.data(), f.payload.size(), t)) {
        last_time_ = t;
        time_synced_ = true;
        last_sync_receive_ms_ = now_ms;
      }
    } else if (f.topic == kIdTxStop) {
      ++tx_stops_;
      configured_ = false;
    } else if (f.topic >= kFirstUserTopic) {
      const std::size_t i = f.topic - kFirstUserTopic;
      if (i < subscribers_.size() && subscribers_[i].callback)
        subscribers_[i].callback(f.payload.data(), f.payload.size());
    }
  }
}

void RosserialDevice::spinOnce(std::uint32_t now_ms, std::vector<std::uint8_t>& tx) {
  std::vector<Frame> frames;
  parser_.poll(now_ms / 1000.0, frames);  // a stalled frame is abandoned, its rescan may hold one
  dispatch(frames, now_ms, tx);
  if (static_cast<std::uint32_t>(now_ms - last_sync_receive_ms_) > config_.sync_timeout_ms) configured_ = false;
  if (configured_ && static_cast<std::uint32_t>(now_ms - last_sync_time_ms_) > config_.sync_period_ms)
    requestSyncTime(now_ms, tx);
}

bool RosserialDevice::publish(std::uint16_t id, const std::vector<std::uint8_t>& payload,
                              std::vector<std::uint8_t>& tx) {
  if (id >= kFirstUserTopic && !configured_) return false;
  if (payload.size() + kFrameOverheadBytes > config_.output_size) return false;
  appendFrame(id, payload.data(), payload.size(), tx);
  return true;
}

void RosserialDevice::log(std::uint8_t level, const std::string& text, std::vector<std::uint8_t>& tx) {
  LogMessage m;
  m.level = level;
  m.msg = text;
  std::vector<std::uint8_t> payload;
  serialize(m, payload);
  publish(kIdLog, payload, tx);
}

}  // namespace rosserial
}  // namespace icanc
