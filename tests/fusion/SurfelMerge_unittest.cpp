// Redundant-surfel merging (Keller et al. 2013 sec. 4.3; TFusionParams::merge_redundant): the
// merge of two surfels (fusion::kernels::mergeSurfels), and SurfelFusion merging planted duplicates
// of a wall while leaving surfels that differ in depth or normal alone.

#include <gtest/gtest.h>
#include <omp.h>

#include <cmath>
#include <vector>

#include "SyntheticScene.h"
#include "rasm/core/SurfelMath.h"
#include "rasm/fusion/SurfelFusion.h"
#include "rasm/fusion/kernels/FusionKernels.h"

using namespace rasm;
using namespace rasm::maps;
using namespace rasm::fusion;

namespace {

const CameraIntrinsics kK(131.25, 131.25, 79.5, 59.5, 160, 120);  // 640x480 Kinect / 4
constexpr double kWallZ = 3.0;

Surfel wallSurfel(const Vec3f& p, float conf, Bgr8 colour, double t) {
  Surfel s;
  s.position = p;
  s.normal = Vec3f(0, 0, -1);  // facing the camera at the origin
  s.basis = Vec3f(1, 0, 0);
  s.radius = surfelRadius(float(kWallZ), -1.0f, float(kK.fx));
  s.confidence = conf;
  s.colour = colour;
  s.t_init_s = t;
  s.t_last_s = t;
  return s;
}

float totalConfidence(const SurfelStore& map) {
  const SurfelArrays a = map.arrays();
  double c = 0;
  for (int i = 0; i < a.size; ++i) c += a.confidence(i);
  return float(c);
}

}  // namespace

TEST(SurfelMerge, MergeAveragesByConfidenceAndKeepsTheHistory) {
  SurfelStoreOptions layout;
  layout.n_classes = 2;
  SurfelStore map(layout);
  Surfel a = wallSurfel(Vec3f(0.1f, 0.2f, 3.0f), 6.0f, Bgr8{100, 100, 100}, 10.0);
  a.segment = 7;
  a.segment_weight = 4.0f;
  a.view_ic.assign(map.options().nViewBins(), 0.0f);
  a.view_ic[0] = 0.8f;
  Surfel b = wallSurfel(Vec3f(0.1f, 0.2f, 3.004f), 2.0f, Bgr8{200, 0, 100}, 8.0);
  b.normal = Vec3f(0.0f, std::sin(0.1f), -std::cos(0.1f));
  b.t_last_s = 12.0;
  b.segment = 7;
  b.segment_weight = 1.5f;
  b.view_ic.assign(map.options().nViewBins(), 0.0f);
  b.view_ic[0] = 0.2f;
  b.view_ic[3] = 0.6f;
  b.radius = a.radius * 0.5f;
  const int ia = map.append(a), ib = map.append(b);

  fusion::kernels::FusionKernelParams prm;
  prm.stable_confidence = 7.5f;  // 6 + 2 crosses it
  const SurfelArrays s = map.arrays();
  EXPECT_FALSE(fusion::kernels::mergeSurfels(s, ia, ib, prm));  // 4 mm move: same 0.5 m block
  // Weights 6/8 and 2/8.
  EXPECT_NEAR(s.position(ia).z(), 3.0f + 0.25f * 0.004f, 1e-6f);
  EXPECT_NEAR(s.confidence(ia), 8.0f, 1e-6f);
  EXPECT_NEAR(s.normal(ia).norm(), 1.0f, 1e-6f);
  EXPECT_NEAR(std::atan2(-s.normal(ia).y(), -s.normal(ia).z()), -0.25f * 0.1f, 2e-3f);
  EXPECT_NEAR(s.radius(ia), 0.75f * a.radius + 0.25f * b.radius, 1e-7f);
  EXPECT_EQ(s.colour(ia).b, 125);  // 0.75 * 100 + 0.25 * 200
  EXPECT_EQ(s.colour(ia).g, 75);
  EXPECT_TRUE(s.stable(ia));
  EXPECT_NEAR(map.get(ia).t_init_s, 8.0, 1e-5);
  EXPECT_NEAR(map.get(ia).t_last_s, 12.0, 1e-5);
  EXPECT_EQ(s.segment[ia], 7u);
  EXPECT_NEAR(s.segment_w[ia], 5.5f, 1e-6f);
  EXPECT_EQ(s.viewRow(ia)[0], quantizeUnit(0.8f));  // element-wise max
  EXPECT_EQ(s.viewRow(ia)[3], quantizeUnit(0.6f));
  EXPECT_NEAR(s.basis[ia].dot(s.normal(ia)), 0.0f, 1e-5f);

  // Class evidence: the survivor keeps its own (both saw the same detections: no double count);
  // a survivor without any takes the loser's.
  {
    SurfelStore cm(layout);
    Surfel k = wallSurfel(Vec3f(0.1f, 0.2f, 3.0f), 6.0f, Bgr8{}, 0.0), l = k;
    l.confidence = 2.0f;
    classEvidenceUpdate(k.classes, 1, 0.8f);
    classEvidenceUpdate(l.classes, 2, 0.9f);
    classEvidenceUpdate(l.classes, 1, 0.3f);
    const int k1 = cm.append(k), l1 = cm.append(l);
    Surfel bare = k;
    bare.classes = ClassEvidence{};
    const int k2 = cm.append(bare), l2 = cm.append(l);
    const SurfelArrays c = cm.arrays();
    fusion::kernels::mergeSurfels(c, k1, l1, prm);
    fusion::kernels::mergeSurfels(c, k2, l2, prm);
    EXPECT_EQ(classLogitUnits(c.classEvidence(k1), 1), classLogitUnits(k.classes, 1));
    EXPECT_EQ(classEvidenceSlot(c.classEvidence(k1), 2), -1);
    for (int q = 0; q < kClassSlots; ++q) {
      EXPECT_EQ(c.classEvidence(k2).id[q], l.classes.id[q]);
      EXPECT_EQ(c.classEvidence(k2).logit[q], l.classes.logit[q]);
    }
  }

  // A capped confidence stays at the cap; a block crossing is reported.
  const int ic = map.append(wallSurfel(Vec3f(0.499f, 0.0f, 3.0f), 1.0f, Bgr8{}, 0.0));
  const int id = map.append(wallSurfel(Vec3f(0.503f, 0.0f, 3.0f), 3.0f, Bgr8{}, 0.0));
  prm.max_confidence = 3.5f;
  const SurfelArrays s2 = map.arrays();
  EXPECT_TRUE(fusion::kernels::mergeSurfels(s2, ic, id, prm));  // 0.499 -> 0.502 crosses x = 0.5
  EXPECT_NEAR(s2.confidence(ic), 3.5f, 0.0f);
}

