#include "icanc/core/cloud_decode.hpp"

#include <cmath>
#include <cstring>
#include <limits>

namespace icanc {

const char* toString(DecodeError error) {
  switch (error) {
    case DecodeError::kNone: return "no error";
    case DecodeError::kEmpty: return "empty cloud (width * height == 0)";
    case DecodeError::kMissingXYZ: return "no x, y or z field";
    case DecodeError::kUnsupportedFieldType:
      return "x/y/z field is not a single FLOAT32 or FLOAT64";
    case DecodeError::kBigEndian: return "byte order differs from this machine's";
    case DecodeError::kInconsistentLayout:
      return "inconsistent layout (field past point_step, point_step 0 or row_step too small)";
    case DecodeError::kTruncatedData: return "data shorter than row_step * height";
    case DecodeError::kTooManyPoints: return "more points than the configured maximum";
  }
  return "unknown decode error";
}

namespace {

bool hostIsBigEndian() {
  const std::uint16_t probe = 0x0102;
  std::uint8_t first = 0;
  std::memcpy(&first, &probe, 1);
  return first == 0x01;
}

const FieldDesc* findField(const std::vector<FieldDesc>& fields, const char* name) {
  for (const FieldDesc& f : fields) {
    if (f.name == name) return &f;
  }
  return nullptr;
}

// Size in bytes of a supported coordinate type, 0 for anything else.
std::uint64_t coordinateSize(std::uint8_t datatype) {
  if (datatype == static_cast<std::uint8_t>(FieldType::kFloat32)) return 4;
  if (datatype == static_cast<std::uint8_t>(FieldType::kFloat64)) return 8;
  return 0;
}

inline float readFloat32(const std::uint8_t* p) {
  float v;
  std::memcpy(&v, p, sizeof(v));
  return v;
}

inline float readCoordinate(const std::uint8_t* p, bool is_double) {
  if (is_double) {
    double v;
    std::memcpy(&v, p, sizeof(v));
    // A double outside float's range (or NaN) has no float value: the cast would be undefined,
    // so it becomes +inf and the point is dropped as non-finite.
    return std::fabs(v) <= static_cast<double>(std::numeric_limits<float>::max())
               ? static_cast<float>(v)
               : std::numeric_limits<float>::infinity();
  }
  return readFloat32(p);
}

// Shared by both paths: drops non-finite and (0, 0, 0) points, transforms and writes the rest.
struct PointSink {
  Eigen::Matrix3f rotation;
  Eigen::Vector3f translation;
  Point* dst;
  std::size_t kept = 0;
  std::size_t nonfinite = 0;
  std::size_t zero = 0;

  inline void push(float x, float y, float z) {
    if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z)) {
      ++nonfinite;
      return;
    }
    if (x == 0.0f && y == 0.0f && z == 0.0f) {  // sensor frame: "no return"
      ++zero;
      return;
    }
    const Eigen::Vector3f v = rotation * Eigen::Vector3f(x, y, z) + translation;
    // A finite coordinate near float's maximum can overflow to inf in the transform (found by
    // test/fuzz/cloud_decode_fuzzer.cpp): such a point is as unusable as a non-finite one.
    if (!v.allFinite()) {
      ++nonfinite;
      return;
    }
    Point& out = dst[kept++];
    out.x = v.x();
    out.y = v.y();
    out.z = v.z();
  }
};

}  // namespace

DecodeError decodeXYZ(const RawCloud& in, const Eigen::Affine3f& transform, std::size_t max_points,
                      Cloud& out, DecodeStats* stats) {
  // On an error the output is left empty (capacity kept) and the stats untouched.
  const auto fail = [&out](DecodeError error) {
    out.clear();
    return error;
  };

  // Every size below is computed in 64 bits from 32-bit inputs, so no product can overflow
  // (2^32 * 2^32 fits in 2^64), and every comparison happens before any read.
  const std::uint64_t width = in.width;
  const std::uint64_t height = in.height;
  const std::uint64_t total = width * height;
  if (total == 0) return fail(DecodeError::kEmpty);
  if (total > static_cast<std::uint64_t>(max_points)) return fail(DecodeError::kTooManyPoints);
  if (in.is_bigendian != hostIsBigEndian()) return fail(DecodeError::kBigEndian);

  const FieldDesc* fx = findField(in.fields, "x");
  const FieldDesc* fy = findField(in.fields, "y");
  const FieldDesc* fz = findField(in.fields, "z");
  if (!fx || !fy || !fz) return fail(DecodeError::kMissingXYZ);

  const FieldDesc* xyz[3] = {fx, fy, fz};
  std::uint64_t sizes[3];
  for (int i = 0; i < 3; ++i) {
    sizes[i] = coordinateSize(xyz[i]->datatype);
    if (sizes[i] == 0 || xyz[i]->count != 1) return fail(DecodeError::kUnsupportedFieldType);
  }

  const std::uint64_t point_step = in.point_step;
  const std::uint64_t row_step = in.row_step;
  if (point_step == 0) return fail(DecodeError::kInconsistentLayout);
  for (int i = 0; i < 3; ++i) {
    if (static_cast<std::uint64_t>(xyz[i]->offset) + sizes[i] > point_step) {
      return fail(DecodeError::kInconsistentLayout);
    }
  }
  if (row_step < width * point_step) return fail(DecodeError::kInconsistentLayout);
  if (in.data == nullptr || static_cast<std::uint64_t>(in.data_size) < row_step * height) {
    return fail(DecodeError::kTruncatedData);
  }
  // From here on: total <= max_points, and every byte read lies below row_step * height.

  const std::size_t n = static_cast<std::size_t>(total);
  if (out.points.size() < n) out.points.resize(n);  // grows only: reuses capacity and contents

  PointSink sink;
  sink.rotation = transform.linear();
  sink.translation = transform.translation();
  sink.dst = out.points.data();

  const std::size_t ox = fx->offset, oy = fy->offset, oz = fz->offset;
  const std::size_t pstep = static_cast<std::size_t>(point_step);
  const std::size_t rstep = static_cast<std::size_t>(row_step);
  const std::size_t w = static_cast<std::size_t>(width);
  const std::size_t h = static_cast<std::size_t>(height);

  if (sizes[0] == 4 && sizes[1] == 4 && sizes[2] == 4) {
    // Common layout: three float32 coordinates.
    for (std::size_t r = 0; r < h; ++r) {
      const std::uint8_t* p = in.data + r * rstep;
      for (std::size_t c = 0; c < w; ++c, p += pstep) {
        sink.push(readFloat32(p + ox), readFloat32(p + oy), readFloat32(p + oz));
      }
    }
  } else {
    const bool dx = sizes[0] == 8, dy = sizes[1] == 8, dz = sizes[2] == 8;
    for (std::size_t r = 0; r < h; ++r) {
      const std::uint8_t* p = in.data + r * rstep;
      for (std::size_t c = 0; c < w; ++c, p += pstep) {
        sink.push(readCoordinate(p + ox, dx), readCoordinate(p + oy, dy),
                  readCoordinate(p + oz, dz));
      }
    }
  }

  out.points.resize(sink.kept);  // shrinking never reallocates
  out.width = static_cast<std::uint32_t>(sink.kept);
  out.height = 1;
  out.is_dense = true;

  if (stats) {
    stats->total = n;
    stats->kept = sink.kept;
    stats->dropped_nonfinite = sink.nonfinite;
    stats->dropped_zero = sink.zero;
  }
  return DecodeError::kNone;
}

}  // namespace icanc
