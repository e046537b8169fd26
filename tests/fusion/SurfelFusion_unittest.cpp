// Surfel fusion (II-B, II-D) on analytic frames: initialization, repeated fusion of a static view,
// stability, carving of a removed object, pruning of old unstable surfels, segment weights (III),
// basis and view bins (V-B), determinism, strict INI params.

#include "rasm/fusion/SurfelFusion.h"

#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <tuple>

#include "SyntheticScene.h"
#include "rasm/compute/Device.h"
#include "rasm/core/ComputeOptions.h"
#include "rasm/core/Error.h"
#include "rasm/core/Params.h"
#include "rasm/core/SurfelMath.h"
#include "rasm/surfel_map/kernels/ViewBins.h"

using namespace rasm;
using namespace rasm::maps;
using namespace rasm::fusion;
using rasm::fusiontest::Box;
using rasm::fusiontest::Scene;

namespace {

const CameraIntrinsics kK(131.25, 131.25, 79.5, 59.5, 160, 120);  // 640x480 Kinect / 4

int countValid(const fusiontest::SyntheticFrame& f, const TFusionParams& p) {
  int n = 0;
  for (int y = 0; y < f.vertex.height(); ++y)
    for (int x = 0; x < f.vertex.width(); ++x) {
      const Vec3f v = f.vertex(x, y), nn = f.normal(x, y);
      if (v.x() == v.x() && nn.x() == nn.x() && v.z() >= p.min_depth_m && v.z() <= p.max_depth_m &&
          -nn.dot(v) / v.norm() >= std::cos(p.max_incidence_deg * M_PI / 180.0))
        ++n;
    }
  return n;
}

Scene wallAndBox() {
  Scene s;
  s.wall_z = 3.0;
  s.boxes.push_back(
      Box{Eigen::Vector3d(-0.3, -0.25, 1.5), Eigen::Vector3d(0.3, 0.25, 1.9), Bgr8{0, 0, 255}});
  return s;
}

}  // namespace

TEST(SurfelFusion, FirstFrameInitializesOneSurfelPerValidPixel) {
  Scene scene;
  const auto f = fusiontest::renderScene(scene, kK, Eigen::Isometry3d::Identity(), 10.0);
  TFusionParams p;
  SurfelFusion fusion(p);
  SurfelStoreOptions layout;
  layout.n_classes = 3;
  SurfelStore map(layout);
  const FusionStats st = fusion.fuse(map, f.input());
  const int valid = countValid(f, p);
  EXPECT_EQ(st.added, valid);
  EXPECT_EQ(st.associated, 0);
  EXPECT_EQ(map.size(), valid);
  std::string why;
  EXPECT_TRUE(map.checkConsistency(&why)) << why;

  // Every surfel has the II-B initial attributes of its pixel.
  const SurfelArrays a = map.arrays();
  const Image<std::int32_t>& px = fusion.pixelSurfels();
  int checked = 0;
  for (int y = 0; y < kK.height; ++y)
    for (int x = 0; x < kK.width; ++x) {
      const int i = px(x, y);
      if (i < 0) continue;
      ++checked;
      ASSERT_LT(i, a.size);
      EXPECT_NEAR((a.position(i) - f.vertex(x, y)).norm(), 0.0f, 1e-5f);
      EXPECT_NEAR(a.normal(i).z(), -1.0f, 1e-4f);
      const float w =
          confidenceWeight(normalizedRadialDistance(float(x), float(y), kK.plain()), 0.6f);
      EXPECT_NEAR(a.confidence(i), w, 1e-6f);
      EXPECT_NEAR(a.segment_w[i], 0.0f, 0.0f);  // no label image
      EXPECT_NEAR(a.radius(i), surfelRadius(3.0f, -1.0f, float(kK.fx)), 1e-6f);
      EXPECT_NEAR(a.basis[i].dot(a.normal(i)), 0.0f, 1e-5f);
      EXPECT_NEAR(a.basis[i].norm(), 1.0f, 1e-5f);
      EXPECT_TRUE(classEvidenceEmpty(a.classEvidence(i)));  // every class at the 0.5 prior
      EXPECT_EQ(a.colour(i).r, 200);
      EXPECT_FALSE(a.stable(i));
      EXPECT_EQ(a.t_init[i], 0.0f);  // first frame is the time origin
    }
  EXPECT_EQ(checked, valid);
  // Surfels were added in row-major pixel order (deterministic compaction).
  int prev = -1;
  for (int y = 0; y < kK.height; ++y)
    for (int x = 0; x < kK.width; ++x)
      if (px(x, y) >= 0) {
        EXPECT_EQ(px(x, y), prev + 1);
        prev = px(x, y);
      }
}

