// CSurfelMap as an MRPT metric map: serialization round trip, INI creation through
// CMultiMetricMap, PLY and .3Dscene export, visualization.

#include "rasm/surfel_map/CSurfelMap.h"

#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/io/CMemoryStream.h>
#include <mrpt/maps/CMultiMetricMap.h>
#include <mrpt/opengl/COpenGLScene.h>
#include <mrpt/opengl/CPointCloudColoured.h>
#include <mrpt/opengl/CSetOfObjects.h>
#include <mrpt/serialization/CArchive.h>

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>

#include "rasm/core/Error.h"

using namespace rasm;
using namespace rasm::maps;

namespace {

void fillRandom(CSurfelMap& map, int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  const SurfelStoreOptions& o = map.store().options();
  for (int i = 0; i < n; ++i) {
    Surfel s;
    s.position = Vec3f(4 * u(rng) - 2, 4 * u(rng) - 2, 3 * u(rng));
    s.normal = Vec3f(u(rng) - 0.5f, u(rng) - 0.5f, 1.0f).normalized();
    s.basis = s.normal.cross(Vec3f(1, 0, 0)).normalized();
    s.radius = 0.01f * u(rng);
    s.confidence = 30.0f * u(rng);
    s.stable = s.confidence > 10.0f;
    s.colour = Bgr8{std::uint8_t(rng()), std::uint8_t(rng()), std::uint8_t(rng())};
    s.t_init_s = 1000.0 + i * 0.01;
    s.t_last_s = 1000.5 + i * 0.01;
    s.segment = rng() % 7;
    s.segment_weight = 3.0f * u(rng);
    const int detections = o.n_classes > 0 ? int(rng() % 7) : 0;  // up to 6 into 4 slots
    for (int k = 0; k < detections; ++k)
      classEvidenceUpdate(s.classes, 1 + int(rng() % o.n_classes), u(rng));
    for (int v = 0; v < o.nViewBins(); ++v) s.view_ic.push_back(u(rng));
    map.append(s);
  }
}

std::string tmpPath(const std::string& name) {
  return (std::filesystem::temp_directory_path() / ("rasm_surfel_map_test_" + name)).string();
}

}  // namespace

TEST(CSurfelMap, SerializationRoundTripsEveryAttribute) {
  CSurfelMap::TCreationOptions co;
  co.n_classes = 6;
  co.view_bins_azimuth = 4;
  co.view_bins_elevation = 3;
  co.block_size_m = 0.3;
  CSurfelMap map(co);
  map.insertionOptions.fusion_keys = {{"max_depth_m", "3.5"}, {"stable_confidence", "8"}};
  map.likelihoodOptions.sigma_m = 0.05;
  map.renderingOptions.visual.colouring = SurfelColouring::Segment;
  fillRandom(map, 777, 2);

  mrpt::io::CMemoryStream buf;
  auto out = mrpt::serialization::archiveFrom(buf);
  out << map;
  buf.Seek(0);
  auto in = mrpt::serialization::archiveFrom(buf);
  mrpt::serialization::CSerializable::Ptr obj;
  in >> obj;
  auto copy = std::dynamic_pointer_cast<CSurfelMap>(obj);
  ASSERT_TRUE(copy);

  EXPECT_EQ(copy->creationOptions().n_classes, 6);
  EXPECT_EQ(copy->creationOptions().view_bins_azimuth, 4);
  EXPECT_EQ(copy->creationOptions().view_bins_elevation, 3);
  EXPECT_EQ(copy->creationOptions().block_size_m, 0.3);
  EXPECT_EQ(copy->insertionOptions.fusion_keys, map.insertionOptions.fusion_keys);
  EXPECT_EQ(copy->likelihoodOptions.sigma_m, 0.05);
  EXPECT_EQ(copy->renderingOptions.visual.colouring, SurfelColouring::Segment);
  EXPECT_EQ(copy->store().timeOrigin(), map.store().timeOrigin());
  ASSERT_EQ(copy->size(), map.size());
  const SurfelArrays a = map.arrays(), b = copy->arrays();
  for (int i = 0; i < a.size; ++i) {
    ASSERT_EQ(a.pos_conf[i], b.pos_conf[i]);
    ASSERT_EQ(a.normal_radius[i], b.normal_radius[i]);
    ASSERT_EQ(a.colour_flags[i], b.colour_flags[i]);
    ASSERT_EQ(a.t_init[i], b.t_init[i]);
    ASSERT_EQ(a.t_last[i], b.t_last[i]);
    ASSERT_EQ(a.basis[i], b.basis[i]);
    ASSERT_EQ(a.segment[i], b.segment[i]);
    ASSERT_EQ(a.segment_w[i], b.segment_w[i]);
    for (int k = 0; k < kClassSlots; ++k) {
      ASSERT_EQ(a.classEvidence(i).id[k], b.classEvidence(i).id[k]);
      ASSERT_EQ(a.classEvidence(i).logit[k], b.classEvidence(i).logit[k]);
    }
    for (int v = 0; v < 12; ++v) ASSERT_EQ(a.viewRow(i)[v], b.viewRow(i)[v]);
  }
  std::string why;
  EXPECT_TRUE(copy->store().checkConsistency(&why)) << why;  // spatial index rebuilt
}

