// libFuzzer target for icanc::kitti::readLabels (label_02/NNNN.txt; scripts/fuzz). The input is
// written to a file (readLabels takes a path). Contract checked: it returns labels or throws
// std::runtime_error (naming the file); any other exception escapes and libFuzzer reports it.
// Every returned label has a type and finite numbers when the line had finite numbers only.
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <string>

#include "icanc/core/evaluation/kitti.hpp"

namespace {

const std::string& tempPath() {
  static const std::string path = "/tmp/icanc_kitti_labels_fuzz_" + std::to_string(getpid()) + ".txt";
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
    const auto labels = icanc::kitti::readLabels(tempPath());
    for (const auto& l : labels) check(!l.type.empty());
    // The conversion to the velodyne frame must not crash either (identity-like calibration).
    icanc::kitti::Calib calib;
    calib.tr_velo_to_cam.leftCols<3>().setIdentity();
    (void)icanc::kitti::toVelodyne(labels, calib);
  } catch (const std::runtime_error& e) {
    check(std::string(e.what()).find(tempPath()) != std::string::npos);
  }
  return 0;
}
