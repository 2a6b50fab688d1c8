// decodeXYZ: every DecodeError, the layouts a PointCloud2 may have, dropped points, transform and
// buffer reuse. Byte buffers are built by hand, as a driver would lay them out.
#include "icanc/core/perception/cloud_decode.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <set>
#include <string>
#include <vector>

#include <gtest/gtest.h>

namespace icanc {
namespace {

constexpr std::uint8_t kF32 = static_cast<std::uint8_t>(FieldType::kFloat32);
constexpr std::uint8_t kF64 = static_cast<std::uint8_t>(FieldType::kFloat64);
constexpr std::uint8_t kU16 = static_cast<std::uint8_t>(FieldType::kUint16);
constexpr std::size_t kMax = 1000000;

bool hostBigEndian() {
  const std::uint16_t probe = 0x0102;
  std::uint8_t first = 0;
  std::memcpy(&first, &probe, 1);
  return first == 0x01;
}

// A PointCloud2-shaped message owning its bytes.
struct Message {
  RawCloud raw;
  std::vector<std::uint8_t> bytes;

  void put32(std::size_t at, float v) { std::memcpy(bytes.data() + at, &v, 4); }
  void put64(std::size_t at, double v) { std::memcpy(bytes.data() + at, &v, 8); }
  // Points the RawCloud at the owned bytes (call after any change to `bytes`).
  const RawCloud& view() {
    raw.data = bytes.data();
    raw.data_size = bytes.size();
    return raw;
  }
};

// The Velodyne-like layout: x, y, z float32 at 0/4/8, intensity float32 at 12, point_step 16.
// `row_padding` bytes (filled with 0xFF, i.e. NaN patterns) end every row.
Message makeXYZI(const std::vector<Eigen::Vector3f>& pts, std::uint32_t height = 1,
                 std::uint32_t row_padding = 0) {
  Message m;
  m.raw.height = height;
  m.raw.width = static_cast<std::uint32_t>(pts.size() / height);
  m.raw.point_step = 16;
  m.raw.row_step = m.raw.width * 16 + row_padding;
  m.raw.is_bigendian = hostBigEndian();
  m.raw.fields = {{"x", 0, kF32, 1}, {"y", 4, kF32, 1}, {"z", 8, kF32, 1}, {"intensity", 12, kF32, 1}};
  m.bytes.assign(static_cast<std::size_t>(m.raw.row_step) * height, 0xFF);
  for (std::uint32_t r = 0; r < height; ++r) {
    for (std::uint32_t c = 0; c < m.raw.width; ++c) {
      const Eigen::Vector3f& p = pts[r * m.raw.width + c];
      const std::size_t at = static_cast<std::size_t>(r) * m.raw.row_step + c * 16;
      m.put32(at + 0, p.x());
      m.put32(at + 4, p.y());
      m.put32(at + 8, p.z());
      m.put32(at + 12, 42.0f);
    }
  }
  m.view();
  return m;
}

std::vector<Eigen::Vector3f> somePoints(int n) {
  std::vector<Eigen::Vector3f> pts;
  for (int i = 0; i < n; ++i) pts.emplace_back(1.0f + i, -2.0f + 0.5f * i, 0.25f * i - 1.0f);
  return pts;
}

DecodeError decode(const RawCloud& raw, Cloud& out, std::size_t max_points = kMax,
                   DecodeStats* stats = nullptr) {
  return decodeXYZ(raw, Eigen::Affine3f::Identity(), max_points, out, stats);
}

void expectPoint(const Point& p, float x, float y, float z) {
  EXPECT_FLOAT_EQ(p.x, x);
  EXPECT_FLOAT_EQ(p.y, y);
  EXPECT_FLOAT_EQ(p.z, z);
}

TEST(CloudDecode, DecodesTheCommonLayout) {
  const auto pts = somePoints(5);
  Message m = makeXYZI(pts);
  Cloud out;
  DecodeStats stats;
  ASSERT_EQ(decode(m.view(), out, kMax, &stats), DecodeError::kNone);
  ASSERT_EQ(out.size(), 5u);
  EXPECT_EQ(out.width, 5u);
  EXPECT_EQ(out.height, 1u);
  EXPECT_TRUE(out.is_dense);
  for (int i = 0; i < 5; ++i) expectPoint(out[i], pts[i].x(), pts[i].y(), pts[i].z());
  EXPECT_EQ(stats.total, 5u);
  EXPECT_EQ(stats.kept, 5u);
  EXPECT_EQ(stats.dropped_nonfinite, 0u);
  EXPECT_EQ(stats.dropped_zero, 0u);
}

TEST(CloudDecode, EveryNthPointReadsOnlyThoseOfEachRow) {
  // Two rows of 5 with padding: every 2nd point is 0, 2, 4 of each row; 1 (and 0) read all.
  const auto pts = somePoints(10);
  Message m = makeXYZI(pts, 2, 8);
  DecodePlan plan;
  ASSERT_EQ(planDecode(m.view(), kMax, plan), DecodeError::kNone);
  const auto read = [&](const DecodePlan& p) {
    std::vector<Eigen::Vector3f> got;
    forEachXYZ(m.raw, p, Eigen::Affine3f::Identity(),
               [&](float x, float y, float z) { got.emplace_back(x, y, z); });
    return got;
  };
  const std::vector<Eigen::Vector3f> every2 = read(everyNthPoint(plan, 2));
  ASSERT_EQ(every2.size(), 6u);
  const int expected[] = {0, 2, 4, 5, 7, 9};
  for (int i = 0; i < 6; ++i) EXPECT_EQ(every2[i], pts[expected[i]]) << i;
  const std::vector<Eigen::Vector3f> every3 = read(everyNthPoint(plan, 3));
  ASSERT_EQ(every3.size(), 4u);  // 0, 3 of each row
  EXPECT_EQ(every3[3], pts[8]);
  EXPECT_EQ(read(everyNthPoint(plan, 1)).size(), 10u);
  EXPECT_EQ(read(everyNthPoint(plan, 0)).size(), 10u);
  EXPECT_EQ(read(everyNthPoint(plan, 7)).size(), 2u);  // a stride beyond the row: its first
  // From a phase: 1, 3 of each row for 2; 2 of each row for 3 from 2; the phase modulo the stride.
  const std::vector<Eigen::Vector3f> odd = read(everyNthPoint(plan, 2, 1));
  ASSERT_EQ(odd.size(), 4u);
  const int expected_odd[] = {1, 3, 6, 8};
  for (int i = 0; i < 4; ++i) EXPECT_EQ(odd[i], pts[expected_odd[i]]) << i;
  const std::vector<Eigen::Vector3f> from2 = read(everyNthPoint(plan, 3, 2));
  ASSERT_EQ(from2.size(), 2u);
  EXPECT_EQ(from2[0], pts[2]);
  EXPECT_EQ(from2[1], pts[7]);
  EXPECT_EQ(read(everyNthPoint(plan, 2, 3)), odd);
  EXPECT_EQ(read(everyNthPoint(plan, 6, 5)).size(), 0u);  // past the row's end: nothing
  EXPECT_EQ(read(everyNthPoint(plan, 1, 1)).size(), 10u);
}

TEST(CloudDecode, RawViewOfAnOrganizedCloudKeepsItsRows) {
  // Two rows of three, a no-return (NaN) in the second: the view reads what a driver's message
  // with the same points would, and every 2nd point of each row from phase 1 is column 1.
  Cloud cloud;
  cloud.width = 3;
  cloud.height = 2;
  cloud.points = {Point(1, 0, 0), Point(2, 0, 0), Point(3, 0, 0),
                  Point(4, 0, 0), Point(NAN, NAN, NAN), Point(6, 0, 0)};
  const RawCloud raw = rawView(cloud);
  EXPECT_EQ(raw.width, 3u);
  EXPECT_EQ(raw.height, 2u);
  DecodePlan plan;
  ASSERT_EQ(planDecode(raw, kMax, plan), DecodeError::kNone);
  const auto read = [&](const DecodePlan& p) {
    std::vector<float> xs;
    forEachXYZ(raw, p, Eigen::Affine3f::Identity(), [&](float x, float, float) { xs.push_back(x); });
    return xs;
  };
  EXPECT_EQ(read(plan), (std::vector<float>{1, 2, 3, 4, 6}));
  EXPECT_EQ(read(everyNthPoint(plan, 2, 1)), (std::vector<float>{2}));
  EXPECT_EQ(read(everyNthPoint(plan, 2)), (std::vector<float>{1, 3, 4, 6}));
}

TEST(CloudDecode, EmptyCloud) {
  Message m = makeXYZI(somePoints(4));
  Cloud out;
  m.raw.width = 0;
  EXPECT_EQ(decode(m.view(), out), DecodeError::kEmpty);
  m.raw.width = 4;
  m.raw.height = 0;
  EXPECT_EQ(decode(m.view(), out), DecodeError::kEmpty);
}

TEST(CloudDecode, TooManyPoints) {
  Message m = makeXYZI(somePoints(10));
  Cloud out;
  EXPECT_EQ(decode(m.view(), out, 9), DecodeError::kTooManyPoints);
  EXPECT_EQ(decode(m.view(), out, 10), DecodeError::kNone);
  // width * height overflows 32 bits: still counted in 64 bits, so it is caught.
  m.raw.width = 0x10000;
  m.raw.height = 0x10000;
  EXPECT_EQ(decode(m.view(), out, 0xFFFFFFFFu), DecodeError::kTooManyPoints);
}

TEST(CloudDecode, BigEndianFlagRejected) {
  Message m = makeXYZI(somePoints(3));
  m.raw.is_bigendian = !hostBigEndian();
  Cloud out;
  EXPECT_EQ(decode(m.view(), out), DecodeError::kBigEndian);
}

TEST(CloudDecode, MissingZ) {
  Message m = makeXYZI(somePoints(3));
  m.raw.fields[2].name = "intensity2";
  Cloud out;
  EXPECT_EQ(decode(m.view(), out), DecodeError::kMissingXYZ);
  m.raw.fields.clear();
  EXPECT_EQ(decode(m.view(), out), DecodeError::kMissingXYZ);
}

// A second field named as a coordinate (intensity renamed x by mistake) would be read or not by
// the fields' order: refused, the coordinate named. Duplicates of fields not read do not matter.
TEST(CloudDecode, DuplicateCoordinateNamesRejected) {
  Message m = makeXYZI(somePoints(3));
  m.raw.fields[3].name = "x";
  Cloud out;
  EXPECT_EQ(decode(m.view(), out), DecodeError::kDuplicateX);
  EXPECT_NE(std::string(toString(DecodeError::kDuplicateX)).find("two fields named x"), std::string::npos);
  EXPECT_TRUE(out.empty());
  m.raw.fields[3].name = "z";
  EXPECT_EQ(decode(m.view(), out), DecodeError::kDuplicateZ);
  m.raw.fields[3].name = "y";
  EXPECT_EQ(decode(m.view(), out), DecodeError::kDuplicateY);
  m.raw.fields[3].name = "intensity";
  m.raw.fields.push_back({"intensity", 12, kF32, 1});
  EXPECT_EQ(decode(m.view(), out), DecodeError::kNone);
}

TEST(CloudDecode, Uint16XRejected) {
  Message m = makeXYZI(somePoints(3));
  m.raw.fields[0].datatype = kU16;
  Cloud out;
  EXPECT_EQ(decode(m.view(), out), DecodeError::kUnsupportedFieldType);
}

TEST(CloudDecode, FieldCountOtherThanOneRejected) {
  Message m = makeXYZI(somePoints(3));
  m.raw.fields[1].count = 2;
  Cloud out;
  EXPECT_EQ(decode(m.view(), out), DecodeError::kUnsupportedFieldType);
  m.raw.fields[1].count = 0;
  EXPECT_EQ(decode(m.view(), out), DecodeError::kUnsupportedFieldType);
}

TEST(CloudDecode, Float64DecodedCorrectly) {
  // x, y, z as float64 at 8/16/0 (not in name order), point_step 32 with 8 bytes of other data.
  Message m;
  m.raw.width = 3;
  m.raw.height = 1;
  m.raw.point_step = 32;
  m.raw.row_step = 96;
  m.raw.is_bigendian = hostBigEndian();
  m.raw.fields = {{"z", 0, kF64, 1}, {"x", 8, kF64, 1}, {"y", 16, kF64, 1}, {"t", 24, kF64, 1}};
  m.bytes.assign(96, 0);
  const double xs[3] = {1.25, -3.5, 1234.5678901234};
  const double ys[3] = {7.75, 0.001, -98.76543210};
  const double zs[3] = {-1.7, 2.0, 0.0};
  for (int i = 0; i < 3; ++i) {
    m.put64(i * 32 + 0, zs[i]);
    m.put64(i * 32 + 8, xs[i]);
    m.put64(i * 32 + 16, ys[i]);
    m.put64(i * 32 + 24, 1e300);
  }
  Cloud out;
  ASSERT_EQ(decode(m.view(), out), DecodeError::kNone);
  ASSERT_EQ(out.size(), 3u);
  for (int i = 0; i < 3; ++i) {
    expectPoint(out[i], static_cast<float>(xs[i]), static_cast<float>(ys[i]),
                static_cast<float>(zs[i]));
  }
}

TEST(CloudDecode, MixedFloat32AndFloat64) {
  Message m;
  m.raw.width = 2;
  m.raw.height = 1;
  m.raw.point_step = 20;  // x f64 @0, y f32 @8, z f64 @12: odd offsets, unaligned reads
  m.raw.row_step = 40;
  m.raw.is_bigendian = hostBigEndian();
  m.raw.fields = {{"x", 0, kF64, 1}, {"y", 8, kF32, 1}, {"z", 12, kF64, 1}};
  m.bytes.assign(40, 0);
  m.put64(0, 1.5);
  m.put32(8, -2.5f);
  m.put64(12, 3.5);
  m.put64(20, 4.0);
  m.put32(28, 5.0f);
  m.put64(32, -6.0);
  Cloud out;
  ASSERT_EQ(decode(m.view(), out), DecodeError::kNone);
  ASSERT_EQ(out.size(), 2u);
  expectPoint(out[0], 1.5f, -2.5f, 3.5f);
  expectPoint(out[1], 4.0f, 5.0f, -6.0f);
}

TEST(CloudDecode, Float64OutsideFloatRangeDroppedAsNonFinite) {
  Message m;
  m.raw.width = 2;
  m.raw.height = 1;
  m.raw.point_step = 24;
  m.raw.row_step = 48;
  m.raw.is_bigendian = hostBigEndian();
  m.raw.fields = {{"x", 0, kF64, 1}, {"y", 8, kF64, 1}, {"z", 16, kF64, 1}};
  m.bytes.assign(48, 0);
  m.put64(0, 1e300);
  m.put64(8, 1.0);
  m.put64(16, 1.0);
  m.put64(24, 1.0);
  m.put64(32, 2.0);
  m.put64(40, 3.0);
  Cloud out;
  DecodeStats stats;
  ASSERT_EQ(decode(m.view(), out, kMax, &stats), DecodeError::kNone);
  ASSERT_EQ(out.size(), 1u);
  expectPoint(out[0], 1.0f, 2.0f, 3.0f);
  EXPECT_EQ(stats.dropped_nonfinite, 1u);
}

TEST(CloudDecode, UnalignedDataPointer) {
  const auto pts = somePoints(7);
  Message m = makeXYZI(pts);
  std::vector<std::uint8_t> shifted(m.bytes.size() + 1);
  std::memcpy(shifted.data() + 1, m.bytes.data(), m.bytes.size());
  RawCloud raw = m.raw;
  raw.data = shifted.data() + 1;
  raw.data_size = m.bytes.size();
  Cloud out;
  ASSERT_EQ(decode(raw, out), DecodeError::kNone);
  ASSERT_EQ(out.size(), 7u);
  for (int i = 0; i < 7; ++i) expectPoint(out[i], pts[i].x(), pts[i].y(), pts[i].z());
}

TEST(CloudDecode, PointStepSmallerThanAField) {
  Message m = makeXYZI(somePoints(3));
  m.raw.point_step = 11;  // z at 8 needs bytes 8..11
  m.raw.row_step = 33;
  Cloud out;
  EXPECT_EQ(decode(m.view(), out), DecodeError::kInconsistentLayout);
  m.raw.point_step = 12;  // exactly enough
  m.raw.row_step = 36;
  EXPECT_EQ(decode(m.view(), out), DecodeError::kNone);
  m.raw.point_step = 0;
  m.raw.row_step = 0;
  EXPECT_EQ(decode(m.view(), out), DecodeError::kInconsistentLayout);
}

TEST(CloudDecode, FieldOffsetNearUint32MaxDoesNotWrap) {
  Message m = makeXYZI(somePoints(3));
  m.raw.fields[1].offset = 0xFFFFFFFEu;  // offset + 4 wraps to 2 in 32 bits
  Cloud out;
  EXPECT_EQ(decode(m.view(), out), DecodeError::kInconsistentLayout);
}

TEST(CloudDecode, RowStepTooSmall) {
  Message m = makeXYZI(somePoints(6), 2);
  m.raw.row_step = 3 * 16 - 1;
  Cloud out;
  EXPECT_EQ(decode(m.view(), out), DecodeError::kInconsistentLayout);
  // width * point_step overflowing 32 bits is not mistaken for a small product.
  m.raw.width = 0x10000000;  // * 16 = 2^32
  m.raw.height = 1;
  m.raw.row_step = 0;
  EXPECT_EQ(decode(m.view(), out, 0xFFFFFFFFu), DecodeError::kInconsistentLayout);
}

TEST(CloudDecode, TruncatedByOneByte) {
  Message m = makeXYZI(somePoints(6), 2, 4);
  Cloud out;
  RawCloud raw = m.view();
  ASSERT_EQ(decode(raw, out), DecodeError::kNone);
  raw.data_size -= 1;
  EXPECT_EQ(decode(raw, out), DecodeError::kTruncatedData);
  raw.data = nullptr;
  raw.data_size = m.bytes.size();
  EXPECT_EQ(decode(raw, out), DecodeError::kTruncatedData);
}

TEST(CloudDecode, HugeDeclaredSizeWithSmallBufferIsTruncated) {
  Message m = makeXYZI(somePoints(2));
  m.raw.width = 1;
  m.raw.height = 0xFFFFFFFFu;
  m.raw.row_step = 0xFFFFFFFFu;  // row_step * height ~ 2^64: must not wrap
  Cloud out;
  EXPECT_EQ(decode(m.view(), out, std::numeric_limits<std::size_t>::max()),
            DecodeError::kTruncatedData);
}

TEST(CloudDecode, RowPaddingHonoured) {
  // 2 rows of 3 points, 8 bytes of 0xFF (NaN) padding after each row: row 1 starts at
  // row_step, not at width * point_step.
  const auto pts = somePoints(6);
  Message m = makeXYZI(pts, 2, 8);
  ASSERT_EQ(m.raw.row_step, 56u);
  Cloud out;
  DecodeStats stats;
  ASSERT_EQ(decode(m.view(), out, kMax, &stats), DecodeError::kNone);
  ASSERT_EQ(out.size(), 6u);
  for (int i = 0; i < 6; ++i) expectPoint(out[i], pts[i].x(), pts[i].y(), pts[i].z());
  EXPECT_EQ(stats.dropped_nonfinite, 0u);
}

TEST(CloudDecode, ErrorLeavesOutputEmptyAndStatsUntouched) {
  Message m = makeXYZI(somePoints(5));
  Cloud out;
  ASSERT_EQ(decode(m.view(), out), DecodeError::kNone);
  ASSERT_EQ(out.size(), 5u);
  DecodeStats stats;
  stats.total = 77;
  m.raw.fields.pop_back();
  m.raw.fields.pop_back();  // no z
  EXPECT_EQ(decode(m.view(), out, kMax, &stats), DecodeError::kMissingXYZ);
  EXPECT_TRUE(out.empty());
  EXPECT_EQ(out.width * out.height, 0u);
  EXPECT_EQ(stats.total, 77u);
}

TEST(CloudDecode, NonFiniteAndZeroPointsDroppedAndCounted) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  const std::vector<Eigen::Vector3f> pts = {
      {1, 2, 3},   {nan, 0, 0}, {0, 0, 0},  {4, 5, 6}, {1, -inf, 1},
      {0, 0, inf}, {0, 0, 0},   {0, 0, 1e-3f}, {7, 8, 9}};
  Message m = makeXYZI(pts);
  Cloud out;
  DecodeStats stats;
  ASSERT_EQ(decode(m.view(), out, kMax, &stats), DecodeError::kNone);
  EXPECT_EQ(stats.total, 9u);
  EXPECT_EQ(stats.kept, 4u);
  EXPECT_EQ(stats.dropped_nonfinite, 3u);
  EXPECT_EQ(stats.dropped_zero, 2u);
  ASSERT_EQ(out.size(), 4u);
  expectPoint(out[0], 1, 2, 3);
  expectPoint(out[1], 4, 5, 6);
  expectPoint(out[2], 0, 0, 1e-3f);  // near zero is a real return
  expectPoint(out[3], 7, 8, 9);
}

TEST(CloudDecode, ZeroTestedInTheSensorFrame) {
  // (0,0,0) in the sensor frame is "no return" even though the transform moves it; a real
  // return that lands on the target frame's origin is kept.
  const std::vector<Eigen::Vector3f> pts = {{0, 0, 0}, {-1, 0, -2}};
  Message m = makeXYZI(pts);
  const Eigen::Affine3f t(Eigen::Translation3f(1, 0, 2));
  Cloud out;
  DecodeStats stats;
  ASSERT_EQ(decodeXYZ(m.view(), t, kMax, out, &stats), DecodeError::kNone);
  EXPECT_EQ(stats.dropped_zero, 1u);
  ASSERT_EQ(out.size(), 1u);
  expectPoint(out[0], 0, 0, 0);
}

TEST(CloudDecode, TransformApplied) {
  // Sensor 1 m forward, 2 m left, 3 m up, yawed +90 deg: the sensor's +x is the target's +y.
  const Eigen::Affine3f t =
      Eigen::Translation3f(1, 2, 3) * Eigen::AngleAxisf(static_cast<float>(M_PI / 2), Eigen::Vector3f::UnitZ());
  Message m = makeXYZI({{1, 0, 0}, {0, 1, -1}, {5, 0, 0}});
  Cloud out;
  ASSERT_EQ(decodeXYZ(m.view(), t, kMax, out), DecodeError::kNone);
  ASSERT_EQ(out.size(), 3u);
  EXPECT_NEAR(out[0].x, 1.0f, 1e-5f);
  EXPECT_NEAR(out[0].y, 3.0f, 1e-5f);
  EXPECT_NEAR(out[0].z, 3.0f, 1e-5f);
  EXPECT_NEAR(out[1].x, 0.0f, 1e-5f);  // sensor +y is target -x
  EXPECT_NEAR(out[1].y, 2.0f, 1e-5f);
  EXPECT_NEAR(out[1].z, 2.0f, 1e-5f);
  EXPECT_NEAR(out[2].x, 1.0f, 1e-5f);
  EXPECT_NEAR(out[2].y, 7.0f, 1e-5f);
}

// Found by test/fuzz/cloud_decode_fuzzer.cpp: finite coordinates near FLT_MAX overflowed to inf
// in the transform and reached the pipeline. They are dropped and counted as non-finite.
TEST(CloudDecode, TransformOverflowDroppedAsNonFinite) {
  const float big = std::numeric_limits<float>::max();
  const Eigen::Affine3f t(Eigen::AngleAxisf(0.3f, Eigen::Vector3f::UnitZ()) * Eigen::Translation3f(0.3f, 0, 0.6f));
  Message m = makeXYZI({{big, big, 0}, {1, 2, 3}, {-big, big, 0}});
  Cloud out;
  DecodeStats stats;
  ASSERT_EQ(decodeXYZ(m.view(), t, kMax, out, &stats), DecodeError::kNone);
  EXPECT_EQ(stats.dropped_nonfinite, 2u);
  ASSERT_EQ(out.size(), 1u);
  for (const Point& p : out.points) EXPECT_TRUE(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z));
}