TEST(SurfelFusion, StaticViewKeepsSurfelCountAndBecomesStable) {
  const Scene scene = wallAndBox();
  TFusionParams p;
  SurfelFusion fusion(p);
  SurfelStore map;
  const int frames = 25;
  int n_first = 0;
  for (int k = 0; k < frames; ++k) {
    const auto f =
        fusiontest::renderScene(scene, kK, Eigen::Isometry3d::Identity(), 100.0 + k / 30.0);
    const FusionStats st = fusion.fuse(map, f.input());
    if (k == 0) {
      n_first = map.size();
    } else {
      // The same view again: every valid pixel finds its surfel; nothing new, nothing removed.
      EXPECT_LE(st.added, n_first / 1000) << "frame " << k;
      EXPECT_GE(st.associated, st.valid_pixels - n_first / 1000);
      EXPECT_EQ(st.removed_carved, 0);
      EXPECT_EQ(st.removed_unstable, 0);
    }
  }
  EXPECT_NEAR(map.size(), n_first, n_first / 1000.0);
  // Confidence accumulates w per frame: surfels with w > 10 / 25 = 0.4 are stable now.
  const SurfelArrays a = map.arrays();
  int stable = 0, expect_stable = 0;
  for (int i = 0; i < a.size; ++i) {
    stable += a.stable(i);
    const Vec3f pc = a.position(i);
    const float u = kK.fx * pc.x() / pc.z() + kK.cx, v = kK.fy * pc.y() / pc.z() + kK.cy;
    const float w = confidenceWeight(normalizedRadialDistance(u, v, kK.plain()), 0.6f);
    if (w * frames >= p.stable_confidence * 1.02f) {
      ++expect_stable;
      EXPECT_TRUE(a.stable(i)) << "surfel " << i << " conf " << a.confidence(i);
    }
    EXPECT_NEAR(a.confidence(i), w * frames, 0.02f * w * frames + 1e-3f);
  }
  EXPECT_GT(expect_stable, a.size / 2);
  EXPECT_GE(stable, expect_stable);
  std::string why;
  EXPECT_TRUE(map.checkConsistency(&why)) << why;
}

TEST(SurfelFusion, SmallMotionsFuseIntoTheSameSurfels) {
  // A slightly moving camera (2 mm, 0.2 deg per frame) still associates most pixels: surfels are
  // averaged, not duplicated.
  Scene scene;
  TFusionParams p;
  SurfelFusion fusion(p);
  SurfelStore map;
  int n_first = 0;
  for (int k = 0; k < 10; ++k) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.translation() = Eigen::Vector3d(0.002 * k, 0.0, 0.0);
    T.linear() = Eigen::AngleAxisd(0.0035 * k, Eigen::Vector3d::UnitY()).toRotationMatrix();
    const auto f = fusiontest::renderScene(scene, kK, T, k / 30.0);
    const FusionStats st = fusion.fuse(map, f.input());
    if (k == 0)
      n_first = map.size();
    else
      EXPECT_GT(st.associated, 0.9 * st.valid_pixels) << "frame " << k;
  }
  EXPECT_LT(map.size(), 1.15 * n_first);
  // All surfels stay on the wall plane.
  const SurfelArrays a = map.arrays();
  for (int i = 0; i < a.size; ++i) ASSERT_NEAR(a.position(i).z(), 3.0f, 1e-3f);
}

