#include "rasm/surfel_map/CSurfelMap.h"

#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/opengl/CSetOfObjects.h>
#include <mrpt/poses/CPose3D.h>
#include <mrpt/rtti/CObject.h>
#include <mrpt/serialization/CArchive.h>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "rasm/core/Error.h"
#include "rasm/core/Params.h"
#include "rasm/core/SE3.h"
#include "rasm/io/RgbdObservation.h"
#include "rasm/surfel_map/SurfelFrameInserter.h"
#include "rasm/surfel_map/SurfelRenderer.h"

using rasm::maps::CSurfelMap;

//  ---- map definition (INI creation through TSetOfMetricMapInitializers) ----
MAP_DEFINITION_REGISTER("rasm::maps::CSurfelMap,surfelMap", rasm::maps::CSurfelMap)

IMPLEMENTS_SERIALIZABLE(CSurfelMap, CMetricMap, rasm::maps)

// Registered by a dynamic initializer defined after runtimeClassId, not by MRPT_INITIALIZER:
// runtimeClassId holds a std::function, so it is itself dynamically initialized unless the
// compiler folds it into constant data (GCC at -O2 does, clang does not), and an MRPT_INITIALIZER
// (__attribute__((constructor))) may run before it and register a class without a name ("class
// 'rasm::maps::CSurfelMap' is not registered" when a map is read). Initializers of one
// translation unit run in the order they are defined.
[[maybe_unused]] static const bool rasm_surfel_map_class_registered =
    (mrpt::rtti::registerClass(CLASS_ID(rasm::maps::CSurfelMap)), true);