TEST(SurfelMerge, RedundancyTestUsesDepthNormalAndDiscGates) {
  SurfelStore map;
  const Vec3f p(0.0f, 0.0f, 3.0f);
  const float r = surfelRadius(3.0f, -1.0f, float(kK.fx));
  const int base = map.append(wallSurfel(p, 1, Bgr8{}, 0));
  const int near_along = map.append(wallSurfel(p + Vec3f(0, 0, 0.025f), 1, Bgr8{}, 0));
  const int far_along = map.append(wallSurfel(p + Vec3f(0, 0, 0.035f), 1, Bgr8{}, 0));
  const int in_disc = map.append(wallSurfel(p + Vec3f(0.9f * r, 0, 0), 1, Bgr8{}, 0));
  const int off_disc = map.append(wallSurfel(p + Vec3f(1.1f * r, 0, 0), 1, Bgr8{}, 0));
  Surfel tilted = wallSurfel(p, 1, Bgr8{}, 0);
  tilted.normal = Vec3f(std::sin(0.35f), 0.0f, -std::cos(0.35f));  // 20 deg
  const int tilt = map.append(tilted);
  fusion::kernels::MergeTest t;
  t.min_cos_normal = std::cos(15.0f * 3.14159265f / 180.0f);
  t.dz_abs_m = 0.03f;
  t.dz_rel = 0.01f;  // max(3 cm, 1% of 3 m) = 3 cm
  const SurfelArrays a = map.arrays();
  EXPECT_TRUE(t.redundant(a, base, near_along, 3.0f));
  EXPECT_FALSE(t.redundant(a, base, far_along, 3.0f));
  EXPECT_TRUE(t.redundant(a, base, far_along, 4.0f));  // 1% of 4 m = 4 cm
  EXPECT_TRUE(t.redundant(a, base, in_disc, 3.0f));
  EXPECT_FALSE(t.redundant(a, base, off_disc, 3.0f));
  EXPECT_FALSE(t.redundant(a, base, tilt, 3.0f));
}

