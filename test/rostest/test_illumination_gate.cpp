// rostest: the camera illumination gate in the graph of launch/icanc.launch with
// camera_image_topic set. The pedestrian of approach_front.yaml walks toward the Zebra twice:
// first with daylight camera images, then with a night street (a street lamp in view). The
// IlluminationMonitor must turn bright, then dark, each only after min_dwell_s of such images;
// in daylight the danger must not switch the lamp on (reason "daylight"), at night it must.
// Malformed images are logged, counted in diagnostics and ignored: the state goes unknown (the
// paper's behaviour) and comes back with good images, the nodelet still running.
#include <functional>

#include <diagnostic_msgs/DiagnosticArray.h>
#include <gtest/gtest.h>

#include "icanc/IlluminationState.h"
#include "icanc/core/camera/illumination.hpp"
#include "camera_images.hpp"
#include "graph_fixture.hpp"

namespace icanc {
namespace test {
namespace {

struct IlluminationLog {
  std::mutex mutex;
  std::vector<IlluminationState::ConstPtr> states;
  void on(const IlluminationState::ConstPtr& m) { std::lock_guard<std::mutex> l(mutex); states.push_back(m); }
  // Time of the first state `s` at or after `from` (zero when none).
  ros::Time first(std::uint8_t s, const ros::Time& from) {
    std::lock_guard<std::mutex> l(mutex);
    for (const auto& m : states)
      if (m->state == s && m->header.stamp >= from) return m->header.stamp;
    return ros::Time();
  }
};

TEST(IlluminationGate, NoDangerLampInDaylightButAtNight) {
  GraphFixture g("approach_front.yaml");
  ros::Publisher image_pub = g.nh().advertise<sensor_msgs::Image>("/test/camera/image", 5);
  IlluminationLog illum;
  ros::Subscriber illum_sub = g.nh().subscribe("/icanc/illumination", 100, &IlluminationLog::on, &illum);
  ASSERT_TRUE(g.waitForGraph()) << "icanc graph did not come up";
  ASSERT_TRUE(waitFor([&] { return image_pub.getNumSubscribers() > 0 && illum_sub.getNumPublishers() > 0; }, 30.0))
      << "IlluminationMonitor not loaded by icanc.launch camera_image_topic:=...";
  // The profile's value, or the code's default where the profile leaves it out.
  double dwell = 0.0;
  ros::param::param("/icanc/illumination_monitor/min_dwell_s", dwell, IlluminationParams().min_dwell_s);
  bool gate = false;
  ASSERT_TRUE(ros::param::get("/icanc/light_controller/illumination/enabled", gate));
  ASSERT_TRUE(gate);

  const sim::Scenario& sc = g.scenario();
  const cv::Mat day = dayImage(), night = nightImage();
  // Runs the scenario once from `start`, with `image` beside every cloud; returns its end.
  const auto run = [&](const ros::Time& start, const cv::Mat& image) {
    ros::Rate rate(sc.rate_hz);
    for (std::size_t k = 0; k < sc.frames() && ros::ok(); ++k) {
      const ros::Time stamp = start + ros::Duration(k / sc.rate_hz);
      image_pub.publish(toImageMsg(image, stamp, "camera"));
      g.publishFrame(k / sc.rate_hz, stamp);
      rate.sleep();
    }
    return ros::Time::now();
  };
  const ros::Time day_start = ros::Time::now();
  const ros::Time night_start = run(day_start, day);
  const ros::Time night_end = run(night_start, night);
  ros::WallDuration(0.5).sleep();

  // The state flips only after the dwell (one image period and the 10 Hz tick of slack).
  const ros::Time bright_at = illum.first(IlluminationState::STATE_BRIGHT, day_start);
  ASSERT_FALSE(bright_at.isZero()) << "never bright with daylight images";
  EXPECT_GE((bright_at - day_start).toSec(), dwell - 0.05);
  EXPECT_LE((bright_at - day_start).toSec(), dwell + 0.5);
  const ros::Time dark_at = illum.first(IlluminationState::STATE_DARK, night_start);
  ASSERT_FALSE(dark_at.isZero()) << "never dark with night images (street lamp in view)";
  EXPECT_GE((dark_at - night_start).toSec(), dwell - 0.05);
  EXPECT_LE((dark_at - night_start).toSec(), dwell + 0.5);
  std::printf("bright %.2f s after the first daylight image, dark %.2f s after the first night "
              "image (dwell %.1f s)\n", (bright_at - day_start).toSec(), (dark_at - night_start).toSec(), dwell);

  Recorder& rec = g.recorder();
  std::lock_guard<std::mutex> lock(rec.mutex);
  std::size_t day_danger = 0, night_danger = 0;
  for (const auto& a : rec.arrays) {
    if (a->num_dangerous == 0) continue;
    if (a->header.stamp >= bright_at && a->header.stamp < night_start) ++day_danger;
    if (a->header.stamp >= dark_at && a->header.stamp < night_end) ++night_danger;
  }
  ASSERT_GT(day_danger, 3u) << "the pedestrian should be dangerous in daylight too";
  ASSERT_GT(night_danger, 3u);

  std::size_t daylight_states = 0, night_danger_on = 0;
  for (const auto& s : rec.states) {
    const ros::Time t = s->header.stamp;
    if (t >= bright_at && t < dark_at) {  // daylight: never on for danger
      EXPECT_FALSE(s->on && s->reason == LightState::REASON_DANGER)
          << "lamp on for danger in daylight at " << (t - day_start).toSec();
      if (s->reason == LightState::REASON_DAYLIGHT) {
        EXPECT_FALSE(s->on);
        EXPECT_EQ(s->reason_text, "daylight");
        ++daylight_states;
      }
    }
    if (t >= dark_at && s->on && s->reason == LightState::REASON_DANGER) ++night_danger_on;
  }
  EXPECT_GT(daylight_states, 10u);
  EXPECT_GT(night_danger_on, 0u) << "lamp never on for danger at night";
  std::printf("dangerous arrays: %zu in daylight, %zu at night; lamp-on-for-danger states at night: %zu\n",
              day_danger, night_danger, night_danger_on);
}

// Images the monitor cannot read: data shorter than step * height, an encoding without a
// luminance (32FC1), an empty image.
std::vector<sensor_msgs::ImageConstPtr> malformedImages(const ros::Time& stamp) {
  std::vector<sensor_msgs::ImageConstPtr> out;
  auto shortData = boost::make_shared<sensor_msgs::Image>(*toImageMsg(dayImage(), stamp, "camera"));
  shortData->data.resize(shortData->data.size() / 2);
  out.push_back(shortData);
  auto floats = boost::make_shared<sensor_msgs::Image>(*toImageMsg(dayImage(), stamp, "camera"));
  floats->encoding = "32FC1";
  floats->step = floats->width * 4;
  floats->data.resize(floats->step * floats->height);
  out.push_back(floats);
  auto empty = boost::make_shared<sensor_msgs::Image>();
  empty->header.stamp = stamp;
  empty->encoding = "bgr8";
  out.push_back(empty);
  return out;
}

TEST(IlluminationGate, MalformedImagesAreCountedAndTheStateGoesUnknown) {
  ros::NodeHandle nh;
  ros::Publisher image_pub = nh.advertise<sensor_msgs::Image>("/test/camera/image", 5);
  IlluminationLog illum;
  ros::Subscriber illum_sub = nh.subscribe("/icanc/illumination", 100, &IlluminationLog::on, &illum);
  std::mutex mutex;
  long bad_images = -1;
  ros::Subscriber diag = nh.subscribe<diagnostic_msgs::DiagnosticArray>("/diagnostics", 100,
      [&](const diagnostic_msgs::DiagnosticArray::ConstPtr& m) {
        for (const auto& st : m->status) {
          if (st.name.find("illumination monitor") == std::string::npos) continue;
          for (const auto& kv : st.values)
            if (kv.key == "bad images") {
              std::lock_guard<std::mutex> l(mutex);
              bad_images = std::stol(kv.value);
            }
        }
      });
  ASSERT_TRUE(waitFor([&] { return image_pub.getNumSubscribers() > 0 && illum_sub.getNumPublishers() > 0; }, 30.0));
  double dwell = 0.0, stale = 0.0;
  ros::param::param("/icanc/illumination_monitor/min_dwell_s", dwell, IlluminationParams().min_dwell_s);
  ros::param::param("/icanc/illumination_monitor/stale_timeout_s", stale, IlluminationParams().stale_timeout_s);
  const auto publishFor = [&](double seconds, const std::function<void(const ros::Time&)>& send) {
    const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(seconds);
    while (ros::ok() && ros::WallTime::now() < end) {
      send(ros::Time::now());
      ros::WallDuration(0.1).sleep();
    }
  };
  const cv::Mat night = nightImage();
  const auto good = [&](const ros::Time& t) { image_pub.publish(toImageMsg(night, t, "camera")); };
  const ros::Time start = ros::Time::now();
  publishFor(dwell + 0.5, good);
  ASSERT_FALSE(illum.first(IlluminationState::STATE_DARK, start).isZero());

  const ros::Time bad_start = ros::Time::now();
  publishFor(stale + 1.5, [&](const ros::Time& t) {
    for (const auto& m : malformedImages(t)) image_pub.publish(m);
  });
  const ros::Time unknown_at = illum.first(IlluminationState::STATE_UNKNOWN, bad_start);
  ASSERT_FALSE(unknown_at.isZero()) << "malformed images kept the state alive";
  EXPECT_LE((unknown_at - bad_start).toSec(), stale + 0.3);
  ASSERT_TRUE(waitFor([&] { std::lock_guard<std::mutex> l(mutex); return bad_images >= 6; }, 3.0))
      << "diagnostics do not count the bad images (last: " << bad_images << ")";

  // Still running: good images bring the state back after the dwell.
  const ros::Time again = ros::Time::now();
  publishFor(dwell + 0.5, good);
  EXPECT_FALSE(illum.first(IlluminationState::STATE_DARK, again).isZero());
}

}  // namespace
}  // namespace test
}  // namespace icanc

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_illumination_gate");
  ros::AsyncSpinner spinner(2);
  spinner.start();
  return RUN_ALL_TESTS();
}