namespace rasm::maps {

namespace {

const char* colouringName(SurfelColouring c) {
  switch (c) {
    case SurfelColouring::Segment:
      return "segment";
    case SurfelColouring::Class:
      return "class";
    case SurfelColouring::Confidence:
      return "confidence";
    case SurfelColouring::Stability:
      return "stability";
    case SurfelColouring::Rgb:
    default:
      return "rgb";
  }
}

}  // namespace

// ---- options ----

SurfelStoreOptions CSurfelMap::TCreationOptions::toStoreOptions() const {
  SurfelStoreOptions o;
  o.n_classes = n_classes;
  o.view_bins_azimuth = view_bins_azimuth;
  o.view_bins_elevation = view_bins_elevation;
  o.block_size_m = float(block_size_m);
  return o;
}

void CSurfelMap::TCreationOptions::loadFromConfigFile(const mrpt::config::CConfigFileBase& c,
                                                      const std::string& s) {
  MRPT_LOAD_CONFIG_VAR(n_classes, int, c, s);
  MRPT_LOAD_CONFIG_VAR(view_bins_azimuth, int, c, s);
  MRPT_LOAD_CONFIG_VAR(view_bins_elevation, int, c, s);
  MRPT_LOAD_CONFIG_VAR(block_size_m, double, c, s);
  requireInRange(n_classes, 0, kMaxClassId, s, "n_classes");
  requireInRange(view_bins_azimuth, 0, 256, s, "view_bins_azimuth");
  requireInRange(view_bins_elevation, 0, 64, s, "view_bins_elevation");
  requireInRange(block_size_m, 0.01, 100.0, s, "block_size_m");
}

void CSurfelMap::TCreationOptions::saveToConfigFile(mrpt::config::CConfigFileBase& c,
                                                    const std::string& s) const {
  c.write(s, "n_classes", n_classes);
  c.write(s, "view_bins_azimuth", view_bins_azimuth);
  c.write(s, "view_bins_elevation", view_bins_elevation);
  c.write(s, "block_size_m", block_size_m);
}

std::string CSurfelMap::TInsertionOptions::fusionIniText() const {
  std::ostringstream s;
  s << "[fusion]\n";
  for (const auto& kv : fusion_keys) s << kv.first << " = " << kv.second << "\n";
  return s.str();
}

void CSurfelMap::TInsertionOptions::loadFromConfigFile(const mrpt::config::CConfigFileBase& c,
                                                       const std::string& s) {
  std::vector<std::string> keys;
  c.getAllKeys(s, keys);
  std::sort(keys.begin(), keys.end());
  fusion_keys.clear();
  for (const auto& k : keys) fusion_keys.emplace_back(k, c.read_string(s, k, ""));
  source = "[" + s + "]";
}

void CSurfelMap::TInsertionOptions::saveToConfigFile(mrpt::config::CConfigFileBase& c,
                                                     const std::string& s) const {
  for (const auto& kv : fusion_keys) c.write(s, kv.first, kv.second);
}

void CSurfelMap::TLikelihoodOptions::loadFromConfigFile(const mrpt::config::CConfigFileBase& c,
                                                        const std::string& s) {
  MRPT_LOAD_CONFIG_VAR(sigma_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(decimation, int, c, s);
  MRPT_LOAD_CONFIG_VAR(max_depth_m, double, c, s);
  requireInRange(sigma_m, 1e-4, 10.0, s, "sigma_m");
  requireInRange(decimation, 1, 64, s, "decimation");
  requireInRange(max_depth_m, 0.1, 100.0, s, "max_depth_m");
}

void CSurfelMap::TLikelihoodOptions::saveToConfigFile(mrpt::config::CConfigFileBase& c,
                                                      const std::string& s) const {
  c.write(s, "sigma_m", sigma_m);
  c.write(s, "decimation", decimation);
  c.write(s, "max_depth_m", max_depth_m);
}

void CSurfelMap::TRenderingOptions::loadFromConfigFile(const mrpt::config::CConfigFileBase& c,
                                                       const std::string& s) {
  const std::string col = c.read_string(s, "colouring", colouringName(visual.colouring));
  bool found = false;
  for (int i = 0; i <= int(SurfelColouring::Stability); ++i)
    if (col == colouringName(SurfelColouring(i))) {
      visual.colouring = SurfelColouring(i);
      found = true;
    }
  if (!found)
    throwInputError("[" + s + "] colouring",
                    "'" + col + "', expected rgb, segment, class, confidence or stability");
  visual.point_size = c.read_float(s, "point_size", visual.point_size);
  visual.stable_only = c.read_bool(s, "stable_only", visual.stable_only);
  visual.min_confidence = c.read_float(s, "min_confidence", visual.min_confidence);
  requireInRange(visual.point_size, 0.1, 100.0, s, "point_size");
}

void CSurfelMap::TRenderingOptions::saveToConfigFile(mrpt::config::CConfigFileBase& c,
                                                     const std::string& s) const {
  c.write(s, "colouring", std::string(colouringName(visual.colouring)));
  c.write(s, "point_size", visual.point_size);
  c.write(s, "stable_only", visual.stable_only);
  c.write(s, "min_confidence", visual.min_confidence);
}

// ---- map definition ----

CSurfelMap::TMapDefinition::TMapDefinition() = default;

void CSurfelMap::TMapDefinition::loadFromConfigFile_map_specific(
    const mrpt::config::CConfigFileBase& source, const std::string& prefix) {
  // Strict: unknown keys in the creation / likelihood / rendering sections are errors. The
  // insertion section holds [fusion] keys, checked when the inserter parses them.
  const std::string what = "map definition " + prefix;
  loadParamsStrict(source, prefix + "_creationOpts", creationOpts, what);
  insertionOpts.loadFromConfigFile(source, prefix + "_insertOpts");
  loadParamsStrict(source, prefix + "_likelihoodOpts", likelihoodOpts, what);
  loadParamsStrict(source, prefix + "_renderOpts", renderOpts, what);
}

void CSurfelMap::TMapDefinition::dumpToTextStream_map_specific(std::ostream& out) const {
  creationOpts.dumpToTextStream(out);
  insertionOpts.dumpToTextStream(out);
  likelihoodOpts.dumpToTextStream(out);
  renderOpts.dumpToTextStream(out);
}

mrpt::maps::CMetricMap* CSurfelMap::internal_CreateFromMapDefinition(
    const mrpt::maps::TMetricMapInitializer& _def) {
  const auto& def = dynamic_cast<const CSurfelMap::TMapDefinition&>(_def);
  auto* m = new CSurfelMap(def.creationOpts);
  m->insertionOptions = def.insertionOpts;
  m->likelihoodOptions = def.likelihoodOpts;
  m->renderingOptions = def.renderOpts;
  return m;
}

// ---- construction ----

CSurfelMap::CSurfelMap() : CSurfelMap(TCreationOptions()) {}

CSurfelMap::CSurfelMap(const TCreationOptions& creation)
    : m_creation(creation), m_store(creation.toStoreOptions()) {}

CSurfelMap::CSurfelMap(const CSurfelMap& o)
    : mrpt::maps::CMetricMap(o),
      insertionOptions(o.insertionOptions),
      likelihoodOptions(o.likelihoodOptions),
      renderingOptions(o.renderingOptions),
      m_creation(o.m_creation),
      m_store(o.m_store),
      m_keyframes(o.m_keyframes),
      m_classes(o.m_classes) {}

CSurfelMap& CSurfelMap::operator=(const CSurfelMap& o) {
  if (this == &o) return *this;
  mrpt::maps::CMetricMap::operator=(o);
  insertionOptions = o.insertionOptions;
  likelihoodOptions = o.likelihoodOptions;
  renderingOptions = o.renderingOptions;
  m_creation = o.m_creation;
  m_store = o.m_store;
  m_keyframes = o.m_keyframes;
  m_classes = o.m_classes;
  m_inserter.reset();
  return *this;
}

CSurfelMap::~CSurfelMap() = default;

void CSurfelMap::resetLayout(const TCreationOptions& creation) {
  m_creation = creation;
  m_store.reset(creation.toStoreOptions());
  m_inserter.reset();
}

void CSurfelMap::internal_clear() {
  m_store.clear();
  m_keyframes.clear();
  m_inserter.reset();  // fusion state (renderer buffers) refers to the old map
}

// ---- serialization ----
// Version 0: creation options, insertion keys, likelihood and rendering options, generic map
// params, time origin, then every SoA array (little-endian floats / raw bytes).
// Version 1: version 0, then the relocalisation keyframes (writeKeyframes).
// Version 2: version 1 with the class evidence as log-odds slots (ClassEvidence.h) instead of
// n_classes u8 linear probabilities per surfel: per surfel 4 class ids (u8) then 4 log-odds
// (int16 little-endian, 1/1024 nat), n_classes <= 255. Versions 0 and 1 still load: old class
// index c becomes class id c + 1 (id 0 is "no class" now), each p != the stored 0.5 prior (u8
// 128) becomes L = logit(p) clamped to +-7 nats, and the classes of highest rank (positive L
// first, then |L|) fill the 4 slots (convertLinearClassRow): the best class is kept. A version-0
// map has no keyframes.
// Version 3: version 2, then the class list (classes()): count, then name and source per class.
// Older maps load with an empty list (their ids follow the default: COCO 1..80, then rasm's).

namespace {

// Bounds on what a keyframe record may declare, so a corrupt file fails with a message instead
// of a huge allocation.
constexpr uint32_t kMaxKeyframeFeatures = 1u << 20;
constexpr int32_t kMaxThumbnailSide = 4096;
/// Sanity caps of a map read back: surfel count (the store indexes surfels with int) and the
/// extent of surfel positions (voxel block coordinates are ints).
constexpr uint64_t kMaxSerializedSurfels = 1u << 28;
constexpr float kMaxSurfelCoordinateM = 1e5f;
/// Longest fusion key, value or class name read back (they are a few dozen characters).
constexpr uint32_t kMaxSerializedString = 1u << 16;
/// At most this many fusion keys (the [fusion] section has about thirty).
constexpr uint32_t kMaxFusionKeys = 4096;

/// A std::string as MRPT's CArchive writes it (uint32 length, then the bytes), refusing a length
/// over kMaxSerializedString: MRPT's own operator>> would allocate whatever a corrupt length says.
std::string readBoundedString(mrpt::serialization::CArchive& in, const std::string& what) {
  uint32_t n;
  in >> n;
  if (n > kMaxSerializedString)
    throwInputError(what, "string of " + std::to_string(n) +
                              " bytes (corrupt file?), expected at most " +
                              std::to_string(kMaxSerializedString));
  std::string s(n, '\0');
  if (n > 0) in.ReadBuffer(s.data(), n);
  return s;
}
// The per-feature arrays are written as flat float buffers.
static_assert(sizeof(Eigen::Vector3f) == 3 * sizeof(float) &&
              sizeof(Eigen::Vector2f) == 2 * sizeof(float));

// Per keyframe: frame index, timestamp, T_world_cam (3x4, row-major doubles), intrinsics
// (fx fy cx cy, width height), feature count n, 3n floats of points, 2n floats of keypoints,
// 32n descriptor bytes, thumbnail width, height and bytes.
void writeKeyframes(mrpt::serialization::CArchive& out, const std::vector<Keyframe>& kfs) {
  out << uint32_t(kfs.size());
  for (std::size_t k = 0; k < kfs.size(); ++k) {
    const Keyframe& kf = kfs[k];
    if (!kf.consistent())
      throw std::logic_error("CSurfelMap::serializeTo: keyframe " + std::to_string(k) +
                             " has per-feature arrays of different lengths");
    out << uint64_t(kf.frame_index) << kf.timestamp_s;
    const Eigen::Matrix4d& M = kf.T_world_cam.matrix();
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 4; ++c) out << M(r, c);
    out << kf.intrinsics.fx << kf.intrinsics.fy << kf.intrinsics.cx << kf.intrinsics.cy
        << int32_t(kf.intrinsics.width) << int32_t(kf.intrinsics.height);
    const std::size_t n = kf.numFeatures();
    out << uint32_t(n);
    if (n > 0) {
      out.WriteBufferFixEndianness(kf.points_world.front().data(), 3 * n);
      out.WriteBufferFixEndianness(kf.keypoints_px.front().data(), 2 * n);
      out.WriteBuffer(kf.descriptors.data(), kf.descriptors.size());
    }
    out << int32_t(kf.thumb_width) << int32_t(kf.thumb_height);
    if (!kf.thumbnail.empty()) out.WriteBuffer(kf.thumbnail.data(), kf.thumbnail.size());
  }
}

void readKeyframes(mrpt::serialization::CArchive& in, std::vector<Keyframe>& kfs) {
  uint32_t count;
  in >> count;
  kfs.clear();
  kfs.reserve(std::min<uint32_t>(count, 1u << 16));
  for (uint32_t k = 0; k < count; ++k) {
    const std::string what = "CSurfelMap keyframe " + std::to_string(k);
    Keyframe kf;
    uint64_t index;
    in >> index >> kf.timestamp_s;
    kf.frame_index = index;
    Eigen::Matrix4d M = Eigen::Matrix4d::Identity();
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 4; ++c) in >> M(r, c);
    if (!M.allFinite() || !std::isfinite(kf.timestamp_s))
      throwInputError(what, "non-finite pose or timestamp (corrupt file?)");
    kf.T_world_cam.matrix() = M;
    int32_t w, h;
    in >> kf.intrinsics.fx >> kf.intrinsics.fy >> kf.intrinsics.cx >> kf.intrinsics.cy >> w >> h;
    kf.intrinsics.width = w;
    kf.intrinsics.height = h;
    if (!kf.intrinsics.valid())
      throwInputError(what, "intrinsics " + kf.intrinsics.toString() + ": " +
                                kf.intrinsics.problem() + " (corrupt file?)");
    uint32_t n;
    in >> n;
    if (n > kMaxKeyframeFeatures)
      throwInputError(what, std::to_string(n) + " features (corrupt file?), expected at most " +
                                std::to_string(kMaxKeyframeFeatures));
    kf.points_world.resize(n);
    kf.keypoints_px.resize(n);
    kf.descriptors.resize(std::size_t(Keyframe::kDescriptorBytes) * n);
    if (n > 0) {
      in.ReadBufferFixEndianness(kf.points_world.front().data(), 3 * std::size_t(n));
      in.ReadBufferFixEndianness(kf.keypoints_px.front().data(), 2 * std::size_t(n));
      in.ReadBuffer(kf.descriptors.data(), kf.descriptors.size());
    }
    int32_t tw, th;
    in >> tw >> th;
    if (tw < 0 || th < 0 || tw > kMaxThumbnailSide || th > kMaxThumbnailSide)
      throwInputError(what, "thumbnail size " + std::to_string(tw) + "x" + std::to_string(th) +
                                " (corrupt file?)");
    kf.thumb_width = tw;
    kf.thumb_height = th;
    kf.thumbnail.resize(std::size_t(tw) * std::size_t(th));
    if (!kf.thumbnail.empty()) in.ReadBuffer(kf.thumbnail.data(), kf.thumbnail.size());
    kfs.push_back(std::move(kf));
  }
}

constexpr std::size_t kClassRecordBytes = kClassSlots * 3;  // 4 ids + 4 int16
constexpr std::size_t kClassChunk = 1 << 16;                // surfels per I/O chunk

void writeClassEvidence(mrpt::serialization::CArchive& out, const ClassEvidence* ev,
                        std::size_t n) {
  std::vector<std::uint8_t> buf(kClassRecordBytes * std::min(n, kClassChunk));
  for (std::size_t k = 0; k < n; k += kClassChunk) {
    const std::size_t m = std::min(n - k, kClassChunk);
    std::uint8_t* p = buf.data();
    for (std::size_t j = 0; j < m; ++j) {
      const ClassEvidence& e = ev[k + j];
      for (int s = 0; s < kClassSlots; ++s) *p++ = e.id[s];
      for (int s = 0; s < kClassSlots; ++s) {
        const auto u = std::uint16_t(e.logit[s]);
        *p++ = std::uint8_t(u & 0xff);
        *p++ = std::uint8_t(u >> 8);
      }
    }
    out.WriteBuffer(buf.data(), m * kClassRecordBytes);
  }
}

void readClassEvidence(mrpt::serialization::CArchive& in, ClassEvidence* ev, std::size_t n,
                       int n_classes) {
  std::vector<std::uint8_t> buf(kClassRecordBytes * std::min(n, kClassChunk));
  for (std::size_t k = 0; k < n; k += kClassChunk) {
    const std::size_t m = std::min(n - k, kClassChunk);
    in.ReadBuffer(buf.data(), m * kClassRecordBytes);
    const std::uint8_t* p = buf.data();
    for (std::size_t j = 0; j < m; ++j) {
      ClassEvidence& e = ev[k + j];
      for (int s = 0; s < kClassSlots; ++s) e.id[s] = *p++;
      for (int s = 0; s < kClassSlots; ++s, p += 2)
        e.logit[s] = std::int16_t(std::uint16_t(p[0] | (std::uint16_t(p[1]) << 8)));
      if (!classEvidenceValid(e, n_classes))
        throwInputError("CSurfelMap surfel " + std::to_string(k + j),
                        "invalid class evidence for n_classes = " + std::to_string(n_classes) +
                            " (corrupt file?)");
    }
  }
}

}  // namespace

