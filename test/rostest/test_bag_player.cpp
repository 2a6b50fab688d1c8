// rostest: icanc/BagPlayer loaded into the manager that runs the icanc nodelets (bag_player.test)
// plays a rendered scenario bag: every cloud reaches the ObstacleDetector as the object the player
// read (the ZeroCopyProbe in the same manager compares addresses), stamped with the host's clock,
// and obstacles and the walker's danger come out.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <mutex>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nodelet/NodeletList.h>
#include <nodelet/NodeletLoad.h>
#include <nodelet/NodeletUnload.h>
#include <ros/package.h>
#include <ros/ros.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <std_msgs/String.h>
#include <std_msgs/UInt32.h>
#include <unistd.h>

#include "icanc/ObstacleArray.h"
#include "graph_fixture.hpp"

namespace icanc {
namespace test {
namespace {

// "topic received=N same_object=M" lines of the probe's report: (received, same) of `topic`.
std::pair<std::size_t, std::size_t> probeCounts(const std::string& report, const std::string& topic) {
  std::istringstream in(report);
  std::string name, received, same;
  while (in >> name >> received >> same)
    if (name == topic)
      return {std::stoul(received.substr(received.find('=') + 1)), std::stoul(same.substr(same.find('=') + 1))};
  return {0, 0};
}

TEST(BagPlayer, PlaysIntoTheDetectorsManagerWithoutCopies) {
  ros::NodeHandle nh, pnh("~");
  std::string scenario = "pedestrian_near_toward.yaml", manager = "/driver_manager";
  pnh.getParam("scenario", scenario);
  pnh.getParam("manager", manager);
  const std::string bag = "/tmp/icanc_test_bag_player_" + std::to_string(getpid()) + ".bag";
  const std::string render = std::string(ICANC_SIM_BAG) + " " + ros::package::getPath("icanc") +
                             "/config/scenarios/" + scenario + " " + bag + " > /dev/null";
  ASSERT_EQ(std::system(render.c_str()), 0) << render;
  std::size_t recorded = 0;
  {
    rosbag::Bag b(bag);
    recorded = rosbag::View(b, rosbag::TopicQuery("/points")).size();
  }
  ASSERT_GT(recorded, 0u);

  std::mutex mutex;
  std::vector<std::pair<ObstacleArray::ConstPtr, ros::WallTime>> arrays;
  std::string report;
  int played = -1;
  ros::Subscriber array_sub = nh.subscribe<ObstacleArray>("/icanc/obstacles_danger", 200,
      [&](const ObstacleArray::ConstPtr& m) {
        std::lock_guard<std::mutex> l(mutex);
        arrays.emplace_back(m, ros::WallTime::now());
      });
  ros::Subscriber report_sub = nh.subscribe<std_msgs::String>("/icanc/zero_copy_probe/report", 1,
      [&](const std_msgs::String::ConstPtr& m) { std::lock_guard<std::mutex> l(mutex); report = m->data; });
  ros::Subscriber finished_sub = nh.subscribe<std_msgs::UInt32>("/bag_player/finished", 1,
      [&](const std_msgs::UInt32::ConstPtr& m) { std::lock_guard<std::mutex> l(mutex); played = m->data; });

  // The graph is up when every nodelet is in the manager and its output reaches this node.
  ASSERT_TRUE(ros::service::waitForService(manager + "/load_nodelet", ros::Duration(30.0)));
  ASSERT_TRUE(waitFor([&] {
    nodelet::NodeletList list;
    if (!ros::service::call(manager + "/list", list)) return false;
    const auto& n = list.response.nodelets;
    return array_sub.getNumPublishers() > 0 &&
           std::find(n.begin(), n.end(), "/icanc/obstacle_detector") != n.end() &&
           std::find(n.begin(), n.end(), "/icanc/zero_copy_probe") != n.end();
  }, 30.0));

  ros::param::set("/bag_player/bag", bag);
  ros::param::set("/bag_player/delay_s", 0.5);
  ros::param::set("/bag_player/trace_publications", true);
  nodelet::NodeletLoad load;
  load.request.name = "/bag_player";
  load.request.type = "icanc/BagPlayer";
  ASSERT_TRUE(ros::service::call(manager + "/load_nodelet", load) && load.response.success);

  // The scenario's seconds at the recorded pace, then the last answers and probe report.
  ASSERT_TRUE(waitFor([&] { std::lock_guard<std::mutex> l(mutex); return played >= 0; }, 30.0))
      << "the player did not finish";
  waitFor([&] {
    std::lock_guard<std::mutex> l(mutex);
    const auto counts = probeCounts(report, "points");
    return arrays.size() >= recorded && counts.first >= recorded && counts.second == counts.first;
  }, 5.0);
  std::unique_lock<std::mutex> lock(mutex);
  const auto counts = probeCounts(report, "points");
  const auto answers = arrays;
  lock.unlock();

  EXPECT_EQ(std::size_t(played), recorded);
  std::printf("played %d clouds; probe: %zu clouds received, %zu the player's objects; %zu arrays\n", played,
              counts.first, counts.second, answers.size());
  EXPECT_EQ(counts.first, std::size_t(played)) << "clouds lost in the manager";
  EXPECT_EQ(counts.second, counts.first) << "copies of the player's clouds were delivered";
  EXPECT_GE(answers.size(), recorded * 9 / 10) << "frames the ObstacleDetector did not answer";
  std::size_t with_obstacles = 0, dangerous = 0;
  double max_stamp_age_s = 0.0;
  for (const auto& a : answers) {
    with_obstacles += !a.first->obstacles.empty();
    dangerous += a.first->num_dangerous > 0;
    // Stamped with the host's clock when played: an answer's stamp is its cloud's, moments ago.
    max_stamp_age_s = std::max(max_stamp_age_s, std::abs(a.second.toSec() - a.first->header.stamp.toSec()));
  }
  std::printf("%zu arrays with obstacles, %zu with a danger; stamps at most %.3f s from their receipt\n",
              with_obstacles, dangerous, max_stamp_age_s);
  EXPECT_GE(with_obstacles, answers.size() * 9 / 10);
  EXPECT_GT(dangerous, 0u) << "the walker toward the vehicle was never dangerous";
  EXPECT_LT(max_stamp_age_s, 1.0) << "the player did not stamp with the host's clock";

  nodelet::NodeletUnload unload;
  unload.request.name = "/bag_player";
  EXPECT_TRUE(ros::service::call(manager + "/unload_nodelet", unload) && unload.response.success);
  std::remove(bag.c_str());
}

}  // namespace
}  // namespace test
}  // namespace icanc

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_bag_player");
  ros::AsyncSpinner spinner(2);
  spinner.start();
  return RUN_ALL_TESTS();
}
