// Synthetic camera images for the camera rostests: a daylight scene, a night street with a
// street lamp, as sensor_msgs/Image (bgr8).
#pragma once

#include <string>

#include <cv_bridge/cv_bridge.h>
#include <opencv2/imgproc.hpp>
#include <sensor_msgs/Image.h>

namespace icanc {
namespace test {

// A night street (luminance ~0.06) with a saturated street lamp over ~3 % of the image.
inline cv::Mat nightImage(int width = 320, int height = 240) {
  cv::Mat image(height, width, CV_8UC3, cv::Scalar(18, 14, 12));
  cv::circle(image, cv::Point(width * 3 / 4, height / 5), width / 14, cv::Scalar(200, 240, 255), cv::FILLED);
  return image;
}

// Overcast daylight (luminance ~0.6).
inline cv::Mat dayImage(int width = 320, int height = 240) {
  return cv::Mat(height, width, CV_8UC3, cv::Scalar(150, 155, 160));
}

inline sensor_msgs::ImageConstPtr toImageMsg(const cv::Mat& image, const ros::Time& stamp,
                                             const std::string& frame) {
  std_msgs::Header header;
  header.stamp = stamp;
  header.frame_id = frame;
  return cv_bridge::CvImage(header, "bgr8", image).toImageMsg();
}

}  // namespace test
}  // namespace icanc