ClassEvidence convertLinearClassRow(const std::uint8_t* row, int n_classes) {
  constexpr std::uint8_t kOldPrior = 128;  // the old quantizeUnit(0.5f)
  struct Item {
    int id, units;
  };
  Item items[kMaxClassId];
  int n = 0;
  for (int c = 0; c < n_classes; ++c) {
    if (row[c] == kOldPrior) continue;
    const int units = quantizeClassLogit(probabilityLogit(float(row[c]) * (1.0f / 255.0f)));
    if (units == 0) continue;
    if (c + 1 > kMaxClassId)
      throw std::invalid_argument("class index " + std::to_string(c) + " has evidence; at most " +
                                  std::to_string(kMaxClassId) + " classes are kept");
    items[n++] = Item{c + 1, units};
  }
  // Highest classEvidenceRank first (lower id on ties): the slot rule then keeps the
  // kClassSlots highest-ranked, among them the best class.
  std::sort(items, items + n, [](const Item& a, const Item& b) {
    const int ra = classEvidenceRank(a.units), rb = classEvidenceRank(b.units);
    return ra != rb ? ra > rb : a.id < b.id;
  });
  ClassEvidence e;
  for (int k = 0; k < n; ++k) classEvidenceAdd(e, items[k].id, items[k].units);
  return e;
}

