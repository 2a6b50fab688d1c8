// Publishing between nodelets as shared ConstPtrs (zero-copy inside one manager), with an optional
// trace of the object's address so a probe in the same manager can prove no copy was made.
#pragma once

#include <cstdint>
#include <string>

#include <boost/make_shared.hpp>
#include <ros/node_handle.h>
#include <ros/publisher.h>

#include "icanc/PublishTrace.h"

namespace icanc {

class ZeroCopyPublisher {
 public:
  // Advertises `topic` on nh; when the private parameter ~trace_publications is true, also
  // advertises ~publish_trace (icanc/PublishTrace) with the address of every message sent.
  template <class M>
  void advertise(ros::NodeHandle& nh, ros::NodeHandle& private_nh, const std::string& topic,
                 std::uint32_t queue_size) {
    pub_ = nh.advertise<M>(topic, queue_size);
    bool trace = false;
    private_nh.param("trace_publications", trace, trace);
    if (trace) trace_ = private_nh.advertise<PublishTrace>("publish_trace", 100);
  }

  template <class M>
  void publish(const boost::shared_ptr<const M>& msg) const {
    if (trace_) {
      auto t = boost::make_shared<PublishTrace>();
      t->topic = pub_.getTopic();
      t->stamp = msg->header.stamp;
      t->address = reinterpret_cast<std::uintptr_t>(msg.get());
      trace_.publish(PublishTrace::ConstPtr(t));
    }
    pub_.publish(msg);
  }

  std::uint32_t subscribers() const { return pub_.getNumSubscribers(); }

 private:
  ros::Publisher pub_;
  ros::Publisher trace_;
};

}  // namespace icanc
