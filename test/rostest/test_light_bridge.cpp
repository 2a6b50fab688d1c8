// rostest: icanc/LightBridge in a nodelet manager against an emulated headlight board on a
// pseudo-terminal (pty_headlight.hpp). Pins: negotiation, commands reaching the board at once and
// at the heartbeat, the board's lamp state coming back, and each fault survived without a crash
// or a stuck lamp: garbage, bad checksums, truncated and oversized frames, unplug/replug, reset
// mid-frame, a board whose command topic has the wrong type (link_up false, errors of each kind
// printed), a stock subscribe-only board kept by its time requests, lamp_status UNKNOWN_FAILSAFE
// while the link is down. Prints the measured command latency
// (lamp_cmd published -> frame handled by the board), the time to detect a lost board and the time
// to resync after garbage.
#include <algorithm>
#include <cstdio>
#include <map>
#include <random>

#include <diagnostic_msgs/DiagnosticArray.h>
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <rosgraph_msgs/Log.h>
#include <std_msgs/Bool.h>

#include "icanc/LampCommand.h"
#include "icanc/LampState.h"
#include "icanc/core/bridge/rosserial_session.hpp"
#include "pty_headlight.hpp"

namespace icanc {
namespace test {
namespace {

using Bytes = std::vector<std::uint8_t>;

template <class Pred>
bool waitFor(Pred pred, double timeout) {
  const double end = steadySeconds() + timeout;
  while (ros::ok() && steadySeconds() < end) {
    if (pred()) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  return pred();
}

double percentile(std::vector<double> v, double q) {
  if (v.empty()) return -1.0;
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<std::size_t>(q * (v.size() - 1) + 0.5))];
}

// What the test sees of the ROS side: link_up, lamp_state, /diagnostics, /rosout.
struct RosSide {
  RosSide() {
    ros::NodeHandle nh;
    cmd_pub = nh.advertise<std_msgs::Bool>("/icanc/lamp_cmd", 10);
    link_sub = nh.subscribe<std_msgs::Bool>("/icanc/light_bridge/link_up", 10,
        [this](const std_msgs::Bool::ConstPtr& m) {
          std::lock_guard<std::mutex> l(mutex);
          link_up = m->data;
          link_changes.push_back({m->data, steadySeconds()});
        });
    state_sub = nh.subscribe<std_msgs::Bool>("/icanc/lamp_state", 100, [this](const std_msgs::Bool::ConstPtr& m) {
      std::lock_guard<std::mutex> l(mutex);
      lamp_states.push_back({m->data, steadySeconds()});
    });
    status_sub = nh.subscribe<LampState>("/icanc/lamp_status", 100, [this](const LampState::ConstPtr& m) {
      std::lock_guard<std::mutex> l(mutex);
      statuses.push_back(*m);
      status_times.push_back(steadySeconds());
    });
    diag_sub = nh.subscribe<diagnostic_msgs::DiagnosticArray>("/diagnostics", 100,
        [this](const diagnostic_msgs::DiagnosticArray::ConstPtr& m) {
          std::lock_guard<std::mutex> l(mutex);
          for (const auto& s : m->status)
            if (s.name.find("light bridge") != std::string::npos) {
              for (const auto& kv : s.values) diag[kv.key] = kv.value;
              ++diag_count;
            }
        });
    rosout_sub = nh.subscribe<rosgraph_msgs::Log>("/rosout", 200, [this](const rosgraph_msgs::Log::ConstPtr& m) {
      std::lock_guard<std::mutex> l(mutex);
      logs.push_back(*m);
    });
  }