TEST(SurfelFusion, PublicPassesAreFuseAndTheIndexMapShowsTheMapAtTheFramePose) {
  // The four passes run one by one give the map fuse() gives; between pass 1 and 2 the index map
  // holds, for a pixel on the box, candidates at the box's depth (label propagation reads it).
  const Scene scene = wallAndBox();
  TFusionParams p;
  SurfelFusion whole(p), passes(p);
  SurfelStore a, b;
  for (int k = 0; k < 4; ++k) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.translation() = Eigen::Vector3d(0.003 * k, 0.0, 0.0);
    const auto f = fusiontest::renderScene(scene, kK, T, k / 30.0);
    const FusionStats sw = whole.fuse(a, f.input());
    FusionStats sp;
    const IndexMapView view = passes.renderIndexMap(b, f.input(), sp);
    ASSERT_TRUE(view.valid());
    ASSERT_EQ(view.width(), kK.width);
    if (k > 0) {
      // Pixel (80, 60) looks at the box front (z = 1.5 - 0.003 * 0: the camera moves in x only).
      int n = 0;
      view.forEachCandidate(80, 60, [&](int i, float z) {
        EXPECT_GE(i, 0);
        EXPECT_LT(i, b.size());
        EXPECT_NEAR(z, 1.5f, 0.01f);
        ++n;
      });
      EXPECT_GT(n, 0);
    }
    passes.updateSurfels(b, f.input(), sp);
    passes.addSurfels(b, f.input(), sp);
    passes.cleanup(b, f.input(), sp);
    EXPECT_FALSE(passes.indexMap().valid()) << "the cleanup moved surfels: the view ends with it";
    EXPECT_EQ(sp.associated, sw.associated);
    EXPECT_EQ(sp.added, sw.added);
    EXPECT_EQ(sp.map_size, sw.map_size);
  }
  ASSERT_EQ(a.size(), b.size());
  const SurfelArrays aa = a.arrays(), ba = b.arrays();
  for (int i = 0; i < aa.size; ++i) ASSERT_EQ(aa.position(i), ba.position(i)) << i;
  // Out of order is a programming error, not a silent half-update.
  const auto f = fusiontest::renderScene(scene, kK, Eigen::Isometry3d::Identity(), 1.0);
  FusionStats st;
  EXPECT_THROW(passes.updateSurfels(b, f.input(), st), std::logic_error);
  passes.renderIndexMap(b, f.input(), st);
  EXPECT_THROW(passes.addSurfels(b, f.input(), st), std::logic_error);
}

TEST(SurfelFusion, MovedObjectIsCarvedAway) {
  TFusionParams p;
  SurfelFusion fusion(p);
  SurfelStore map;
  const Scene with_box = wallAndBox();
  Scene without_box;
  double t = 0.0;
  for (int k = 0; k < 20; ++k, t += 1.0 / 30)
    fusion.fuse(map,
                fusiontest::renderScene(with_box, kK, Eigen::Isometry3d::Identity(), t).input());
  auto countBox = [&] {
    int n = 0;
    const SurfelArrays a = map.arrays();
    for (int i = 0; i < a.size; ++i) n += a.position(i).z() < 2.5f;
    return n;
  };
  const int box_before = countBox();
  ASSERT_GT(box_before, 500);
  // The box is gone: the wall behind it is observed. Stable box surfels lose half their confidence
  // per frame (20 w -> 10 w -> 5 w < 10: demoted), unstable ones go at once.
  FusionStats last;
  int carved = 0, demoted = 0;
  for (int k = 0; k < 4; ++k, t += 1.0 / 30) {
    last = fusion.fuse(
        map, fusiontest::renderScene(without_box, kK, Eigen::Isometry3d::Identity(), t).input());
    carved += last.removed_carved;
    demoted += last.demoted_carved;
  }
  EXPECT_EQ(countBox(), 0);
  EXPECT_GE(carved, box_before);
  EXPECT_GT(demoted, 0);
  // The wall behind the box is now mapped: every valid pixel of the last frame has a surfel.
  EXPECT_EQ(last.added + last.associated, last.valid_pixels);
  std::string why;
  EXPECT_TRUE(map.checkConsistency(&why)) << why;
}

