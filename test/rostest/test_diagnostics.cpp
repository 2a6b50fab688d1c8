// rostest: every nodelet of launch/icanc.launch reports its input on /diagnostics as
// "<node>: input topic status" (rate, processing time, invalid and dropped frames; InputMonitor in
// nodelet_support), and the controller its lamp state (off while the clouds flow, ON fail-safe
// once they stop). Clouds at the expected 10 Hz give no rate
// warning; clouds at 2 Hz give WARN "Frequency too low." and count the missing frames as dropped.
#include <atomic>
#include <map>
#include <thread>

#include <diagnostic_msgs/DiagnosticArray.h>
#include <gtest/gtest.h>

#include "graph_fixture.hpp"

namespace icanc {
namespace test {
namespace {

const char* const kNodes[] = {"icanc/obstacle_detector", "icanc/danger_detector", "icanc/light_controller"};

class Diagnostics : public ::testing::Test {
 protected:
  Diagnostics() : g_("approach_front.yaml") {
    sub_ = g_.nh().subscribe<diagnostic_msgs::DiagnosticArray>("/diagnostics", 100,
        [this](const diagnostic_msgs::DiagnosticArray::ConstPtr& m) {
          std::lock_guard<std::mutex> lock(mutex_);
          for (const auto& s : m->status) latest_[s.name] = s;
        });
  }

  ~Diagnostics() override { stop(); }

  // Publishes clouds of the scenario (a standing scene: t fixed at 1 s) at `rate_hz` from a
  // thread until stop(), so the statuses are read while the input flows.
  void start(double rate_hz) {
    stop();
    running_ = true;
    publisher_ = std::thread([this, rate_hz] {
      ros::Rate rate(rate_hz);
      while (running_ && ros::ok()) {
        g_.publishFrame(1.0, ros::Time::now());
        rate.sleep();
      }
    });
  }
  void stop() {
    running_ = false;
    if (publisher_.joinable()) publisher_.join();
  }

  // Waits for the next /diagnostics report of every node after this call, then returns the status.
  diagnostic_msgs::DiagnosticStatus fresh(const std::string& name) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      latest_.erase(name);
    }
    waitFor([&] {
      std::lock_guard<std::mutex> lock(mutex_);
      return latest_.count(name) > 0;
    }, 3.0);
    std::lock_guard<std::mutex> lock(mutex_);
    return latest_.count(name) ? latest_[name] : diagnostic_msgs::DiagnosticStatus();
  }

  static std::string value(const diagnostic_msgs::DiagnosticStatus& s, const std::string& key) {
    for (const auto& kv : s.values)
      if (kv.key == key) return kv.value;
    return "";
  }

  GraphFixture g_;
  std::atomic<bool> running_{false};
  std::thread publisher_;
  std::mutex mutex_;
  std::map<std::string, diagnostic_msgs::DiagnosticStatus> latest_;
  // Declared last, so destroyed first: a subscriber's destructor waits for a running callback,
  // which then never writes into members already freed (ASan caught it at fixture teardown).
  ros::Subscriber sub_;
};

TEST_F(Diagnostics, InputRateProcessingTimeDroppedFramesAndLampState) {
  ASSERT_TRUE(g_.waitForGraph()) << "icanc graph did not come up";

  // At the expected rate for longer than the 10 s frequency window: no rate warning.
  start(10.0);
  ros::WallDuration(12.0).sleep();
  for (const char* node : kNodes) {
    const auto s = fresh(std::string(node) + ": input topic status");
    ASSERT_FALSE(s.name.empty()) << node << " reports no input status";
    std::printf("%s: level %d '%s', frequency %s, processing mean %s ms\n", s.name.c_str(), s.level,
                s.message.c_str(), value(s, "Actual frequency (Hz)").c_str(),
                value(s, "processing ms (mean since last report)").c_str());
    EXPECT_EQ(s.message.find("Frequency too low"), std::string::npos) << s.name << ": " << s.message;
    EXPECT_EQ(std::stod(value(s, "expected rate [Hz]")), 10.0);
    EXPECT_GT(std::stol(value(s, "frames processed")), 80);
    EXPECT_EQ(value(s, "invalid frames"), "0");
    EXPECT_GT(std::stod(value(s, "processing ms (mean since last report)")), 0.0);
  }
  // The lamp state in the controller's status: off, nothing in the standing scene is dangerous.
  const auto off = fresh("icanc/light_controller: light controller");
  EXPECT_EQ(value(off, "lamp on"), "False");
  EXPECT_EQ(value(off, "reason"), "off");

  // Five times slower than expected, for a whole window: WARN, and four frames missing per gap.
  start(2.0);
  ros::WallDuration(11.0).sleep();
  for (const char* node : kNodes) {
    const auto s = fresh(std::string(node) + ": input topic status");
    std::printf("%s: level %d '%s', frequency %s, dropped %s\n", s.name.c_str(), s.level,
                s.message.c_str(), value(s, "Actual frequency (Hz)").c_str(),
                value(s, "dropped frames").c_str());
    EXPECT_EQ(s.level, diagnostic_msgs::DiagnosticStatus::WARN) << s.name;
    EXPECT_NE(s.message.find("Frequency too low"), std::string::npos) << s.name << ": " << s.message;
    EXPECT_GE(std::stol(value(s, "dropped frames")), 4 * 18) << s.name;
  }
  stop();

  // The clouds stopped: the lamp state in the controller's status is ON, fail-safe, and WARN.
  ros::WallDuration(0.5).sleep();  // > stale_timeout_s
  const auto lamp = fresh("icanc/light_controller: light controller");
  EXPECT_EQ(lamp.level, diagnostic_msgs::DiagnosticStatus::WARN);
  EXPECT_EQ(value(lamp, "lamp on"), "True");
  EXPECT_EQ(value(lamp, "reason"), "sensor stale");
}

}  // namespace
}  // namespace test
}  // namespace icanc

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_diagnostics");
  ros::AsyncSpinner spinner(2);
  spinner.start();
  return RUN_ALL_TESTS();
}