uint8_t CSurfelMap::serializeGetVersion() const {
  return 3;
}

void CSurfelMap::serializeTo(mrpt::serialization::CArchive& out) const {
  out << int32_t(m_creation.n_classes) << int32_t(m_creation.view_bins_azimuth)
      << int32_t(m_creation.view_bins_elevation) << m_creation.block_size_m;
  out << uint32_t(insertionOptions.fusion_keys.size());
  for (const auto& kv : insertionOptions.fusion_keys) out << kv.first << kv.second;
  out << likelihoodOptions.sigma_m << int32_t(likelihoodOptions.decimation)
      << likelihoodOptions.max_depth_m;
  out << int32_t(renderingOptions.visual.colouring) << renderingOptions.visual.point_size
      << renderingOptions.visual.stable_only << renderingOptions.visual.min_confidence;
  out << genericMapParams;
  out << m_store.timeOrigin();

  const SurfelArrays a = m_store.arrays();
  const std::size_t n = std::size_t(a.size);
  out << uint64_t(n);
  if (n > 0) {  // (CArchive asserts on the null arrays of an empty store)
    out.WriteBufferFixEndianness(reinterpret_cast<const float*>(a.pos_conf), 4 * n);
    out.WriteBufferFixEndianness(reinterpret_cast<const float*>(a.normal_radius), 4 * n);
    out.WriteBufferFixEndianness(a.colour_flags, n);
    out.WriteBufferFixEndianness(a.t_init, n);
    out.WriteBufferFixEndianness(a.t_last, n);
    out.WriteBufferFixEndianness(reinterpret_cast<const float*>(a.basis), 3 * n);
    out.WriteBufferFixEndianness(a.segment, n);
    out.WriteBufferFixEndianness(a.segment_w, n);
    if (a.n_classes > 0) writeClassEvidence(out, a.class_ev, n);  // version 2
    if (a.n_view_bins > 0) out.WriteBuffer(a.view_ic, n * std::size_t(a.n_view_bins));
  }
  writeKeyframes(out, m_keyframes);   // version 1
  out << uint32_t(m_classes.size());  // version 3
  for (const MapClass& c : m_classes) out << c.name << c.source;
}