TEST(SurfelFusion, CarvingTraversalsAgree) {
  // One rule (CarveTest), two traversals: the CPU path takes the update pass's verdicts for the
  // surfels it updated and the candidate lists' centres for the others; CarveKernel (the CUDA
  // path's, and the CPU's with simd_off = fusion) judges every visible surfel on its current
  // state. Two identical runs whose cleanups carve by one traversal each must stay equal bit
  // for bit while the box moves 30 cm (its old place carved, stable surfels demoted).
  TFusionParams p;
  SurfelFusion fa(p), fb(p);
  SurfelStore a, b;
  const Scene with_box = wallAndBox();
  Scene moved = with_box;
  moved.boxes[0].lo.x() += 0.3;
  moved.boxes[0].hi.x() += 0.3;
  struct KernelCarving {  // simd_off = fusion for one cleanup, restored whatever happens
    KernelCarving() { compute::setSimdEnabled(compute::SimdPath::Fusion, false); }
    ~KernelCarving() { compute::setSimdEnabled(compute::SimdPath::Fusion, true); }
  };
  double t = 0.0;
  int removed = 0, demoted = 0;
  for (int k = 0; k < 28; ++k, t += 1.0 / 30) {
    const Eigen::Isometry3d T(Eigen::Translation3d(0.01 * std::sin(0.5 * k), 0.0, 0.0));
    const auto f = fusiontest::renderScene(k < 20 ? with_box : moved, kK, T, t);
    FusionStats sa, sb;
    fa.renderIndexMap(a, f.input(), sa);
    fa.updateSurfels(a, f.input(), sa);
    fa.addSurfels(a, f.input(), sa);
    fa.cleanup(a, f.input(), sa);
    fb.renderIndexMap(b, f.input(), sb);
    fb.updateSurfels(b, f.input(), sb);
    fb.addSurfels(b, f.input(), sb);
    {
      KernelCarving kernel;
      fb.cleanup(b, f.input(), sb);
    }
    ASSERT_EQ(sa.removed_carved, sb.removed_carved) << "frame " << k;
    ASSERT_EQ(sa.demoted_carved, sb.demoted_carved) << "frame " << k;
    removed += sa.removed_carved;
    demoted += sa.demoted_carved;
    ASSERT_EQ(a.size(), b.size()) << "frame " << k;
    const SurfelArrays aa = a.arrays(), ba = b.arrays();
    for (int i = 0; i < aa.size; ++i) {
      ASSERT_EQ(aa.position(i), ba.position(i)) << "frame " << k << " surfel " << i;
      ASSERT_EQ(aa.pos_conf[i].w(), ba.pos_conf[i].w()) << "frame " << k << " surfel " << i;
      ASSERT_EQ(aa.stable(i), ba.stable(i)) << "frame " << k << " surfel " << i;
    }
  }
  // The box's old place, 30 x 50 cm at 1.5 m under a 131 px focal length: 26 x 44 = 1145 pixels'
  // surfels, stable after 20 frames, demoted and then removed in the 8 frames after the move
  // (half of them at least: the frame's border rows and the wall's new edge keep some).
  EXPECT_GT(removed, 570);
  EXPECT_GT(demoted, 570);
}

TEST(SurfelFusion, OneBadFrameDoesNotEraseStableStructure) {
  TFusionParams p;
  SurfelFusion fusion(p);
  SurfelStore map;
  const Scene with_box = wallAndBox();
  double t = 0.0;
  for (int k = 0; k < 30; ++k, t += 1.0 / 30)
    fusion.fuse(map,
                fusiontest::renderScene(with_box, kK, Eigen::Isometry3d::Identity(), t).input());
  const int n = map.size();
  fusion.fuse(map, fusiontest::renderScene(Scene(), kK, Eigen::Isometry3d::Identity(), t)
                       .input());  // box missing once
  int box = 0;
  const SurfelArrays a = map.arrays();
  for (int i = 0; i < a.size; ++i) box += a.position(i).z() < 2.5f;
  EXPECT_GT(box, 500);  // stable box surfels (w ~ 30 w_pixel) only lost confidence
  EXPECT_GE(map.size(), n - n / 10);
}

