#pragma once
// Inputs of the device check (scripts/device-check.sh, docs/device-check.md), as written by
// tests/device/dump_inputs.cpp on a CPU machine and read by tests/device/device_check.cpp on the
// GPU machine, which has neither MRPT nor OpenCV. Plain C++17 (standard library only).
//
// A folder (device/data/) holds:
//
//   meta.txt     one "key value..." per line ('#' starts a comment): intrinsics, poses (4x4
//                row-major doubles, T_a_b maps b into a), parameters of the stages, what the
//                CPU product computed for the same frame (reference counts and pose).
//   <name>.bin   one array each: a 64-byte BlobHeader, then count * elem_bytes bytes, images
//                dense row-major (no row padding), little-endian. Element types: ElemType.
//
// Arrays (W x H = 640 x 480 for 7-Scenes; N surfels; F frames):
//   frame<k>_depth_raw   f32 W x H      (frame 0) depth as read (m, 0 = none)
//   frame<k>_depth       f32 W x H      level-0 depth the vertex map is made from (the
//                                       product's bilateral filter applied)
//   frame0_colour        bgr8 W x H     colour registered to depth
//   frame0_vertex        vec3f W x H    the product's level-0 vertex map (camera frame)
//   frame0_normal        vec3f W x H    the product's level-0 normal map (camera frame)
//   model_index          i32 W x H      the product's model render for ICP at T_world_model
//   model_vertex         vec3f W x H      (the SSE CPU renderer; world frame; NaN x = none)
//   model_normal         vec3f W x H
//   model_visible        i32 count      surfels the CUDA splat launcher gets for that render
//                                       (SurfelRenderer::collectVisible)
//   fuse_visible         i32 count      surfels of the 4x index map at T_world_cam (fusion)
//   map_pos_conf         vec4f N        SurfelArrays of the map before frame 0 is fused
//   map_normal_radius    vec4f N
//   map_colour_flags     u32 N
//   map_t_last           f32 N
//   map_basis            vec3f N
//   map_segment          u32 N
//   map_segment_w        f32 N
//   map_view_ic          u8 N * n_view_bins

#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace rasm::device {

enum class ElemType : std::uint32_t {
  U8 = 1,
  U16 = 2,
  U32 = 3,
  I32 = 4,
  I64 = 5,
  U64 = 6,
  F32 = 7,
  F64 = 8,
  Vec3f = 9,   ///< 3 x f32 (x, y, z)
  Vec4f = 10,  ///< 4 x f32
  Bgr8 = 11,   ///< 3 x u8 (b, g, r)
};

inline std::uint32_t elemBytes(ElemType t) {
  switch (t) {
    case ElemType::U8:
      return 1;
    case ElemType::U16:
      return 2;
    case ElemType::U32:
    case ElemType::I32:
    case ElemType::F32:
      return 4;
    case ElemType::I64:
    case ElemType::U64:
    case ElemType::F64:
      return 8;
    case ElemType::Vec3f:
      return 12;
    case ElemType::Vec4f:
      return 16;
    case ElemType::Bgr8:
      return 3;
  }
  return 0;
}

struct BlobHeader {
  char magic[8] = {'R', 'A', 'S', 'M', 'D', 'E', 'V', '1'};
  std::uint32_t elem_type = 0;   ///< ElemType
  std::uint32_t elem_bytes = 0;  ///< bytes per element (checked against the reader's type)
  std::uint64_t count = 0;       ///< elements
  std::uint32_t width = 0;       ///< images: width x height == count; arrays: count x 1
  std::uint32_t height = 0;
  char reserved[32] = {};
};
static_assert(sizeof(BlobHeader) == 64, "BlobHeader is 64 bytes on disk");

/// An array as loaded: raw bytes plus its shape.
struct Blob {
  ElemType type = ElemType::U8;
  std::uint64_t count = 0;
  int width = 0, height = 0;
  std::vector<unsigned char> bytes;

  template <typename T>
  const T* as(ElemType expected) const {
    if (type != expected || sizeof(T) != elemBytes(expected))
      throw std::runtime_error("device data: element type mismatch");
    return reinterpret_cast<const T*>(bytes.data());
  }
};

