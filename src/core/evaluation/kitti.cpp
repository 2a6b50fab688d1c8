#include "icanc/core/evaluation/kitti.hpp"

#include "icanc/core/perception/box.hpp"

#include <lzma.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include <Eigen/SVD>

namespace icanc {
namespace kitti {
namespace {

constexpr std::size_t kBytesPerPoint = 16;  // 4 x float32

[[noreturn]] void fail(const std::string& path, const std::string& what) {
  throw std::runtime_error("KITTI: " + path + ": " + what);
}

bool endsWith(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() &&
         s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

// Reads the whole file into `buf` (resized, capacity kept between calls).
void slurp(const std::string& path, std::vector<std::uint8_t>& buf) {
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  if (!in) fail(path, std::string("cannot open (") + std::strerror(errno) + ")");
  const std::streamoff size = in.tellg();
  if (size < 0) fail(path, "cannot determine file size");
  buf.resize(static_cast<std::size_t>(size));
  in.seekg(0);
  if (size > 0 && !in.read(reinterpret_cast<char*>(buf.data()), size)) fail(path, "read error");
}

const char* lzmaMessage(lzma_ret r) {
  switch (r) {
    case LZMA_MEM_ERROR: return "out of memory";
    case LZMA_MEMLIMIT_ERROR: return "memory limit reached";
    case LZMA_FORMAT_ERROR: return "not an xz stream";
    case LZMA_OPTIONS_ERROR: return "unsupported xz options";
    case LZMA_DATA_ERROR: return "corrupt xz data";
    case LZMA_BUF_ERROR: return "truncated xz stream";
    case LZMA_UNSUPPORTED_CHECK: return "unsupported xz integrity check";
    default: return "xz decoder error";
  }
}

// Decompresses an in-memory .xz file into `out` (resized; its capacity is reused across calls).
void unxz(const std::string& path, const std::vector<std::uint8_t>& in,
          std::vector<std::uint8_t>& out) {
  lzma_stream strm = LZMA_STREAM_INIT;
  lzma_ret r = lzma_stream_decoder(&strm, UINT64_MAX, LZMA_CONCATENATED);
  if (r != LZMA_OK) fail(path, std::string("cannot start xz decoder: ") + lzmaMessage(r));

  // A velodyne .bin compresses about 2.5:1; start from the reused capacity or a guess.
  out.resize(std::max<std::size_t>({out.capacity(), in.size() * 4, 1 << 16}));
  strm.next_in = in.data();
  strm.avail_in = in.size();
  strm.next_out = out.data();
  strm.avail_out = out.size();
  for (;;) {
    r = lzma_code(&strm, LZMA_FINISH);
    if (r == LZMA_STREAM_END) break;
    if (r != LZMA_OK) {
      lzma_end(&strm);
      fail(path, lzmaMessage(r));
    }
    if (strm.avail_out == 0) {
      const std::size_t used = out.size();
      out.resize(used * 2);
      strm.next_out = out.data() + used;
      strm.avail_out = out.size() - used;
    }
  }
  out.resize(static_cast<std::size_t>(strm.total_out));
  lzma_end(&strm);
}

float loadLittleEndianFloat(const std::uint8_t* p) {
  std::uint32_t u = static_cast<std::uint32_t>(p[0]) | (static_cast<std::uint32_t>(p[1]) << 8) |
                    (static_cast<std::uint32_t>(p[2]) << 16) |
                    (static_cast<std::uint32_t>(p[3]) << 24);
  float f;
  std::memcpy(&f, &u, sizeof f);
  return f;
}

// Strict number parsing: the whole token must be consumed.
bool parseDouble(const std::string& tok, double& v) {
  if (tok.empty()) return false;
  errno = 0;
  char* end = nullptr;
  v = std::strtod(tok.c_str(), &end);
  return end == tok.c_str() + tok.size() && errno != ERANGE;
}

bool parseInt(const std::string& tok, int& v) {
  if (tok.empty()) return false;
  errno = 0;
  char* end = nullptr;
  const long l = std::strtol(tok.c_str(), &end, 10);
  if (end != tok.c_str() + tok.size() || errno == ERANGE || l < INT32_MIN || l > INT32_MAX)
    return false;
  v = static_cast<int>(l);
  return true;
}

std::vector<std::string> splitWhitespace(const std::string& line) {
  std::vector<std::string> toks;
  std::istringstream ss(line);
  std::string t;
  while (ss >> t) toks.push_back(t);
  return toks;
}

// Nearest rotation (SVD projection) to a calibration matrix that is only orthonormal to ~1e-4.
Eigen::Matrix3d nearestRotation(const Eigen::Matrix3d& m) {
  Eigen::JacobiSVD<Eigen::Matrix3d> svd(m, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d d = Eigen::Matrix3d::Identity();
  d(2, 2) = (svd.matrixU() * svd.matrixV().transpose()).determinant() < 0 ? -1.0 : 1.0;
  return svd.matrixU() * d * svd.matrixV().transpose();
}

}  // namespace

std::string velodynePath(const std::string& dir, int frame) {
  char name[64];
  std::snprintf(name, sizeof(name), "/velodyne/%06d.bin", frame);
  const std::string bin = dir + name;
  return std::ifstream(bin).good() ? bin : bin + ".xz";
}

void readVelodyne(const std::string& path, Cloud& out) {
  // Buffers reused across calls on the same thread (a sequence is read frame after frame).
  thread_local std::vector<std::uint8_t> file_buf;
  thread_local std::vector<std::uint8_t> raw_buf;

  slurp(path, file_buf);
  const std::vector<std::uint8_t>* raw = &file_buf;
  if (endsWith(path, ".xz")) {
    unxz(path, file_buf, raw_buf);
    raw = &raw_buf;
  }
  const std::size_t bytes = raw->size();
  if (bytes % kBytesPerPoint != 0) {
    fail(path, "size " + std::to_string(bytes) + " bytes is not a multiple of 16 (x y z intensity float32)");
  }
  const std::size_t n = bytes / kBytesPerPoint;
  out.resize(n);  // also sets width = n, height = 1
  const std::uint8_t* p = raw->data();
  for (std::size_t i = 0; i < n; ++i, p += kBytesPerPoint) {
    Point& q = out.points[i];
    q.x = loadLittleEndianFloat(p);
    q.y = loadLittleEndianFloat(p + 4);
    q.z = loadLittleEndianFloat(p + 8);
  }
  out.width = static_cast<std::uint32_t>(n);
  out.height = 1;
  out.is_dense = false;  // a trailing all-zero point is kept; the decoder drops it
}

Eigen::Isometry3d Calib::veloToCamRect() const {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() = nearestRotation(r0_rect * tr_velo_to_cam.leftCols<3>());
  t.translation() = r0_rect * tr_velo_to_cam.col(3);
  return t;
}

Eigen::Isometry3d Calib::camRectToVelo() const { return veloToCamRect().inverse(); }

Calib readCalib(const std::string& path) {
  std::ifstream in(path);
  if (!in) fail(path, std::string("cannot open (") + std::strerror(errno) + ")");
  Calib c;
  bool have_r0 = false, have_tr = false;
  std::string line;
  int line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    std::vector<std::string> toks = splitWhitespace(line);
    if (toks.empty()) continue;
    std::string key = toks[0];
    if (!key.empty() && key.back() == ':') key.pop_back();
    std::size_t want = 0;
    if (key == "R0_rect" || key == "R_rect") want = 9;
    else if (key == "Tr_velo_to_cam" || key == "Tr_velo_cam") want = 12;
    else continue;  // P0..P3, Tr_imu_to_velo, ... are not needed
    if (toks.size() != want + 1) {
      fail(path, "line " + std::to_string(line_no) + ": " + key + " needs " +
                     std::to_string(want) + " numbers, got " + std::to_string(toks.size() - 1));
    }
    std::vector<double> v(want);
    for (std::size_t i = 0; i < want; ++i) {
      if (!parseDouble(toks[i + 1], v[i])) {
        fail(path, "line " + std::to_string(line_no) + ": bad number '" + toks[i + 1] + "'");
      }
    }
    if (want == 9) {
      for (int r = 0; r < 3; ++r)
        for (int k = 0; k < 3; ++k) c.r0_rect(r, k) = v[3 * r + k];
      have_r0 = true;
    } else {
      for (int r = 0; r < 3; ++r)
        for (int k = 0; k < 4; ++k) c.tr_velo_to_cam(r, k) = v[4 * r + k];
      have_tr = true;
    }
  }
  if (!have_r0) fail(path, "no R0_rect / R_rect entry");
  if (!have_tr) fail(path, "no Tr_velo_to_cam / Tr_velo_cam entry");
  return c;
}

std::vector<Label> readLabels(const std::string& path) {
  std::ifstream in(path);
  if (!in) fail(path, std::string("cannot open (") + std::strerror(errno) + ")");
  std::vector<Label> labels;
  std::string line;
  int line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    const std::vector<std::string> t = splitWhitespace(line);
    if (t.empty()) continue;
    const std::string where = "line " + std::to_string(line_no) + ": ";
    if (t.size() != 17 && t.size() != 18) {
      fail(path, where + "expected 17 fields (18 with score), got " + std::to_string(t.size()));
    }
    Label l;
    double d[11];  // alpha, bbox x4, h w l, x y z  -> indices 5..15 ; rotation_y at 16
    bool ok = parseInt(t[0], l.frame) && parseInt(t[1], l.track_id) &&
              parseInt(t[3], l.truncated) && parseInt(t[4], l.occluded);
    for (int i = 0; ok && i < 11; ++i) ok = parseDouble(t[5 + i], d[i]);
    ok = ok && parseDouble(t[16], l.rotation_y);
    double score = 0;
    if (ok && t.size() == 18) ok = parseDouble(t[17], score);
    if (!ok) fail(path, where + "malformed field in '" + line + "'");
    l.type = t[2];
    l.h = d[5];
    l.w = d[6];
    l.l = d[7];
    l.bottom_center_cam = Eigen::Vector3d(d[8], d[9], d[10]);
    labels.push_back(std::move(l));
  }
  return labels;
}

std::vector<VeloBox> toVelodyne(const std::vector<Label>& labels, const Calib& calib) {
  const Eigen::Isometry3d cam_to_velo = calib.camRectToVelo();
  std::vector<VeloBox> boxes;
  boxes.reserve(labels.size());
  for (const Label& l : labels) {
    if (l.type == "DontCare") continue;
    VeloBox b;
    b.frame = l.frame;
    b.track_id = l.track_id;
    b.type = l.type;
    // Camera y points down: the centre is h/2 above the bottom centre.
    const Eigen::Vector3d center_cam = l.bottom_center_cam + Eigen::Vector3d(0.0, -0.5 * l.h, 0.0);
    b.center = cam_to_velo * center_cam;
    b.size = Eigen::Vector3d(l.l, l.w, l.h);
    // rotation_y is about camera +y: heading = R_y(ry) * (1, 0, 0) = (cos ry, 0, -sin ry).
    const Eigen::Vector3d heading_cam(std::cos(l.rotation_y), 0.0, -std::sin(l.rotation_y));
    const Eigen::Vector3d heading_velo = cam_to_velo.linear() * heading_cam;
    b.yaw = std::atan2(heading_velo.y(), heading_velo.x());
    boxes.push_back(std::move(b));
  }
  return boxes;
}

bool contains(const VeloBox& box, const Eigen::Vector3d& p, double margin_m) {
  return orientedBoxContains(box.center, box.size, box.yaw, p, margin_m);
}

}  // namespace kitti
}  // namespace icanc