TEST(SurfelFusion, OldUnstableSurfelsArePruned) {
  TFusionParams p;
  p.unstable_max_age_s = 2.0;
  p.unstable_max_idle_s = 100.0;  // age only (idle pruning: next test)
  SurfelFusion fusion(p);
  SurfelStore map;
  Scene scene;
  // 12 frames: centre surfels (w > 10/12) become stable, the periphery stays unstable.
  for (int k = 0; k < 12; ++k)
    fusion.fuse(
        map, fusiontest::renderScene(scene, kK, Eigen::Isometry3d::Identity(), k / 30.0).input());
  int stable = 0;
  for (int i = 0; i < map.size(); ++i) stable += map.arrays().stable(i);
  ASSERT_GT(stable, 0);
  ASSERT_LT(stable, map.size());
  // Look away (empty frame) 1.5 s later: nothing is old enough yet.
  fusiontest::SyntheticFrame empty =
      fusiontest::renderScene(scene, kK, Eigen::Isometry3d::Identity(), 1.5, 0.5);
  const int before = map.size();
  FusionStats st = fusion.fuse(map, empty.input());
  EXPECT_EQ(st.removed_unstable, 0);
  EXPECT_EQ(map.size(), before);
  // 2.5 s after the first frame: every unstable surfel is older than 2 s.
  empty.frame.timestamp_s = 2.5;
  st = fusion.fuse(map, empty.input());
  EXPECT_EQ(st.removed_unstable, before - stable);
  EXPECT_EQ(map.size(), stable);
  for (int i = 0; i < map.size(); ++i) EXPECT_TRUE(map.arrays().stable(i));
  std::string why;
  EXPECT_TRUE(map.checkConsistency(&why)) << why;
}

TEST(SurfelFusion, IdleUnstableSurfelsArePrunedBeforeTheAgeLimit) {
  TFusionParams p;
  p.unstable_max_age_s = 100.0;
  p.unstable_max_idle_s = 0.5;
  SurfelFusion fusion(p);
  SurfelStore map;
  // Left half of the view seen once at t = 0, the whole view fused again at t = 0.3 and 0.6 s:
  // the left half is re-observed, nothing is idle for 0.5 s yet.
  Scene scene;
  auto frame = fusiontest::renderScene(scene, kK, Eigen::Isometry3d::Identity(), 0.0);
  fusion.fuse(map, frame.input());
  const int n = map.size();
  for (double t : {0.3, 0.6}) {
    frame.frame.timestamp_s = t;
    EXPECT_EQ(fusion.fuse(map, frame.input()).removed_unstable, 0);
  }
  // Now only the right half is observed (left half depth invalid) at t = 0.9 and 1.2 s: the
  // left half's surfels were last fused at 0.6 s, idle for 0.6 s > 0.5 s at t = 1.2 s.
  auto right = fusiontest::renderScene(scene, kK, Eigen::Isometry3d::Identity(), 0.9);
  for (int y = 0; y < kK.height; ++y)
    for (int x = 0; x < kK.width / 2; ++x) right.frame.depth_m(x, y) = 0.0f;
  computeVertexMap(right.frame.depth_m, kK, right.vertex);
  computeNormalMap(right.vertex, right.normal);
  right.frame.timestamp_s = 0.9;
  EXPECT_EQ(fusion.fuse(map, right.input()).removed_unstable, 0);
  right.frame.timestamp_s = 1.2;
  const FusionStats st = fusion.fuse(map, right.input());
  EXPECT_GT(st.removed_unstable, n / 2 - kK.height * 2);
  EXPECT_LT(st.removed_unstable, n / 2 + kK.height * 2);
  for (int i = 0; i < map.size(); ++i) EXPECT_GT(map.arrays().position(i).x(), -0.05f);
}

TEST(SurfelFusion, SegmentWeightsFollowThePropagatedLabels) {
  Scene scene;
  TFusionParams p;
  SurfelFusion fusion(p);
  SurfelStore map;
  const auto f = fusiontest::renderScene(scene, kK, Eigen::Isometry3d::Identity(), 0.0);
  Image<std::uint32_t> l7(kK.width, kK.height, 7u), l9(kK.width, kK.height, 9u);
  fusion.fuse(map, f.input(&l7));
  const int cx = kK.width / 2, cy = kK.height / 2;
  const int i = fusion.pixelSurfels()(cx, cy);
  ASSERT_GE(i, 0);
  const float w = map.arrays().confidence(i);  // one measurement: w of that pixel
  EXPECT_EQ(map.arrays().segment[i], 7u);
  EXPECT_FLOAT_EQ(map.arrays().segment_w[i], w);
  // Surfel indices may change at every fuse() (compaction, re-sorting by block): follow the
  // pixel's surfel through pixelSurfels(). The same surfel keeps being updated (count constant).
  const int n = map.size();
  const auto fuseAndFollow = [&](const Image<std::uint32_t>* labels) {
    const FusionStats st = fusion.fuse(map, labels ? f.input(labels) : f.input());
    const int j = fusion.pixelSurfels()(cx, cy);
    EXPECT_GE(j, 0);
    EXPECT_EQ(map.size(), n);
    EXPECT_EQ(st.added, 0);
    return std::make_pair(j, st);
  };
  int j = fuseAndFollow(&l7).first;
  EXPECT_NEAR(map.arrays().segment_w[j], 2 * w, 1e-5f);
  // Label 9 twice: 2w - w = w, then 0 -> relabel to 9 with weight w.
  j = fuseAndFollow(&l9).first;
  EXPECT_EQ(map.arrays().segment[j], 7u);
  EXPECT_NEAR(map.arrays().segment_w[j], w, 1e-5f);
  FusionStats st;
  std::tie(j, st) = fuseAndFollow(&l9);
  EXPECT_EQ(map.arrays().segment[j], 9u);
  EXPECT_NEAR(map.arrays().segment_w[j], w, 1e-5f);
  EXPECT_EQ(st.relabelled, st.associated);
  // Without a label image the segment is left alone.
  j = fuseAndFollow(nullptr).first;
  EXPECT_EQ(map.arrays().segment[j], 9u);
}

