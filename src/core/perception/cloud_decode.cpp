#include "icanc/core/perception/cloud_decode.hpp"

#include <cstddef>

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
    case DecodeError::kDuplicateX: return "two fields named x: which one is the coordinate is unknown";
    case DecodeError::kDuplicateY: return "two fields named y: which one is the coordinate is unknown";
    case DecodeError::kDuplicateZ: return "two fields named z: which one is the coordinate is unknown";
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

int countField(const std::vector<FieldDesc>& fields, const char* name) {
  int n = 0;
  for (const FieldDesc& f : fields) n += f.name == name;
  return n;
}

// Size in bytes of a supported coordinate type, 0 for anything else.
std::uint64_t coordinateSize(std::uint8_t datatype) {
  if (datatype == static_cast<std::uint8_t>(FieldType::kFloat32)) return 4;
  if (datatype == static_cast<std::uint8_t>(FieldType::kFloat64)) return 8;
  return 0;
}

}  // namespace

RawCloud rawView(const Cloud& cloud) {
  RawCloud raw;
  raw.width = cloud.width;
  raw.height = cloud.height;
  raw.point_step = sizeof(Point);
  raw.row_step = raw.width * raw.point_step;
  raw.fields = {{"x", offsetof(Point, x), static_cast<std::uint8_t>(FieldType::kFloat32), 1},
                {"y", offsetof(Point, y), static_cast<std::uint8_t>(FieldType::kFloat32), 1},
                {"z", offsetof(Point, z), static_cast<std::uint8_t>(FieldType::kFloat32), 1}};
  raw.data = reinterpret_cast<const std::uint8_t*>(cloud.points.data());
  raw.data_size = cloud.points.size() * sizeof(Point);
  return raw;
}

DecodeError planDecode(const RawCloud& in, std::size_t max_points, DecodePlan& plan) {
  // Every size below is computed in 64 bits from 32-bit inputs, so no product can overflow
  // (2^32 * 2^32 fits in 2^64), and every comparison happens before any read.
  const std::uint64_t width = in.width;
  const std::uint64_t height = in.height;
  const std::uint64_t total = width * height;
  if (total == 0) return DecodeError::kEmpty;
  if (total > static_cast<std::uint64_t>(max_points)) return DecodeError::kTooManyPoints;
  if (in.is_bigendian != hostIsBigEndian()) return DecodeError::kBigEndian;

  const FieldDesc* fx = findField(in.fields, "x");
  const FieldDesc* fy = findField(in.fields, "y");
  const FieldDesc* fz = findField(in.fields, "z");
  if (!fx || !fy || !fz) return DecodeError::kMissingXYZ;
  // A second field of a coordinate's name (another field renamed by mistake) would be read or
  // not depending on its order: refused. Duplicates of fields not read here do not matter.
  if (countField(in.fields, "x") > 1) return DecodeError::kDuplicateX;
  if (countField(in.fields, "y") > 1) return DecodeError::kDuplicateY;
  if (countField(in.fields, "z") > 1) return DecodeError::kDuplicateZ;

  const FieldDesc* xyz[3] = {fx, fy, fz};
  std::uint64_t sizes[3];
  for (int i = 0; i < 3; ++i) {
    sizes[i] = coordinateSize(xyz[i]->datatype);
    if (sizes[i] == 0 || xyz[i]->count != 1) return DecodeError::kUnsupportedFieldType;
  }

  const std::uint64_t point_step = in.point_step;
  const std::uint64_t row_step = in.row_step;
  if (point_step == 0) return DecodeError::kInconsistentLayout;
  for (int i = 0; i < 3; ++i) {
    if (static_cast<std::uint64_t>(xyz[i]->offset) + sizes[i] > point_step) {
      return DecodeError::kInconsistentLayout;
    }
  }
  if (row_step < width * point_step) return DecodeError::kInconsistentLayout;
  if (in.data == nullptr || static_cast<std::uint64_t>(in.data_size) < row_step * height) {
    return DecodeError::kTruncatedData;
  }
  // From here on: total <= max_points, and every byte read lies below row_step * height.
  plan.ox = fx->offset;
  plan.oy = fy->offset;
  plan.oz = fz->offset;
  plan.dx = sizes[0] == 8;
  plan.dy = sizes[1] == 8;
  plan.dz = sizes[2] == 8;
  plan.point_step = static_cast<std::size_t>(point_step);
  plan.row_step = static_cast<std::size_t>(row_step);
  plan.width = static_cast<std::size_t>(width);
  plan.height = static_cast<std::size_t>(height);
  return DecodeError::kNone;
}

DecodeError decodeXYZ(const RawCloud& in, const Eigen::Affine3f& transform, std::size_t max_points,
                      Cloud& out, DecodeStats* stats) {
  // On an error the output is left empty (capacity kept) and the stats untouched.
  DecodePlan plan;
  const DecodeError error = planDecode(in, max_points, plan);
  if (error != DecodeError::kNone) {
    out.clear();
    return error;
  }
  const std::size_t n = plan.width * plan.height;
  if (out.points.size() < n) out.points.resize(n);  // grows only: reuses capacity and contents
  Point* dst = out.points.data();
  std::size_t kept = 0;
  const DecodeStats s = forEachXYZ(in, plan, transform, [dst, &kept](float x, float y, float z) {
    Point& p = dst[kept++];
    p.x = x;
    p.y = y;
    p.z = z;
  });
  out.points.resize(kept);  // shrinking never reallocates
  out.width = static_cast<std::uint32_t>(kept);
  out.height = 1;
  out.is_dense = true;
  if (stats) *stats = s;
  return DecodeError::kNone;
}

}  // namespace icanc
