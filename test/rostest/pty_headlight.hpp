// An emulated icanc_headlight board on a pseudo-terminal, for the LightBridge rostests: the
// device side of rosserial (icanc/core/bridge/rosserial_device.hpp, behaving like ros_lib) running the
// sketch's fail-safe logic (firmware/icanc_headlight/headlight_logic.h) in its own thread, with a
// symlink at a fixed path standing for /dev/ttyACM0. Faults are injected from the test thread:
// unplug (the pty and the symlink vanish), replug (new pty, same path), reset (power cycle, if
// asked mid-frame), raw bytes (garbage, bad checksums, truncated or oversized frames) and a mute
// (the board stops talking for a while).
#pragma once

#include <fcntl.h>
#include <poll.h>
#include <pty.h>
#include <termios.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "../../firmware/icanc_headlight/headlight_logic.h"
#include "icanc/core/bridge/rosserial_device.hpp"

namespace icanc {
namespace test {

inline double steadySeconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

struct PtyHeadlightOptions {
  std::string cmd_type = rosserial::kBoolType;  // of the board's lamp_cmd subscriber
  std::string cmd_md5 = rosserial::kBoolMd5;
  std::uint32_t command_timeout_ms = 500;
  std::uint32_t state_period_ms = 100;
  // false: a stock subscribe-only sketch (no lamp_state publisher): it sends nothing but ros_lib's
  // time request every 2.5 s.
  bool report_state = true;
  // Non-empty: the board also subscribes this std_msgs/UInt8MultiArray (segment levels).
  std::string levels_topic;
};

class PtyHeadlight {
 public:
  using Options = PtyHeadlightOptions;
  struct Command {
    bool value;
    double time_s;  // steadySeconds() when the frame was handled
  };

  explicit PtyHeadlight(std::string link) : link_(std::move(link)), start_(steadySeconds()) {
    running_ = true;
    thread_ = std::thread(&PtyHeadlight::loop, this);
  }
  ~PtyHeadlight() {
    running_ = false;
    thread_.join();
    unplug();
  }

  // A board (new pseudo-terminal) appears at the link path.
  bool plug(const Options& options = Options()) {
    std::lock_guard<std::mutex> lock(mutex_);
    closeLocked();
    termios raw;
    cfmakeraw(&raw);  // raw from the start: no echo of what the bridge writes before it opens
    char name[128];
    if (openpty(&master_, &slave_, name, &raw, nullptr) != 0) return false;
    fcntl(master_, F_SETFL, fcntl(master_, F_GETFL) | O_NONBLOCK);
    powerUpLocked(options);
    ::unlink(link_.c_str());
    return ::symlink(name, link_.c_str()) == 0;
  }

  // The board is pulled out: its pseudo-terminal closes (the bridge sees a hang-up) and the link
  // path disappears. The board keeps running its logic (on its own, it fails safe ON).
  void unplug() {
    std::lock_guard<std::mutex> lock(mutex_);
    closeLocked();
    ::unlink(link_.c_str());
  }

  // Power cycle; with `mid_frame`, the board dies half-way through a lamp_state frame.
  void reset(bool mid_frame) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (mid_frame && master_ >= 0) {
      const auto frame = rosserial::encodeFrame(state_id_, {static_cast<std::uint8_t>(logic_.lampOn())});
      writeLocked(std::vector<std::uint8_t>(frame.begin(), frame.begin() + 5));
    }
    powerUpLocked(options_);
  }

  void inject(const std::vector<std::uint8_t>& bytes, double mute_s = 0.0) {
    std::lock_guard<std::mutex> lock(mutex_);
    writeLocked(bytes);
    mute_until_ = steadySeconds() + mute_s;
  }

  std::vector<Command> commands() {
    std::lock_guard<std::mutex> lock(mutex_);
    return commands_;
  }
  std::size_t commandCount() {
    std::lock_guard<std::mutex> lock(mutex_);
    return commands_.size();
  }
  bool lampOn() {
    std::lock_guard<std::mutex> lock(mutex_);
    return logic_.lampOn();
  }
  bool connected() {
    std::lock_guard<std::mutex> lock(mutex_);
    return device_ && device_->connected();
  }
  std::vector<std::vector<std::uint8_t>> levels() {  // every levels frame handled
    std::lock_guard<std::mutex> lock(mutex_);
    return levels_;
  }
  std::uint8_t segmentDuty(std::uint8_t i) {  // the sketch's PWM duty of segment i now
    std::lock_guard<std::mutex> lock(mutex_);
    return segments_.duty(i, logic_, millis());
  }
  std::uint16_t stateId() {
    std::lock_guard<std::mutex> lock(mutex_);
    return state_id_;
  }
  const std::string& link() const { return link_; }

