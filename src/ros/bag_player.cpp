#include "icanc/ros/bag_player.hpp"

#include <pthread.h>

#include <cmath>
#include <exception>
#include <map>
#include <vector>

#include <geometry_msgs/TwistStamped.h>
#include <nav_msgs/Odometry.h>
#include <nav_msgs/Path.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/PointCloud2.h>
#include <std_msgs/UInt32.h>
#include <tf2_msgs/TFMessage.h>

#include "icanc/ros/zero_copy.hpp"

namespace icanc {
namespace {

enum class Kind { kCloud, kTf, kStaticTf, kOdometry, kTwist, kPath };

// The kind of a recorded topic the player plays; false for one it leaves out.
bool kindOf(const rosbag::ConnectionInfo& c, Kind& kind) {
  if (c.datatype == "sensor_msgs/PointCloud2") kind = Kind::kCloud;
  else if (c.datatype == "tf2_msgs/TFMessage") kind = c.topic == "/tf_static" ? Kind::kStaticTf : Kind::kTf;
  else if (c.datatype == "nav_msgs/Odometry") kind = Kind::kOdometry;
  else if (c.datatype == "geometry_msgs/TwistStamped") kind = Kind::kTwist;
  else if (c.datatype == "nav_msgs/Path") kind = Kind::kPath;
  else return false;
  return true;
}

void shift(ros::Time& stamp, const ros::Duration& by) {
  if (!stamp.isZero()) stamp += by;
}

void shift(tf2_msgs::TFMessage& tf, const ros::Duration& by) {
  for (auto& t : tf.transforms) shift(t.header.stamp, by);
}

void shift(nav_msgs::Path& path, const ros::Duration& by) {
  shift(path.header.stamp, by);
  for (auto& p : path.poses) shift(p.header.stamp, by);
}

// Reads a message of type M from `m`, shifts its stamps and publishes the object read.
template <class M, class Shift>
bool publishShifted(const rosbag::MessageInstance& m, const ros::Publisher& pub, Shift shift_stamps) {
  const boost::shared_ptr<M> msg = m.instantiate<M>();
  if (!msg) return false;
  shift_stamps(*msg);
  pub.publish(boost::shared_ptr<const M>(msg));
  return true;
}

}  // namespace

std::string validate(const BagPlayerOptions& o) {
  if (o.bag.empty()) return "bag: no bag given";
  if (!(o.rate > 0.0) || !std::isfinite(o.rate)) return "rate: must be > 0";
  if (!(o.delay_s >= 0.0) || !std::isfinite(o.delay_s)) return "delay_s: must be >= 0";
  return "";
}

BagPlayer::BagPlayer(const ros::NodeHandle& nh, const ros::NodeHandle& private_nh,
                     const BagPlayerOptions& options)
    : nh_(nh), private_nh_(private_nh), options_(options) {}

BagPlayer::~BagPlayer() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  wake_.notify_all();
  if (thread_.joinable()) thread_.join();
}

void BagPlayer::start() { thread_ = std::thread(&BagPlayer::run, this); }

bool BagPlayer::sleepUntil(std::chrono::steady_clock::time_point deadline) {
  std::unique_lock<std::mutex> lock(mutex_);
  return !wake_.wait_until(lock, deadline, [this] { return stop_; });
}

void BagPlayer::run() {
  pthread_setname_np(pthread_self(), options_.thread_name.substr(0, 15).c_str());
  finished_pub_ = private_nh_.advertise<std_msgs::UInt32>("finished", 1, true);
  // A damaged bag stops the playing, never the manager the player shares with the graph.
  try {
    play();
  } catch (const std::exception& e) {
    ROS_ERROR("[%s] %s stopped after %llu clouds: %s", private_nh_.getNamespace().c_str(),
              options_.bag.c_str(), static_cast<unsigned long long>(clouds_.load()), e.what());
  }
}

