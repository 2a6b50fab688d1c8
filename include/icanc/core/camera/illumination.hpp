// Scene illumination from the camera image: ICanC only has work to do in low light. A robust
// brightness (a percentile of luminance over a subsampled grid, so a street lamp covering a few
// per cent of the image does not move it) feeds a dark/bright state machine with hysteresis (two
// thresholds) and a minimum dwell time. Time is an argument (the nodelet passes ROS time of
// receipt, as the LightController does), never read from a clock.
//
//   unknown --brightness <= dark_at--> dark, --brightness >= bright_at--> bright (after dwell)
//   dark  --brightness >= bright_at for min_dwell_s--> bright
//   bright --brightness <= dark_at for min_dwell_s--> dark
//   any  --no image for stale_timeout_s (or time going backwards)--> unknown
//
// Unknown means "no trustworthy camera": the LightController then behaves as the paper.
#pragma once

#include <cstdint>
#include <string>

#include <opencv2/core.hpp>

namespace icanc {

struct IlluminationParams {
  int grid_step_px = 4;          // luminance sampled every grid_step_px pixels in x and y
  double percentile = 0.5;       // brightness = this quantile of luminance (0.5: median)
  double dark_at = 0.15;         // brightness [0, 1] at or below which the scene is dark
  double bright_at = 0.30;       // brightness at or above which it is bright (> dark_at)
  double min_dwell_s = 2.0;      // a new state is taken after every image for this long asked for it
  double stale_timeout_s = 1.0;  // no image this long: state unknown (> 0)
};

// First problem found, or "" when valid.
std::string validate(const IlluminationParams& params);

enum class Illumination : std::uint8_t { kUnknown = 0, kDark = 1, kBright = 2 };
const char* toString(Illumination state);

// How the three channels of an 8- or 16-bit colour image are ordered.
enum class ChannelOrder : std::uint8_t { kBgr, kRgb };

// Scene brightness in [0, 1]: the `percentile` quantile of Rec. 601 luminance over every
// grid_step-th pixel of `image` (CV_8UC1, CV_16UC1, CV_8UC3 or CV_16UC3; 3 channels in `order`).
// Throws std::invalid_argument for an empty image or another pixel type.
double sceneBrightness(const cv::Mat& image, ChannelOrder order, int grid_step_px, double percentile);

class IlluminationMonitor {
 public:
  explicit IlluminationMonitor(const IlluminationParams& params = IlluminationParams());

  // A brightness measured on an image stamped `now`. Returns true when state() changed.
  bool onBrightness(double now, double brightness);
  // Advances the clock without an image (staleness). Returns true when state() changed.
  bool tick(double now);

  Illumination state() const { return state_; }
  double brightness() const { return brightness_; }  // last measurement (0 before any)
  // The state the measurements ask for while it has not yet held for min_dwell_s.
  Illumination pending() const { return candidate_; }
  const IlluminationParams& params() const { return params_; }

 private:
  void reset();
  Illumination wanted(double brightness) const;

  IlluminationParams params_;
  Illumination state_ = Illumination::kUnknown;
  Illumination candidate_ = Illumination::kUnknown;
  double candidate_since_s_ = 0.0;
  double brightness_ = 0.0;
  bool has_image_ = false;
  double last_image_s_ = 0.0;
  bool has_now_ = false;
  double last_now_s_ = 0.0;
};

}  // namespace icanc
