// rostest: the CameraOverlay nodelet loaded by launch/icanc.launch camera_image_topic:=...
// (camera_info found beside the image). A camera 0.5 m ahead of base_link and 1 m up looks along
// +x (fx = fy = 500 px, 640x480); a dangerous 1 m cube 10 m ahead must appear as red edges at the
// pixels the pinhole model gives by hand, a safe box to the left in green, a box behind the
// camera nowhere; without a transform the image still comes through, unannotated.
#include <gtest/gtest.h>
#include <sensor_msgs/CameraInfo.h>
#include <tf2_ros/static_transform_broadcaster.h>

#include "camera_images.hpp"
#include "graph_fixture.hpp"

namespace icanc {
namespace test {
namespace {

constexpr double kF = 500.0, kCx = 320.0, kCy = 240.0;

sensor_msgs::CameraInfo cameraInfo(const ros::Time& stamp) {
  sensor_msgs::CameraInfo info;
  info.header.stamp = stamp;
  info.header.frame_id = "camera_optical";
  info.width = 640;
  info.height = 480;
  info.distortion_model = "plumb_bob";
  info.D = {0, 0, 0, 0, 0};
  info.K = {kF, 0, kCx, 0, kF, kCy, 0, 0, 1};
  info.R = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  info.P = {kF, 0, kCx, 0, 0, kF, kCy, 0, 0, 0, 1, 0};
  return info;
}

Obstacle box(std::uint32_t id, double x, double y, bool dangerous) {
  Obstacle o;
  o.id = id;
  o.pose.position.x = x;
  o.pose.position.y = y;
  o.pose.position.z = 1.0;  // level with the camera
  o.pose.orientation.w = 1.0;
  o.dimensions.x = o.dimensions.y = o.dimensions.z = 1.0;
  o.speed = 2.0f;
  o.dangerous = dangerous;
  return o;
}

struct ImageLog {
  std::mutex mutex;
  cv::Mat last;
  int count = 0;
  void on(const sensor_msgs::ImageConstPtr& m) {
    std::lock_guard<std::mutex> l(mutex);
    last = cv_bridge::toCvCopy(m, "bgr8")->image;
    ++count;
  }
};

// Red pixels (the overlay's danger colour) in a window of half-size r around (u, v).
int redAround(const cv::Mat& image, double u, double v, int r = 3) {
  const cv::Rect roi(cvRound(u) - r, cvRound(v) - r, 2 * r + 1, 2 * r + 1);
  cv::Mat mask;
  cv::inRange(image(roi & cv::Rect(0, 0, image.cols, image.rows)), cv::Scalar(0, 0, 150),
              cv::Scalar(90, 90, 255), mask);
  return cv::countNonZero(mask);
}

TEST(OverlayImage, DangerousBoxInRedAtItsProjectedPixels) {
  ros::NodeHandle nh;
  ros::Publisher image_pub = nh.advertise<sensor_msgs::Image>("/test/camera/image_rect_color", 5);
  ros::Publisher info_pub = nh.advertise<sensor_msgs::CameraInfo>("/test/camera/camera_info", 5, true);
  ros::Publisher obstacles_pub = nh.advertise<ObstacleArray>("/icanc/obstacles_danger", 5);
  ImageLog out;
  ros::Subscriber sub = nh.subscribe("/icanc/camera/overlay", 5, &ImageLog::on, &out);
  ASSERT_TRUE(waitFor([&] {
    return image_pub.getNumSubscribers() > 0 && info_pub.getNumSubscribers() > 0 &&
           obstacles_pub.getNumSubscribers() > 0 && sub.getNumPublishers() > 0;
  }, 30.0)) << "CameraOverlay not loaded by icanc.launch camera_image_topic:=...";
  info_pub.publish(cameraInfo(ros::Time::now()));
  const cv::Mat night = nightImage(640, 480);

  // Without a transform: the image passes unannotated (no red anywhere).
  const auto publishPair = [&](const ros::Time& stamp) {
    ObstacleArray a;
    a.header.stamp = stamp;
    a.header.frame_id = "base_link";
    a.obstacles = {box(7, 10.0, 0.0, true), box(3, 10.0, 3.0, false), box(9, -5.0, 0.0, true)};
    a.num_dangerous = 2;
    obstacles_pub.publish(a);
    ros::WallDuration(0.05).sleep();
    image_pub.publish(toImageMsg(night, stamp, "camera_optical"));
  };
  int seen = 0;
  {
    std::lock_guard<std::mutex> l(out.mutex);
    seen = out.count;
  }
  publishPair(ros::Time::now());
  ASSERT_TRUE(waitFor([&] { std::lock_guard<std::mutex> l(out.mutex); return out.count > seen; }, 5.0));
  {
    std::lock_guard<std::mutex> l(out.mutex);
    cv::Mat mask;
    cv::inRange(out.last, cv::Scalar(0, 0, 150), cv::Scalar(90, 90, 255), mask);
    EXPECT_EQ(cv::countNonZero(mask), 0) << "boxes drawn without a transform";
    seen = out.count;
  }

  // The camera mount: 0.5 m ahead, 1 m up, optical axes (z forward, x right, y down).
  tf2_ros::StaticTransformBroadcaster tf;
  geometry_msgs::TransformStamped mount;
  mount.header.stamp = ros::Time::now();
  mount.header.frame_id = "base_link";
  mount.child_frame_id = "camera_optical";
  mount.transform.translation.x = 0.5;
  mount.transform.translation.z = 1.0;
  mount.transform.rotation.x = -0.5;  // columns: x_opt = -y, y_opt = -z, z_opt = +x
  mount.transform.rotation.y = 0.5;
  mount.transform.rotation.z = -0.5;
  mount.transform.rotation.w = 0.5;
  tf.sendTransform(mount);
  ros::WallDuration(0.5).sleep();
  // Until the listener has the transform, images may still come unannotated.
  cv::Mat image;
  ASSERT_TRUE(waitFor([&] {
    publishPair(ros::Time::now());
    ros::WallDuration(0.2).sleep();
    std::lock_guard<std::mutex> l(out.mutex);
    if (out.count == seen) return false;
    seen = out.count;
    image = out.last.clone();
    return redAround(image, kCx - kF * 0.5 / 9.0, kCy) > 0;
  }, 10.0)) << "no red where the dangerous box projects";

  // The near face is 9 m in front of the camera: its edges at 320 +- 500 * 0.5 / 9 = 292.2 and
  // 347.8 px, v = 240 -+ 27.8 px; the far face at 10 m: +- 25 px.
  const double n = kF * 0.5 / 9.0, f = kF * 0.5 / 10.0;
  EXPECT_GT(redAround(image, kCx - n, kCy), 2);  // left edge, middle
  EXPECT_GT(redAround(image, kCx + n, kCy), 2);  // right edge
  EXPECT_GT(redAround(image, kCx, kCy - n), 2);  // top edge
  EXPECT_GT(redAround(image, kCx, kCy + n), 2);  // bottom edge
  EXPECT_GT(redAround(image, kCx - f, kCy - f), 0);  // a far-face corner
  EXPECT_EQ(redAround(image, kCx, kCy, 8), 0);    // inside the box: no edge
  EXPECT_EQ(redAround(image, kCx, kCy + 120, 20), 0);  // below it
  // The safe box 3 m to the left (u = 320 - 500 * 3 / 9.5 = 162) in green, no red there.
  cv::Mat green;
  cv::inRange(image(cv::Rect(120, 190, 80, 100)), cv::Scalar(0, 150, 0), cv::Scalar(90, 255, 90), green);
  EXPECT_GT(cv::countNonZero(green), 20);
  EXPECT_EQ(redAround(image, 162, 240, 35), 0);
  // Red pixels only around the dangerous box and its label (the box behind is not drawn).
  cv::Mat red;
  cv::inRange(image, cv::Scalar(0, 0, 150), cv::Scalar(90, 90, 255), red);
  red(cv::Rect(280, 180, 140, 100)).setTo(0);  // the box (292..348, 212..268) and its label above
  EXPECT_EQ(cv::countNonZero(red), 0);
}

}  // namespace
}  // namespace test
}  // namespace icanc

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_overlay_image");
  ros::AsyncSpinner spinner(2);
  spinner.start();
  return RUN_ALL_TESTS();
}
