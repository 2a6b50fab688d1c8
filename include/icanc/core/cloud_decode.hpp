// Decoding of a PointCloud2-shaped byte buffer into x/y/z points, with every layout check a
// malformed message can fail. ROS-free: the nodelet fills RawCloud from sensor_msgs/PointCloud2.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "icanc/core/types.hpp"

namespace icanc {

// Values of sensor_msgs/PointField::datatype.
enum class FieldType : std::uint8_t {
  kInt8 = 1, kUint8 = 2, kInt16 = 3, kUint16 = 4, kInt32 = 5, kUint32 = 6, kFloat32 = 7, kFloat64 = 8
};

struct FieldDesc {
  std::string name;
  std::uint32_t offset = 0;
  std::uint8_t datatype = 0;  // FieldType value
  std::uint32_t count = 1;
};

struct RawCloud {
  std::uint32_t width = 0;
  std::uint32_t height = 0;
  std::uint32_t point_step = 0;
  std::uint32_t row_step = 0;
  bool is_bigendian = false;
  std::vector<FieldDesc> fields;
  const std::uint8_t* data = nullptr;
  std::size_t data_size = 0;
};

enum class DecodeError {
  kNone,
  kEmpty,                 // width * height == 0
  kMissingXYZ,            // no x, y or z field
  kUnsupportedFieldType,  // x/y/z not FLOAT32 or FLOAT64, or count != 1
  kBigEndian,             // byte order differs from this machine's
  kInconsistentLayout,    // field past point_step, row_step < width * point_step, ...
  kTruncatedData,         // data shorter than row_step * height
  kTooManyPoints,         // width * height above the configured maximum
};

const char* toString(DecodeError error);

struct DecodeStats {
  std::size_t total = 0;             // points in the message
  std::size_t kept = 0;              // points written to the output
  std::size_t dropped_nonfinite = 0; // NaN / Inf coordinates (and FLOAT64 beyond float's range,
                                     // and points whose transform overflows float)
  std::size_t dropped_zero = 0;      // exact (0, 0, 0): "no return" on many drivers
};

// Validates the layout, then writes every finite, non-zero point transformed by `transform`
// (sensor frame -> target frame) into `out` (cleared first; its capacity is reused). On an error
// `out` is left empty and nothing else is touched.
DecodeError decodeXYZ(const RawCloud& in, const Eigen::Affine3f& transform, std::size_t max_points,
                      Cloud& out, DecodeStats* stats = nullptr);

// Where x, y and z lie in a validated cloud (planDecode).
struct DecodePlan {
  std::size_t ox = 0, oy = 0, oz = 0;  // byte offsets in a point
  bool dx = false, dy = false, dz = false;  // FLOAT64 (else FLOAT32)
  std::size_t point_step = 0, row_step = 0, width = 0, height = 0;
};

// The layout checks of decodeXYZ alone: kNone and `plan` filled when the cloud can be read.
DecodeError planDecode(const RawCloud& in, std::size_t max_points, DecodePlan& plan);

namespace decode_detail {
inline float readFloat32(const std::uint8_t* p) {
  float v;
  std::memcpy(&v, p, sizeof(v));
  return v;
}
inline float readCoordinate(const std::uint8_t* p, bool is_double) {
  if (!is_double) return readFloat32(p);
  double v;
  std::memcpy(&v, p, sizeof(v));
  // A double outside float's range (or NaN) has no float value: the cast would be undefined, so
  // it becomes +inf and the point is dropped as non-finite.
  return std::fabs(v) <= static_cast<double>(std::numeric_limits<float>::max())
             ? static_cast<float>(v)
             : std::numeric_limits<float>::infinity();
}
}  // namespace decode_detail

// Reads every point of a cloud planDecode accepted, drops non-finite and (0, 0, 0) points,
// transforms the rest and calls sink(x, y, z) for each: decodeXYZ writes them into a cloud, the
// fast detector bins them as they are read (one pass over the message, no intermediate cloud).
template <class Sink>
DecodeStats forEachXYZ(const RawCloud& in, const DecodePlan& plan, const Eigen::Affine3f& transform,
                       Sink&& sink) {
  const Eigen::Matrix3f rotation = transform.linear();
  const Eigen::Vector3f translation = transform.translation();
  DecodeStats stats;
  stats.total = plan.width * plan.height;
  const auto push = [&](float x, float y, float z) {
    if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z)) {
      ++stats.dropped_nonfinite;
      return;
    }
    if (x == 0.0f && y == 0.0f && z == 0.0f) {  // sensor frame: "no return"
      ++stats.dropped_zero;
      return;
    }
    const Eigen::Vector3f v = rotation * Eigen::Vector3f(x, y, z) + translation;
    // A finite coordinate near float's maximum can overflow to inf in the transform (found by
    // test/fuzz/cloud_decode_fuzzer.cpp): such a point is as unusable as a non-finite one.
    if (!v.allFinite()) {
      ++stats.dropped_nonfinite;
      return;
    }
    ++stats.kept;
    sink(v.x(), v.y(), v.z());
  };
  using decode_detail::readCoordinate;
  using decode_detail::readFloat32;
  if (!plan.dx && !plan.dy && !plan.dz) {  // common layout: three float32 coordinates
    for (std::size_t r = 0; r < plan.height; ++r) {
      const std::uint8_t* p = in.data + r * plan.row_step;
      for (std::size_t c = 0; c < plan.width; ++c, p += plan.point_step)
        push(readFloat32(p + plan.ox), readFloat32(p + plan.oy), readFloat32(p + plan.oz));
    }
  } else {
    for (std::size_t r = 0; r < plan.height; ++r) {
      const std::uint8_t* p = in.data + r * plan.row_step;
      for (std::size_t c = 0; c < plan.width; ++c, p += plan.point_step)
        push(readCoordinate(p + plan.ox, plan.dx), readCoordinate(p + plan.oy, plan.dy),
             readCoordinate(p + plan.oz, plan.dz));
    }
  }
  return stats;
}

}  // namespace icanc
