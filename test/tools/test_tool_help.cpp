// Every program in src/tools answers --help at once, without a ROS master (the master named in the
// environment does not exist: a tool that contacted it would wait and be killed by `timeout`), on
// stdout with exit status 0; the ROS tools refuse bad usage the same way, with status 2.
#include <sys/wait.h>

#include <cstdio>
#include <string>

#include <gtest/gtest.h>

namespace {

struct Outcome {
  int status = -1;  // exit status; 124: killed by timeout
  std::string out;
};

Outcome run(const std::string& tool, const std::string& args) {
  // 127.0.0.1:9 (discard) has no master; 10 s is far more than any usage message takes.
  const std::string cmd = "ROS_MASTER_URI=http://127.0.0.1:9 timeout 10 " + std::string(ICANC_TOOL_DIR) +
                          "/" + tool + " " + args + " 2>/dev/null";
  Outcome r;
  std::FILE* p = popen(cmd.c_str(), "r");
  if (!p) return r;
  char buf[512];
  while (std::fgets(buf, sizeof buf, p)) r.out += buf;
  const int st = pclose(p);
  r.status = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
  return r;
}

const char* const kTools[] = {"icanc_bench",        "icanc_energy",        "icanc_eval",
                              "icanc_kitti2bag",    "icanc_kitti_detect",  "icanc_latency_log",
                              "icanc_montecarlo",   "icanc_overlay_figure", "icanc_sim_bag",
                              "icanc_sim_odometry", "icanc_summary"};

TEST(ToolHelp, EveryToolAnswersHelpWithoutAMaster) {
  for (const char* tool : kTools) {
    const Outcome r = run(tool, "--help");
    EXPECT_EQ(r.status, 0) << tool;
    EXPECT_NE(r.out.find("usage:"), std::string::npos) << tool << " printed: " << r.out;
  }
}

TEST(ToolHelp, RosToolsRefuseBadUsageWithoutAMaster) {
  EXPECT_EQ(run("icanc_eval", "").status, 2);
  EXPECT_EQ(run("icanc_eval", "x.bag --rate").status, 2);
  EXPECT_EQ(run("icanc_eval", "x.bag --no-such-option 1").status, 2);
  EXPECT_EQ(run("icanc_latency_log", "only_one.csv").status, 2);
  EXPECT_EQ(run("icanc_summary", "stray_argument").status, 2);
}

TEST(ToolHelp, BagToolsRefuseMissingArguments) {
  EXPECT_EQ(run("icanc_sim_bag", "").status, 2);
  EXPECT_EQ(run("icanc_kitti2bag", "").status, 2);
  EXPECT_EQ(run("icanc_kitti_detect", "").status, 2);
  EXPECT_EQ(run("icanc_overlay_figure", "").status, 2);
  EXPECT_EQ(run("icanc_sim_odometry", "").status, 2);
}

}  // namespace