TEST(CSurfelMap, CreatedFromIniThroughCMultiMetricMap) {
  const std::string ini = R"(
[MAP]
surfelMap_count = 1
pointsMap_count = 1

[MAP_surfelMap_00_creationOpts]
n_classes = 80
view_bins_azimuth = 6
view_bins_elevation = 2
block_size_m = 0.4

[MAP_surfelMap_00_insertOpts]
max_depth_m = 4.0
stable_confidence = 12

[MAP_surfelMap_00_renderOpts]
colouring = class
point_size = 3
)";
  mrpt::config::CConfigFileMemory cfg(ini);
  mrpt::maps::TSetOfMetricMapInitializers inits;
  inits.loadFromConfigFile(cfg, "MAP");
  ASSERT_EQ(inits.size(), 2u);
  mrpt::maps::CMultiMetricMap mm(inits);
  auto sm = mm.mapByClass<CSurfelMap>();
  ASSERT_TRUE(sm);
  EXPECT_EQ(sm->creationOptions().n_classes, 80);
  EXPECT_EQ(sm->store().options().nViewBins(), 12);
  EXPECT_FLOAT_EQ(sm->store().options().block_size_m, 0.4f);
  EXPECT_EQ(sm->renderingOptions.visual.colouring, SurfelColouring::Class);
  EXPECT_EQ(sm->insertionOptions.fusion_keys.size(), 2u);
  EXPECT_NE(sm->insertionOptions.fusionIniText().find("stable_confidence = 12"), std::string::npos);
  EXPECT_TRUE(sm->isEmpty());
}

TEST(CSurfelMap, UnknownCreationKeyIsAnError) {
  mrpt::config::CConfigFileMemory cfg(
      "[MAP]\nsurfelMap_count = 1\n[MAP_surfelMap_00_creationOpts]\nn_clases = 3\n");
  mrpt::maps::TSetOfMetricMapInitializers inits;
  try {
    inits.loadFromConfigFile(cfg, "MAP");
    FAIL() << "expected an error for the misspelt key";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("n_clases"), std::string::npos) << e.what();
  }
}