namespace {

struct PlantedMap {
  SurfelStore map;
  std::vector<std::pair<int, int>> dup_pixels;  ///< pixels whose surfel got a planted duplicate
  std::vector<float> dup_conf_before;           ///< original + duplicate confidence
  int n_first = 0, n_dups = 0, n_decoys = 0;
};

// Wall fused once; then, for every 5th pixel of the central rows, a duplicate 4 mm behind and a
// third of a radius aside (same pixel, overlapping disc), and for every 7th a decoy that must
// stay: 10 cm behind (beyond the 3 cm depth gate) or 1 mm behind and tilted by 60 deg (beyond the
// 15 deg merge gate, and beyond fusion's 50 deg association gate, so updates do not turn it
// toward the wall).
void plant(SurfelFusion& fusion, PlantedMap& pm, const fusiontest::SyntheticFrame& f,
           float dup_confidence = 0.7f) {
  fusion.fuse(pm.map, f.input());
  pm.n_first = pm.map.size();
  const Image<std::int32_t> px = fusion.pixelSurfels();
  for (int y = 10; y < kK.height - 10; ++y)
    for (int x = 10; x < kK.width - 10; ++x) {
      const int i = px(x, y);
      if (i < 0) continue;  // (box edges: no normal)
      const Surfel s = pm.map.get(i);
      const int k = y * kK.width + x;
      if (k % 5 == 0) {
        Surfel d = wallSurfel(s.position + Vec3f(s.radius / 3, 0, 0.004f), dup_confidence,
                              Bgr8{0, 255, 0}, 0.0);
        pm.map.append(d);
        pm.dup_pixels.emplace_back(x, y);
        pm.dup_conf_before.push_back(s.confidence + d.confidence);
        ++pm.n_dups;
      } else if (k % 7 == 0) {
        Surfel d = wallSurfel(s.position + Vec3f(0, 0, 0.10f), 0.7f, Bgr8{}, 0.0);
        if ((k / 7) % 2) {
          // 1 mm behind the wall surfel: an exact depth tie would leave the 4x map's per-sub-pixel
          // nearest surfel to the index order, which re-sorting the store changes.
          d.position = s.position + Vec3f(0, 0, 0.001f);
          d.normal = Vec3f(std::sin(1.05f), 0.0f, -std::cos(1.05f));
        }
        pm.map.append(d);
        ++pm.n_decoys;
      }
    }
}

}  // namespace

// The duplicate is the less confident surfel (merged into the one the pixel updates) or the more
// confident one (the pixel's surfel is merged away: pixelSurfels() must follow it to the survivor).
class PlantedDuplicates : public ::testing::TestWithParam<float> {};

TEST_P(PlantedDuplicates, AreMergedAndOthersKept) {
  const float dup_confidence = GetParam();
  fusiontest::Scene scene;
  scene.wall_z = kWallZ;
  const auto f0 = fusiontest::renderScene(scene, kK, Eigen::Isometry3d::Identity(), 0.0);
  const auto f1 = fusiontest::renderScene(scene, kK, Eigen::Isometry3d::Identity(), 1.0 / 30);
  TFusionParams p;
  p.merge_row_stride = 1;
  SurfelFusion fusion(p);
  PlantedMap pm;
  plant(fusion, pm, f0, dup_confidence);
  ASSERT_EQ(pm.n_first, (kK.width - 2) *
                            (kK.height - 2));  // the wall fills the view (no normals on the border)
  ASSERT_GT(pm.n_dups, 1000);
  ASSERT_GT(pm.n_decoys, 500);
  const float conf_before = totalConfidence(pm.map);

  const FusionStats st = fusion.fuse(pm.map, f1.input());
  EXPECT_EQ(st.merged, pm.n_dups);
  EXPECT_EQ(st.removed_carved + st.removed_unstable, 0);
  EXPECT_EQ(st.added, 0);
  EXPECT_EQ(pm.map.size(), pm.n_first + pm.n_decoys);
  std::string why;
  EXPECT_TRUE(pm.map.checkConsistency(&why)) << why;
  // Confidence is conserved by merging: before + the w of every associated pixel.
  double w_sum = 0;
  for (int y = 0; y < kK.height; ++y)
    for (int x = 0; x < kK.width; ++x)
      if (fusion.pixelSurfels()(x, y) >= 0)
        w_sum += confidenceWeight(normalizedRadialDistance(float(x), float(y), kK.plain()), 0.6f);
  EXPECT_NEAR(totalConfidence(pm.map), conf_before + w_sum, 1e-4 * (conf_before + w_sum));
  // Each duplicated pixel now refers to one surfel holding both confidences and this frame's w,
  // on the wall within the 4 mm offset, its colour between grey and green.
  const SurfelArrays a = pm.map.arrays();
  for (std::size_t k = 0; k < pm.dup_pixels.size(); ++k) {
    const auto [x, y] = pm.dup_pixels[k];
    const int i = fusion.pixelSurfels()(x, y);
    ASSERT_GE(i, 0) << x << "," << y;
    const float w =
        confidenceWeight(normalizedRadialDistance(float(x), float(y), kK.plain()), 0.6f);
    EXPECT_NEAR(a.confidence(i), pm.dup_conf_before[k] + w, 1e-4f);
    EXPECT_GE(a.position(i).z(), float(kWallZ) - 1e-5f);
    EXPECT_LE(a.position(i).z(), float(kWallZ) + 0.004f);
    EXPECT_GT(a.colour(i).g, 200);
    EXPECT_LT(a.colour(i).r, 200);
  }
}

