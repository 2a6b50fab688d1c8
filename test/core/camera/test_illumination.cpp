// Pins the illumination estimate (robust to a street lamp, to noise, to the pixel format) and the
// dark/bright state machine (hysteresis, dwell, staleness).
#include <random>
#include <stdexcept>

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "icanc/core/camera/illumination.hpp"

namespace icanc {
namespace {

constexpr int kW = 640, kH = 480;

cv::Mat grey(int level) { return cv::Mat(kH, kW, CV_8UC3, cv::Scalar(level, level, level)); }

// A night street: dark sky and road, plus a street lamp (a saturated disc) covering `lamp_fraction`
// of the image.
cv::Mat nightWithLamp(double lamp_fraction) {
  cv::Mat image = grey(15);
  const int radius = static_cast<int>(std::sqrt(lamp_fraction * kW * kH / CV_PI));
  cv::circle(image, cv::Point(480, 120), radius, cv::Scalar(255, 255, 255), cv::FILLED);
  return image;
}

double brightness(const cv::Mat& image, ChannelOrder order = ChannelOrder::kBgr) {
  const IlluminationParams p;
  return sceneBrightness(image, order, p.grid_step_px, p.percentile);
}

TEST(SceneBrightness, DarkDimAndBrightScenes) {
  EXPECT_NEAR(brightness(grey(10)), 10 / 255.0, 1e-6);
  EXPECT_NEAR(brightness(grey(50)), 50 / 255.0, 1e-6);
  EXPECT_NEAR(brightness(grey(180)), 180 / 255.0, 1e-6);
  const IlluminationParams p;
  EXPECT_LE(brightness(grey(10)), p.dark_at);
  EXPECT_GT(brightness(grey(50)), p.dark_at);  // dim: inside the hysteresis band
  EXPECT_LT(brightness(grey(50)), p.bright_at);
  EXPECT_GE(brightness(grey(180)), p.bright_at);
}

TEST(SceneBrightness, AStreetLampDoesNotLightTheScene) {
  const double dark = brightness(grey(15));
  const double with_lamp = brightness(nightWithLamp(0.05));  // 5 % of the pixels saturated
  EXPECT_NEAR(with_lamp, dark, 1e-6);
  // A plain mean would be fooled: the lamp raises it by more than half.
  EXPECT_GT(cv::mean(nightWithLamp(0.05))[0] / 255.0, 1.5 * dark);
  EXPECT_LE(with_lamp, IlluminationParams().dark_at);
}

TEST(SceneBrightness, NoiseMovesItLittle) {
  cv::Mat image(kH, kW, CV_8UC3);
  cv::randn(image, cv::Scalar::all(20), cv::Scalar::all(12));  // dark scene, sensor noise
  EXPECT_NEAR(brightness(image), 20 / 255.0, 3 / 255.0);
}

TEST(SceneBrightness, HalfBrightHalfDarkFollowsThePercentile) {
  cv::Mat image = grey(10);
  image(cv::Rect(0, 0, kW, kH / 4)).setTo(cv::Scalar::all(200));  // bright sky, top quarter
  EXPECT_NEAR(sceneBrightness(image, ChannelOrder::kBgr, 4, 0.5), 10 / 255.0, 1e-6);
  EXPECT_NEAR(sceneBrightness(image, ChannelOrder::kBgr, 4, 0.9), 200 / 255.0, 1e-6);
  EXPECT_NEAR(sceneBrightness(image, ChannelOrder::kBgr, 1, 0.5), 10 / 255.0, 1e-6);
}

TEST(SceneBrightness, LuminanceOfColourChannelsAndFormats) {
  // Pure blue in BGR order is dark (0.114); the same bytes read as RGB are red (0.299).
  const cv::Mat blue(kH, kW, CV_8UC3, cv::Scalar(255, 0, 0));
  EXPECT_NEAR(brightness(blue, ChannelOrder::kBgr), 0.114, 0.005);
  EXPECT_NEAR(brightness(blue, ChannelOrder::kRgb), 0.299, 0.005);
  EXPECT_NEAR(brightness(cv::Mat(kH, kW, CV_8UC1, cv::Scalar(128))), 128 / 255.0, 1e-6);
  EXPECT_NEAR(brightness(cv::Mat(kH, kW, CV_16UC1, cv::Scalar(32768))), 32768 / 65535.0, 1e-6);
  EXPECT_THROW(brightness(cv::Mat()), std::invalid_argument);
  EXPECT_THROW(brightness(cv::Mat(kH, kW, CV_32FC1, cv::Scalar(0.5))), std::invalid_argument);
  EXPECT_THROW(brightness(cv::Mat(kH, kW, CV_8UC4, cv::Scalar::all(9))), std::invalid_argument);
}

IlluminationParams testParams() {
  IlluminationParams p;
  p.dark_at = 0.15;
  p.bright_at = 0.30;
  p.min_dwell_s = 2.0;
  p.stale_timeout_s = 1.0;
  return p;
}

// Feeds `b` at 10 Hz over [t0, t1).
void feed(IlluminationMonitor& m, double t0, double t1, double b) {
  for (double t = t0; t < t1 - 1e-9; t += 0.1) m.onBrightness(t, b);
}

TEST(IlluminationMonitor, UnknownUntilTheFirstStateHasHeldForTheDwell) {
  IlluminationMonitor m(testParams());
  EXPECT_EQ(m.state(), Illumination::kUnknown);
  feed(m, 0.0, 1.95, 0.05);
  EXPECT_EQ(m.state(), Illumination::kUnknown);
  EXPECT_EQ(m.pending(), Illumination::kDark);
  EXPECT_TRUE(m.onBrightness(2.0, 0.05));
  EXPECT_EQ(m.state(), Illumination::kDark);
}

TEST(IlluminationMonitor, BrightOnlyAfterTheDwellAndBackToDarkAfterTheDwell) {
  IlluminationMonitor m(testParams());
  feed(m, 0.0, 2.1, 0.05);
  ASSERT_EQ(m.state(), Illumination::kDark);
  feed(m, 2.1, 4.05, 0.6);  // 1.95 s of daylight: not yet
  EXPECT_EQ(m.state(), Illumination::kDark);
  m.onBrightness(4.1, 0.6);  // 2.0 s
  EXPECT_EQ(m.state(), Illumination::kBright);
  feed(m, 4.2, 6.1, 0.05);
  EXPECT_EQ(m.state(), Illumination::kBright);
  m.onBrightness(6.2, 0.05);
  EXPECT_EQ(m.state(), Illumination::kDark);
}

TEST(IlluminationMonitor, FlickerShorterThanTheDwellNeverFlipsIt) {
  IlluminationMonitor m(testParams());
  feed(m, 0.0, 2.1, 0.05);
  ASSERT_EQ(m.state(), Illumination::kDark);
  // Headlights of oncoming cars: 1.5 s bright, 0.5 s dark, again and again.
  for (double t = 2.1; t < 20.0; t += 2.0) {
    feed(m, t, t + 1.5, 0.8);
    feed(m, t + 1.5, t + 2.0, 0.05);
    EXPECT_EQ(m.state(), Illumination::kDark) << t;
  }
}

TEST(IlluminationMonitor, HysteresisBandKeepsTheState) {
  IlluminationMonitor m(testParams());
  feed(m, 0.0, 2.1, 0.6);
  ASSERT_EQ(m.state(), Illumination::kBright);
  feed(m, 2.1, 10.0, 0.2);  // dim: between the thresholds
  EXPECT_EQ(m.state(), Illumination::kBright);
  feed(m, 10.0, 12.1, 0.05);
  ASSERT_EQ(m.state(), Illumination::kDark);
  feed(m, 12.1, 20.0, 0.2);
  EXPECT_EQ(m.state(), Illumination::kDark);
  // From unknown, dim counts as dark (the paper's behaviour: lamp logic active).
  IlluminationMonitor fresh(testParams());
  feed(fresh, 0.0, 2.1, 0.2);
  EXPECT_EQ(fresh.state(), Illumination::kDark);
}

TEST(IlluminationMonitor, StaleCameraIsUnknownAndTimeBackwardsStartsOver) {
  IlluminationMonitor m(testParams());
  feed(m, 0.0, 2.1, 0.6);
  ASSERT_EQ(m.state(), Illumination::kBright);
  EXPECT_FALSE(m.tick(3.0));  // last image at 2.0: 1.0 s ago, not yet stale
  EXPECT_TRUE(m.tick(3.05));
  EXPECT_EQ(m.state(), Illumination::kUnknown);
  // Images again: the dwell starts over.
  feed(m, 4.0, 5.0, 0.6);
  EXPECT_EQ(m.state(), Illumination::kUnknown);
  feed(m, 5.0, 6.1, 0.6);
  EXPECT_EQ(m.state(), Illumination::kBright);
  m.onBrightness(1.0, 0.6);  // bag loop
  EXPECT_EQ(m.state(), Illumination::kUnknown);
}

TEST(IlluminationParams, Validation) {
  EXPECT_EQ(validate(IlluminationParams()), "");
  IlluminationParams p;
  p.bright_at = 0.1;  // below dark_at
  EXPECT_NE(validate(p).find("dark_at"), std::string::npos);
  p = IlluminationParams();
  p.grid_step_px = 0;
  EXPECT_NE(validate(p), "");
  p = IlluminationParams();
  p.stale_timeout_s = 0.0;
  EXPECT_NE(validate(p), "");
  p = IlluminationParams();
  p.percentile = 1.5;
  EXPECT_NE(validate(p), "");
}

}  // namespace
}  // namespace icanc