  void command(bool on) {
    std_msgs::Bool m;
    m.data = on;
    cmd_pub.publish(m);
  }
  bool linkUp() {
    std::lock_guard<std::mutex> l(mutex);
    return link_up;
  }
  // When link_up first went false after t0 (-1: not yet); it may come back up within the same
  // millisecond, so the history is searched rather than the current value.
  double linkDownAfter(double t0) {
    std::lock_guard<std::mutex> l(mutex);
    for (const auto& c : link_changes)
      if (!c.first && c.second >= t0) return c.second;
    return -1.0;
  }
  // When a lamp_status with `state` first arrived after t0 (-1: not yet).
  double statusAfter(double t0, std::uint8_t state) {
    std::lock_guard<std::mutex> l(mutex);
    for (std::size_t i = 0; i < statuses.size(); ++i)
      if (status_times[i] >= t0 && statuses[i].state == state) return status_times[i];
    return -1.0;
  }
  // The last lamp_status (state 255 when none yet).
  LampState lastStatus() {
    std::lock_guard<std::mutex> l(mutex);
    if (statuses.empty()) {
      LampState none;
      none.state = 255;
      return none;
    }
    return statuses.back();
  }
  std::size_t stateCount() {
    std::lock_guard<std::mutex> l(mutex);
    return lamp_states.size();
  }
  std::pair<bool, double> lastState() {
    std::lock_guard<std::mutex> l(mutex);
    return lamp_states.empty() ? std::make_pair(true, 0.0) : lamp_states.back();
  }
  // A diagnostics value as a number (-1 when absent); waits for a fresh diagnostics message.
  double diagValue(const std::string& key, bool fresh = true) {
    if (fresh) {
      std::size_t n;
      {
        std::lock_guard<std::mutex> l(mutex);
        n = diag_count;
      }
      waitFor([&] { std::lock_guard<std::mutex> l(mutex); return diag_count > n; }, 3.0);
    }
    std::lock_guard<std::mutex> l(mutex);
    auto it = diag.find(key);
    return it == diag.end() ? -1.0 : std::atof(it->second.c_str());
  }
  std::string diagText(const std::string& key) {
    std::lock_guard<std::mutex> l(mutex);
    auto it = diag.find(key);
    return it == diag.end() ? "" : it->second;
  }
  bool logged(std::uint8_t level, const std::string& text, double timeout = 5.0) {
    return waitFor([&] {
      std::lock_guard<std::mutex> l(mutex);
      for (const auto& m : logs)
        if (m.level >= level && m.msg.find(text) != std::string::npos) return true;
      return false;
    }, timeout);
  }

  ros::Publisher cmd_pub;
  std::mutex mutex;
  bool link_up = false;
  std::vector<std::pair<bool, double>> link_changes, lamp_states;
  std::map<std::string, std::string> diag;
  std::size_t diag_count = 0;
  std::vector<rosgraph_msgs::Log> logs;
  std::vector<LampState> statuses;
  std::vector<double> status_times;  // steady time each status arrived
  // Declared last, so destroyed first: a subscriber's destructor waits for a running callback,
  // which then never writes into members already freed (ASan caught it at fixture teardown).
  ros::Subscriber link_sub, state_sub, status_sub, diag_sub, rosout_sub;
};

// The LightController's part: lamp_cmd at 10 Hz with the wanted value, in a thread.
class Controller {
 public:
  explicit Controller(RosSide& ros) : ros_(ros) {
    thread_ = std::thread([this] {
      while (running_ && ros::ok()) {
        if (active_) ros_.command(value_);
        std::this_thread::sleep_for(std::chrono::milliseconds(100));
      }
    });
  }
  ~Controller() {
    running_ = false;
    thread_.join();
  }
  void set(bool on) {
    value_ = on;
    active_ = true;
    ros_.command(on);
  }
  void stop() { active_ = false; }

 private:
  RosSide& ros_;
  std::atomic<bool> running_{true}, active_{false}, value_{true};
  std::thread thread_;
};

PtyHeadlight* g_board = nullptr;
RosSide* g_ros = nullptr;
Controller* g_controller = nullptr;
int g_baud = 57600;

class LightBridge : public ::testing::Test {
 protected:
  PtyHeadlight& board() { return *g_board; }
  RosSide& ros() { return *g_ros; }
  Controller& controller() { return *g_controller; }

