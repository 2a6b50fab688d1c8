// The tools' common -h / --help: answered before anything else (before ros::init, a master or a
// file is touched), on stdout with exit status 0, so `rosrun icanc TOOL --help` never waits for a
// ROS master. Paths on the tools' command lines are relative to the current directory, as for any
// command-line program (rosrun keeps it); `$(rospack find icanc)/config/...` names the package's
// files from anywhere.
#pragma once

#include <cstdio>
#include <cstring>

namespace icanc {
namespace tools {

inline bool wantsHelp(int argc, char** argv) {
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "-h") == 0 || std::strcmp(argv[i], "--help") == 0) return true;
  }
  return false;
}

// Prints `usage` and the path note; to stdout for --help, to stderr for bad usage.
inline int printUsage(const char* usage, bool asked) {
  std::FILE* out = asked ? stdout : stderr;
  std::fputs(usage, out);
  std::fputs("Paths are relative to the current directory; $(rospack find icanc)/config/... names "
             "the package's files.\n",
             out);
  return asked ? 0 : 2;
}

}  // namespace tools
}  // namespace icanc
