// Writing /tf_static into a bag as a latched topic, as `rosbag record` would: rosbag needs the
// complete connection header (type, md5sum, definition) when one is given.
#pragma once

#include <string>

#include <boost/make_shared.hpp>
#include <rosbag/bag.h>
#include <tf2_msgs/TFMessage.h>

namespace icanc {

inline void writeStaticTransforms(rosbag::Bag& bag, const ros::Time& stamp,
                                  const tf2_msgs::TFMessage& transforms, const std::string& callerid) {
  auto header = boost::make_shared<ros::M_string>();
  (*header)["type"] = ros::message_traits::datatype<tf2_msgs::TFMessage>();
  (*header)["md5sum"] = ros::message_traits::md5sum<tf2_msgs::TFMessage>();
  (*header)["message_definition"] = ros::message_traits::definition<tf2_msgs::TFMessage>();
  (*header)["latching"] = "1";
  (*header)["callerid"] = callerid;
  bag.write("/tf_static", stamp, transforms, header);
}

}  // namespace icanc
