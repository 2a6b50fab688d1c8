// icanc/IlluminationMonitor: scene brightness from the camera image (icanc/illumination.hpp) and
// a dark/bright state with hysteresis and dwell, for the LightController's illumination gate.
// Subscribes camera/image through image_transport, publishes icanc/IlluminationState on `illumination`
// for every image and on state changes (a stale camera becomes STATE_UNKNOWN). Time is ROS time
// of receipt, as in the LightController (sim time during replay). Glue only.
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>

#include <boost/make_shared.hpp>
#include <cv_bridge/cv_bridge.h>
#include <image_transport/image_transport.h>
#include <nodelet/nodelet.h>
#include <pluginlib/class_list_macros.hpp>
#include <sensor_msgs/image_encodings.h>

#include "icanc/IlluminationState.h"
#include "icanc/core/camera/illumination.hpp"
#include "icanc/ros/nodelet_support.hpp"

namespace icanc {

class IlluminationMonitorNodelet : public nodelet::Nodelet {
 private:
  void onInit() override {
    ros::NodeHandle& nh = getNodeHandle();
    ros::NodeHandle& pnh = getPrivateNodeHandle();
    ParamReader reader(pnh);
    IlluminationParams params;
    readParams(reader, params);
    reader.read("tick_rate_hz", tick_rate_hz_);
    std::string why = validate(params);
    if (why.empty() && !(tick_rate_hz_ > 0.0)) why = "tick_rate_hz must be > 0";
    if (!checkParams(getName(), reader, why)) return;
    monitor_.reset(new IlluminationMonitor(params));

    diagnostics_.reset(new Diagnostics(nh, pnh, getName(), "camera"));
    diagnostics_->updater().add("illumination monitor", this, &IlluminationMonitorNodelet::diagnose);
    pub_ = nh.advertise<IlluminationState>("illumination", 10);
    it_.reset(new image_transport::ImageTransport(nh));
    sub_ = it_->subscribe("camera/image", 2, &IlluminationMonitorNodelet::onImage, this);
    timer_ = nh.createTimer(ros::Duration(1.0 / tick_rate_hz_), &IlluminationMonitorNodelet::onTick, this);
    NODELET_INFO("IlluminationMonitor on %s: dark at <= %.2f, bright at >= %.2f, dwell %.1f s, "
                 "stale after %.1f s", sub_.getTopic().c_str(), params.dark_at, params.bright_at,
                 params.min_dwell_s, params.stale_timeout_s);
  }

  // The brightness of `msg`, or a negative value (logged, counted) for an image it cannot read.
  double measure(const sensor_msgs::ImageConstPtr& msg) {
    namespace enc = sensor_msgs::image_encodings;
    try {
      if (msg->width == 0 || msg->height == 0 ||
          msg->data.size() < static_cast<std::size_t>(msg->step) * msg->height)
        throw std::invalid_argument("data holds " + std::to_string(msg->data.size()) +
                                    " bytes, less than step * height");
      const std::string& e = msg->encoding;
      const IlluminationParams& p = monitor_->params();
      if (e == enc::BGR8 || e == enc::BGR16 || e == enc::RGB8 || e == enc::RGB16 || e == enc::MONO8 ||
          e == enc::MONO16) {
        const ChannelOrder order = (e == enc::RGB8 || e == enc::RGB16) ? ChannelOrder::kRgb : ChannelOrder::kBgr;
        return sceneBrightness(cv_bridge::toCvShare(msg)->image, order, p.grid_step_px, p.percentile);
      }
      // Anything else cv_bridge can convert (bgra8, yuv422, bayer_*): through mono8.
      return sceneBrightness(cv_bridge::toCvShare(msg, enc::MONO8)->image, ChannelOrder::kBgr,
                             p.grid_step_px, p.percentile);
    } catch (const std::exception& ex) {  // cv_bridge::Exception, std::invalid_argument, cv::Exception
      ++bad_images_;
      NODELET_ERROR_THROTTLE(5.0, "IlluminationMonitor: cannot read image (%ux%u, encoding '%s'): %s; "
                             "ignored (the state goes unknown if no good image follows)",
                             msg->width, msg->height, msg->encoding.c_str(), ex.what());
      return -1.0;
    }
  }

  void onImage(const sensor_msgs::ImageConstPtr& msg) {
    std::lock_guard<std::mutex> lock(mutex_);
    const double b = measure(msg);
    if (b < 0.0) return;
    const ros::Time now = ros::Time::now();
    ++images_;
    frame_id_ = msg->header.frame_id;
    image_stamp_ = msg->header.stamp;
    if (monitor_->onBrightness(now.toSec(), b)) logChange();
    publish(now);
  }

  void onTick(const ros::TimerEvent&) {
    std::lock_guard<std::mutex> lock(mutex_);
    const ros::Time now = ros::Time::now();
    if (!monitor_->tick(now.toSec())) return;
    if (monitor_->state() == Illumination::kUnknown) {
      ++stale_events_;
      NODELET_WARN("IlluminationMonitor: no camera image on %s for %.1f s: state unknown "
                   "(the LightController behaves as the paper)", sub_.getTopic().c_str(),
                   monitor_->params().stale_timeout_s);
    }
    publish(now);
  }

  void logChange() {
    ++changes_;
    NODELET_INFO("IlluminationMonitor: scene %s (brightness %.3f)", toString(monitor_->state()),
                 monitor_->brightness());
  }

  void publish(const ros::Time& now) {
    auto msg = boost::make_shared<IlluminationState>();
    msg->header.stamp = now;
    msg->header.frame_id = frame_id_;
    msg->state = static_cast<std::uint8_t>(monitor_->state());
    msg->state_text = toString(monitor_->state());
    msg->brightness = static_cast<float>(monitor_->brightness());
    msg->image_stamp = image_stamp_;
    pub_.publish(IlluminationState::ConstPtr(msg));
  }

  void diagnose(diagnostic_updater::DiagnosticStatusWrapper& stat) {
    std::lock_guard<std::mutex> lock(mutex_);
    const Illumination state = monitor_->state();
    if (state == Illumination::kUnknown)
      stat.summary(diagnostic_msgs::DiagnosticStatus::WARN, "unknown: no camera image (paper behaviour)");
    else
      stat.summary(diagnostic_msgs::DiagnosticStatus::OK, toString(state));
    stat.add("state", toString(state));
    stat.add("brightness", monitor_->brightness());
    stat.add("pending state", toString(monitor_->pending()));
    stat.add("images", images_);
    stat.add("bad images", bad_images_);
    stat.add("state changes", changes_);
    stat.add("camera stale events", stale_events_);
  }

  std::unique_ptr<IlluminationMonitor> monitor_;
  std::unique_ptr<Diagnostics> diagnostics_;
  std::unique_ptr<image_transport::ImageTransport> it_;
  image_transport::Subscriber sub_;
  ros::Publisher pub_;
  ros::Timer timer_;
  double tick_rate_hz_ = 10.0;

  std::mutex mutex_;  // image, timer and diagnostics callbacks
  std::string frame_id_;
  ros::Time image_stamp_;
  std::uint64_t images_ = 0, bad_images_ = 0, changes_ = 0, stale_events_ = 0;
};

}  // namespace icanc

PLUGINLIB_EXPORT_CLASS(icanc::IlluminationMonitorNodelet, nodelet::Nodelet)
