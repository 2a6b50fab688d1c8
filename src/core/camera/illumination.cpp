#include "icanc/core/camera/illumination.hpp"

#include <algorithm>
#include <sstream>
#include <stdexcept>
#include <vector>

#include <opencv2/imgproc.hpp>

namespace icanc {

std::string validate(const IlluminationParams& p) {
  std::ostringstream why;
  if (!(p.grid_step_px >= 1))
    why << "illumination.grid_step_px must be >= 1 (got " << p.grid_step_px << ")";
  else if (!(p.percentile >= 0.0 && p.percentile <= 1.0))
    why << "illumination.percentile must be in [0, 1] (got " << p.percentile << ")";
  else if (!(p.dark_at >= 0.0 && p.dark_at < p.bright_at && p.bright_at <= 1.0))
    why << "illumination thresholds need 0 <= dark_at < bright_at <= 1 (got dark_at " << p.dark_at
        << ", bright_at " << p.bright_at << ")";
  else if (!(p.min_dwell_s >= 0.0))
    why << "illumination.min_dwell_s must be >= 0 (got " << p.min_dwell_s << ")";
  else if (!(p.stale_timeout_s > 0.0))
    why << "illumination.stale_timeout_s must be > 0 (got " << p.stale_timeout_s << ")";
  return why.str();
}

const char* toString(Illumination state) {
  switch (state) {
    case Illumination::kUnknown: return "unknown";
    case Illumination::kDark: return "dark";
    case Illumination::kBright: return "bright";
  }
  return "invalid";
}

double sceneBrightness(const cv::Mat& image, ChannelOrder order, int grid_step_px, double percentile) {
  if (image.empty()) throw std::invalid_argument("sceneBrightness: empty image");
  const int depth = image.depth();
  const int channels = image.channels();
  if ((depth != CV_8U && depth != CV_16U) || (channels != 1 && channels != 3))
    throw std::invalid_argument("sceneBrightness: expected 8- or 16-bit, 1 or 3 channels (got " +
                                cv::typeToString(image.type()) + ")");
  const int step = std::max(1, grid_step_px);
  // The grid: every step-th row and column (nearest neighbour keeps pixel values unmixed).
  cv::Mat grid;
  const cv::Size size((image.cols + step - 1) / step, (image.rows + step - 1) / step);
  if (step == 1)
    grid = image;
  else
    cv::resize(image, grid, size, 0.0, 0.0, cv::INTER_NEAREST);
  cv::Mat luminance;
  if (channels == 3)
    cv::cvtColor(grid, luminance, order == ChannelOrder::kBgr ? cv::COLOR_BGR2GRAY : cv::COLOR_RGB2GRAY);
  else
    luminance = grid;
  cv::Mat scaled;
  luminance.convertTo(scaled, CV_32F, depth == CV_8U ? 1.0 / 255.0 : 1.0 / 65535.0);
  std::vector<float> values(scaled.begin<float>(), scaled.end<float>());
  const std::size_t k = static_cast<std::size_t>(
      std::min(1.0, std::max(0.0, percentile)) * static_cast<double>(values.size() - 1) + 0.5);
  std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(k), values.end());
  return values[k];
}

IlluminationMonitor::IlluminationMonitor(const IlluminationParams& params) : params_(params) {}

void IlluminationMonitor::reset() {
  state_ = candidate_ = Illumination::kUnknown;
  has_image_ = false;
}

Illumination IlluminationMonitor::wanted(double b) const {
  // Hysteresis: between the thresholds the state stays; from unknown it counts as dark (the
  // paper's behaviour, lamp logic active).
  if (b >= params_.bright_at) return Illumination::kBright;
  if (b <= params_.dark_at) return Illumination::kDark;
  return state_ == Illumination::kUnknown ? Illumination::kDark : state_;
}

bool IlluminationMonitor::tick(double now) {
  const Illumination was = state_;
  if (has_now_ && now < last_now_s_) reset();  // bag loop: start over
  has_now_ = true;
  last_now_s_ = now;
  // 1 ns of slack: stamps in seconds as doubles.
  if (has_image_ && now - last_image_s_ > params_.stale_timeout_s + 1e-9) reset();
  return was != state_;
}

bool IlluminationMonitor::onBrightness(double now, double brightness) {
  const Illumination was = state_;
  tick(now);
  has_image_ = true;
  last_image_s_ = now;
  brightness_ = brightness;
  const Illumination want = wanted(brightness);
  if (want == state_) {
    candidate_ = state_;
  } else {
    if (want != candidate_) {
      candidate_ = want;
      candidate_since_s_ = now;
    }
    if (now - candidate_since_s_ >= params_.min_dwell_s - 1e-9) state_ = want;
  }
  return was != state_;
}

}  // namespace icanc
