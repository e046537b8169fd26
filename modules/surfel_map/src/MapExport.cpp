#include "rasm/surfel_map/MapExport.h"

#include <mrpt/opengl/CGridPlaneXY.h>
#include <mrpt/opengl/COpenGLScene.h>
#include <mrpt/opengl/CPointCloudColoured.h>
#include <mrpt/opengl/CSetOfObjects.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>

#include "rasm/core/Error.h"

static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__,
              "the PLY writer assumes a little-endian host");

namespace rasm::maps {

namespace {

// Property list of the PLY (order, type, name) — the reader accepts exactly this layout, or
// kPlyPropertiesUint (before segment and class became int32: Open3D's tensor reader drops uint).
const char* const kPlyProperties[] = {
    "float x",          "float y",
    "float z",          "float nx",
    "float ny",         "float nz",
    "uchar red",        "uchar green",
    "uchar blue",       "float radius",
    "float confidence", "int segment",
    "int class",        "float class_probability",
    "uchar stable",
};
const char* const kPlyPropertiesUint[] = {
    "float x",          "float y",
    "float z",          "float nx",
    "float ny",         "float nz",
    "uchar red",        "uchar green",
    "uchar blue",       "float radius",
    "float confidence", "uint segment",
    "uchar class",      "float class_probability",
    "uchar stable",
};
constexpr std::size_t kPlyPropertyCount = sizeof(kPlyProperties) / sizeof(kPlyProperties[0]);
constexpr std::size_t kPlyRecordBytes = 6 * 4 + 3 + 4 + 4 + 4 + 4 + 4 + 1;
constexpr std::size_t kPlyRecordBytesUint = 6 * 4 + 3 + 4 + 4 + 4 + 1 + 4 + 1;

template <typename T>
void put(char*& p, const T& v) {
  std::memcpy(p, &v, sizeof(T));
  p += sizeof(T);
}
template <typename T>
T get(const char*& p) {
  T v;
  std::memcpy(&v, p, sizeof(T));
  p += sizeof(T);
  return v;
}

bool selected(const SurfelArrays& a, int i, bool stable_only, float min_conf) {
  return (!stable_only || a.stable(i)) && a.confidence(i) >= min_conf;
}

Bgr8 visualColour(const SurfelArrays& a, int i, SurfelColouring mode, float max_conf) {
  switch (mode) {
    case SurfelColouring::Segment:
      return labelColour(a.segment[i]);
    case SurfelColouring::Class:
      return classColour(bestClass(a, i));
    case SurfelColouring::Confidence: {
      const float t = std::min(1.0f, a.confidence(i) / std::max(max_conf, 1e-6f));
      return Bgr8{std::uint8_t(255 * (1 - t)), 0, std::uint8_t(255 * t)};
    }
    case SurfelColouring::Stability:
      return a.stable(i) ? Bgr8{0, 200, 0} : Bgr8{0, 0, 220};
    case SurfelColouring::Rgb:
    default:
      return a.colour(i);
  }
}

}  // namespace

Bgr8 classColour(const BestClass& b) {
  // The class's colour, faded towards the "none" grey as p falls to the 0.5 prior.
  const Bgr8 c = labelColour(b.id), g = labelColour(0);
  const float t = std::min(1.0f, std::max(0.0f, 2.0f * (b.probability - 0.5f)));
  const auto mix = [t](std::uint8_t x, std::uint8_t y) {
    return std::uint8_t(float(y) + t * (float(x) - float(y)) + 0.5f);
  };
  return Bgr8{mix(c.b, g.b), mix(c.g, g.g), mix(c.r, g.r)};
}

BestClass bestClass(const SurfelArrays& a, int i) {
  return a.n_classes > 0 ? bestClass(a.classEvidence(i)) : BestClass{};
}

Bgr8 labelColour(long long label) {
  if (label <= 0) return Bgr8{128, 128, 128};
  // Golden-ratio hue walk: neighbouring labels get well separated hues.
  const double h = std::fmod(double(label) * 0.618033988749895, 1.0) * 6.0;
  const int sector = int(h);
  const double f = h - sector;
  const double v = 0.95, s = 0.75;
  const double p = v * (1 - s), q = v * (1 - s * f), t = v * (1 - s * (1 - f));
  double r = v, g = t, b = p;
  switch (sector) {
    case 1:
      r = q;
      g = v;
      b = p;
      break;
    case 2:
      r = p;
      g = v;
      b = t;
      break;
    case 3:
      r = p;
      g = q;
      b = v;
      break;
    case 4:
      r = t;
      g = p;
      b = v;
      break;
    case 5:
      r = v;
      g = p;
      b = q;
      break;
    default:
      break;
  }
  return Bgr8{std::uint8_t(255 * b), std::uint8_t(255 * g), std::uint8_t(255 * r)};
}

void writeSurfelPly(const SurfelStore& map, const std::string& path, bool stable_only,
                    SurfelColouring colouring) {
  const SurfelArrays a = map.arrays();
  std::vector<int> ids;
  ids.reserve(a.size);
  for (int i = 0; i < a.size; ++i)
    if (selected(a, i, stable_only, 0.0f)) ids.push_back(i);

  std::ofstream f(path, std::ios::binary);
  if (!f) throwInputError("PLY file " + path, "cannot be opened for writing");
  f << "ply\nformat binary_little_endian 1.0\ncomment rasm surfel map (II-A attributes)\n"
    << "element vertex " << ids.size() << "\n";
  for (const char* p : kPlyProperties) f << "property " << p << "\n";
  f << "end_header\n";

  float max_conf = 0.0f;  // (visualColour's scale for the confidence colouring)
  if (colouring == SurfelColouring::Confidence)
    for (int i : ids) max_conf = std::max(max_conf, a.confidence(i));
  std::vector<char> buf(kPlyRecordBytes * std::min<std::size_t>(ids.size(), 65536));
  std::size_t k = 0;
  while (k < ids.size()) {
    const std::size_t n = std::min<std::size_t>(ids.size() - k, 65536);
    char* p = buf.data();
    for (std::size_t j = 0; j < n; ++j) {
      const int i = ids[k + j];
      const Vec4f pc = a.pos_conf[i], nr = a.normal_radius[i];
      const Bgr8 c =
          colouring == SurfelColouring::Rgb ? a.colour(i) : visualColour(a, i, colouring, max_conf);
      put(p, pc.x());
      put(p, pc.y());
      put(p, pc.z());
      put(p, nr.x());
      put(p, nr.y());
      put(p, nr.z());
      put(p, c.r);
      put(p, c.g);
      put(p, c.b);
      put(p, nr.w());
      put(p, pc.w());
      put(p, std::int32_t(a.segment[i]));
      const BestClass b = bestClass(a, i);
      put(p, std::int32_t(b.id));
      put(p, b.probability);
      put(p, std::uint8_t(a.stable(i) ? 1 : 0));
    }
    f.write(buf.data(), std::streamsize(n * kPlyRecordBytes));
    k += n;
  }
  f.close();  // the last buffer is flushed here: a full disk may show only now
  if (!f) throwInputError("PLY file " + path, "write failed (disk full?)");
}

PlySurfels readSurfelPly(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  const std::string what = "PLY file " + path;
  if (!f) throwInputError(what, "cannot be opened");
  std::string line;
  std::getline(f, line);
  if (line != "ply") throwInputError(what, "not a PLY file (first line '" + line + "')");
  std::size_t n = 0;
  std::vector<std::string> props;
  bool format_ok = false;
  while (std::getline(f, line)) {
    if (line == "end_header") break;
    std::istringstream s(line);
    std::string kw;
    s >> kw;
    if (kw == "format") {
      std::string fmt;
      s >> fmt;
      format_ok = fmt == "binary_little_endian";
    } else if (kw == "element") {
      std::string name;
      s >> name >> n;
      if (name != "vertex") throwInputError(what, "unexpected element '" + name + "'");
    } else if (kw == "property") {
      props.push_back(line.substr(9));
    }
  }
  if (!format_ok) throwInputError(what, "expected format binary_little_endian");
  if (props.size() != kPlyPropertyCount)
    throwInputError(what, "expected the rasm surfel property layout (MapExport.h)");
  // The earlier layout (uint segment, uchar class) is told by its segment property.
  const bool uint_ids = props[11] == kPlyPropertiesUint[11];
  const char* const* expected = uint_ids ? kPlyPropertiesUint : kPlyProperties;
  for (std::size_t i = 0; i < kPlyPropertyCount; ++i)
    if (props[i] != expected[i])
      throwInputError(what, "property " + std::to_string(i) + " is '" + props[i] + "', expected '" +
                                expected[i] + "'");
  const std::size_t record_bytes = uint_ids ? kPlyRecordBytesUint : kPlyRecordBytes;
  // The header's count is checked against the bytes the file holds before anything is allocated
  // (a corrupt count must be an error, not a huge allocation).
  const std::streamoff data_start = f.tellg();
  f.seekg(0, std::ios::end);
  const std::streamoff file_end = f.tellg();
  f.seekg(data_start);
  const std::size_t available = data_start >= 0 && file_end >= data_start
                                    ? std::size_t(file_end - data_start)
                                    : std::size_t(0);
  if (n > available / record_bytes)
    throwInputError(what, "truncated or corrupt: the header says " + std::to_string(n) +
                              " vertices of " + std::to_string(record_bytes) +
                              " bytes, the file holds " + std::to_string(available) +
                              " bytes after its header");
  std::vector<char> buf(n * record_bytes);
  f.read(buf.data(), std::streamsize(buf.size()));
  if (std::size_t(f.gcount()) != buf.size())
    throwInputError(what, "truncated: expected " + std::to_string(n) + " vertices");
  PlySurfels out;
  out.position.resize(n);
  out.normal.resize(n);
  out.colour.resize(n);
  out.radius.resize(n);
  out.confidence.resize(n);
  out.segment.resize(n);
  out.class_id.resize(n);
  out.class_probability.resize(n);
  out.stable.resize(n);
  const char* p = buf.data();
  for (std::size_t i = 0; i < n; ++i) {
    const float x = get<float>(p), y = get<float>(p), z = get<float>(p);
    const float nx = get<float>(p), ny = get<float>(p), nz = get<float>(p);
    out.position[i] = Vec3f(x, y, z);
    out.normal[i] = Vec3f(nx, ny, nz);
    const std::uint8_t r = get<std::uint8_t>(p), g = get<std::uint8_t>(p), b = get<std::uint8_t>(p);
    out.colour[i] = Bgr8{b, g, r};
    out.radius[i] = get<float>(p);
    out.confidence[i] = get<float>(p);
    if (uint_ids) {
      out.segment[i] = get<std::uint32_t>(p);
      out.class_id[i] = get<std::uint8_t>(p);
    } else {
      out.segment[i] = std::uint32_t(get<std::int32_t>(p));
      out.class_id[i] = get<std::int32_t>(p);
    }
    out.class_probability[i] = get<float>(p);
    out.stable[i] = get<std::uint8_t>(p);
  }
  return out;
}

void surfelsToOpenGL(const SurfelStore& map, const SurfelVisualOptions& opt,
                     mrpt::opengl::CSetOfObjects& o) {
  const SurfelArrays a = map.arrays();
  auto cloud = mrpt::opengl::CPointCloudColoured::Create();
  cloud->setName("rasm_surfels");
  cloud->setPointSize(opt.point_size);
  cloud->reserve(a.size);
  float max_conf = 0.0f;
  for (int i = 0; i < a.size; ++i) max_conf = std::max(max_conf, a.confidence(i));
  for (int i = 0; i < a.size; ++i) {
    if (!selected(a, i, opt.stable_only, opt.min_confidence)) continue;
    const Vec3f p = a.position(i);
    const Bgr8 c = visualColour(a, i, opt.colouring, max_conf);
    cloud->push_back(p.x(), p.y(), p.z(), c.r / 255.0f, c.g / 255.0f, c.b / 255.0f);
  }
  o.insert(cloud);
}

std::shared_ptr<mrpt::opengl::COpenGLScene> surfelScene(const SurfelStore& map,
                                                        const SurfelVisualOptions& opt) {
  auto scene = std::make_shared<mrpt::opengl::COpenGLScene>();
  auto objs = mrpt::opengl::CSetOfObjects::Create();
  surfelsToOpenGL(map, opt, *objs);
  scene->insert(mrpt::opengl::CGridPlaneXY::Create(-10, 10, -10, 10, 0, 1));
  scene->insert(objs);
  return scene;
}

void writeSurfelScene(const SurfelStore& map, const std::string& path,
                      const SurfelVisualOptions& opt) {
  if (!surfelScene(map, opt)->saveToFile(path))
    throwInputError(".3Dscene file " + path, "cannot be written");
}

}  // namespace rasm::maps