int32_t CSurfelMap::readLayoutAndOptions(mrpt::serialization::CArchive& in, uint8_t version,
                                         const std::string& what) {
  int32_t nc, az, el;
  TCreationOptions co;
  in >> nc >> az >> el >> co.block_size_m;
  if (!(co.block_size_m >= 0.01 && co.block_size_m <= 100.0))
    throwInputError(what, "block size " + std::to_string(co.block_size_m) +
                              " m (corrupt file?), expected [0.01, 100] m");
  if (nc < 0 || nc > (version >= 2 ? kMaxClassId : 4096) || az < 0 || az > 256 || el < 0 || el > 64)
    throwInputError(what, "layout n_classes = " + std::to_string(nc) + ", view bins " +
                              std::to_string(az) + " x " + std::to_string(el) + " (corrupt file?)");
  // Old maps with more than 255 classes keep 255 (evidence beyond them is an error below).
  co.n_classes = std::min<int>(nc, kMaxClassId);
  co.view_bins_azimuth = az;
  co.view_bins_elevation = el;
  uint32_t nkeys;
  in >> nkeys;
  if (nkeys > kMaxFusionKeys)
    throwInputError(what, std::to_string(nkeys) +
                              " fusion keys (corrupt file?), expected at most " +
                              std::to_string(kMaxFusionKeys));
  insertionOptions.fusion_keys.clear();
  for (uint32_t k = 0; k < nkeys; ++k) {
    std::string key = readBoundedString(in, what + " fusion key");
    insertionOptions.fusion_keys.emplace_back(std::move(key),
                                              readBoundedString(in, what + " fusion value"));
  }
  int32_t dec, colouring;
  in >> likelihoodOptions.sigma_m >> dec >> likelihoodOptions.max_depth_m;
  likelihoodOptions.decimation = dec;
  in >> colouring >> renderingOptions.visual.point_size >> renderingOptions.visual.stable_only >>
      renderingOptions.visual.min_confidence;
  renderingOptions.visual.colouring = SurfelColouring(colouring);
  in >> genericMapParams;
  double t0;
  in >> t0;

  resetLayout(co);
  m_store.setTimeOrigin(t0);
  return nc;
}

