// Shared by the rostest gtest nodes: renders a scenario with the simulator and publishes its
// clouds (stamped with ROS time) and the sensor mount on /tf_static, and records what the icanc
// graph answers.
#pragma once

#include <functional>
#include <mutex>
#include <random>
#include <string>
#include <vector>

#include <pcl_conversions/pcl_conversions.h>
#include <ros/package.h>
#include <ros/ros.h>
#include <sensor_msgs/PointCloud2.h>
#include <tf2_eigen/tf2_eigen.h>
#include <tf2_ros/static_transform_broadcaster.h>

#include "icanc/LightState.h"
#include "icanc/ObstacleArray.h"
#include "icanc/core/input/stamp_check.hpp"
#include "icanc/sim/lidar_sim.hpp"
#include "icanc/sim/scenario.hpp"

namespace icanc {
namespace test {

inline std::string scenarioPath(const std::string& file) {
  return ros::package::getPath("icanc") + "/test/rostest/" + file;
}

// Factor on wall-clock latency tolerances: the sanitized build (scripts/test --sanitize, ASan +
// UBSan in the nodelets and the test) runs 2-3x slower; its logic is checked with the same
// thresholds, only the scheduling slack grows.
inline double latencySlack() {
#if defined(__SANITIZE_ADDRESS__)
  return 3.0;
#else
  return 1.0;
#endif
}

// Waits up to `timeout` seconds of wall time for pred(), spinning callbacks.
template <class Pred>
bool waitFor(Pred pred, double timeout) {
  const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(timeout);
  while (ros::ok() && ros::WallTime::now() < end) {
    if (pred()) return true;
    ros::WallDuration(0.01).sleep();
  }
  return pred();
}

// Paces frames sent by hand as a sensor sends them: each at the wall time its stamp gives, counted
// from the first frame. A frame that cannot keep that pace (the graph answered late, the test
// paused to reconfigure) is held instead until its receipt is a stall after the previous one
// (beyond kStampRateMaxGapS), and the pace starts again from it: the ObstacleDetector's stamp-rate
// check sees a sensor in step or a new stream, never a sensor clock running slow.
class StampPacer {
 public:
  // Returns when the frame stamped `stamp` is due; call just before publishing it.
  void wait(const ros::Time& stamp) {
    if (!stamp0_.isZero()) {
      const ros::WallTime due = wall0_ + ros::WallDuration((stamp - stamp0_).toSec());
      if (ros::WallTime::now() <= due + ros::WallDuration(kLateS)) {
        sleepUntil(due);
        last_ = ros::WallTime::now();
        return;
      }
      sleepUntil(last_ + ros::WallDuration(kStampRateMaxGapS + kLateS));
    }
    stamp0_ = stamp;
    wall0_ = last_ = ros::WallTime::now();
  }

 private:
  static constexpr double kLateS = 0.1;  // lateness taken up by the pace [s]
  static void sleepUntil(const ros::WallTime& t) {
    const ros::WallTime now = ros::WallTime::now();
    if (now < t) (t - now).sleep();
  }
  ros::Time stamp0_;
  ros::WallTime wall0_, last_;
};

struct Recorder {
  std::mutex mutex;
  std::vector<LightState::ConstPtr> states;
  std::vector<ObstacleArray::ConstPtr> arrays;  // obstacles_danger
  std::vector<ObstacleArray::ConstPtr> detections;  // obstacles

