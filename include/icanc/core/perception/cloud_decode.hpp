// Decoding of a PointCloud2-shaped byte buffer into x/y/z points, with every layout check a
// malformed message can fail. ROS-free: the nodelet fills RawCloud from sensor_msgs/PointCloud2.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <type_traits>
#include <vector>

#include <Eigen/Geometry>

#include "icanc/core/common/always_inline.hpp"
#include "icanc/core/common/types.hpp"

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
  kDuplicateX,            // two fields named x (or y, z): which holds the coordinate is unknown
  kDuplicateY,
  kDuplicateZ,
};

const char* toString(DecodeError error);

struct DecodeStats {
  std::size_t total = 0;             // points in the message
  std::size_t kept = 0;              // points written to the output
  std::size_t dropped_nonfinite = 0; // NaN / Inf coordinates (and FLOAT64 beyond float's range,
                                     // and points whose transform or whose transformed
                                     // coordinates' sum overflows float: beyond 1e38 m)
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

// A cloud of this project's points seen as the PointCloud2 buffer a driver would publish: x, y, z
// float32 at offsets 0, 4, 8 of each padded point, its rows and columns as the cloud has them
// (organized scans keep their beams and azimuths). No copy: valid while `cloud` lives unchanged.
RawCloud rawView(const Cloud& cloud);

// The layout checks of decodeXYZ alone: kNone and `plan` filled when the cloud can be read.
DecodeError planDecode(const RawCloud& in, std::size_t max_points, DecodePlan& plan);

// `plan` reading only every n-th point of each row, from point `phase` on (points phase,
// phase + n, ...; n 0 or 1: all of them; phase taken modulo n). A consumer that wants a thinned
// cloud (LidarOdometry's input_stride) then never decodes the points it would skip.
inline DecodePlan everyNthPoint(DecodePlan plan, std::size_t n, std::size_t phase = 0) {
  if (n <= 1 || plan.width == 0) return plan;
  phase %= n;
  if (phase >= plan.width) {
    plan.width = 0;
    return plan;
  }
  plan.ox += phase * plan.point_step;
  plan.oy += phase * plan.point_step;
  plan.oz += phase * plan.point_step;
  plan.width = (plan.width - phase + n - 1) / n;
  plan.point_step *= n;
  return plan;
}

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

namespace decode_detail {
struct NoObserver {
  void operator()(float, float, float) const {}
};
}  // namespace decode_detail

// Reads every point of a cloud planDecode accepted, drops non-finite and (0, 0, 0) points,
// transforms the rest and calls sink(x, y, z) for each: decodeXYZ writes them into a cloud, the
// fast detector bins them as they are read (one pass over the message, no intermediate cloud).
// observe(x, y, z), when given, sees each point the sink gets as the message has it (the cloud's
// own frame), before the transform: the blind-sensor check counts returns in the same pass.
template <class Sink, class Observer = decode_detail::NoObserver>
DecodeStats forEachXYZ(const RawCloud& in, const DecodePlan& plan, const Eigen::Affine3f& transform,
                       Sink&& sink, Observer&& observe = Observer()) {
  // The transform as twelve scalars, applied by hand: at -O2 GCC leaves Eigen's 3x3 product as a
  // call per point here.
  const Eigen::Matrix3f r = transform.linear();
  const Eigen::Vector3f t = transform.translation();
  const float r00 = r(0, 0), r01 = r(0, 1), r02 = r(0, 2), r10 = r(1, 0), r11 = r(1, 1),
              r12 = r(1, 2), r20 = r(2, 0), r21 = r(2, 1), r22 = r(2, 2);
  const float t0 = t.x(), t1 = t.y(), t2 = t.z();
  DecodeStats stats;
  stats.total = plan.width * plan.height;
  // `rotate` is a compile-time flag: without a rotation (sensor frame = target frame, or a mount
  // with translation only) the transform is three additions.
  const auto push = [&](auto rotate, float x, float y, float z) ICANC_ALWAYS_INLINE {
    if (x == 0.0f && y == 0.0f && z == 0.0f) {  // sensor frame: "no return"
      ++stats.dropped_zero;
      return;
    }
    float vx = x + t0, vy = y + t1, vz = z + t2;
    if (decltype(rotate)::value) {
      vx = r00 * x + r01 * y + r02 * z + t0;
      vy = r10 * x + r11 * y + r12 * z + t1;
      vz = r20 * x + r21 * y + r22 * z + t2;
    }
    // Every output uses every input, and NaN or Inf survives any product (Inf * 0 is NaN), so
    // one test after the transform drops non-finite input as well as a finite coordinate near
    // float's maximum that overflows in the transform (found by test/fuzz/cloud_decode_fuzzer.cpp).
    // The test is on the sum, which is non-finite when any term is (or when it overflows, only
    // for coordinates beyond 1e38 m, unusable as well).
    if (!std::isfinite(vx + vy + vz)) {
      ++stats.dropped_nonfinite;
      return;
    }
    ++stats.kept;
    observe(x, y, z);
    sink(vx, vy, vz);
  };
  const auto read_all = [&](auto rotate) {
    using decode_detail::readCoordinate;
    using decode_detail::readFloat32;
    if (!plan.dx && !plan.dy && !plan.dz) {  // common layout: three float32 coordinates
      for (std::size_t row = 0; row < plan.height; ++row) {
        const std::uint8_t* p = in.data + row * plan.row_step;
        for (std::size_t c = 0; c < plan.width; ++c, p += plan.point_step)
          push(rotate, readFloat32(p + plan.ox), readFloat32(p + plan.oy), readFloat32(p + plan.oz));
      }
    } else {
      for (std::size_t row = 0; row < plan.height; ++row) {
        const std::uint8_t* p = in.data + row * plan.row_step;
        for (std::size_t c = 0; c < plan.width; ++c, p += plan.point_step)
          push(rotate, readCoordinate(p + plan.ox, plan.dx), readCoordinate(p + plan.oy, plan.dy),
               readCoordinate(p + plan.oz, plan.dz));
      }
    }
  };
  if (r.isIdentity(0.0f))
    read_all(std::false_type());
  else
    read_all(std::true_type());
  return stats;
}

}  // namespace icanc