inline void writeBlob(const std::string& path, ElemType type, const void* data, std::uint64_t count,
                      int width = -1, int height = 1) {
  BlobHeader h;
  h.elem_type = std::uint32_t(type);
  h.elem_bytes = elemBytes(type);
  h.count = count;
  h.width = width < 0 ? std::uint32_t(count) : std::uint32_t(width);
  h.height = std::uint32_t(height);
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) throw std::runtime_error("cannot write " + path);
  const std::size_t n = std::size_t(count) * h.elem_bytes;
  const bool ok =
      std::fwrite(&h, sizeof h, 1, f) == 1 && (n == 0 || std::fwrite(data, 1, n, f) == n);
  if (std::fclose(f) != 0 || !ok) throw std::runtime_error("short write to " + path);
}

inline Blob readBlob(const std::string& path) {
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) throw std::runtime_error("cannot read " + path + " (run scripts/device-prepare.sh)");
  BlobHeader h;
  Blob b;
  bool ok = std::fread(&h, sizeof h, 1, f) == 1 && std::memcmp(h.magic, "RASMDEV1", 8) == 0;
  if (ok) {
    b.type = ElemType(h.elem_type);
    b.count = h.count;
    b.width = int(h.width);
    b.height = int(h.height);
    ok = elemBytes(b.type) == h.elem_bytes && std::uint64_t(h.width) * h.height == h.count;
  }
  if (ok) {
    b.bytes.resize(std::size_t(h.count) * h.elem_bytes);
    ok = b.bytes.empty() || std::fread(b.bytes.data(), 1, b.bytes.size(), f) == b.bytes.size();
  }
  std::fclose(f);
  if (!ok) throw std::runtime_error(path + ": not a device-check array (bad header or short file)");
  return b;
}

/// meta.txt: "key value [value ...]" lines, kept as text.
class Meta {
 public:
  void set(const std::string& key, const std::string& value) {
    if (!m_.count(key)) order_.push_back(key);
    m_[key] = value;
  }
  void set(const std::string& key, double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.17g", v);
    set(key, std::string(buf));
  }
  void setValues(const std::string& key, const double* v, int n) {
    std::string s;
    char buf[64];
    for (int i = 0; i < n; ++i) {
      std::snprintf(buf, sizeof buf, "%s%.17g", i ? " " : "", v[i]);
      s += buf;
    }
    set(key, s);
  }
  bool has(const std::string& key) const { return m_.count(key) != 0; }
  const std::string& str(const std::string& key) const {
    auto it = m_.find(key);
    if (it == m_.end()) throw std::runtime_error("device data: meta.txt has no key '" + key + "'");
    return it->second;
  }
  double num(const std::string& key) const { return values(key, 1)[0]; }
  std::vector<double> values(const std::string& key, int n) const {
    std::istringstream in(str(key));
    std::vector<double> v;
    double x;
    while (in >> x) v.push_back(x);
    if (int(v.size()) != n)
      throw std::runtime_error("device data: meta key '" + key + "' needs " + std::to_string(n) +
                               " values");
    return v;
  }

  void write(const std::string& path, const std::string& header_comment) const {
    std::ofstream out(path);
    out << "# " << header_comment << "\n";
    for (const std::string& k : order_) out << k << " " << m_.at(k) << "\n";
    if (!out) throw std::runtime_error("cannot write " + path);
  }
  static Meta read(const std::string& path) {
    std::ifstream in(path);
    if (!in) throw std::runtime_error("cannot read " + path + " (run scripts/device-prepare.sh)");
    Meta m;
    std::string line;
    while (std::getline(in, line)) {
      if (line.empty() || line[0] == '#') continue;
      const std::size_t sp = line.find(' ');
      m.set(line.substr(0, sp), sp == std::string::npos ? std::string() : line.substr(sp + 1));
    }
    return m;
  }

 private:
  std::map<std::string, std::string> m_;
  std::vector<std::string> order_;
};

}  // namespace rasm::device