  void onState(const LightState::ConstPtr& m) { std::lock_guard<std::mutex> l(mutex); states.push_back(m); }
  void onArray(const ObstacleArray::ConstPtr& m) { std::lock_guard<std::mutex> l(mutex); arrays.push_back(m); }
  void onDetections(const ObstacleArray::ConstPtr& m) { std::lock_guard<std::mutex> l(mutex); detections.push_back(m); }
  std::size_t count(const std::vector<ObstacleArray::ConstPtr>& v) { std::lock_guard<std::mutex> l(mutex); return v.size(); }
  // The array of v (detections or arrays) stamped `stamp`, waited for up to timeout s of wall time
  // (null when none came).
  ObstacleArray::ConstPtr waitForStamp(const std::vector<ObstacleArray::ConstPtr>& v, const ros::Time& stamp,
                                       double timeout = 10.0) {
    ObstacleArray::ConstPtr found;
    waitFor([&] {
      std::lock_guard<std::mutex> l(mutex);
      for (const auto& a : v)
        if (a->header.stamp == stamp) found = a;
      return found != nullptr;
    }, timeout);
    return found;
  }
};

class GraphFixture {
 public:
  // publish_mount false: the sensor's mount is sent only by publishMount() (a late /tf_static).
  explicit GraphFixture(const std::string& scenario_file, bool publish_mount = true)
      : scenario_(sim::loadScenario(scenarioPath(scenario_file))),
        model_(sim::LidarModel::byName(scenario_.lidar)),
        rng_(scenario_.seed) {
    cloud_pub_ = nh_.advertise<sensor_msgs::PointCloud2>("/test/points", 5);
    state_sub_ = nh_.subscribe("/icanc/light_state", 100, &Recorder::onState, &rec_);
    array_sub_ = nh_.subscribe("/icanc/obstacles_danger", 100, &Recorder::onArray, &rec_);
    detections_sub_ = nh_.subscribe("/icanc/obstacles", 100, &Recorder::onDetections, &rec_);
    if (publish_mount) publishMount();
  }

  void publishMount() {
    geometry_msgs::TransformStamped mount = tf2::eigenToTransform(scenario_.sensor_mount.cast<double>());
    mount.header.stamp = ros::Time::now();
    mount.header.frame_id = scenario_.vehicle_frame;
    mount.child_frame_id = scenario_.sensor_frame;
    tf_.sendTransform(mount);
  }

  // Waits until the ObstacleDetector subscribes and the graph's outputs are connected.
  bool waitForGraph(double timeout = 30.0) {
    return waitFor([&] {
      return cloud_pub_.getNumSubscribers() > 0 && state_sub_.getNumPublishers() > 0 &&
             array_sub_.getNumPublishers() > 0;
    }, timeout);
  }

  // Renders the scene at scenario time t and publishes it stamped `stamp`, after `edit` (when
  // given) has changed the rendered cloud (in the sensor frame).
  void publishFrame(double t, const ros::Time& stamp,
                    const std::function<void(Cloud&)>& edit = nullptr) {
    sim::renderScan(scenario_.scene, t, scenario_.sensorPose(t), model_, scenario_.noise, rng_, scan_);
    if (edit) edit(scan_);
    auto msg = boost::make_shared<sensor_msgs::PointCloud2>();
    pcl::toROSMsg(scan_, *msg);
    msg->header.stamp = stamp;
    msg->header.frame_id = scenario_.sensor_frame;
    cloud_pub_.publish(sensor_msgs::PointCloud2::ConstPtr(msg));
  }

  void publishRaw(const sensor_msgs::PointCloud2::ConstPtr& msg) { cloud_pub_.publish(msg); }

  // Publishes every frame of the scenario at its rate, stamped from now on; returns the first stamp.
  ros::Time playScenario() {
    const ros::Time t0 = ros::Time::now();
    ros::Rate rate(scenario_.rate_hz);
    for (std::size_t k = 0; k < scenario_.frames() && ros::ok(); ++k) {
      const double t = k / scenario_.rate_hz;
      publishFrame(t, t0 + ros::Duration(t));
      rate.sleep();
    }
    return t0;
  }

  const sim::Scenario& scenario() const { return scenario_; }
  Recorder& recorder() { return rec_; }
  ros::NodeHandle& nh() { return nh_; }

 private:
  ros::NodeHandle nh_;
  sim::Scenario scenario_;
  sim::LidarModel model_;
  std::mt19937_64 rng_;
  Cloud scan_;
  ros::Publisher cloud_pub_;
  tf2_ros::StaticTransformBroadcaster tf_;
  Recorder rec_;
  // Declared last, so destroyed first: a subscriber's destructor waits for a running callback,
  // which then never writes into members already freed (ASan caught it at fixture teardown).
  ros::Subscriber state_sub_, array_sub_, detections_sub_;
};

}  // namespace test
}  // namespace icanc