TEST(SurfelFusion, BasisStaysInPlaneAndViewBinsRecordTheView) {
  Scene scene;
  TFusionParams p;
  p.ic_d_min_m = 1.0f;
  p.ic_lambda1 = 0.5f;
  SurfelFusion fusion(p);
  SurfelStoreOptions layout;
  layout.view_bins_azimuth = 8;
  layout.view_bins_elevation = 2;
  SurfelStore map(layout);
  fusion.fuse(map, fusiontest::renderScene(scene, kK, Eigen::Isometry3d::Identity(), 0.0).input());
  // A second view from the side (camera 0.8 m to the left, looking at the wall centre).
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = Eigen::Vector3d(-0.8, 0.0, 0.0);
  T.linear() = Eigen::AngleAxisd(std::atan2(0.8, 3.0), Eigen::Vector3d::UnitY()).toRotationMatrix();
  fusion.fuse(map, fusiontest::renderScene(scene, kK, T, 0.1).input());
  const SurfelArrays a = map.arrays();
  const Vec3f c0 = Vec3f::Zero(), c1 = T.translation().cast<float>();
  int two_bins = 0;
  for (int i = 0; i < a.size; ++i) {
    EXPECT_NEAR(a.basis[i].dot(a.normal(i)), 0.0f, 1e-4f);
    EXPECT_NEAR(a.basis[i].norm(), 1.0f, 1e-4f);
    // IC(s) = exp(-lambda1 (max(d, d_min) - d_min)) of one of the two views, quantised to 1/255.
    const Vec3f p_s = a.position(i);
    const float ic0 = maps::kernels::informationContent((p_s - c0).norm(), 0.5f, 1.0f);
    const float ic1 = maps::kernels::informationContent((p_s - c1).norm(), 0.5f, 1.0f);
    int nonzero = 0;
    for (int b = 0; b < a.n_view_bins; ++b) {
      const float ic = dequantizeUnit(a.viewRow(i)[b]);
      if (ic > 0.0f) {
        ++nonzero;
        EXPECT_LT(std::min(std::abs(ic - ic0), std::abs(ic - ic1)), 0.6f / 255.0f + 2e-3f)
            << "surfel " << i;
      }
    }
    EXPECT_GE(nonzero, 1);
    two_bins += nonzero >= 2;
  }
  EXPECT_GT(two_bins, 0);  // seen from two directions that fall into different bins
}

TEST(SurfelFusion, ResultIsIndependentOfThreadCount) {
  const Scene scene = wallAndBox();
  auto run = [&](int threads) {
    omp_set_num_threads(threads);
    SurfelFusion fusion;
    SurfelStore map;
    for (int k = 0; k < 5; ++k) {
      Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
      T.translation() = Eigen::Vector3d(0.01 * k, 0.005 * k, 0.0);
      fusion.fuse(map, fusiontest::renderScene(k < 3 ? scene : Scene(), kK, T, k / 30.0).input());
    }
    return map;
  };
  const int nt = omp_get_max_threads();
  const SurfelStore a = run(1), b = run(std::max(2, nt));
  omp_set_num_threads(nt);
  ASSERT_EQ(a.size(), b.size());
  for (int i = 0; i < a.size(); ++i) {
    ASSERT_EQ(a.arrays().pos_conf[i], b.arrays().pos_conf[i]);
    ASSERT_EQ(a.arrays().normal_radius[i], b.arrays().normal_radius[i]);
    ASSERT_EQ(a.arrays().colour_flags[i], b.arrays().colour_flags[i]);
  }
}