void BagPlayer::play() {
  const std::string name = private_nh_.getNamespace();
  rosbag::Bag bag;
  try {
    bag.open(options_.bag, rosbag::bagmode::Read);
  } catch (const rosbag::BagException& e) {
    ROS_ERROR("[%s] cannot read %s: %s; nothing played", name.c_str(), options_.bag.c_str(), e.what());
    return;
  }

  // A publisher per played topic, under its recorded name; the static transforms merged by child
  // frame (the last one recorded for each), sent once, latched.
  std::map<std::string, Kind> kinds;
  std::map<std::string, ros::Publisher> pubs;
  std::map<std::string, ZeroCopyPublisher> cloud_pubs;
  std::map<std::string, geometry_msgs::TransformStamped> statics;
  std::vector<std::string> timed;
  {
    rosbag::View all(bag);
    for (const rosbag::ConnectionInfo* c : all.getConnections()) {
      Kind kind;
      if (!kindOf(*c, kind) || kinds.count(c->topic)) continue;
      kinds[c->topic] = kind;
      if (kind != Kind::kStaticTf) timed.push_back(c->topic);
      switch (kind) {
        case Kind::kCloud:
          cloud_pubs[c->topic].advertise<sensor_msgs::PointCloud2>(nh_, private_nh_, c->topic, 10);
          break;
        case Kind::kTf: pubs[c->topic] = nh_.advertise<tf2_msgs::TFMessage>(c->topic, 100); break;
        case Kind::kStaticTf: pubs[c->topic] = nh_.advertise<tf2_msgs::TFMessage>(c->topic, 1, true); break;
        case Kind::kOdometry: pubs[c->topic] = nh_.advertise<nav_msgs::Odometry>(c->topic, 100); break;
        case Kind::kTwist: pubs[c->topic] = nh_.advertise<geometry_msgs::TwistStamped>(c->topic, 100); break;
        case Kind::kPath: pubs[c->topic] = nh_.advertise<nav_msgs::Path>(c->topic, 10); break;
      }
    }
  }
  if (cloud_pubs.empty()) {
    ROS_ERROR("[%s] %s has no sensor_msgs/PointCloud2 topic; nothing played", name.c_str(),
              options_.bag.c_str());
    return;
  }
  std::string static_topic;
  for (const auto& kv : kinds)
    if (kv.second == Kind::kStaticTf) static_topic = kv.first;
  if (!static_topic.empty())
    for (const rosbag::MessageInstance& m : rosbag::View(bag, rosbag::TopicQuery(static_topic)))
      if (auto tf = m.instantiate<tf2_msgs::TFMessage>())
        for (const auto& t : tf->transforms) statics[t.child_frame_id] = t;

  rosbag::View view(bag, rosbag::TopicQuery(timed));
  const ros::Time begin = view.getBeginTime();
  ROS_INFO("[%s] playing %s: %zu topics (%zu of clouds), %.1f s at %g times the recorded pace, "
           "from a thread '%s'%s", name.c_str(), options_.bag.c_str(), kinds.size(), cloud_pubs.size(),
           (view.getEndTime() - begin).toSec(), options_.rate, options_.thread_name.c_str(),
           options_.restamp ? ", stamped with the host's clock" : ", recorded stamps");

  using Clock = std::chrono::steady_clock;
  if (!sleepUntil(Clock::now() + std::chrono::duration_cast<Clock::duration>(
                                     std::chrono::duration<double>(options_.delay_s))))
    return;
  const Clock::time_point start = Clock::now();
  const ros::Duration offset = options_.restamp ? ros::Time::now() - begin : ros::Duration(0.0);

  if (!statics.empty()) {
    auto tf = boost::make_shared<tf2_msgs::TFMessage>();
    for (auto& kv : statics) tf->transforms.push_back(kv.second);
    shift(*tf, offset);
    pubs[static_topic].publish(tf2_msgs::TFMessage::ConstPtr(tf));
  }

  for (const rosbag::MessageInstance& m : view) {
    const Clock::time_point due = start + std::chrono::duration_cast<Clock::duration>(
                                              std::chrono::duration<double>((m.getTime() - begin).toSec() / options_.rate));
    if (!sleepUntil(due)) return;
    const std::string& topic = m.getTopic();
    switch (kinds[topic]) {
      case Kind::kCloud: {
        const sensor_msgs::PointCloud2::Ptr cloud = m.instantiate<sensor_msgs::PointCloud2>();
        if (!cloud) break;
        shift(cloud->header.stamp, offset);
        cloud_pubs[topic].publish(sensor_msgs::PointCloud2::ConstPtr(cloud));
        ++clouds_;
        break;
      }
      case Kind::kTf:
        publishShifted<tf2_msgs::TFMessage>(m, pubs[topic], [&](tf2_msgs::TFMessage& tf) { shift(tf, offset); });
        break;
      case Kind::kOdometry:
        publishShifted<nav_msgs::Odometry>(m, pubs[topic], [&](nav_msgs::Odometry& o) { shift(o.header.stamp, offset); });
        break;
      case Kind::kTwist:
        publishShifted<geometry_msgs::TwistStamped>(m, pubs[topic],
                                                    [&](geometry_msgs::TwistStamped& t) { shift(t.header.stamp, offset); });
        break;
      case Kind::kPath:
        publishShifted<nav_msgs::Path>(m, pubs[topic], [&](nav_msgs::Path& p) { shift(p, offset); });
        break;
      case Kind::kStaticTf: break;
    }
  }

  ROS_INFO("[%s] %s played: %llu clouds in %.1f s", name.c_str(), options_.bag.c_str(),
           static_cast<unsigned long long>(clouds_.load()),
           std::chrono::duration<double>(Clock::now() - start).count());
  finished_ = true;
  std_msgs::UInt32 count;
  count.data = static_cast<std::uint32_t>(clouds_.load());
  finished_pub_.publish(count);
  // The thread stays, idle, until the player is stopped: its CPU time stays readable in
  // /proc/PID/task (the manager's share of reading the bag).
  std::unique_lock<std::mutex> lock(mutex_);
  wake_.wait(lock, [this] { return stop_; });
}

}  // namespace icanc