void CSurfelMap::readSurfelArrays(mrpt::serialization::CArchive& in, uint8_t version, int32_t nc,
                                  const std::string& what) {
  uint64_t n;
  in >> n;
  if (n > uint64_t(kMaxSerializedSurfels))
    throwInputError(what, std::to_string(n) + " surfels (corrupt file?), expected at most " +
                              std::to_string(kMaxSerializedSurfels));
  // The first array is read in chunks before the store is allocated, so a corrupt count in a
  // short file fails at its end instead of allocating ~100 bytes per surfel it claims.
  std::vector<float> pos_conf;
  for (uint64_t k = 0; k < n; k += kClassChunk) {
    const std::size_t m = std::size_t(std::min<uint64_t>(n - k, kClassChunk));
    pos_conf.resize(pos_conf.size() + 4 * m);
    in.ReadBufferFixEndianness(pos_conf.data() + pos_conf.size() - 4 * m, 4 * m);
  }
  for (std::size_t i = 0; i < pos_conf.size(); ++i)
    if (!(std::fabs(pos_conf[i]) <= (i % 4 == 3 ? 1e30f : kMaxSurfelCoordinateM)))
      throwInputError(what + " surfel " + std::to_string(i / 4),
                      "position or confidence " + std::to_string(pos_conf[i]) +
                          " is not finite or beyond " + std::to_string(kMaxSurfelCoordinateM) +
                          " m (corrupt file?)");
  m_store.allocate(int(n));
  const SurfelArrays a = m_store.arrays();
  if (n > 0) {
    std::copy(pos_conf.begin(), pos_conf.end(), reinterpret_cast<float*>(a.pos_conf));
    pos_conf = {};
    in.ReadBufferFixEndianness(reinterpret_cast<float*>(a.normal_radius), 4 * n);
    const float* nr = reinterpret_cast<const float*>(a.normal_radius);
    for (std::size_t i = 0; i < 4 * n; ++i)
      if (!(std::fabs(nr[i]) <= 1e6f))
        throwInputError(
            what + " surfel " + std::to_string(i / 4),
            "normal or radius " + std::to_string(nr[i]) + " is not finite (corrupt file?)");
    in.ReadBufferFixEndianness(a.colour_flags, n);
    for (std::size_t i = 0; i < n; ++i)  // a saved map holds live surfels only
      if (a.colour_flags[i] & kSurfelFree)
        throwInputError(what + " surfel " + std::to_string(i),
                        "is marked as a free slot (corrupt file?)");
    in.ReadBufferFixEndianness(a.t_init, n);
    in.ReadBufferFixEndianness(a.t_last, n);
    in.ReadBufferFixEndianness(reinterpret_cast<float*>(a.basis), 3 * n);
    in.ReadBufferFixEndianness(a.segment, n);
    in.ReadBufferFixEndianness(a.segment_w, n);
    if (version >= 2) {
      if (a.n_classes > 0) readClassEvidence(in, a.class_ev, n, a.n_classes);
    } else if (nc > 0) {
      // Versions 0 and 1: n_classes linear u8 probabilities per surfel, converted.
      const std::size_t chunk = std::max<std::size_t>(1, (std::size_t(1) << 24) / nc);
      std::vector<std::uint8_t> rows(std::min<std::size_t>(n, chunk) * std::size_t(nc));
      for (std::size_t k = 0; k < n; k += chunk) {
        const std::size_t m = std::min<std::size_t>(n - k, chunk);
        in.ReadBuffer(rows.data(), m * std::size_t(nc));
        for (std::size_t j = 0; j < m; ++j) {
          try {
            a.class_ev[k + j] = convertLinearClassRow(rows.data() + j * nc, nc);
          } catch (const std::invalid_argument& e) {
            throwInputError(what + " surfel " + std::to_string(k + j), e.what());
          }
        }
      }
    }
    if (a.n_view_bins > 0) in.ReadBuffer(a.view_ic, n * std::size_t(a.n_view_bins));
  }
}