TEST(CSurfelMap, PlyWrittenAndReadBack) {
  CSurfelMap::TCreationOptions co;
  co.n_classes = 4;
  CSurfelMap map(co);
  fillRandom(map, 500, 4);
  // Make the class of surfel 3 unambiguous: class 2 detected twice at 0.9 and class 4 once at
  // 0.6; surfel 4 has only negative evidence (no class above the prior); 5 has none.
  const SurfelArrays a = map.arrays();
  classEvidenceClear(a.classEvidence(3));
  classEvidenceUpdate(a.classEvidence(3), 2, 0.9f);
  classEvidenceUpdate(a.classEvidence(3), 2, 0.9f);
  classEvidenceUpdate(a.classEvidence(3), 4, 0.6f);
  classEvidenceClear(a.classEvidence(4));
  for (int c = 1; c <= 4; ++c) classEvidenceUpdate(a.classEvidence(4), c, 0.3f);
  classEvidenceClear(a.classEvidence(5));
  const std::string path = tmpPath("map.ply");
  map.saveMetricMapRepresentationToFile(path.substr(0, path.size() - 4));
  const PlySurfels p = readSurfelPly(path);
  ASSERT_EQ(p.size(), 500u);
  for (int i : {0, 3, 4, 250, 499}) {
    EXPECT_EQ(p.position[i], a.position(i));
    EXPECT_EQ(p.normal[i], a.normal(i));
    EXPECT_EQ(p.radius[i], a.radius(i));
    EXPECT_EQ(p.confidence[i], a.confidence(i));
    EXPECT_EQ(p.segment[i], a.segment[i]);
    EXPECT_EQ(p.stable[i], a.stable(i) ? 1 : 0);
    EXPECT_EQ(p.colour[i].r, a.colour(i).r);
    EXPECT_EQ(p.colour[i].b, a.colour(i).b);
  }
  EXPECT_EQ(p.class_id[3], 2);
  EXPECT_NEAR(p.class_probability[3], 0.9 * 0.9 / (0.9 * 0.9 + 0.1 * 0.1), 1e-3);  // 0.988
  EXPECT_EQ(p.class_probability[3], classProbability(a.classEvidence(3), 2));
  EXPECT_EQ(p.class_id[4], 0);
  EXPECT_EQ(p.class_probability[4], 0.5f);
  EXPECT_EQ(p.class_id[5], 0);
  EXPECT_EQ(p.class_probability[5], 0.5f);
  for (int i = 0; i < a.size; ++i) {
    const BestClass b = bestClass(a.classEvidence(i));
    ASSERT_EQ(p.class_id[i], b.id);
    ASSERT_EQ(p.class_probability[i], b.probability);
  }
  // Header declares the properties in the documented order.
  std::FILE* f = std::fopen(path.c_str(), "rb");
  ASSERT_NE(f, nullptr);
  char head[512] = {0};
  ASSERT_GT(std::fread(head, 1, sizeof(head) - 1, f), 0u);
  std::fclose(f);
  const std::string h(head);
  EXPECT_NE(h.find("format binary_little_endian 1.0"), std::string::npos);
  // Integer ids as int32, which every common reader takes (Open3D's tensor reader drops uint).
  EXPECT_NE(h.find("property float confidence\nproperty int segment\nproperty int class\n"
                   "property float class_probability\nproperty uchar stable\nend_header"),
            std::string::npos)
      << h;
  EXPECT_EQ(h.find("uint"), std::string::npos) << h;
  // Stable-only export.
  map.saveToPly(path, true);
  int stable = 0;
  for (int i = 0; i < a.size; ++i) stable += a.stable(i);
  EXPECT_EQ(int(readSurfelPly(path).size()), stable);
  std::filesystem::remove(path);
  EXPECT_THROW(readSurfelPly(path), InputError);
}

TEST(CSurfelMap, PlyWithACorruptVertexCountIsAnErrorNotAnAllocation) {
  CSurfelMap map;
  fillRandom(map, 3, 0);
  const std::string path = tmpPath("count.ply");
  map.saveToPly(path, false);
  std::ifstream in(path, std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  in.close();
  const std::size_t at = bytes.find("element vertex 3\n");
  ASSERT_NE(at, std::string::npos);
  for (const char* count : {"30000000000000", "4", "18446744073709551615"}) {
    std::string corrupt = bytes;
    corrupt.replace(at, 17, std::string("element vertex ") + count + "\n");
    std::ofstream(path, std::ios::binary) << corrupt;
    try {
      readSurfelPly(path);
      ADD_FAILURE() << count << " vertices read from a file of 3";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(std::string("the header says ") + count + " vertices"),
                std::string::npos)
          << e.what();
    }
  }
  std::filesystem::remove(path);
}

