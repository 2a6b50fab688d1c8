// icanc/CameraOverlay: draws the tracked boxes of `obstacles_danger` into the camera image
// (icanc/camera_overlay.hpp), dangerous ones in red with id and speed, and publishes it on
// camera/overlay. Subscribes camera/image (image_transport, a rectified image such as
// image_rect_color) and camera/camera_info (the latest one is used); boxes go from the obstacles'
// frame into the image's optical frame through tf2, projected by
// image_geometry::PinholeCameraModel. Glue only.
#include <memory>
#include <mutex>

#include <cv_bridge/cv_bridge.h>
#include <image_geometry/pinhole_camera_model.h>
#include <image_transport/image_transport.h>
#include <nodelet/nodelet.h>
#include <pluginlib/class_list_macros.hpp>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/image_encodings.h>
#include <tf2/utils.h>
#include <tf2_eigen/tf2_eigen.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>

#include "icanc/ObstacleArray.h"
#include "icanc/core/camera/camera_overlay.hpp"
#include "icanc/ros/nodelet_support.hpp"

namespace icanc {

class CameraOverlayNodelet : public nodelet::Nodelet {
 private:
  void onInit() override {
    ros::NodeHandle& nh = getNodeHandle();
    ros::NodeHandle& pnh = getPrivateNodeHandle();
    ParamReader reader(pnh);
    reader.read("max_obstacle_age_s", max_obstacle_age_s_);
    reader.read("draw_safe", style_.draw_safe);
    reader.read("near_m", style_.near_m);
    std::string why;
    if (!(max_obstacle_age_s_ > 0.0)) why = "max_obstacle_age_s must be > 0";
    else if (!(style_.near_m > 0.0)) why = "near_m must be > 0";
    if (!checkParams(getName(), reader, why)) return;

    tf_buffer_.reset(new tf2_ros::Buffer);
    // /tf on this nodelet's own callback queue: no thread polling for it.
    tf_listener_.reset(new tf2_ros::TransformListener(*tf_buffer_, nh, /*spin_thread=*/false));
    diagnostics_.reset(new Diagnostics(nh, pnh, getName(), "camera"));
    diagnostics_->updater().add("camera overlay", this, &CameraOverlayNodelet::diagnose);
    it_.reset(new image_transport::ImageTransport(nh));
    pub_ = it_->advertise("camera/overlay", 2);
    info_sub_ = nh.subscribe("camera/camera_info", 2, &CameraOverlayNodelet::onInfo, this);
    obstacles_sub_ = nh.subscribe("obstacles_danger", 5, &CameraOverlayNodelet::onObstacles, this);
    image_sub_ = it_->subscribe("camera/image", 2, &CameraOverlayNodelet::onImage, this);
    NODELET_INFO("CameraOverlay: %s + %s + %s -> %s", image_sub_.getTopic().c_str(),
                 info_sub_.getTopic().c_str(), obstacles_sub_.getTopic().c_str(), pub_.getTopic().c_str());
  }

  void onInfo(const sensor_msgs::CameraInfoConstPtr& msg) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (msg->K[0] <= 0.0 || msg->K[4] <= 0.0 || msg->P[0] <= 0.0 || msg->P[5] <= 0.0) {
      ++bad_inputs_;
      NODELET_ERROR_THROTTLE(5.0, "CameraOverlay: camera_info without a focal length (uncalibrated?): ignored");
      return;
    }
    model_.fromCameraInfo(msg);
    has_model_ = true;
  }

  void onObstacles(const ObstacleArray::ConstPtr& msg) {
    std::lock_guard<std::mutex> lock(mutex_);
    obstacles_ = msg;
  }