  // The board follows a command within `timeout`.
  bool boardFollows(bool on, double timeout = 0.5) {
    controller().set(on);
    return waitFor([&] { return board().lampOn() == on; }, timeout);
  }
  bool synced(double timeout = 10.0) {
    return waitFor([&] { return ros().linkUp() && board().connected(); }, timeout);
  }
  // The link stays up and the lamp follows commands both ways after a fault.
  void expectHealthy(const char* after) {
    EXPECT_TRUE(ros().linkUp()) << "link dropped after " << after;
    EXPECT_TRUE(boardFollows(true)) << "lamp stuck after " << after;
    EXPECT_TRUE(boardFollows(false)) << "lamp stuck after " << after;
  }
};

TEST_F(LightBridge, NegotiatesAndTheLampFollowsCommands) {
  ASSERT_TRUE(board().plug());
  ASSERT_TRUE(synced(15.0)) << "no negotiation with the emulated board";
  EXPECT_TRUE(board().lampOn()) << "no lamp_cmd yet: the lamp is ON";
  ASSERT_TRUE(boardFollows(false));
  // The board's actual state comes back on lamp_state.
  EXPECT_TRUE(waitFor([&] { auto s = ros().lastState(); return ros().stateCount() > 0 && !s.first; }, 1.0));
  ASSERT_TRUE(boardFollows(true));
  EXPECT_TRUE(waitFor([&] { return ros().lastState().first; }, 1.0));
  EXPECT_TRUE(waitFor([&] { return ros().diagText("link state") == "synced"; }, 3.0))
      << ros().diagText("link state");
  // lamp_status: the same report, stamped, with the link.
  EXPECT_TRUE(waitFor([&] { return ros().lastStatus().state == LampState::ON; }, 1.0));
  EXPECT_TRUE(ros().lastStatus().link_up);
  EXPECT_TRUE(ros().lastStatus().commanded_on);
  EXPECT_GT(ros().lastStatus().header.stamp.toSec(), 0.0);
}

TEST_F(LightBridge, HeartbeatRepeatsAnUnchangedCommandThenFailsSafe) {
  ASSERT_TRUE(boardFollows(false));
  controller().stop();
  ros().command(false);
  std::this_thread::sleep_for(std::chrono::milliseconds(50));
  const std::size_t before = board().commandCount();
  std::this_thread::sleep_for(std::chrono::milliseconds(800));
  const auto cmds = board().commands();
  const std::size_t n = cmds.size() - before;
  // The heartbeat's period is judged by the median gap between the frames the board received, so
  // one stall of a loaded machine (CI, ASan) does not decide it; the count only bounds it.
  EXPECT_GE(n, 4u) << "heartbeat at 10 Hz expected";
  EXPECT_LE(n, 10u);
  std::vector<double> gaps_ms;
  for (std::size_t i = before + 1; i < cmds.size(); ++i)
    gaps_ms.push_back((cmds[i].time_s - cmds[i - 1].time_s) * 1000.0);
  const double median_gap_ms = percentile(gaps_ms, 0.5);
  EXPECT_GT(median_gap_ms, 70.0) << "heartbeat faster than 10 Hz";
  EXPECT_LT(median_gap_ms, 140.0) << "heartbeat slower than 10 Hz";
  for (std::size_t i = before; i < cmds.size(); ++i) EXPECT_FALSE(cmds[i].value);
  // The lamp is OFF, unless the board's own watchdog fired: a stall of the loaded machine (the
  // sanitized suite on 2 cores) that left more than its 500 ms between two heartbeats.
  double widest_gap_ms = gaps_ms.empty() ? 0.0 : *std::max_element(gaps_ms.begin(), gaps_ms.end());
  if (!cmds.empty()) widest_gap_ms = std::max(widest_gap_ms, (steadySeconds() - cmds.back().time_s) * 1000.0);
  if (widest_gap_ms < 0.9 * icanc_fw::HeadlightLogic::kDefaultTimeoutMs) {
    EXPECT_FALSE(board().lampOn()) << "widest heartbeat gap " << widest_gap_ms << " ms";
  }
  // No lamp_cmd for cmd_stale_timeout_s (1 s): the bridge commands ON.
  EXPECT_TRUE(waitFor([&] { return board().lampOn(); }, 1.0)) << "stale lamp_cmd must fail safe ON";
  EXPECT_TRUE(board().commands().back().value);
  ASSERT_TRUE(boardFollows(false));
}

TEST_F(LightBridge, CommandLatency) {
  ASSERT_TRUE(boardFollows(false));
  controller().stop();
  std::vector<double> latency_ms;
  bool value = false;
  for (int i = 0; i < 200; ++i) {
    value = !value;
    const std::size_t before = board().commandCount();
    const double t0 = steadySeconds();
    ros().command(value);
    double t1 = -1.0;
    waitFor([&] {
      const auto cmds = board().commands();
      for (std::size_t k = before; k < cmds.size(); ++k)
        if (cmds[k].value == value && cmds[k].time_s >= t0) {
          t1 = cmds[k].time_s;
          return true;
        }
      return false;
    }, 1.0);
    if (t1 > 0) latency_ms.push_back((t1 - t0) * 1000.0);
    std::this_thread::sleep_for(std::chrono::milliseconds(25));
  }
  ASSERT_GE(latency_ms.size(), 195u);
  const double p50 = percentile(latency_ms, 0.5), p99 = percentile(latency_ms, 0.99);
  const double write_p50 = ros().diagValue("command latency p50 [ms]");
  const double write_p99 = ros().diagValue("command latency p99 [ms]", false);
  const double wire_ms = 9 * 10 * 1000.0 / g_baud;  // a Bool frame is 9 bytes of 10 bits
  std::printf("[ MEASURE ] baud %d: lamp_cmd publish -> board handled the frame: p50 %.3f ms, p99 %.3f "
              "ms (n=%zu); bridge callback -> frame written and drained: p50 %.3f ms, p99 %.3f ms; "
              "wire time of the 9-byte frame on a real UART %.3f ms (a pty has none)\n",
              g_baud, p50, p99, latency_ms.size(), write_p50, write_p99, wire_ms);
  // Timings are for the benchmark's log above; the pin is loose enough that a loaded machine's
  // stalls (which move p99, not p50) do not decide it.
  EXPECT_LT(p50, 50.0);
  ASSERT_TRUE(boardFollows(false));
}

TEST_F(LightBridge, GarbageIsCountedAndResyncedAtOnce) {
  ASSERT_TRUE(boardFollows(false));
  const double garbage_before = ros().diagValue("faults: garbage bytes");
  const double losses_before = ros().diagValue("link losses", false);
  std::mt19937 rng(7);
  Bytes garbage(2000);
  for (auto& b : garbage) b = static_cast<std::uint8_t>(rng() % 256);
  // Garbage, then one good lamp_state frame saying ON while the lamp is OFF: the time until it
  // comes out on /icanc/lamp_state is the time to resync.
  Bytes s = garbage;
  const Bytes marker = rosserial::encodeFrame(board().stateId(), {1});
  s.insert(s.end(), marker.begin(), marker.end());
  const double t0 = steadySeconds();
  board().inject(s, 0.05);  // the board holds its own frames back until the marker is through
  ASSERT_TRUE(waitFor([&] { auto st = ros().lastState(); return st.first && st.second >= t0; }, 2.0));
  const double resync_ms = (ros().lastState().second - t0) * 1000.0;
  std::printf("[ MEASURE ] baud %d: 2000 garbage bytes then a good frame: republished %.3f ms after "
              "the garbage was written\n", g_baud, resync_ms);
  EXPECT_GE(ros().diagValue("faults: garbage bytes") - garbage_before, 1500.0);
  EXPECT_EQ(ros().diagValue("link losses", false), losses_before);
  expectHealthy("garbage");
  EXPECT_TRUE(ros().logged(rosgraph_msgs::Log::WARN, "garbage bytes"));
}

TEST_F(LightBridge, BadChecksumsTruncatedAndOversizedFramesAreCountedAndSurvived) {
  ASSERT_TRUE(boardFollows(false));
  const std::uint16_t id = board().stateId();
  Bytes bad_len = rosserial::encodeFrame(id, {1});
  bad_len[4] ^= 0x20;
  Bytes bad_msg = rosserial::encodeFrame(id, {1});
  bad_msg.back() ^= 0x01;
  const Bytes oversized = {0xFF, 0xFE, 0x00, 0x40, 0xBF, 0x7D, 0x00};  // 16 KiB announced
  const Bytes full = rosserial::encodeFrame(id, {1});
  const Bytes truncated(full.begin(), full.begin() + 6);

  struct Case {
    const char* name;
    const char* counter;
    Bytes bytes;
    double mute_s;
  };
  const Case cases[] = {
      {"bad length checksum", "faults: bad length checksum", bad_len, 0.0},
      {"bad message checksum", "faults: bad message checksum", bad_msg, 0.0},
      {"oversized length", "faults: oversized length", oversized, 0.0},
      {"truncated frame", "faults: truncated frames", truncated, 0.3},  // then silence
  };
  for (const Case& c : cases) {
    const double before = ros().diagValue(c.counter);
    const double losses = ros().diagValue("link losses", false);
    board().inject(c.bytes, c.mute_s);
    EXPECT_TRUE(waitFor([&] { return ros().diagValue(c.counter) >= before + 1; }, 5.0)) << c.name;
    EXPECT_EQ(ros().diagValue("link losses", false), losses) << c.name;
    EXPECT_FALSE(ros().lastState().first) << "a corrupted 'ON' report was republished: " << c.name;
    expectHealthy(c.name);
  }
}

TEST_F(LightBridge, UnplugAndReplugAreSurvived) {
  ASSERT_TRUE(boardFollows(false));
  const double t0 = steadySeconds();
  board().unplug();
  ASSERT_TRUE(waitFor([&] { return ros().linkDownAfter(t0) > 0; }, 5.0));
  const double detect_ms = (ros().linkDownAfter(t0) - t0) * 1000.0;
  // The bridge no longer knows the lamp: unknown, the device failing safe.
  EXPECT_TRUE(waitFor([&] { return ros().lastStatus().state == LampState::UNKNOWN_FAILSAFE; }, 1.0))
      << "lamp_status " << int(ros().lastStatus().state);
  EXPECT_FALSE(ros().lastStatus().link_up);
  // Cut off, the board fails safe ON after its command timeout (500 ms).
  EXPECT_TRUE(waitFor([&] { return board().lampOn(); }, 1.0));
  std::this_thread::sleep_for(std::chrono::milliseconds(1500));  // unplugged for a while
  const double t1 = steadySeconds();
  ASSERT_TRUE(board().plug());
  ASSERT_TRUE(synced(10.0)) << "no renegotiation after replug";
  const double resync_ms = (steadySeconds() - t1) * 1000.0;
  std::printf("[ MEASURE ] baud %d: unplug detected (link_up false) after %.1f ms; replug -> synced "
              "after %.1f ms (reconnect_period_s 0.5)\n", g_baud, detect_ms, resync_ms);
  EXPECT_LT(detect_ms, 500.0) << "a vanished port is a hang-up, seen at once";
  EXPECT_GE(ros().diagValue("port losses"), 1.0);
  EXPECT_TRUE(ros().logged(rosgraph_msgs::Log::ERROR, "lost"));
  EXPECT_TRUE(boardFollows(false, 1.0));
  expectHealthy("unplug/replug");
}

TEST_F(LightBridge, ResetMidFrameIsDetectedAndRenegotiated) {
  ASSERT_TRUE(boardFollows(false));
  const double truncated = ros().diagValue("faults: truncated frames");
  const double t0 = steadySeconds();
  board().reset(true);  // half a frame, then a silent, unconfigured board
  EXPECT_TRUE(board().lampOn()) << "power-up: lamp ON";
  ASSERT_TRUE(waitFor([&] { return ros().linkDownAfter(t0) > 0; }, 10.0));
  const double detect_ms = (ros().linkDownAfter(t0) - t0) * 1000.0;
  ASSERT_TRUE(synced(5.0));
  const double back_ms = (steadySeconds() - t0) * 1000.0;
  std::printf("[ MEASURE ] baud %d: silent (reset) board detected after %.1f ms (link_timeout_s "
              "%.1f, the default); renegotiated %.1f ms after the reset\n", g_baud, detect_ms,
              LightBridgeParams().link_timeout_s, back_ms);
  const double timeout_ms = LightBridgeParams().link_timeout_s * 1000.0;
  EXPECT_GT(detect_ms, timeout_ms - 500.0);  // from the last frame before the reset
  EXPECT_LT(detect_ms, timeout_ms + 1500.0);
  EXPECT_GE(ros().diagValue("faults: truncated frames"), truncated + 1);
  expectHealthy("reset mid-frame");
}

// A board that stops answering (reset: silent and unconfigured) has failed safe ON long before
// link_timeout_s drops the link: lamp_status says UNKNOWN_FAILSAFE within lamp_report_timeout_s
// of its last report (plus one report period and scheduling), while the link is still up.
TEST_F(LightBridge, SilentBoardIsUnknownBeforeTheLinkTimesOut) {
  ASSERT_TRUE(boardFollows(false));
  ASSERT_TRUE(waitFor([&] { return ros().lastStatus().state == LampState::OFF; }, 2.0));
  const double t0 = steadySeconds();
  board().reset(false);
  ASSERT_TRUE(waitFor([&] { return ros().statusAfter(t0, LampState::UNKNOWN_FAILSAFE) > 0; }, 3.0))
      << "lamp_status kept the silent board's last state";
  const double unknown_ms = (ros().statusAfter(t0, LampState::UNKNOWN_FAILSAFE) - t0) * 1000.0;
  const double limit_ms = (LightBridgeParams().lamp_report_timeout_s + 0.1 + 0.2) * 1000.0;
  std::printf("[ MEASURE ] baud %d: silent board reported unknown after %.1f ms\n", g_baud, unknown_ms);
  EXPECT_LT(unknown_ms, limit_ms);
  EXPECT_LT(unknown_ms, LightBridgeParams().link_timeout_s * 1000.0 - 1000.0);
  EXPECT_LT(ros().linkDownAfter(t0), 0.0) << "unknown by the report timeout, not by a link loss";
  EXPECT_TRUE(board().lampOn());
  EXPECT_TRUE(waitFor([&] { return ros().diagValue("lamp reports overdue (status unknown)") >= 1.0; }, 3.0));
  ASSERT_TRUE(waitFor([&] { return ros().linkDownAfter(t0) > 0; }, 10.0));
  ASSERT_TRUE(synced(5.0));
  expectHealthy("a silent board");
}

TEST_F(LightBridge, WrongCommandTypeIsRefused) {
  // First another kind of device error: a malformed TopicInfo. Its throttle must not hide the
  // type mismatch that follows (one 10 s throttle for all kinds did).
  ASSERT_TRUE(boardFollows(false));
  board().inject(rosserial::encodeFrame(rosserial::kIdPublisher, {0x01, 0x02}));
  ASSERT_TRUE(ros().logged(rosgraph_msgs::Log::ERROR, "malformed rosserial_msgs/TopicInfo", 3.0));
  const double t_malformed = steadySeconds();
  board().unplug();
  ASSERT_TRUE(waitFor([&] { return !ros().linkUp(); }, 5.0));
  PtyHeadlight::Options wrong;
  wrong.cmd_type = "std_msgs/Int32";
  wrong.cmd_md5 = "da5909fbe378aeaf85e547e830cc1bb7";
  ASSERT_TRUE(board().plug(wrong));
  const std::size_t before = board().commandCount();
  controller().set(false);
  EXPECT_TRUE(ros().logged(rosgraph_msgs::Log::ERROR, "refusing to send lamp commands", 10.0));
  EXPECT_LT(steadySeconds() - t_malformed, 9.0) << "the mismatch error waited for another kind's throttle (10 s)";
  EXPECT_EQ(ros().lastStatus().state, LampState::UNKNOWN_FAILSAFE);
  std::this_thread::sleep_for(std::chrono::milliseconds(1500));
  EXPECT_EQ(board().commandCount(), before) << "commands sent to a subscriber of another type";
  EXPECT_TRUE(board().lampOn());
  EXPECT_FALSE(ros().linkUp());
  EXPECT_TRUE(waitFor([&] { return ros().diagText("link state") == "type mismatch"; }, 3.0))
      << ros().diagText("link state");
  // The right board again.
  board().unplug();
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  ASSERT_TRUE(board().plug());
  ASSERT_TRUE(synced(10.0));
  expectHealthy("type mismatch");
}

// A synced board re-announcing its command subscriber with another type: link_up goes false
// (it stayed true), lamp_status unknown, no command sent; the next negotiation (the
// emulated board still has its Bool subscriber) brings it back.
TEST_F(LightBridge, TypeChangeWhileSyncedDropsLinkUp) {
  ASSERT_TRUE(boardFollows(false));
  ASSERT_TRUE(ros().linkUp());
  rosserial::TopicInfo t;
  t.topic_id = 100;  // the board's first (only) subscriber
  t.topic_name = "lamp_cmd";
  t.message_type = "std_msgs/Int32";
  t.md5sum = "da5909fbe378aeaf85e547e830cc1bb7";
  t.buffer_size = 512;
  Bytes payload;
  rosserial::serialize(t, payload);
  const double t0 = steadySeconds();
  board().inject(rosserial::encodeFrame(rosserial::kIdSubscriber, payload));
  EXPECT_TRUE(waitFor([&] { return ros().linkDownAfter(t0) > 0; }, 2.0)) << "link_up stayed true";
  EXPECT_TRUE(waitFor([&] {
    std::lock_guard<std::mutex> l(ros().mutex);
    for (const auto& s : ros().statuses)
      if (s.state == LampState::UNKNOWN_FAILSAFE && s.header.stamp.toSec() > 0 && !s.link_up) return true;
    return false;
  }, 2.0));
  ASSERT_TRUE(synced(10.0));
  expectHealthy("a type change while synced");
}

// A stock ros_lib sketch with one Bool subscriber and no publisher sends only its time requests
// (every 2.5 s): the default link timeout keeps it (14 drops in 12 s with 1 s).
TEST_F(LightBridge, StockSubscribeOnlyBoardStaysSynced) {
  board().unplug();
  ASSERT_TRUE(waitFor([&] { return !ros().linkUp(); }, 5.0));
  PtyHeadlight::Options stock;
  stock.report_state = false;
  ASSERT_TRUE(board().plug(stock));
  ASSERT_TRUE(synced(10.0));
  const double losses = ros().diagValue("link losses");
  const double t0 = steadySeconds();
  bool on = false;
  while (steadySeconds() < t0 + 12.0) {
    EXPECT_TRUE(boardFollows(on, 2.0));
    on = !on;
    std::this_thread::sleep_for(std::chrono::milliseconds(500));
  }
  EXPECT_LT(ros().linkDownAfter(t0), 0.0) << "dropped "
      << (ros().linkDownAfter(t0) - t0) << " s after sync";
  EXPECT_EQ(ros().diagValue("link losses"), losses);
  EXPECT_GE(ros().diagValue("time replies", false), 4.0);
  EXPECT_EQ(ros().lastStatus().state, LampState::NOT_REPORTED);
  EXPECT_TRUE(ros().lastStatus().link_up);
  std::printf("[ MEASURE ] baud %d: stock subscribe-only board: %.0f link losses in 12 s (link_timeout_s "
              "%.1f)\n", g_baud, ros().diagValue("link losses", false) - losses,
              LightBridgeParams().link_timeout_s);
  board().unplug();
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  ASSERT_TRUE(board().plug());
  ASSERT_TRUE(synced(10.0));
}

// Only in light_bridge_launch.test: launch/icanc.launch with bridge_port set loads the bridge in
// the graph's manager, and the LightController's lamp_cmd (fail-safe ON: no clouds) reaches the
// board at the controller's rate.
// light_bridge_levels.test: the bridge with device_levels_topic, a board with a lamp_levels
// subscriber. Levels reach the board with the commands; 255 for every segment before any
// lamp_command and once it stops; the board's PWM duties follow.
TEST_F(LightBridge, SegmentLevelsReachTheBoard) {
  PtyHeadlightOptions options;
  options.levels_topic = "lamp_levels";
  ASSERT_TRUE(board().plug(options));
  ASSERT_TRUE(synced(15.0)) << "no negotiation with the emulated board";
  EXPECT_TRUE(waitFor([&] { auto l = board().levels(); return !l.empty() && l.back() == Bytes{255}; }, 2.0))
      << "no lamp_command yet: every segment 255";
  ASSERT_TRUE(boardFollows(false));
  ros::NodeHandle nh;
  ros::Publisher pub = nh.advertise<LampCommand>("/icanc/lamp_command", 10);
  ASSERT_TRUE(waitFor([&] { return pub.getNumSubscribers() > 0; }, 5.0));
  LampCommand command;
  command.levels = {0.0f, 0.0f, 0.0f, 0.6f, 0.6f, 0.0f, 0.0f, 0.0f};
  command.reason = LampCommand::_reason_type(1);
  const Bytes expected{0, 0, 0, 153, 153, 0, 0, 0};
  for (int i = 0; i < 10; ++i) {  // as the LightController: 10 Hz
    command.header.stamp = ros::Time::now();
    pub.publish(command);
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  auto levels = board().levels();
  ASSERT_FALSE(levels.empty());
  EXPECT_EQ(levels.back(), expected);
  EXPECT_EQ(board().segmentDuty(3), 153);
  EXPECT_EQ(board().segmentDuty(0), 0);
  // lamp_command stops (lamp_cmd goes on): after cmd_stale_timeout_s every segment is 255 again.
  EXPECT_TRUE(waitFor([&] { auto l = board().levels(); return l.back() == Bytes(8, 255); }, 2.0))
      << "stale levels must fail safe to 255";
  EXPECT_EQ(board().segmentDuty(0), 255);
  // The binary lamp still follows lamp_cmd (OFF). Waited for, not read once: on a loaded machine
  // (the sanitized suite on 2 cores) a heartbeat gap past the board's 500 ms watchdog turns the
  // lamp ON for a moment, as it must; stale levels holding it ON would fail this wait.
  EXPECT_TRUE(waitFor([&] { return !board().lampOn(); }, 1.5)) << "the binary lamp must follow lamp_cmd (OFF)";
}

TEST_F(LightBridge, LaunchFileServesTheLightController) {
  ASSERT_TRUE(board().plug());
  ASSERT_TRUE(synced(15.0)) << "no bridge in the launch file's manager?";
  const std::size_t before = board().commandCount();
  std::this_thread::sleep_for(std::chrono::milliseconds(1000));
  const auto cmds = board().commands();
  EXPECT_GE(cmds.size() - before, 8u);
  for (std::size_t i = before; i < cmds.size(); ++i) EXPECT_TRUE(cmds[i].value);
  EXPECT_TRUE(board().lampOn());
  EXPECT_TRUE(waitFor([&] { return ros().stateCount() > 0 && ros().lastState().first; }, 1.0));
}

}  // namespace
}  // namespace test
}  // namespace icanc

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_light_bridge");
  ros::AsyncSpinner spinner(2);
  spinner.start();
  ros::NodeHandle pnh("~");
  std::string port;
  pnh.param<std::string>("port", port, "/tmp/icanc_headlight_pty");
  pnh.param("baud", icanc::test::g_baud, 57600);
  icanc::test::RosSide ros_side;
  icanc::test::Controller controller(ros_side);
  icanc::test::PtyHeadlight board(port);
  icanc::test::g_board = &board;
  icanc::test::g_ros = &ros_side;
  icanc::test::g_controller = &controller;
  const int result = RUN_ALL_TESTS();
  spinner.stop();
  return result;
}