namespace {
std::vector<MapClass> readClassList(mrpt::serialization::CArchive& in, const std::string& what) {
  std::vector<MapClass> classes;
  uint32_t nclasses;
  in >> nclasses;
  if (nclasses > uint32_t(kMaxClassId))
    throwInputError(what, "class list of " + std::to_string(nclasses) + " names (at most " +
                              std::to_string(kMaxClassId) + "; corrupt file?)");
  classes.resize(nclasses);
  for (MapClass& c : classes) {
    c.name = readBoundedString(in, what + " class name");
    c.source = readBoundedString(in, what + " class source");
  }
  return classes;
}
}  // namespace

void CSurfelMap::serializeFrom(mrpt::serialization::CArchive& in, uint8_t version) {
  switch (version) {
    case 0:
    case 1:
    case 2:
    case 3: {
      const std::string what = "CSurfelMap (serialization version " + std::to_string(version) + ")";
      const int32_t nc = readLayoutAndOptions(in, version, what);
      readSurfelArrays(in, version, nc, what);
      m_store.rebuildIndex();
      if (version >= 1)
        readKeyframes(in, m_keyframes);
      else
        m_keyframes.clear();
      m_classes.clear();
      if (version >= 3) m_classes = readClassList(in, what);
    } break;
    default:
      MRPT_THROW_UNKNOWN_SERIALIZATION_VERSION(version);
  }
}

// ---- CMetricMap ----