TEST(CSurfelMap, PlyOfTheEarlierUintLayoutStillReads) {
  // Maps written before segment and class became int32: uint segment, uchar class.
  const std::string path = tmpPath("uint_layout.ply");
  {
    std::ofstream f(path, std::ios::binary);
    f << "ply\nformat binary_little_endian 1.0\nelement vertex 1\n";
    for (const char* p :
         {"float x", "float y", "float z", "float nx", "float ny", "float nz", "uchar red",
          "uchar green", "uchar blue", "float radius", "float confidence", "uint segment",
          "uchar class", "float class_probability", "uchar stable"})
      f << "property " << p << "\n";
    f << "end_header\n";
    const float xyz_n[6] = {1.f, 2.f, 3.f, 0.f, 0.f, 1.f};
    f.write(reinterpret_cast<const char*>(xyz_n), sizeof xyz_n);
    const unsigned char rgb[3] = {10, 20, 30};
    f.write(reinterpret_cast<const char*>(rgb), 3);
    const float radius_conf[2] = {0.01f, 7.f};
    f.write(reinterpret_cast<const char*>(radius_conf), sizeof radius_conf);
    const std::uint32_t segment = 3000000000u;
    f.write(reinterpret_cast<const char*>(&segment), 4);
    const unsigned char cls = 57;
    f.write(reinterpret_cast<const char*>(&cls), 1);
    const float p = 0.75f;
    f.write(reinterpret_cast<const char*>(&p), 4);
    const unsigned char stable = 1;
    f.write(reinterpret_cast<const char*>(&stable), 1);
  }
  const PlySurfels s = readSurfelPly(path);
  ASSERT_EQ(s.size(), 1u);
  EXPECT_EQ(s.position[0], Vec3f(1.f, 2.f, 3.f));
  EXPECT_EQ(s.colour[0].r, 10);
  EXPECT_EQ(s.confidence[0], 7.f);
  EXPECT_EQ(s.segment[0], 3000000000u);
  EXPECT_EQ(s.class_id[0], 57);
  EXPECT_EQ(s.class_probability[0], 0.75f);
  EXPECT_EQ(s.stable[0], 1);
  std::filesystem::remove(path);
}

TEST(CSurfelMap, VisualizationAndSceneFile) {
  CSurfelMap map;
  fillRandom(map, 300, 8);
  mrpt::opengl::CSetOfObjects objs;
  map.getVisualizationInto(objs);
  auto cloud = objs.getByClass<mrpt::opengl::CPointCloudColoured>();
  ASSERT_TRUE(cloud);
  EXPECT_EQ(cloud->size(), 300u);

  const std::string path = tmpPath("map.3Dscene");
  map.saveTo3DScene(path);
  mrpt::opengl::COpenGLScene scene;
  ASSERT_TRUE(scene.loadFromFile(path));
  EXPECT_TRUE(scene.getByClass<mrpt::opengl::CPointCloudColoured>());
  std::filesystem::remove(path);
  EXPECT_NE(map.asString().find("300 surfels"), std::string::npos);
}

TEST(CSurfelMap, CopyAndClear) {
  CSurfelMap map;
  fillRandom(map, 50, 9);
  CSurfelMap copy(map);
  EXPECT_EQ(copy.size(), 50);
  map.clear();
  EXPECT_TRUE(map.isEmpty());
  EXPECT_EQ(copy.size(), 50);
  auto cloned = std::unique_ptr<mrpt::rtti::CObject>(copy.clone());
  EXPECT_EQ(dynamic_cast<CSurfelMap&>(*cloned).size(), 50);
}