 private:
  std::uint32_t millis() const { return static_cast<std::uint32_t>((steadySeconds() - start_) * 1000.0); }

  void powerUpLocked(const Options& options) {
    options_ = options;
    device_.reset(new rosserial::RosserialDevice());
    logic_ = icanc_fw::HeadlightLogic(options.command_timeout_ms);
    state_id_ = options.report_state
                    ? device_->advertise("lamp_state", rosserial::kBoolType, rosserial::kBoolMd5)
                    : 0;
    device_->subscribe("lamp_cmd", options.cmd_type, options.cmd_md5, [this](const std::uint8_t* d, std::size_t n) {
      bool v = true;
      if (n == 1 && rosserial::deserializeBool(d, n, v)) {
        logic_.onCommand(v, millis());
        commands_.push_back(Command{v, steadySeconds()});
      } else {
        ++bad_commands_;
      }
    });
    segments_ = icanc_fw::SegmentLevels(options.command_timeout_ms);
    if (!options.levels_topic.empty())
      device_->subscribe(options.levels_topic, rosserial::kUInt8ArrayType, rosserial::kUInt8ArrayMd5,
                         [this](const std::uint8_t* d, std::size_t n) {
                           std::vector<std::uint8_t> levels;
                           if (!rosserial::deserializeUInt8Array(d, n, levels)) return;
                           segments_.onLevels(levels.data(), static_cast<std::uint32_t>(levels.size()), millis());
                           levels_.push_back(levels);
                         });
    last_state_ms_ = millis();
  }

  void closeLocked() {
    if (master_ >= 0) ::close(master_);
    if (slave_ >= 0) ::close(slave_);
    master_ = slave_ = -1;
  }

  void writeLocked(const std::vector<std::uint8_t>& bytes) {
    if (master_ < 0 || bytes.empty()) return;
    std::size_t done = 0;
    for (int tries = 0; done < bytes.size() && tries < 100; ++tries) {
      const ssize_t n = ::write(master_, bytes.data() + done, bytes.size() - done);
      if (n > 0)
        done += static_cast<std::size_t>(n);
      else
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
  }

  void loop() {
    std::vector<std::uint8_t> buf(1024), tx;
    while (running_) {
      int fd;
      {
        std::lock_guard<std::mutex> lock(mutex_);
        fd = master_;
      }
      if (fd >= 0) {
        pollfd p{fd, POLLIN, 0};
        ::poll(&p, 1, 2);
      } else {
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
      }
      std::lock_guard<std::mutex> lock(mutex_);
      tx.clear();
      const std::uint32_t now = millis();
      if (master_ >= 0) {
        const ssize_t n = ::read(master_, buf.data(), buf.size());
        if (n > 0) device_->receive(buf.data(), static_cast<std::size_t>(n), now, tx);
      }
      device_->spinOnce(now, tx);
      const bool was_on = logic_.lampOn();
      const bool on = logic_.update(device_->connected(), now);  // unplugged, it only times out
      if (!device_->connected()) segments_.onDisconnect();
      if (state_id_ != 0 && (on != was_on || now - last_state_ms_ >= options_.state_period_ms)) {
        device_->publish(state_id_, {static_cast<std::uint8_t>(on)}, tx);
        last_state_ms_ = now;
      }
      if (steadySeconds() >= mute_until_) writeLocked(tx);
    }
  }

  const std::string link_;
  const double start_;
  std::atomic<bool> running_{false};
  std::thread thread_;

  std::mutex mutex_;
  int master_ = -1, slave_ = -1;  // the slave stays open here so the master never reads EIO
  Options options_;
  std::unique_ptr<rosserial::RosserialDevice> device_{new rosserial::RosserialDevice()};
  icanc_fw::HeadlightLogic logic_;
  icanc_fw::SegmentLevels segments_;
  std::vector<std::vector<std::uint8_t>> levels_;
  std::uint16_t state_id_ = 0;
  std::uint32_t last_state_ms_ = 0;
  double mute_until_ = 0.0;
  std::vector<Command> commands_;
  std::size_t bad_commands_ = 0;
};

}  // namespace test
}  // namespace icanc
