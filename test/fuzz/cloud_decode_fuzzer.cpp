// libFuzzer target for icanc::decodeXYZ (PointCloud2 layout checks and decoding; scripts/fuzz).
//
// Input layout: a 32-byte header, then the data buffer.
//   [0..3] width, [4..7] height, [8..11] point_step, [12..15] row_step (little-endian uint32);
//   [16] flags: bit 0 is_bigendian, bit 1 FLOAT64 coordinates, bit 2 drop field z,
//        bit 3 rename x, bit 4 an extra "intensity" field; [17] max_points selector;
//   [18..20] x/y/z offsets, [21..23] x/y/z datatypes when bit 5 of [16] is set (else 7 or 8),
//   [24..26] x/y/z counts minus 1 when bit 6 is set; [27..31] unused.
// Checks, aborting on violation: on an error the output is empty; on success every output point is
// finite, kept + dropped == width * height <= max_points, and no read leaves the buffer (ASan,
// the data is copied into an exactly sized heap block).
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "icanc/core/perception/cloud_decode.hpp"

namespace {

void check(bool ok) {
  if (!ok) std::abort();
}

std::uint32_t u32(const std::uint8_t* p) {
  return static_cast<std::uint32_t>(p[0]) | static_cast<std::uint32_t>(p[1]) << 8 |
         static_cast<std::uint32_t>(p[2]) << 16 | static_cast<std::uint32_t>(p[3]) << 24;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace icanc;
  if (size < 32) return 0;
  RawCloud in;
  in.width = u32(data);
  in.height = u32(data + 4);
  in.point_step = u32(data + 8);
  in.row_step = u32(data + 12);
  const std::uint8_t flags = data[16];
  in.is_bigendian = flags & 1;
  const std::size_t max_points = 1 + static_cast<std::size_t>(data[17]) * 64;  // 1 ... 16321
  const char* names[3] = {"x", "y", "z"};
  for (int i = 0; i < 3; ++i) {
    if (i == 2 && (flags & 4)) continue;
    FieldDesc f;
    f.name = (i == 0 && (flags & 8)) ? "X" : names[i];
    f.offset = data[18 + i];
    f.datatype = (flags & 32) ? data[21 + i] : ((flags & 2) ? 8 : 7);
    f.count = (flags & 64) ? 1u + data[24 + i] : 1u;
    in.fields.push_back(f);
  }
  if (flags & 16) in.fields.push_back(FieldDesc{"intensity", 12, 7, 1});
  // The data in a heap block of exactly its size, so ASan catches any read past it.
  const std::size_t n = size - 32;
  std::uint8_t* buffer = static_cast<std::uint8_t*>(std::malloc(n ? n : 1));
  if (n) std::memcpy(buffer, data + 32, n);
  in.data = n ? buffer : nullptr;
  in.data_size = n;

  Cloud out;
  out.points.resize(3);  // stale content must not survive an error
  DecodeStats stats;
  const Eigen::Affine3f transform(Eigen::AngleAxisf(0.3f, Eigen::Vector3f::UnitZ()) *
                                  Eigen::Translation3f(0.3f, 0.0f, 0.6f));
  const DecodeError error = decodeXYZ(in, transform, max_points, out, &stats);
  if (error != DecodeError::kNone) {
    check(out.points.empty());
    check(std::string(toString(error)).size() > 0);
  } else {
    const std::uint64_t total = static_cast<std::uint64_t>(in.width) * in.height;
    check(total <= max_points);
    check(stats.total == total);
    check(stats.kept == out.points.size());
    check(stats.kept + stats.dropped_nonfinite + stats.dropped_zero == stats.total);
    for (const Point& p : out.points)
      check(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z));
    // Decoding again into the same (now larger) cloud gives the same result.
    Cloud again = out;
    check(decodeXYZ(in, transform, max_points, again) == DecodeError::kNone);
    check(again.points.size() == out.points.size());
  }
  std::free(buffer);
  return 0;
}
