// Decoding of a PointCloud2-shaped byte buffer into x/y/z points, with every layout check a
// malformed message can fail. ROS-free: the nodelet fills RawCloud from sensor_msgs/PointCloud2.
#pragma once

#include <cstddef>
#include <cstdint>
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

}  // namespace icanc
