// CPU time of the calling thread, for the tools' timings beside their wall (steady_clock) times.
#pragma once

#include <time.h>

namespace icanc {
namespace tools {

// [ms]: unlike wall time, not inflated by other work on the machine (cache sharing still is), so
// the cost per frame can be read on a loaded machine too.
inline double threadCpuMs() {
  timespec t;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return t.tv_sec * 1e3 + t.tv_nsec * 1e-6;
}

}  // namespace tools
}  // namespace icanc
