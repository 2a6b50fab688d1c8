// A probe nodelet for the zero-copy rostest: loaded into the same manager as the icanc nodelets,
// it subscribes to their outputs and to their ~publish_trace topics, and checks that every
// message it receives is the very object the publisher handed to roscpp (same stamp, same
// address). It publishes its counts on ~report (std_msgs/String, latched) every second.
// With ~cloud_topic and ~cloud_trace (a cloud publisher's ~publish_trace, e.g. the BagPlayer's), it
// checks the clouds on that topic the same way.
#include <map>
#include <mutex>
#include <set>
#include <sstream>
#include <utility>

#include <nodelet/nodelet.h>
#include <sensor_msgs/PointCloud2.h>
#include <pluginlib/class_list_macros.hpp>
#include <ros/ros.h>
#include <std_msgs/String.h>

#include "icanc/LightState.h"
#include "icanc/ObstacleArray.h"
#include "icanc/PublishTrace.h"

namespace icanc {
namespace test {

class ZeroCopyProbe : public nodelet::Nodelet {
 private:
  using Key = std::pair<std::uint64_t, std::uint64_t>;  // (stamp ns, address)

  void onInit() override {
    ros::NodeHandle& nh = getNodeHandle();
    for (const char* node : {"obstacle_detector", "danger_detector", "light_controller"})
      traces_.push_back(nh.subscribe(std::string(node) + "/publish_trace", 1000, &ZeroCopyProbe::onTrace, this));
    subs_.push_back(nh.subscribe<ObstacleArray>("obstacles", 100, [this](const ObstacleArray::ConstPtr& m) {
      received("obstacles", m->header.stamp, m.get());
    }));
    subs_.push_back(nh.subscribe<ObstacleArray>("obstacles_danger", 100, [this](const ObstacleArray::ConstPtr& m) {
      received("obstacles_danger", m->header.stamp, m.get());
    }));
    subs_.push_back(nh.subscribe<LightState>("light_state", 100, [this](const LightState::ConstPtr& m) {
      received("light_state", m->header.stamp, m.get());
    }));
    std::string cloud_topic, cloud_trace;
    getPrivateNodeHandle().getParam("cloud_topic", cloud_topic);
    getPrivateNodeHandle().getParam("cloud_trace", cloud_trace);
    if (!cloud_topic.empty() && !cloud_trace.empty()) {
      traces_.push_back(nh.subscribe(cloud_trace, 1000, &ZeroCopyProbe::onTrace, this));
      subs_.push_back(nh.subscribe<sensor_msgs::PointCloud2>(
          cloud_topic, 100, [this, cloud_topic](const sensor_msgs::PointCloud2::ConstPtr& m) {
            received(shortTopic(cloud_topic), m->header.stamp, m.get());
          }));
    }
    report_pub_ = getPrivateNodeHandle().advertise<std_msgs::String>("report", 1, true);
    timer_ = nh.createWallTimer(ros::WallDuration(1.0), [this](const ros::WallTimerEvent&) { report(); });
  }

  static std::string shortTopic(const std::string& topic) {
    return topic.substr(topic.rfind('/') + 1);
  }

  void onTrace(const PublishTrace::ConstPtr& t) {
    std::lock_guard<std::mutex> lock(mutex_);
    sent_[shortTopic(t->topic)].insert(Key(t->stamp.toNSec(), t->address));
  }

  void received(const std::string& topic, const ros::Time& stamp, const void* address) {
    std::lock_guard<std::mutex> lock(mutex_);
    received_[topic].push_back(Key(stamp.toNSec(), reinterpret_cast<std::uintptr_t>(address)));
  }

  // "topic received=N same_object=M" per topic; a received message whose trace has not arrived
  // yet is checked again at the next report.
  void report() {
    std::lock_guard<std::mutex> lock(mutex_);
    std::ostringstream out;
    for (const auto& kv : received_) {
      const auto& sent = sent_[kv.first];
      std::size_t same = 0;
      for (const Key& k : kv.second) same += sent.count(k);
      out << kv.first << " received=" << kv.second.size() << " same_object=" << same << "\n";
    }
    std_msgs::String msg;
    msg.data = out.str();
    report_pub_.publish(msg);
  }

  std::mutex mutex_;
  std::map<std::string, std::set<Key>> sent_;
  std::map<std::string, std::vector<Key>> received_;
  ros::Publisher report_pub_;
  // Destroyed before the maps and the mutex they guard (a subscriber's destructor waits for a
  // running callback), after the timer.
  std::vector<ros::Subscriber> subs_, traces_;
  ros::WallTimer timer_;
};

}  // namespace test
}  // namespace icanc

PLUGINLIB_EXPORT_CLASS(icanc::test::ZeroCopyProbe, nodelet::Nodelet)
