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

#include <cstdio>
#include <filesystem>
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
    for (int c = 0; c < o.n_classes; ++c) s.class_p.push_back(u(rng));
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
    for (int c = 0; c < 6; ++c) ASSERT_EQ(a.classRow(i)[c], b.classRow(i)[c]);
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
  // Make the class of surfel 3 unambiguous: class 2 at 0.9, the others at the prior.
  const SurfelArrays a = map.arrays();
  for (int c = 0; c < 4; ++c) a.classRow(3)[c] = quantizeUnit(c == 2 ? 0.9f : 0.5f);
  for (int c = 0; c < 4; ++c) a.classRow(4)[c] = quantizeUnit(0.3f);  // none above the prior
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
  EXPECT_EQ(p.class_id[4], -1);
  // Header declares the properties in the documented order.
  std::FILE* f = std::fopen(path.c_str(), "rb");
  ASSERT_NE(f, nullptr);
  char head[512] = {0};
  ASSERT_GT(std::fread(head, 1, sizeof(head) - 1, f), 0u);
  std::fclose(f);
  const std::string h(head);
  EXPECT_NE(h.find("format binary_little_endian 1.0"), std::string::npos);
  EXPECT_NE(h.find("property int class\nproperty uchar stable\nend_header"), std::string::npos);
  // Stable-only export.
  map.saveToPly(path, true);
  int stable = 0;
  for (int i = 0; i < a.size; ++i) stable += a.stable(i);
  EXPECT_EQ(int(readSurfelPly(path).size()), stable);
  std::filesystem::remove(path);
  EXPECT_THROW(readSurfelPly(path), InputError);
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
