// Object-centric information (V-B): the predicted view-bin gain of a view over a map fused by the
// real fusion (SurfelFusion) from synthetic depth of a flat wall, and its class weighting.

#include <gtest/gtest.h>

#include <cmath>
#include <numeric>
#include <vector>

#include "rasm/core/FrameProcessing.h"
#include "rasm/exploration/ObjectInformation.h"
#include "rasm/exploration/ViewPredictor.h"
#include "rasm/fusion/SurfelFusion.h"
#include "rasm/surfel_map/kernels/ViewBins.h"

namespace rasm::exploration {
namespace {

const double kWallX = 3.0;  // the wall is the plane x = 3, facing -x
const Eigen::Vector3d kTarget(kWallX, 0.0, 1.0);
const CameraIntrinsics kK(120.0, 120.0, 79.5, 59.5, 160, 120);

/// Optical camera at `eye` looking at `target` (image up = world +z).
Eigen::Isometry3d cameraLookingAt(const Eigen::Vector3d& eye, const Eigen::Vector3d& target) {
  const Eigen::Vector3d z = (target - eye).normalized();
  const Eigen::Vector3d x = z.cross(Eigen::Vector3d::UnitZ()).normalized();
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() << x, z.cross(x), z;
  T.translation() = eye;
  return T;
}

/// Depth of the wall plane seen from T (0 where the ray misses it).
Image<float> wallDepth(const Eigen::Isometry3d& T) {
  Image<float> depth(kK.width, kK.height, 0.0f);
  for (int y = 0; y < kK.height; ++y)
    for (int x = 0; x < kK.width; ++x) {
      const Eigen::Vector3d r =
          T.linear() * Eigen::Vector3d((x - kK.cx) / kK.fx, (y - kK.cy) / kK.fy, 1.0);
      const double t = (kWallX - T.translation().x()) / r.x();
      if (r.x() > 0.0 && t > 0.0) depth(x, y) = float(t);  // z of the hit (r has z_cam = 1)
    }
  return depth;
}

void fuseWall(fusion::SurfelFusion& fusion, maps::SurfelStore& store, const Eigen::Isometry3d& T,
              double time_s) {
  const Image<float> depth = wallDepth(T);
  Image<Vec3f> vertex, normal;
  computeVertexMap(depth, kK, vertex);
  computeNormalMap(vertex, normal);
  fusion::FusionInput in;
  in.depth_m = depth.view();
  in.vertex_cam = vertex.view();
  in.normal_cam = normal.view();
  in.K = kK;
  in.T_world_cam = T;
  in.timestamp_s = time_s;
  fusion.fuse(store, in);
}

class ObjectInformationTest : public ::testing::Test {
 protected:
  void SetUp() override {
    params_.predict_width = kK.width;
    params_.predict_height = kK.height;
    fuseWall(fusion_, store_, viewA(), 0.0);
    ASSERT_GT(store_.size(), 10000);
  }
  static Eigen::Isometry3d viewA() {  // head-on at 2.5 m: IC = exp(-0.5 * 1.5) = 0.47
    return cameraLookingAt(Eigen::Vector3d(0.5, 0.0, 1.0), kTarget);
  }
  InformationGain gainOf(const Eigen::Isometry3d& T) {
    ViewPredictor predictor(params_, model());
    return predictor.predict(store_, octree_, T, kK).information;
  }
  ViewInfoModel model() const { return ViewInfoModel::of(fusion_.params(), store_.options()); }