TEST(CloudDecode, CapacityReused) {
  Message big = makeXYZI(somePoints(100));
  Message small = makeXYZI(somePoints(50));
  Cloud out;
  ASSERT_EQ(decode(big.view(), out), DecodeError::kNone);
  const Point* data = out.points.data();
  const std::size_t capacity = out.points.capacity();
  ASSERT_EQ(decode(small.view(), out), DecodeError::kNone);
  EXPECT_EQ(out.size(), 50u);
  EXPECT_EQ(out.width, 50u);
  EXPECT_EQ(out.points.data(), data);
  ASSERT_EQ(decode(big.view(), out), DecodeError::kNone);
  EXPECT_EQ(out.size(), 100u);
  EXPECT_EQ(out.points.data(), data);
  EXPECT_EQ(out.points.capacity(), capacity);
  // An error keeps the buffer too.
  big.raw.is_bigendian = !hostBigEndian();
  ASSERT_EQ(decode(big.view(), out), DecodeError::kBigEndian);
  big.raw.is_bigendian = hostBigEndian();
  ASSERT_EQ(decode(big.view(), out), DecodeError::kNone);
  EXPECT_EQ(out.points.data(), data);
  EXPECT_FLOAT_EQ(out[99].x, 100.0f);
}

TEST(CloudDecode, ToStringDistinctForEveryError) {
  const DecodeError all[] = {DecodeError::kNone,         DecodeError::kEmpty,
                             DecodeError::kMissingXYZ,   DecodeError::kUnsupportedFieldType,
                             DecodeError::kBigEndian,    DecodeError::kInconsistentLayout,
                             DecodeError::kTruncatedData, DecodeError::kTooManyPoints};
  std::set<std::string> seen;
  for (const DecodeError e : all) {
    const std::string s = toString(e);
    EXPECT_FALSE(s.empty());
    seen.insert(s);
  }
  EXPECT_EQ(seen.size(), sizeof(all) / sizeof(all[0]));
}

