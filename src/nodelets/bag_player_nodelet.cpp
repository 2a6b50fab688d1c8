// icanc/BagPlayer: plays a bag inside the nodelet manager it is loaded into, as a LiDAR driver
// replaying a capture does in its own manager (velodyne_driver reading a pcap): the clouds, /tf,
// /tf_static, odometry, twist and path topics at the recorded pace on the wall clock, read and
// published from a thread of its own (named bag_player in /proc/PID/task), so that the nodelets of
// the same manager receive the very objects it read (icanc/ros/bag_player.hpp).
//
//   ~bag (string, required)      the bag; a relative path is taken from the manager's directory
//   ~rate (1.0)                  times the recorded pace
//   ~delay_s (1.0)               wall time from loading to the first message [s]
//   ~restamp (true)              stamps shifted so that the first message is stamped now, as a
//                                driver stamps with the host's clock (false: recorded stamps)
//   ~trace_publications (false)  ~publish_trace with every cloud's address (zero-copy probe)
//   ~finished (std_msgs/UInt32, latched)  the number of clouds played, once the bag has played
//   Topic remappings given to the loader apply (e.g. /tf:=/bag/tf beside LiDAR odometry).
#include <memory>

#include <nodelet/nodelet.h>
#include <pluginlib/class_list_macros.hpp>

#include "icanc/ros/bag_player.hpp"
#include "icanc/ros/nodelet_support.hpp"

namespace icanc {

class BagPlayerNodelet : public nodelet::Nodelet {
 private:
  void onInit() override {
    ParamReader reader(getPrivateNodeHandle());
    BagPlayerOptions options;
    reader.read("bag", options.bag);
    reader.read("rate", options.rate);
    reader.read("delay_s", options.delay_s);
    reader.read("restamp", options.restamp);
    reader.accept("trace_publications");  // ZeroCopyPublisher's
    std::string why = validate(options);
    if (why.empty() && options.restamp && ros::Time::isSimTime())
      why = "restamp: stamping with the host's clock needs the wall clock (use_sim_time is true)";
    if (!checkParams(getName(), reader, why)) return;
    player_.reset(new BagPlayer(getNodeHandle(), getPrivateNodeHandle(), options));
    player_->start();
  }

  std::unique_ptr<BagPlayer> player_;
};

}  // namespace icanc

PLUGINLIB_EXPORT_CLASS(icanc::BagPlayerNodelet, nodelet::Nodelet)