// [fusion] resort_unsorted_fraction: re-sorting the store by block before a frame changes surfel
// indices only. With merging off (its pairing follows index order) the map after a moving
// sequence is the same set of surfels whether the store is re-sorted before every frame or never;
// with every stage on, the spatial index (blocks, stable parts) stays consistent frame by frame.
TEST(SurfelFusion, ResortingTheStoreKeepsTheMapAndTheIndex) {
  const Scene scene = wallAndBox();
  using Key = std::tuple<float, float, float, float, float, float, float, float, std::uint32_t>;
  auto run = [&](float resort, bool merge, std::vector<Key>* keys) {
    TFusionParams p;
    p.resort_unsorted_fraction = resort;
    p.merge_redundant = merge;
    p.stable_confidence = 3.0f;  // surfels turn stable (and carving demotes some) within the run
    SurfelFusion fusion(p);
    SurfelStore map;
    int resorted = 0;
    for (int k = 0; k < 12; ++k) {
      Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
      T.translation() = Eigen::Vector3d(0.02 * k, 0.01 * k, 0.005 * k);
      T.linear() = Eigen::AngleAxisd(0.01 * k, Eigen::Vector3d::UnitY()).toRotationMatrix();
      const FusionStats st = fusion.fuse(
          map, fusiontest::renderScene(k < 8 ? scene : Scene(), kK, T, k / 30.0).input());
      resorted += st.resorted ? 1 : 0;
      std::string why;
      EXPECT_TRUE(map.checkConsistency(&why)) << "frame " << k << ": " << why;
    }
    if (keys) {
      const SurfelArrays a = map.arrays();
      for (int i = 0; i < a.size; ++i)
        keys->emplace_back(a.pos_conf[i].x(), a.pos_conf[i].y(), a.pos_conf[i].z(),
                           a.pos_conf[i].w(), a.normal_radius[i].x(), a.normal_radius[i].y(),
                           a.normal_radius[i].z(), a.normal_radius[i].w(), a.colour_flags[i]);
      std::sort(keys->begin(), keys->end());
    }
    return resorted;
  };
  std::vector<Key> never, always;
  EXPECT_EQ(run(1.0f, false, &never), 0);
  EXPECT_GE(run(0.0f, false, &always), 10);
  ASSERT_EQ(never.size(), always.size());
  EXPECT_TRUE(never == always);
  EXPECT_GE(run(0.0f, true, nullptr), 10);
}

