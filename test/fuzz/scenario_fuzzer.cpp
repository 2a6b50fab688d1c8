// libFuzzer target for icanc::sim::loadScenario (scenario YAML files; scripts/fuzz). The input is
// written to a file (loadScenario takes a path). Contract checked: it returns a scenario or throws
// std::runtime_error (yaml-cpp's exceptions derive from it); any other exception escapes and
// libFuzzer reports it. A returned scenario satisfies the checks the loader documents, its frame
// count is computable, and its first pose and objects can be evaluated.
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <string>

#include "icanc/sim/scenario.hpp"

namespace {

const std::string& tempPath() {
  static const std::string path = "/tmp/icanc_scenario_fuzz_" + std::to_string(getpid()) + ".yaml";
  return path;
}

void check(bool ok) {
  if (!ok) std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::FILE* f = std::fopen(tempPath().c_str(), "wb");
  if (!f) return 0;
  if (size) std::fwrite(data, 1, size, f);
  std::fclose(f);
  try {
    const icanc::sim::Scenario s = icanc::sim::loadScenario(tempPath());
    check(s.duration_s > 0.0 && s.rate_hz > 0.0 && s.rate_hz <= 100.0);
    check(!s.profile.empty());
    (void)s.frames();
    (void)s.sensorPose(0.0);
    (void)s.sensorPose(s.duration_s);
  } catch (const std::runtime_error&) {
  }
  return 0;
}