  // The obstacles as overlay objects, or empty (reason in `why`) when there is nothing to draw.
  std::vector<OverlayObject> objectsFor(const ros::Time& image_stamp, const std::string& camera_frame,
                                        Eigen::Isometry3d& camera_from_vehicle, std::string& why) {
    std::vector<OverlayObject> objects;
    if (!obstacles_) { why = "no obstacles yet"; return objects; }
    if (std::abs((image_stamp - obstacles_->header.stamp).toSec()) > max_obstacle_age_s_) {
      why = "obstacles older than max_obstacle_age_s";
      return objects;
    }
    try {
      // The camera is mounted on the vehicle: the latest transform is the right one.
      camera_from_vehicle = tf2::transformToEigen(
          tf_buffer_->lookupTransform(camera_frame, obstacles_->header.frame_id, ros::Time(0)));
    } catch (const tf2::TransformException& ex) {
      ++tf_failures_;
      why = std::string("no transform: ") + ex.what();
      NODELET_WARN_THROTTLE(5.0, "CameraOverlay: %s -> %s: %s; image published without boxes",
                            obstacles_->header.frame_id.c_str(), camera_frame.c_str(), ex.what());
      return objects;
    }
    for (const Obstacle& o : obstacles_->obstacles) {
      OverlayObject v;
      v.id = o.id;
      v.center = Eigen::Vector3d(o.pose.position.x, o.pose.position.y, o.pose.position.z);
      v.size = Eigen::Vector3d(o.dimensions.x, o.dimensions.y, o.dimensions.z);
      v.yaw = tf2::getYaw(o.pose.orientation);
      v.speed_mps = o.speed;
      v.dangerous = o.dangerous;
      objects.push_back(v);
    }
    return objects;
  }

  void onImage(const sensor_msgs::ImageConstPtr& msg) {
    std::lock_guard<std::mutex> lock(mutex_);
    cv_bridge::CvImagePtr out;
    try {
      if (msg->width == 0 || msg->height == 0 ||
          msg->data.size() < static_cast<std::size_t>(msg->step) * msg->height)
        throw std::invalid_argument("data shorter than step * height");
      out = cv_bridge::toCvCopy(msg, sensor_msgs::image_encodings::BGR8);
    } catch (const std::exception& ex) {
      ++bad_inputs_;
      NODELET_ERROR_THROTTLE(5.0, "CameraOverlay: cannot convert image (encoding '%s') to bgr8: %s",
                             msg->encoding.c_str(), ex.what());
      return;
    }
    ++images_;
    if (!has_model_) {
      ++images_without_boxes_;
      NODELET_WARN_THROTTLE(5.0, "CameraOverlay: no camera_info on %s yet: image published without boxes",
                            info_sub_.getTopic().c_str());
    } else {
      const std::string& frame = msg->header.frame_id.empty() ? model_.tfFrame() : msg->header.frame_id;
      Eigen::Isometry3d camera_from_vehicle;
      std::vector<OverlayObject> objects = objectsFor(msg->header.stamp, frame, camera_from_vehicle, last_why_);
      if (objects.empty()) ++images_without_boxes_;
      const image_geometry::PinholeCameraModel& model = model_;
      last_drawn_ = drawOverlay(out->image, objects, camera_from_vehicle,
                                [&model](const cv::Point3d& p) { return model.project3dToPixel(p); }, style_);
      last_dangerous_ = 0;
      for (const OverlayObject& o : objects) last_dangerous_ += o.dangerous;
    }
    pub_.publish(out->toImageMsg());
  }

  void diagnose(diagnostic_updater::DiagnosticStatusWrapper& stat) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!has_model_)
      stat.summary(diagnostic_msgs::DiagnosticStatus::WARN, "no camera_info");
    else
      stat.summary(diagnostic_msgs::DiagnosticStatus::OK, "ok");
    stat.add("images", images_);
    stat.add("images without boxes", images_without_boxes_);
    stat.add("last reason without boxes", last_why_);
    stat.add("bad inputs", bad_inputs_);
    stat.add("tf failures", tf_failures_);
    stat.add("boxes drawn (last image)", last_drawn_);
    stat.add("dangerous (last image)", last_dangerous_);
  }

  double max_obstacle_age_s_ = 0.5;
  OverlayStyle style_;
  std::unique_ptr<tf2_ros::Buffer> tf_buffer_;
  std::unique_ptr<tf2_ros::TransformListener> tf_listener_;
  std::unique_ptr<Diagnostics> diagnostics_;
  std::unique_ptr<image_transport::ImageTransport> it_;
  image_transport::Publisher pub_;
  image_transport::Subscriber image_sub_;
  ros::Subscriber info_sub_, obstacles_sub_;

  std::mutex mutex_;  // image, camera_info, obstacles and diagnostics callbacks
  image_geometry::PinholeCameraModel model_;
  bool has_model_ = false;
  ObstacleArray::ConstPtr obstacles_;
  std::string last_why_;
  std::uint64_t images_ = 0, images_without_boxes_ = 0, bad_inputs_ = 0, tf_failures_ = 0;
  int last_drawn_ = 0, last_dangerous_ = 0;
};

}  // namespace icanc

PLUGINLIB_EXPORT_CLASS(icanc::CameraOverlayNodelet, nodelet::Nodelet)