bool CSurfelMap::internal_insertObservation(
    const mrpt::obs::CObservation& obs,
    const std::optional<const mrpt::poses::CPose3D>& robotPose) {
  const auto* scan = dynamic_cast<const mrpt::obs::CObservation3DRangeScan*>(&obs);
  if (!scan) return false;
  const std::string source = "CSurfelMap::insertObservation(" + scan->sensorLabel + ")";
  scan->load();  // externally stored images (lazy load)
  RgbdFrame frame = io::frameFromObservation(*scan, source);
  frame.timestamp_s = mrpt::Clock::toDouble(scan->timestamp);
  const mrpt::poses::CPose3D T_world_robot = robotPose ? *robotPose : mrpt::poses::CPose3D();
  const Eigen::Isometry3d T_world_cam = opticalFromMrptSensorPose(T_world_robot + scan->sensorPose);
  const std::string ini = insertionOptions.fusionIniText();
  if (!m_inserter || ini != m_inserter_ini) {
    m_inserter = makeSurfelFrameInserter(ini, insertionOptions.source);
    m_inserter_ini = ini;
  }
  m_inserter->insertFrame(m_store, frame, T_world_cam);
  return true;
}

bool CSurfelMap::internal_canComputeObservationLikelihood(
    const mrpt::obs::CObservation& obs) const {
  return dynamic_cast<const mrpt::obs::CObservation3DRangeScan*>(&obs) != nullptr && !isEmpty();
}

double CSurfelMap::internal_computeObservationLikelihood(
    const mrpt::obs::CObservation& obs, const mrpt::poses::CPose3D& takenFrom) const {
  const auto* scan = dynamic_cast<const mrpt::obs::CObservation3DRangeScan*>(&obs);
  if (!scan || isEmpty()) return 0.0;
  scan->load();
  const RgbdFrame frame =
      io::frameFromObservation(*scan, "CSurfelMap::computeObservationLikelihood");
  const Eigen::Isometry3d T_world_cam = opticalFromMrptSensorPose(takenFrom + scan->sensorPose);
  // Gaussian on the depth residual of the splat-rendered map, on a decimated pixel grid; pixels
  // the map does not explain (no surfel, or residual beyond 3 sigma) count as 3-sigma outliers so
  // the value stays bounded and comparable between poses.
  SurfelRenderer renderer;
  RenderOptions ro;
  ro.max_depth_m = float(likelihoodOptions.max_depth_m);
  ro.outputs = kRenderDepth;
  RenderedMaps rm;
  renderer.render(m_store, T_world_cam, frame.intrinsics, ro, rm);
  const double inv_s = 1.0 / likelihoodOptions.sigma_m, outlier = -0.5 * 9.0;
  double ll = 0.0;
  const int step = std::max(1, likelihoodOptions.decimation);
  for (int y = step / 2; y < frame.height(); y += step)  // cell centres: avoid the border rows
    for (int x = step / 2; x < frame.width(); x += step) {
      const float z = frame.depth_m(x, y);
      if (!(z > 0.0f) || z > likelihoodOptions.max_depth_m) continue;
      const float zr = rm.depth_m(x, y);
      if (!(zr > 0.0f)) {
        ll += outlier;
        continue;
      }
      const double r = (double(z) - zr) * inv_s;
      ll += std::max(-0.5 * r * r, outlier);
    }
  return ll;
}

void CSurfelMap::saveMetricMapRepresentationToFile(const std::string& filNamePrefix) const {
  writeSurfelPly(m_store, filNamePrefix + ".ply");
}

void CSurfelMap::getVisualizationInto(mrpt::opengl::CSetOfObjects& o) const {
  if (genericMapParams.enableSaveAs3DObject) surfelsToOpenGL(m_store, renderingOptions.visual, o);
}

std::string CSurfelMap::asString() const {
  std::ostringstream s;
  int stable = 0;
  const SurfelArrays a = m_store.arrays();
  for (int i = 0; i < a.size; ++i) stable += a.stable(i) ? 1 : 0;
  s << "rasm::maps::CSurfelMap: " << a.size << " surfels (" << stable
    << " stable), n_classes=" << a.n_classes << ", view bins " << m_creation.view_bins_azimuth
    << "x" << m_creation.view_bins_elevation << ", " << m_store.spatialIndex().numBlocks()
    << " blocks of " << m_creation.block_size_m << " m, "
    << m_store.memoryBytes() / (1024.0 * 1024.0) << " MiB";
  return s.str();
}

}  // namespace rasm::maps