INSTANTIATE_TEST_SUITE_P(SurfelMerge, PlantedDuplicates, ::testing::Values(0.7f, 5.0f));

TEST(SurfelMerge, DisabledOrStridedMerging) {
  fusiontest::Scene scene;
  scene.wall_z = kWallZ;
  const auto f0 = fusiontest::renderScene(scene, kK, Eigen::Isometry3d::Identity(), 0.0);
  {
    TFusionParams p;
    p.merge_redundant = false;
    SurfelFusion fusion(p);
    PlantedMap pm;
    plant(fusion, pm, f0);
    const FusionStats st = fusion.fuse(
        pm.map,
        fusiontest::renderScene(scene, kK, Eigen::Isometry3d::Identity(), 1.0 / 30).input());
    EXPECT_EQ(st.merged, 0);
    EXPECT_EQ(pm.map.size(), pm.n_first + pm.n_dups + pm.n_decoys);
  }
  {
    // Stride 3: each frame merges a third of the rows; after 3 frames every duplicate is gone.
    TFusionParams p;
    p.merge_row_stride = 3;
    SurfelFusion fusion(p);
    PlantedMap pm;
    plant(fusion, pm, f0);
    int merged = 0, added = 0, removed = 0;
    for (int k = 1; k <= 3; ++k) {
      const FusionStats st = fusion.fuse(
          pm.map,
          fusiontest::renderScene(scene, kK, Eigen::Isometry3d::Identity(), k / 30.0).input());
      EXPECT_LT(st.merged, pm.n_dups * 0.4) << "frame " << k;
      EXPECT_GT(st.merged, pm.n_dups * 0.27) << "frame " << k;
      merged += st.merged;
      added += st.added;
      removed += st.removed_carved + st.removed_unstable;
    }
    EXPECT_EQ(merged, pm.n_dups);
    // A merged survivor sits between the two centres; a pixel whose 4x4 block it left may find
    // no candidate and no covering neighbour and add a surfel: a handful, not a duplicate layer.
    EXPECT_LT(added, pm.n_first / 500);
    EXPECT_EQ(removed, 0);
    EXPECT_EQ(pm.map.size(), pm.n_first + pm.n_decoys + added);
  }
}

TEST(SurfelMerge, ResultIsIndependentOfThreadCount) {
  // The renderer's order of a pixel's candidates depends on the thread schedule; merging (order
  // sensitive for chains of overlapping surfels and in float sums) must not.
  fusiontest::Scene scene;
  scene.wall_z = kWallZ;
  scene.boxes.push_back(fusiontest::Box{Eigen::Vector3d(-0.3, -0.25, 1.5),
                                        Eigen::Vector3d(0.3, 0.25, 1.9), Bgr8{0, 0, 255}});
  auto run = [&](int threads) {
    omp_set_num_threads(threads);
    TFusionParams p;
    p.merge_row_stride = 1;
    SurfelFusion fusion(p);
    PlantedMap pm;
    plant(fusion, pm, fusiontest::renderScene(scene, kK, Eigen::Isometry3d::Identity(), 0.0));
    int merged = 0;
    for (int k = 1; k < 6; ++k) {
      Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
      T.translation() = Eigen::Vector3d(0.004 * k, -0.003 * k, 0.002 * k);
      merged += fusion.fuse(pm.map, fusiontest::renderScene(scene, kK, T, k / 30.0).input()).merged;
    }
    EXPECT_GE(merged, pm.n_dups);
    return std::move(pm.map);
  };
  const int nt = omp_get_max_threads();
  const SurfelStore a = run(1), b = run(std::max(3, nt));
  omp_set_num_threads(nt);
  ASSERT_EQ(a.size(), b.size());
  for (int i = 0; i < a.size(); ++i) {
    ASSERT_EQ(a.arrays().pos_conf[i], b.arrays().pos_conf[i]) << i;
    ASSERT_EQ(a.arrays().normal_radius[i], b.arrays().normal_radius[i]) << i;
    ASSERT_EQ(a.arrays().colour_flags[i], b.arrays().colour_flags[i]) << i;
  }
}