namespace {

std::vector<std::uint8_t> streamBytes(const mrpt::io::CMemoryStream& buf) {
  const auto* p = static_cast<const std::uint8_t*>(buf.getRawBufferData());
  return std::vector<std::uint8_t>(p, p + buf.getTotalBytesCount());
}

/// MRPT's framing of one object in an archive (CArchive::WriteObject): class-name length | 0x80,
/// the name, the serialization version, the payload, the end flag 0x88. Checked against the real
/// framing in the test below.
std::vector<std::uint8_t> framed(std::uint8_t version, const std::vector<std::uint8_t>& payload) {
  const std::string name = CLASS_ID(CSurfelMap)->className;
  std::vector<std::uint8_t> b;
  b.push_back(std::uint8_t(name.size() | 0x80));
  b.insert(b.end(), name.begin(), name.end());
  b.push_back(version);
  b.insert(b.end(), payload.begin(), payload.end());
  b.push_back(0x88);
  return b;
}

/// The protected payload writer of the current version.
struct SerializationAccess : CSurfelMap {
  using CSurfelMap::CSurfelMap;
  using CSurfelMap::serializeTo;
};

/// The payload of serialization versions 0 and 1 (CSurfelMap::serializeTo up to commit 355c550):
/// m's options and surfels, but the classes as `nc` linear u8 probabilities per surfel (`rows`,
/// 128 = the 0.5 prior); version 1 ends with the keyframes (none here).
std::vector<std::uint8_t> oldPayload(const CSurfelMap& m, const std::vector<std::uint8_t>& rows,
                                     int nc, int version) {
  mrpt::io::CMemoryStream buf;
  auto out = mrpt::serialization::archiveFrom(buf);
  const CSurfelMap::TCreationOptions& co = m.creationOptions();
  out << int32_t(nc) << int32_t(co.view_bins_azimuth) << int32_t(co.view_bins_elevation)
      << co.block_size_m;
  out << uint32_t(m.insertionOptions.fusion_keys.size());
  for (const auto& kv : m.insertionOptions.fusion_keys) out << kv.first << kv.second;
  out << m.likelihoodOptions.sigma_m << int32_t(m.likelihoodOptions.decimation)
      << m.likelihoodOptions.max_depth_m;
  out << int32_t(m.renderingOptions.visual.colouring) << m.renderingOptions.visual.point_size
      << m.renderingOptions.visual.stable_only << m.renderingOptions.visual.min_confidence;
  out << m.genericMapParams;
  out << m.store().timeOrigin();
  const SurfelArrays a = m.arrays();
  const std::size_t n = std::size_t(a.size);
  out << uint64_t(n);
  out.WriteBufferFixEndianness(reinterpret_cast<const float*>(a.pos_conf), 4 * n);
  out.WriteBufferFixEndianness(reinterpret_cast<const float*>(a.normal_radius), 4 * n);
  out.WriteBufferFixEndianness(a.colour_flags, n);
  out.WriteBufferFixEndianness(a.t_init, n);
  out.WriteBufferFixEndianness(a.t_last, n);
  out.WriteBufferFixEndianness(reinterpret_cast<const float*>(a.basis), 3 * n);
  out.WriteBufferFixEndianness(a.segment, n);
  out.WriteBufferFixEndianness(a.segment_w, n);
  if (nc > 0) out.WriteBuffer(rows.data(), n * std::size_t(nc));
  if (a.n_view_bins > 0) out.WriteBuffer(a.view_ic, n * std::size_t(a.n_view_bins));
  if (version >= 1) out << uint32_t(0);  // no keyframes
  return streamBytes(buf);
}

std::shared_ptr<CSurfelMap> readMap(const std::vector<std::uint8_t>& bytes) {
  mrpt::io::CMemoryStream buf;
  buf.assignMemoryNotOwn(bytes.data(), bytes.size());
  auto in = mrpt::serialization::archiveFrom(buf);
  mrpt::serialization::CSerializable::Ptr obj;
  in >> obj;
  return std::dynamic_pointer_cast<CSurfelMap>(obj);
}

/// The old argmaxClass: the class index with the largest u8 above 128 (the first on ties), -1.
int oldArgmax(const std::uint8_t* row, int nc) {
  int best = -1;
  std::uint8_t best_q = 128;
  for (int c = 0; c < nc; ++c)
    if (row[c] > best_q) {
      best_q = row[c];
      best = c;
    }
  return best;
}

}  // namespace

TEST(CSurfelMap, MrptFramingOfTheTestStreamsIsTheRealOne) {
  CSurfelMap::TCreationOptions co;
  co.n_classes = 9;
  SerializationAccess map(co);
  fillRandom(map, 50, 6);
  mrpt::io::CMemoryStream real;
  auto out = mrpt::serialization::archiveFrom(real);
  out << static_cast<const CSurfelMap&>(map);
  mrpt::io::CMemoryStream payload;
  auto pout = mrpt::serialization::archiveFrom(payload);
  map.serializeTo(pout);
  EXPECT_EQ(streamBytes(real), framed(3, streamBytes(payload)));
}

