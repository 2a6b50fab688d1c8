// rostest: messages between the icanc nodelets travel as shared ConstPtrs. A probe nodelet in the
// same manager (zero_copy_probe.cpp) compares the address of every object it receives with the
// address the publishing nodelet traced on ~publish_trace. zero_copy_driver_manager.test: the same
// with every nodelet loaded into a manager started outside icanc.launch (a LiDAR driver's).
#include <algorithm>
#include <sstream>

#include <gtest/gtest.h>
#include <nodelet/NodeletList.h>
#include <std_msgs/String.h>

#include "graph_fixture.hpp"

namespace icanc {
namespace test {
namespace {

struct Counts {
  std::size_t received = 0, same = 0;
};

std::map<std::string, Counts> parse(const std::string& report) {
  std::map<std::string, Counts> out;
  std::istringstream in(report);
  std::string topic, received, same;
  while (in >> topic >> received >> same) {
    out[topic].received = std::stoul(received.substr(received.find('=') + 1));
    out[topic].same = std::stoul(same.substr(same.find('=') + 1));
  }
  return out;
}

TEST(ZeroCopy, ProbeInTheManagerReceivesThePublishersOwnObjects) {
  GraphFixture g("approach_front.yaml");
  ASSERT_TRUE(g.waitForGraph());
  const ros::Time t0 = ros::Time::now();
  ros::Rate rate(10.0);
  for (int k = 0; k < 30 && ros::ok(); ++k) {
    g.publishFrame(k * 0.1, t0 + ros::Duration(k * 0.1));
    rate.sleep();
  }
  std::mutex mutex;
  std::string report;
  ros::Subscriber sub = g.nh().subscribe<std_msgs::String>(
      "/icanc/zero_copy_probe/report", 1, [&](const std_msgs::String::ConstPtr& m) {
        std::lock_guard<std::mutex> lock(mutex);
        report = m->data;
      });
  // Wait for a report that has settled (every received object matched or enough time passed).
  std::map<std::string, Counts> counts;
  waitFor([&] {
    std::lock_guard<std::mutex> lock(mutex);
    counts = parse(report);
    return counts.size() == 3 && counts["obstacles"].received >= 25 &&
           counts["obstacles"].same == counts["obstacles"].received &&
           counts["obstacles_danger"].same == counts["obstacles_danger"].received &&
           counts["light_state"].same == counts["light_state"].received;
  }, 15.0);
  std::printf("probe report:\n%s", report.c_str());
  for (const char* topic : {"obstacles", "obstacles_danger", "light_state"}) {
    EXPECT_GE(counts[topic].received, 25u) << topic;
    EXPECT_EQ(counts[topic].same, counts[topic].received) << topic << ": copies were delivered";
  }
}

// The nodelets run in the manager named by the test's ~manager (icanc.launch's own by default, or
// a LiDAR driver's with manager:=/driver_manager, where icanc.launch starts none of its own).
TEST(ZeroCopy, NodeletsRunInTheNamedManager) {
  ros::NodeHandle private_nh("~");
  std::string manager = "/icanc/icanc_manager";
  private_nh.getParam("manager", manager);
  ASSERT_TRUE(ros::service::waitForService(manager + "/list", ros::Duration(30.0)));
  nodelet::NodeletList list;
  ASSERT_TRUE(ros::service::call(manager + "/list", list));
  for (const char* name : {"/icanc/obstacle_detector", "/icanc/danger_detector", "/icanc/light_controller"})
    EXPECT_NE(std::find(list.response.nodelets.begin(), list.response.nodelets.end(), name),
              list.response.nodelets.end()) << name << " not in " << manager;
  ros::V_string nodes;
  ASSERT_TRUE(ros::master::getNodes(nodes));
  const bool own = std::find(nodes.begin(), nodes.end(), "/icanc/icanc_manager") != nodes.end();
  EXPECT_EQ(own, manager == "/icanc/icanc_manager") << "icanc.launch's own manager is running: " << own;
}

}  // namespace
}  // namespace test
}  // namespace icanc

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_zero_copy");
  ros::AsyncSpinner spinner(2);
  spinner.start();
  return RUN_ALL_TESTS();
}