// Class evidence (IV) is per surfel: fusion's compaction (carving, pruning), re-sorting by block
// and merging move it with its surfel. Each surfel of the first frame gets evidence derived from
// a tag kept in its segment label (fusion leaves labels alone without a label image); after a
// moving sequence in which the box disappears, every surviving tagged surfel still carries its
// tag's evidence, and surfels created later carry none (unless a merge gave them a tagged
// surfel's label and evidence together).
TEST(SurfelFusion, ClassEvidenceTravelsWithItsSurfel) {
  const Scene scene = wallAndBox();
  TFusionParams p;
  p.resort_unsorted_fraction = 0.0f;  // re-sort before every frame
  p.merge_row_stride = 1;
  p.stable_confidence = 3.0f;
  SurfelFusion fusion(p);
  SurfelStore map;  // the default layout: kDefaultNumClasses classes
  ASSERT_EQ(map.options().n_classes, kDefaultNumClasses);
  fusion.fuse(map, fusiontest::renderScene(scene, kK, Eigen::Isometry3d::Identity(), 0.0).input());
  const auto evidenceOf = [](std::uint32_t tag) {
    ClassEvidence e;
    classEvidenceAdd(e, 1 + int(tag % 96), 1 + int(tag % 5000));
    classEvidenceAdd(e, 1 + int((tag / 96) % 96), -1 - int(tag % 3000));
    return e;
  };
  {
    const SurfelArrays a = map.arrays();
    for (int i = 0; i < a.size; ++i) {
      a.segment[i] = std::uint32_t(i + 1);
      a.classEvidence(i) = evidenceOf(std::uint32_t(i + 1));
    }
  }
  const int n0 = map.size();
  int removed = 0, merged = 0, resorted = 0;
  for (int k = 1; k < 12; ++k) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.translation() = Eigen::Vector3d(0.02 * k, 0.01 * k, 0.005 * k);
    T.linear() = Eigen::AngleAxisd(0.01 * k, Eigen::Vector3d::UnitY()).toRotationMatrix();
    const FusionStats st =
        fusion.fuse(map, fusiontest::renderScene(k < 8 ? scene : Scene(), kK, T, k / 30.0).input());
    removed += st.removed_carved + st.removed_unstable;
    merged += st.merged;
    resorted += st.resorted ? 1 : 0;
  }
  EXPECT_GT(removed, 100);
  EXPECT_GT(merged, 0);
  EXPECT_GE(resorted, 10);
  const SurfelArrays a = map.arrays();
  int tagged = 0;
  for (int i = 0; i < a.size; ++i) {
    const ClassEvidence& e = a.classEvidence(i);
    const std::uint32_t tag = a.segment[i];
    if (tag == 0) {
      ASSERT_TRUE(classEvidenceEmpty(e)) << "surfel " << i;
      continue;
    }
    ++tagged;
    const ClassEvidence want = evidenceOf(tag);
    for (int q = 0; q < kClassSlots; ++q) {
      ASSERT_EQ(e.id[q], want.id[q]) << "surfel " << i << " tag " << tag;
      ASSERT_EQ(e.logit[q], want.logit[q]) << "surfel " << i << " tag " << tag;
    }
  }
  EXPECT_GT(tagged, n0 / 2);
  EXPECT_LT(tagged, n0);
}

TEST(SurfelFusion, InputSizeMismatchIsAnInputError) {
  const auto f = fusiontest::renderScene(Scene(), kK, Eigen::Isometry3d::Identity(), 0.0);
  FusionInput in = f.input();
  in.K.width = 320;
  SurfelStore map;
  SurfelFusion fusion;
  EXPECT_THROW(fusion.fuse(map, in), InputError);
}

TEST(TFusionParams, StrictIniLoading) {
  TFusionParams p;
  mrpt::config::CConfigFileMemory ok("[fusion]\nconfidence_sigma = 0.5\nstable_confidence = 12\n");
  loadParamsStrict(ok, "fusion", p, "test.ini");
  EXPECT_FLOAT_EQ(p.confidence_sigma, 0.5f);
  EXPECT_FLOAT_EQ(p.stable_confidence, 12.0f);
  mrpt::config::CConfigFileMemory bad("[fusion]\nstable_confidense = 12\n");
  try {
    loadParamsStrict(bad, "fusion", p, "test.ini");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("stable_confidense"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("test.ini"), std::string::npos);
  }
  mrpt::config::CConfigFileMemory range("[fusion]\ncarve_stable_decay = 1.5\n");
  EXPECT_THROW(loadParamsStrict(range, "fusion", p, "test.ini"), InputError);
  // Paper default (II-B).
  EXPECT_FLOAT_EQ(TFusionParams().confidence_sigma, 0.6f);
}

TEST(SurfelFusionCuda, MatchesCpu) {
  const auto avail = compute::cudaAvailability();
  if (!avail.available) GTEST_SKIP() << avail.reason;
  const Scene scene = wallAndBox();
  SurfelStore cpu_map, gpu_map;
  SurfelFusion cpu(TFusionParams(), compute::Backend::Cpu),
      gpu(TFusionParams(), compute::Backend::Cuda);
  for (int k = 0; k < 4; ++k) {
    const auto f = fusiontest::renderScene(scene, kK, Eigen::Isometry3d::Identity(), k / 30.0);
    cpu.fuse(cpu_map, f.input());
    gpu.fuse(gpu_map, f.input());
  }
  ASSERT_EQ(cpu_map.size(), gpu_map.size());
  for (int i = 0; i < cpu_map.size(); ++i) {
    EXPECT_NEAR((cpu_map.arrays().position(i) - gpu_map.arrays().position(i)).norm(), 0.0f, 1e-5f);
    EXPECT_NEAR(cpu_map.arrays().confidence(i), gpu_map.arrays().confidence(i), 1e-4f);
  }
}