  TExplorationParams params_;
  fusion::SurfelFusion fusion_;
  maps::SurfelStore store_;
  OccupancyOctree octree_;
};

TEST_F(ObjectInformationTest, AThinnedMapPredictsWhatTheWholeMapDoes) {
  // The wall fused from 2.5 m has a surfel per pixel footprint (~2 cm); every 4th surfel with
  // twice the radius still covers it without holes, so a view from 1.5 m (inside the fused part)
  // renders the same depth: the same rays through the octree (dH equal up to the splats' edges)
  // and the same pixels with the same view bins (dIC per pixel within the surfel spacing's IC
  // step, 0.01, and the quantisation).
  const Eigen::Isometry3d closer = cameraLookingAt(Eigen::Vector3d(1.5, 0.0, 1.0), kTarget);
  ViewPredictor predictor(params_, model());
  const ViewPrediction whole = predictor.predict(store_, octree_, closer, kK);
  TExplorationParams thin_params = params_;
  thin_params.predict_max_surfels = store_.size() / 4;
  maps::SurfelStore thinned;
  const maps::SurfelStore& used = predictionStore(store_, thin_params, thinned);
  ASSERT_EQ(&used, &thinned);
  EXPECT_NEAR(thinned.size(), store_.size() / 4, 1);
  const ViewPrediction thin = predictor.predict(thinned, octree_, closer, kK);
  ASSERT_GT(whole.information.pixels, kK.width * kK.height * 9 / 10);
  EXPECT_NEAR(thin.information.pixels, whole.information.pixels, whole.information.pixels / 100);
  EXPECT_NEAR(thin.information.unweighted / thin.information.pixels,
              whole.information.unweighted / whole.information.pixels, 0.01 + 2.0 / 255);
  EXPECT_NEAR(thin.entropy_reduction, whole.entropy_reduction, 0.02 * whole.entropy_reduction);
  // Within the limit the map itself is used.
  thin_params.predict_max_surfels = store_.size();
  EXPECT_EQ(&predictionStore(store_, thin_params, thinned), &store_);
  thin_params.predict_max_surfels = 0;
  EXPECT_EQ(&predictionStore(store_, thin_params, thinned), &store_);
}

TEST_F(ObjectInformationTest, RepeatedViewGainsNothing) {
  const InformationGain g = gainOf(viewA());
  EXPECT_GT(g.pixels, kK.width * kK.height / 2);
  EXPECT_EQ(g.unweighted, 0.0);  // every bin already holds this view's quantised IC
}

TEST_F(ObjectInformationTest, CloserViewGainsTheICDifferenceInTheSameBin) {
  // Head-on at 1.5 m: same bin (elevation ring 1), IC 0.78 instead of 0.47 near the target.
  const Eigen::Isometry3d closer = cameraLookingAt(Eigen::Vector3d(1.5, 0.0, 1.0), kTarget);
  const InformationGain g = gainOf(closer);
  ASSERT_GT(g.pixels, 0);
  // The same bin for every point P of the wall in view (A and the closer camera differ along the
  // normal only: same azimuth; elevation above 45 deg from both), so each pixel gains
  // IC(|P - closer|) - IC(|P - A|) at its ray's wall point, give or take the quantisation and the
  // surfel spacing (2 cm: 0.01 in IC).
  const auto ic = [](double d) { return std::exp(-0.5 * std::max(d - 1.0, 0.0)); };
  double expected = 0.0;
  for (int y = 0; y < kK.height; ++y)
    for (int x = 0; x < kK.width; ++x) {
      const Eigen::Vector3d r =
          closer.linear() * Eigen::Vector3d((x - kK.cx) / kK.fx, (y - kK.cy) / kK.fy, 1.0);
      const Eigen::Vector3d P = closer.translation() + r * ((kWallX - 1.5) / r.x());
      expected += ic((P - closer.translation()).norm()) - ic((P - viewA().translation()).norm());
    }
  EXPECT_NEAR(g.unweighted / g.pixels, expected / (kK.width * kK.height), 0.01 + 2.0 / 255);
  EXPECT_GT(g.unweighted / g.pixels, 0.25);
}

TEST_F(ObjectInformationTest, NewDirectionGainsAnEmptyBinAndFusingItLeavesNothing) {
  // 60 degrees off the normal at the same 2.5 m: elevation ring 0 (asin(0.5) < 45 deg), empty.
  const Eigen::Vector3d eye(kWallX - 2.5 * std::cos(M_PI / 3), 2.5 * std::sin(M_PI / 3), 1.0);
  const Eigen::Isometry3d oblique = cameraLookingAt(eye, kTarget);
  const InformationGain before = gainOf(oblique);
  ASSERT_GT(before.pixels, 0);
  // An empty bin gains the whole IC: between IC(2.5) = 0.47 at the target and IC of the
  // farthest wall point in view.
  EXPECT_GT(before.unweighted / before.pixels, 0.2);
  EXPECT_GT(before.unweighted, 0.0);
  EXPECT_GT(before.unweighted, gainOf(viewA()).unweighted);
  // Fusion of that very view fills the bins of the surfels it associates or adds: over exactly
  // those surfels (the pixels' surfels of the frame) the prediction is now 0, i.e. it chose the
  // bins fusion chose. (Surfels in view that no pixel associated keep their empty bin: fusion
  // updates one surfel per pixel, so the head-on map, denser than the oblique view's pixels,
  // keeps some gain; docs/exploration.md.)
  fuseWall(fusion_, store_, oblique, 0.1);
  const InformationGain fused =
      predictedInformationGain(store_, fusion_.pixelSurfels(), oblique, model(), 1.0f);
  EXPECT_GT(fused.pixels, kK.width * kK.height / 4);  // the far side is beyond max depth
  EXPECT_LT(fused.unweighted, 1e-3 * before.unweighted);
  EXPECT_LT(gainOf(oblique).unweighted, 0.5 * before.unweighted);
}

TEST_F(ObjectInformationTest, GainIsWeightedByClassUncertainty) {
  const Eigen::Isometry3d closer = cameraLookingAt(Eigen::Vector3d(1.5, 0.0, 1.0), kTarget);
  const InformationGain none = gainOf(closer);
  EXPECT_NEAR(none.weighted, params_.ic_weight_floor * none.unweighted, 1e-9 * none.unweighted);
  std::vector<int> all(std::size_t(store_.size()));
  std::iota(all.begin(), all.end(), 0);
  store_.addClassEvidence(all, 3, 0.6f);  // one weak detection: p_best = 0.6, u = 0.8
  const InformationGain weak = gainOf(closer);
  EXPECT_NEAR(weak.weighted, 0.8 * weak.unweighted, 1e-3 * weak.unweighted);
}

TEST(ClassUncertaintyWeight, FloorWithoutEvidenceOneWhenUndecidedFloorWhenSettled) {
  maps::ClassEvidence e;
  EXPECT_EQ(classUncertaintyWeight(e, 0.25f), 0.25f);
  maps::classEvidenceUpdate(e, 7, 0.5f + 1e-3f);  // barely above the prior
  EXPECT_NEAR(classUncertaintyWeight(e, 0.25f), 1.0f, 0.01f);
  for (int k = 0; k < 5; ++k) maps::classEvidenceUpdate(e, 7, 0.9f);  // p -> 0.9999 (clamped)
  EXPECT_EQ(classUncertaintyWeight(e, 0.25f), 0.25f);
  maps::ClassEvidence against;
  maps::classEvidenceUpdate(against, 7, 0.1f);  // evidence only against: no class above 0.5
  EXPECT_EQ(classUncertaintyWeight(against, 0.25f), 1.0f);
}

TEST(ScaledIntrinsics, QuarterOfVga) {
  const CameraIntrinsics K(525.0, 525.0, 319.5, 239.5, 640, 480);
  const CameraIntrinsics q = K.resized(160, 120);
  EXPECT_DOUBLE_EQ(q.fx, 131.25);
  EXPECT_DOUBLE_EQ(q.cx, 79.5);
  EXPECT_DOUBLE_EQ(q.cy, 59.5);
  EXPECT_TRUE(q == K.level(2));
}

}  // namespace
}  // namespace rasm::exploration