// Version 0 and 1 maps (linear u8 probabilities per class) load into the log-odds slots: old
// class index c is id c + 1, every surfel keeps its best class, the four highest-ranked classes
// keep their probability within the quantisation, the others fall back to the prior.
TEST(CSurfelMap, ReadsVersion0And1MapsWithTheSameBestClass) {
  const int nc = 90;
  CSurfelMap::TCreationOptions co;
  co.n_classes = nc;
  co.view_bins_azimuth = 4;
  co.view_bins_elevation = 2;
  CSurfelMap map(co);
  map.insertionOptions.fusion_keys = {{"max_depth_m", "3.5"}};
  const int n = 600;
  fillRandom(map, n, 12);
  std::mt19937 rng(3);
  std::vector<std::uint8_t> rows(std::size_t(n) * nc, 128);
  for (int i = 3; i < n; ++i) {  // 0: all at the prior; 1 and 2: planted below
    std::uint8_t* r = rows.data() + std::size_t(i) * nc;
    const int k = int(rng() % 8);  // 0..7 classes away from the prior, some only below it
    for (int j = 0; j < k; ++j) r[rng() % nc] = std::uint8_t(rng() % 256);
  }
  rows[std::size_t(1) * nc + 89] = 255;  // p = 1 (clamped) on the last class index
  rows[std::size_t(1) * nc + 3] = 200;
  std::vector<std::uint8_t>::iterator r2 = rows.begin() + 2 * nc;  // a tie: the lower index wins
  r2[10] = 220;
  r2[4] = 220;
  for (int version : {0, 1}) {
    const auto copy = readMap(framed(std::uint8_t(version), oldPayload(map, rows, nc, version)));
    ASSERT_TRUE(copy) << "version " << version;
    EXPECT_EQ(copy->creationOptions().n_classes, nc);
    EXPECT_EQ(copy->insertionOptions.fusion_keys, map.insertionOptions.fusion_keys);
    ASSERT_EQ(copy->size(), n);
    EXPECT_TRUE(copy->keyframes().empty());
    const SurfelArrays a = map.arrays(), b = copy->arrays();
    int with_class = 0;
    for (int i = 0; i < n; ++i) {
      ASSERT_EQ(a.pos_conf[i], b.pos_conf[i]);
      ASSERT_EQ(a.colour_flags[i], b.colour_flags[i]);
      ASSERT_EQ(a.segment[i], b.segment[i]);
      for (int v = 0; v < a.n_view_bins; ++v) ASSERT_EQ(a.viewRow(i)[v], b.viewRow(i)[v]);
      const std::uint8_t* r = rows.data() + std::size_t(i) * nc;
      const ClassEvidence& e = b.classEvidence(i);
      ASSERT_TRUE(classEvidenceValid(e, nc));
      const BestClass best = bestClass(e);
      ASSERT_EQ(best.id, oldArgmax(r, nc) + 1) << "surfel " << i << ", version " << version;
      with_class += best.id != 0;
      // Every slotted class has its old probability (clamped to 7 nats) within 1/8192 + float.
      int away = 0, weakest_kept = 1 << 30;
      for (int c = 0; c < nc; ++c) away += r[c] != 128;
      for (int k = 0; k < kClassSlots; ++k) {
        if (e.id[k] == 0) continue;
        const double p_old = std::clamp(r[e.id[k] - 1] / 255.0, 1.0 - logitProbability(7.0f),
                                        double(logitProbability(7.0f)));
        EXPECT_NEAR(classProbability(e, e.id[k]), p_old, 1.0 / 8192 + 1e-6);
        weakest_kept = std::min(weakest_kept, classEvidenceRank(e.logit[k]));
      }
      // The slots hold min(4, classes away from the prior) classes; the dropped ones rank no
      // higher than the lowest-ranked kept one (ClassEvidence.h slot rule).
      int slotted = 0;
      for (int k = 0; k < kClassSlots; ++k) slotted += e.id[k] != 0;
      EXPECT_EQ(slotted, std::min(kClassSlots, away)) << "surfel " << i;
      for (int c = 0; c < nc; ++c)
        if (r[c] != 128 && classEvidenceSlot(e, c + 1) < 0)
          EXPECT_LE(classEvidenceRank(quantizeClassLogit(probabilityLogit(r[c] / 255.0f))),
                    weakest_kept);
    }
    EXPECT_GT(with_class, n / 2);
    EXPECT_EQ(bestClass(b.classEvidence(0)).id, 0);
    EXPECT_EQ(bestClass(b.classEvidence(1)).id, 90);
    EXPECT_EQ(classLogitUnits(b.classEvidence(1), 90), kClassLogitMaxUnits);
    EXPECT_EQ(bestClass(b.classEvidence(2)).id, 5);
    // Written again, it is a version-2 map that reads back bit-identically.
    mrpt::io::CMemoryStream buf;
    auto out = mrpt::serialization::archiveFrom(buf);
    out << *copy;
    const auto again = readMap(streamBytes(buf));
    ASSERT_TRUE(again);
    for (int i = 0; i < n; ++i)
      for (int k = 0; k < kClassSlots; ++k) {
        ASSERT_EQ(again->arrays().classEvidence(i).id[k], b.classEvidence(i).id[k]);
        ASSERT_EQ(again->arrays().classEvidence(i).logit[k], b.classEvidence(i).logit[k]);
      }
  }
  // Old maps may have had more than 255 classes: they keep 255, evidence beyond is an error.
  std::vector<std::uint8_t> wide(std::size_t(n) * 300, 128);
  wide[7 * 300 + 254] = 200;  // index 254 = id 255: kept
  const auto w = readMap(framed(1, oldPayload(map, wide, 300, 1)));
  ASSERT_TRUE(w);
  EXPECT_EQ(w->creationOptions().n_classes, 255);
  EXPECT_EQ(bestClass(w->arrays().classEvidence(7)).id, 255);
  wide[9 * 300 + 280] = 200;
  EXPECT_THROW(readMap(framed(1, oldPayload(map, wide, 300, 1))), std::exception);
}