TEST(CloudDecode, TypicalFrameTiming) {
  // ~120k points, the HDL-64E's frame: correctness check plus a printed timing.
  constexpr int kN = 120000;
  std::vector<Eigen::Vector3f> pts;
  pts.reserve(kN);
  for (int i = 0; i < kN; ++i) {
    const float a = 0.001f * i;
    pts.emplace_back(10.0f * std::cos(a), 10.0f * std::sin(a), -1.0f + 1e-5f * i);
  }
  Message m = makeXYZI(pts, 64 /* rows */);
  const Eigen::Affine3f t(Eigen::Translation3f(0, 0, 1.73f));
  Cloud out;
  ASSERT_EQ(decodeXYZ(m.view(), t, kMax, out), DecodeError::kNone);  // warm-up, allocates
  const auto t0 = std::chrono::steady_clock::now();
  constexpr int kRuns = 20;
  for (int i = 0; i < kRuns; ++i) ASSERT_EQ(decodeXYZ(m.view(), t, kMax, out), DecodeError::kNone);
  const double ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count() /
      kRuns;
  std::printf("[ timing   ] decodeXYZ of %d float32 points: %.3f ms per frame\n", kN, ms);
  ASSERT_EQ(out.size(), static_cast<std::size_t>(kN));
  EXPECT_NEAR(out[kN - 1].z, -1.0f + 1e-5f * (kN - 1) + 1.73f, 1e-4f);
}

}  // namespace
}  // namespace icanc