TEST(CSurfelMap, CorruptClassEvidenceIsAnError) {
  CSurfelMap::TCreationOptions co;
  co.n_classes = 9;
  SerializationAccess map(co);
  fillRandom(map, 5, 7);
  classEvidenceClear(map.arrays().classEvidence(2));
  classEvidenceAdd(map.arrays().classEvidence(2), 9, 100);
  mrpt::io::CMemoryStream payload;
  auto pout = mrpt::serialization::archiveFrom(payload);
  map.serializeTo(pout);
  std::vector<std::uint8_t> p = streamBytes(payload);
  // Find surfel 2's record (ids 9 0 0 0, logit 100 0 0 0) and make its id 10 > n_classes.
  const std::uint8_t rec[] = {9, 0, 0, 0, 100, 0, 0, 0, 0, 0, 0, 0};
  auto it = std::search(p.begin(), p.end(), std::begin(rec), std::end(rec));
  ASSERT_NE(it, p.end());
  *it = 10;
  try {
    readMap(framed(2, p));
    FAIL() << "corrupt class evidence accepted";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("class evidence"), std::string::npos) << e.what();
  }
}

// A saved map holds live surfels only: a record flagged as a free slot (found by fuzz_surfelmap:
// the store was left inconsistent, every later allocation could hand the slot out twice) is an
// input error naming the surfel.
TEST(CSurfelMap, SurfelMarkedFreeIsAnError) {
  SerializationAccess map;
  fillRandom(map, 5, 3);
  map.arrays().colour_flags[3] |= kSurfelFree;
  mrpt::io::CMemoryStream payload;
  auto pout = mrpt::serialization::archiveFrom(payload);
  map.serializeTo(pout);
  try {
    readMap(framed(3, streamBytes(payload)));
    FAIL() << "a surfel flagged free was accepted";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("surfel 3: is marked as a free slot"), std::string::npos)
        << e.what();
  }
}

TEST(CSurfelMap, ClassColouringShowsTheBestClassFadedByItsProbability) {
  CSurfelMap map;  // the default layout names the 80 COCO classes and the project's
  EXPECT_EQ(map.creationOptions().n_classes, kDefaultNumClasses);
  fillRandom(map, 3, 1);
  const SurfelArrays a = map.arrays();
  for (int i = 0; i < 3; ++i) classEvidenceClear(a.classEvidence(i));
  for (int k = 0; k < 10; ++k) classEvidenceUpdate(a.classEvidence(0), 57, 0.99f);  // clamped
  classEvidenceUpdate(a.classEvidence(1), 57, 0.75f);                               // p = 0.75
  map.renderingOptions.visual.colouring = SurfelColouring::Class;
  mrpt::opengl::CSetOfObjects objs;
  map.getVisualizationInto(objs);
  auto cloud = objs.getByClass<mrpt::opengl::CPointCloudColoured>();
  ASSERT_TRUE(cloud);
  ASSERT_EQ(cloud->size(), 3u);
  const Bgr8 full = labelColour(57), grey = labelColour(0);
  const auto c0 = cloud->getPointColor(0), c1 = cloud->getPointColor(1);
  const auto c2 = cloud->getPointColor(2);
  EXPECT_NEAR(c0.R, full.r, 1);
  EXPECT_NEAR(c0.G, full.g, 1);
  EXPECT_NEAR(c0.B, full.b, 1);
  EXPECT_NEAR(c1.R, (full.r + grey.r) / 2.0, 2);  // halfway: 2 (p - 0.5) = 0.5
  EXPECT_NEAR(c1.B, (full.b + grey.b) / 2.0, 2);
  EXPECT_EQ(c2.R, grey.r);
  EXPECT_EQ(c2.G, grey.g);
}
