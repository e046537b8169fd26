// Tracker of section II-C on analytic scenes: known motions recovered, basin of convergence of
// the pyramid, degeneracy, lost tracks and recovery, noise.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <optional>
#include <random>
#include <tuple>

#include "rasm/core/Error.h"
#include "rasm/core/FrameProcessing.h"
#include "rasm/core/SE3.h"
#include "rasm/tracking/IcpTracker.h"
#include "tracking/SyntheticScene.h"

using namespace rasm;
using namespace rasm::tracking;
using rasm::test::lookAt;
using rasm::test::motion;
using rasm::test::Scene;
using rasm::test::WorldMaps;

namespace {

constexpr double kDeg = M_PI / 180.0;

const CameraIntrinsics K = CameraIntrinsics::preset("kinect_v1");

std::vector<FrameLevel> pyramidOf(const Image<float>& depth) {
  std::vector<FrameLevel> pyr;
  buildFramePyramid(depth, K, TTrackingParams::kMaxLevels, pyr);
  return pyr;
}

ModelMaps modelMaps(ImageView<const Vec3f> vertex, ImageView<const Vec3f> normal,
                    const Eigen::Isometry3d& T_world_model) {
  ModelMaps m;
  m.vertex_world = vertex;
  m.normal_world = normal;
  m.K = K;
  m.T_world_model = T_world_model;
  return m;
}

ModelMaps modelOf(const WorldMaps& m, const Eigen::Isometry3d& T_world_model) {
  return modelMaps(m.vertex.view(), m.normal.view(), T_world_model);
}

/// Frame A at T_a (the model), frame B at T_b; tracking B from `guess`.
struct Pair {
  Eigen::Isometry3d T_a, T_b;
  std::vector<FrameLevel> pyr_a, pyr_b;
  std::unique_ptr<WorldMaps> model;

  Pair(const Scene& scene, const Eigen::Isometry3d& Ta, const Eigen::Isometry3d& Tb,
       double sigma_m = 0.0)
      : T_a(Ta), T_b(Tb) {
    pyr_a = pyramidOf(scene.render(K, T_a, sigma_m, 11));
    pyr_b = pyramidOf(scene.render(K, T_b, sigma_m, 22));
    model = std::make_unique<WorldMaps>(pyr_a[0], T_a);
  }
  TrackingResult align(IcpTracker& tr, const Eigen::Isometry3d& guess) const {
    return tr.align(pyr_b, modelOf(*model, T_a), guess);
  }
};

const Eigen::Isometry3d kRoomPose = lookAt({0.3, -1.5, 1.3}, {-0.2, 0.8, 0.5});

void expectPoseNear(const Eigen::Isometry3d& est, const Eigen::Isometry3d& gt, double tol_m,
                    double tol_deg) {
  EXPECT_LT(translationDistance(gt, est), tol_m) << "translation error (m)";
  EXPECT_LT(rotationAngle(gt, est) / kDeg, tol_deg) << "rotation error (deg)";
}

}  // namespace

TEST(IcpTracker, RecoversKnownMotionWithoutNoise) {
  const Eigen::Isometry3d T_b = kRoomPose * motion({0.03, -0.02, 0.04}, {0.3, 1, 0.2}, 2.5);
  const Pair p(Scene::room(), kRoomPose, T_b);
  IcpTracker tr;
  const TrackingResult r = p.align(tr, kRoomPose);
  EXPECT_TRUE(r.ok) << toString(r.status);
  EXPECT_EQ(r.status, TrackingStatus::Ok);
  expectPoseNear(r.T_world_cam, T_b, 1e-3, 0.05);
  EXPECT_GT(r.inlier_fraction, 0.8);
  EXPECT_LT(r.rms_m, 1e-3);
  EXPECT_GT(r.min_eigenvalue, tr.params().min_eigenvalue);
  EXPECT_EQ(r.unconstrained_directions, 0);
  ASSERT_EQ(r.levels.size(), 3u);
  EXPECT_EQ(r.levels.front().level, 2);
  EXPECT_EQ(r.levels.back().level, 0);
}

TEST(IcpTracker, SubsampledAndFullLevel0AgreeWithoutNoise) {
  const Eigen::Isometry3d T_b = kRoomPose * motion({-0.02, 0.01, 0.03}, {1, 0.2, -0.4}, 2.0);
  const Pair p(Scene::room(), kRoomPose, T_b);
  for (int stride : {1, 2, 3}) {
    TTrackingParams P;
    P.level0_pixel_stride = stride;
    IcpTracker tr(P);
    const TrackingResult r = p.align(tr, kRoomPose);
    EXPECT_EQ(r.status, TrackingStatus::Ok) << "stride " << stride;
    expectPoseNear(r.T_world_cam, T_b, 1e-3, 0.05);
  }
}

// II-C: the quarter- and half-resolution passes widen the basin of convergence. From 10 cm /
// 5 deg both the pyramid and full resolution alone (same level-0 thresholds, as many iterations
// as the whole pyramid) converge on this scene; from 25 cm / 12 deg the pyramid still converges
// (16 of the 16 draws below) while full resolution alone mostly does not (6 of 16).
TEST(IcpTracker, CoarseToFineWidensBasinOfConvergence) {
  const Scene scene = Scene::room();
  std::vector<FrameLevel> pyr_a = pyramidOf(scene.render(K, kRoomPose));
  const WorldMaps model(pyr_a[0], kRoomPose);
  TTrackingParams pyramid;
  pyramid.max_jump_translation_m = 1.0;  // judge by the pose error alone here
  pyramid.max_jump_rotation_deg = 45.0;
  TTrackingParams single = pyramid;
  single.num_levels = 1;
  single.iterations[0] = pyramid.iterations[0] + pyramid.iterations[1] + pyramid.iterations[2];

  std::mt19937 rng(7);
  std::normal_distribution<double> N(0, 1);
  auto converged = [&](const TTrackingParams& P, const std::vector<FrameLevel>& pyr_b,
                       const Eigen::Isometry3d& T_b) {
    IcpTracker tr(P);
    const TrackingResult r = tr.align(pyr_b, modelOf(model, kRoomPose), kRoomPose);
    return r.ok && translationDistance(T_b, r.T_world_cam) < 1e-3 &&
           rotationAngle(T_b, r.T_world_cam) < 0.05 * kDeg;
  };
  for (const auto& [offset_m, offset_deg, trials] :
       {std::tuple{0.1, 5.0, 4}, std::tuple{0.25, 12.0, 16}}) {
    int ok_pyramid = 0, ok_single = 0;
    for (int i = 0; i < trials; ++i) {
      const Eigen::Vector3d t(N(rng), N(rng), N(rng)), axis(N(rng), N(rng), N(rng));
      const Eigen::Isometry3d T_b = kRoomPose * motion(offset_m * t.normalized(), axis, offset_deg);
      const std::vector<FrameLevel> pyr_b = pyramidOf(scene.render(K, T_b));
      ok_pyramid += converged(pyramid, pyr_b, T_b);
      ok_single += converged(single, pyr_b, T_b);
    }
    SCOPED_TRACE(::testing::Message()
                 << offset_m << " m / " << offset_deg << " deg: pyramid " << ok_pyramid << "/"
                 << trials << ", single level " << ok_single << "/" << trials);
    ::testing::Test::RecordProperty("converged_pyramid_" + std::to_string(int(offset_deg)) + "deg",
                                    ok_pyramid);
    ::testing::Test::RecordProperty("converged_single_" + std::to_string(int(offset_deg)) + "deg",
                                    ok_single);
    if (offset_m < 0.15) {
      EXPECT_EQ(ok_pyramid, trials);
    } else {
      EXPECT_GE(ok_pyramid, trials - 1);
      EXPECT_LE(ok_single, ok_pyramid - 6);
    }
  }
}

TEST(IcpTracker, SingleWallIsDegenerate) {
  // Camera 2 m from the wall y = 2, looking slightly oblique; the motion has components in and
  // out of the plane. Only the normal translation (world y) and the rotations about the in-plane
  // axes (world x, z) are observable.
  const Eigen::Isometry3d T_a = lookAt({0.3, 0, 1.3}, {0.5, 2, 1.0});
  const Eigen::Isometry3d T_b = T_a * motion({0.01, 0.02, 0.03}, {0, 1, 0}, 1.0);
  const Pair p(Scene::wall(), T_a, T_b);
  IcpTracker tr;
  const TrackingResult r = p.align(tr, T_a);
  EXPECT_EQ(r.status, TrackingStatus::Degenerate);
  EXPECT_EQ(r.unconstrained_directions, 3);
  EXPECT_LT(r.min_eigenvalue, 1e-6);
  EXPECT_TRUE(r.ok) << "a degenerate frame that agrees everywhere with the model is accepted";
  // The three weakest directions: translation in the plane (x, z) and rotation about y.
  for (int i = 0; i < 3; ++i) {
    const auto v = r.eigenvectors.col(i);
    EXPECT_LT(std::abs(v(1)), 1e-3) << "translation along the wall normal is constrained";
    EXPECT_LT(std::abs(v(3)), 1e-3);
    EXPECT_LT(std::abs(v(5)), 1e-3);
  }
  // Constrained parts are recovered: distance to the wall and the tilt of the optical axis.
  EXPECT_NEAR(r.T_world_cam.translation().y(), T_b.translation().y(), 1e-3);
  const Eigen::Vector3d n_cam_est = r.T_world_cam.linear().transpose() * Eigen::Vector3d::UnitY();
  const Eigen::Vector3d n_cam_gt = T_b.linear().transpose() * Eigen::Vector3d::UnitY();
  EXPECT_LT(std::acos(std::min(1.0, n_cam_est.dot(n_cam_gt))) / kDeg, 0.05);
  // Unconstrained parts stay at the guess (no drift along the wall).
  EXPECT_NEAR(r.T_world_cam.translation().x(), T_a.translation().x(), 1e-3);
  EXPECT_NEAR(r.T_world_cam.translation().z(), T_a.translation().z(), 1e-3);

  TTrackingParams strict;
  strict.degenerate_min_inlier_fraction = 1.5;  // never accept degenerate frames
  IcpTracker tr2(strict);
  EXPECT_FALSE(p.align(tr2, T_a).ok);
}

TEST(IcpTracker, ShortDegenerateRunsRideOnTheVelocityLongOnesAreLost) {
  // Sliding along a single wall: every frame is degenerate (translation in the plane is not
  // observable). With the inlier rule off, only the run rule can accept them: at most
  // degenerate_max_run_frames in a row after a reset, then lost; 0 = none.
  const Eigen::Isometry3d T0 = lookAt({0.3, 0, 1.3}, {0.5, 2, 1.0});
  const Eigen::Isometry3d step = motion({0.01, 0.0, 0.0}, {0, 1, 0}, 0.0);
  const Scene scene = Scene::wall();
  for (const int run : {0, 3}) {
    TTrackingParams P;
    P.degenerate_min_inlier_fraction = 1.5;
    P.degenerate_max_run_frames = run;
    IcpTracker tr(P);
    tr.reset(T0);
    Eigen::Isometry3d T = T0;
    for (int k = 1; k <= run + 2; ++k) {
      T = T * step;
      const WorldMaps model(pyramidOf(scene.render(K, tr.lastGoodPose()))[0], tr.lastGoodPose());
      const TrackingResult r =
          tr.track(pyramidOf(scene.render(K, T)), modelOf(model, tr.lastGoodPose()));
      EXPECT_EQ(r.status, TrackingStatus::Degenerate) << "frame " << k;
      EXPECT_EQ(r.ok, k <= run) << "run " << run << ", frame " << k;
      EXPECT_EQ(r.on_motion_model, k <= run);
    }
  }
}

TEST(IcpTracker, EmptyModelIsLost) {
  const Pair p(Scene::room(), kRoomPose, kRoomPose);
  IcpTracker tr;
  const TrackingResult r = tr.align(p.pyr_b, modelMaps({}, {}, kRoomPose), kRoomPose);
  EXPECT_FALSE(r.ok);
  EXPECT_EQ(r.status, TrackingStatus::TooFewInliers);
  EXPECT_EQ(r.inliers, 0);

  // All-invalid maps of the right size behave the same.
  const Vec3f nan = Vec3f::Constant(std::numeric_limits<float>::quiet_NaN());
  const Image<Vec3f> invalid(K.width, K.height, nan);
  const TrackingResult r2 =
      tr.align(p.pyr_b, modelMaps(invalid.view(), invalid.view(), kRoomPose), kRoomPose);
  EXPECT_FALSE(r2.ok);
  EXPECT_EQ(r2.status, TrackingStatus::TooFewInliers);
}

TEST(IcpTracker, UnrelatedModelIsLost) {
  // The model is the room seen from elsewhere, but claimed to be rendered from the frame's pose.
  const Scene scene = Scene::room();
  const std::vector<FrameLevel> pyr = pyramidOf(scene.render(K, kRoomPose));
  for (const Eigen::Isometry3d& T_other : {lookAt({-1.5, 1.5, 1.0}, {1.0, -1.0, 0.3}),
                                           kRoomPose * motion({0.5, 0, 0}, {0, 1, 0}, 40)}) {
    const WorldMaps other(pyramidOf(scene.render(K, T_other))[0], T_other);
    IcpTracker tr;
    const TrackingResult r = tr.align(pyr, modelOf(other, kRoomPose), kRoomPose);
    EXPECT_FALSE(r.ok) << toString(r.status);
  }
}

TEST(IcpTracker, ConstantVelocityLossAndRecovery) {
  const Scene scene = Scene::room();
  const Eigen::Isometry3d step = motion({0.02, 0.0, 0.01}, {0, 1, 0}, 1.0);
  std::vector<Eigen::Isometry3d> gt{kRoomPose};
  for (int i = 1; i < 6; ++i) gt.push_back(gt.back() * step);

  TTrackingParams P;  // default: constant velocity
  P.lost_velocity_frames = 5;
  IcpTracker tr(P);
  EXPECT_EQ(tr.track(pyramidOf(scene.render(K, gt[1])), ModelMaps{}).status,
            TrackingStatus::NotInitialized);
  tr.reset(gt[0]);
  // The model is what the Mapper would render: the scene seen from the last good pose.
  auto trackFrame = [&](int i) {
    const WorldMaps model(pyramidOf(scene.render(K, tr.lastGoodPose()))[0], tr.lastGoodPose());
    return tr.track(pyramidOf(scene.render(K, gt[i])), modelOf(model, tr.lastGoodPose()));
  };
  for (int i = 1; i <= 2; ++i) {
    const TrackingResult r = trackFrame(i);
    ASSERT_TRUE(r.ok) << "frame " << i << ": " << toString(r.status);
    expectPoseNear(r.T_world_cam, gt[i], 1e-3, 0.05);
  }
  // After two frames the velocity is known: the prediction is the next true pose.
  expectPoseNear(tr.predictPose(), gt[3], 2e-3, 0.1);

  // Frame 3 is lost (no model); the state keeps the last good pose and, for up to
  // lost_velocity_frames, the velocity: the guess for frame 4 is two steps on.
  const TrackingResult lost =
      tr.track(pyramidOf(scene.render(K, gt[3])), modelMaps({}, {}, tr.lastGoodPose()));
  EXPECT_FALSE(lost.ok);
  expectPoseNear(lost.T_world_cam_guess, gt[3], 2e-3, 0.1);
  expectPoseNear(tr.lastGoodPose(), gt[2], 1e-3, 0.05);
  EXPECT_TRUE(tr.extrapolatingThroughLoss());
  expectPoseNear(tr.predictPose(), gt[4], 3e-3, 0.15);

  // Frame 4 aligns again (against the model rendered at frame 3's guess, as the Mapper does).
  const WorldMaps at3(pyramidOf(scene.render(K, lost.T_world_cam_guess))[0],
                      lost.T_world_cam_guess);
  const TrackingResult back =
      tr.track(pyramidOf(scene.render(K, gt[4])), modelOf(at3, lost.T_world_cam_guess));
  EXPECT_TRUE(back.ok) << toString(back.status);
  expectPoseNear(back.T_world_cam, gt[4], 1e-3, 0.05);
  expectPoseNear(tr.lastGoodPose(), gt[4], 1e-3, 0.05);
  // The velocity is frame 3's guess to frame 4, one step: the next guess is frame 5.
  expectPoseNear(tr.predictPose(), gt[5], 3e-3, 0.15);
}

TEST(IcpTracker, VelocityThroughLossEndsAfterLostVelocityFrames) {
  // A pan at 5 deg per frame (150 deg/s at 30 Hz): with zero velocity after a loss, the guess
  // stays at the last good pose; with lost_velocity_frames it follows the pan, then stops.
  const Scene scene = Scene::room();
  const Eigen::Isometry3d step = motion({0.0, 0.0, 0.0}, {0, 1, 0}, 5.0);
  for (const int keep : {0, 2}) {
    TTrackingParams P;
    P.lost_velocity_frames = keep;
    IcpTracker tr(P);
    tr.reset(kRoomPose);
    Eigen::Isometry3d T = kRoomPose;
    for (int i = 1; i <= 2; ++i) {
      T = T * step;
      const WorldMaps model(pyramidOf(scene.render(K, tr.lastGoodPose()))[0], tr.lastGoodPose());
      ASSERT_TRUE(tr.track(pyramidOf(scene.render(K, T)), modelOf(model, tr.lastGoodPose())).ok);
    }
    const Eigen::Isometry3d last_good = tr.lastGoodPose();
    for (int lost = 1; lost <= 3; ++lost) {
      T = T * step;
      EXPECT_FALSE(
          tr.track(pyramidOf(scene.render(K, T)), modelMaps({}, {}, tr.lastGoodPose())).ok);
      EXPECT_EQ(tr.lostFrames(), lost);
      if (lost <= keep) {
        EXPECT_TRUE(tr.extrapolatingThroughLoss());
        expectPoseNear(tr.predictPose(), T * step, 3e-3, 0.3);  // the pan goes on
      } else {
        EXPECT_FALSE(tr.extrapolatingThroughLoss());
        expectPoseNear(tr.predictPose(), last_good, 1e-9, 1e-9);  // zero velocity
      }
    }
  }
}

TEST(IcpTracker, PreviousPoseMotionModel) {
  TTrackingParams P;
  P.motion_model = MotionModel::PreviousPose;
  IcpTracker tr(P);
  tr.reset(kRoomPose);
  const Eigen::Isometry3d T_b = kRoomPose * motion({0.02, 0.0, 0.01}, {0, 1, 0}, 1.0);
  const Pair p(Scene::room(), kRoomPose, T_b);
  const TrackingResult r = tr.track(p.pyr_b, modelOf(*p.model, kRoomPose));
  ASSERT_TRUE(r.ok);
  expectPoseNear(r.T_world_cam_guess, kRoomPose, 1e-12, 1e-9);
  expectPoseNear(tr.predictPose(), r.T_world_cam, 1e-12, 1e-9);
}

TEST(IcpTracker, GaussianDepthNoise) {
  // 1.5 mm depth noise on both frames (the model is a single noisy frame, noisier than a fused
  // map). The error stays far below the noise: tens of thousands of residuals average it out.
  const Eigen::Isometry3d T_b = kRoomPose * motion({0.03, -0.02, 0.04}, {0.3, 1, 0.2}, 2.5);
  const Pair p(Scene::room(), kRoomPose, T_b, 0.0015);
  for (double huber : {0.0, 0.005}) {
    TTrackingParams P;
    P.huber_delta_m = huber;
    IcpTracker tr(P);
    const TrackingResult r = p.align(tr, kRoomPose);
    EXPECT_TRUE(r.ok) << toString(r.status);
    expectPoseNear(r.T_world_cam, T_b, 2e-3, 0.1);
    EXPECT_NEAR(r.rms_m, 0.0015 * std::sqrt(2.0), 1e-3) << "residual of two noisy surfaces";
  }
}

TEST(IcpTracker, RejectsMalformedInput) {
  const Pair p(Scene::room(), kRoomPose, kRoomPose);
  IcpTracker tr;
  std::vector<FrameLevel> two(p.pyr_b.begin(), p.pyr_b.begin() + 2);
  EXPECT_THROW(tr.align(two, modelOf(*p.model, kRoomPose), kRoomPose), InputError);
  ModelMaps bad = modelOf(*p.model, kRoomPose);
  bad.K = K.level(1);
  EXPECT_THROW(tr.align(p.pyr_b, bad, kRoomPose), InputError);
  bad = modelOf(*p.model, kRoomPose);
  bad.normal_world.width -= 1;
  EXPECT_THROW(tr.align(p.pyr_b, bad, kRoomPose), InputError);
  TTrackingParams P;
  P.num_levels = 5;
  EXPECT_THROW(IcpTracker{P}, InputError);
}

TEST(IcpTracker, PhotometricTermConstrainsTexturedWall) {
  // The wall of SingleWallIsDegenerate, textured: geometry alone leaves the in-plane translation
  // and the rotation about the normal at the guess; with the photometric term the whole motion is
  // recovered (to ~1 mm / 0.05 deg: noise-free images, 8-bit intensity).
  const Scene scene = Scene::texturedWall();
  const Eigen::Isometry3d T_a = lookAt({0.3, 0, 1.3}, {0.5, 2, 1.0});
  const Eigen::Isometry3d T_b = T_a * motion({0.01, 0.02, 0.03}, {0, 1, 0}, 1.0);
  const Pair p(scene, T_a, T_b);
  const Image<Bgr8> colour_a = scene.renderColour(K, T_a), colour_b = scene.renderColour(K, T_b);
  ModelMaps m = modelOf(*p.model, T_a);
  m.colour = colour_a.cview();

  TTrackingParams P;
  IcpTracker geometric(P);
  const TrackingResult rg = geometric.align(p.pyr_b, m, T_a, colour_b.cview());
  EXPECT_EQ(rg.status, TrackingStatus::Degenerate) << "photometric_weight = 0: colour ignored";
  EXPECT_EQ(rg.photometric_inliers, 0);
  EXPECT_GT(translationDistance(T_b, rg.T_world_cam), 0.02);

  P.photometric_weight = 0.01;
  IcpTracker joint(P);
  const TrackingResult rj = joint.align(p.pyr_b, m, T_a, colour_b.cview());
  EXPECT_EQ(rj.status, TrackingStatus::Ok) << toString(rj.status);
  EXPECT_EQ(rj.unconstrained_directions, 0);
  EXPECT_GT(rj.photometric_inliers, 10000);
  EXPECT_LT(rj.photometric_rms, 0.01);
  expectPoseNear(rj.T_world_cam, T_b, 1e-3, 0.05);

  // Without the frame's colour the term is off, whatever the weight.
  const TrackingResult rn = joint.align(p.pyr_b, m, T_a);
  EXPECT_EQ(rn.status, TrackingStatus::Degenerate);
}

// [tracking] model_level = 1: the model rendered at half resolution (the frame's level 1). The
// model of this noise-free scene is exact on its planes, so the full-resolution frame points meet
// it with zero point-to-plane residual at the true pose wherever they land on the coarser grid:
// the same 1 mm / 0.05 deg as with a full-resolution model.
TEST(IcpTracker, HalfResolutionModelRecoversKnownMotion) {
  const Eigen::Isometry3d T_b = kRoomPose * motion({0.03, -0.02, 0.04}, {0.3, 1, 0.2}, 2.5);
  const Pair p(Scene::room(), kRoomPose, T_b);
  const WorldMaps half(p.pyr_a[1], kRoomPose);
  ModelMaps m = modelMaps(half.vertex.view(), half.normal.view(), kRoomPose);
  m.K = K.level(1);
  TTrackingParams P;
  P.model_level = 1;
  IcpTracker tr(P);
  const TrackingResult r = tr.align(p.pyr_b, m, kRoomPose);
  EXPECT_EQ(r.status, TrackingStatus::Ok) << toString(r.status);
  expectPoseNear(r.T_world_cam, T_b, 1e-3, 0.05);
  EXPECT_GT(r.inlier_fraction, 0.8);

  // A model of another size than frame level model_level is refused, naming the key.
  IcpTracker full_expected;  // model_level = 0 wants a full-resolution model
  try {
    (void)full_expected.align(p.pyr_b, m, kRoomPose);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("model_level"), std::string::npos) << e.what();
  }
}

// IcpTracker::track's denser_model: a frame the (stable-surfel) model cannot support for lack of
// coverage is aligned once more against the denser model, from the same guess. Here the sparse
// model keeps a 40 x 40 pixel window of the room (1600 points < min_inliers), the dense one all
// of it; the retry must recover the true motion as an aligned frame would (1 mm / 0.05 deg), and
// the hook is not called when the first alignment succeeds.
TEST(IcpTracker, DenserModelRetriesAFrameTheSparseModelCannotSupport) {
  const Eigen::Isometry3d T_b = kRoomPose * motion({0.02, 0.01, -0.02}, {0.2, 1, 0.1}, 2.0);
  const Pair p(Scene::room(), kRoomPose, T_b);
  WorldMaps sparse = *p.model;
  const Vec3f nan = Vec3f::Constant(std::numeric_limits<float>::quiet_NaN());
  for (int y = 0; y < K.height; ++y)
    for (int x = 0; x < K.width; ++x)
      if (std::abs(x - K.width / 2) >= 20 || std::abs(y - K.height / 2) >= 20)
        sparse.vertex(x, y) = sparse.normal(x, y) = nan;

  int calls = 0;
  const IcpTracker::DenserModel dense = [&]() -> std::optional<ModelMaps> {
    ++calls;
    return modelOf(*p.model, kRoomPose);
  };
  {
    IcpTracker tr;
    tr.reset(kRoomPose);
    const TrackingResult r = tr.track(p.pyr_b, modelOf(sparse, kRoomPose));
    EXPECT_EQ(r.status, TrackingStatus::TooFewInliers) << "the sparse model alone fails";
    EXPECT_FALSE(r.ok);
  }
  {
    IcpTracker tr;
    tr.reset(kRoomPose);
    const TrackingResult r = tr.track(p.pyr_b, modelOf(sparse, kRoomPose), {}, nullptr, dense);
    EXPECT_EQ(calls, 1);
    EXPECT_EQ(r.status, TrackingStatus::Ok) << toString(r.status);
    EXPECT_TRUE(r.denser_model);
    expectPoseNear(r.T_world_cam, T_b, 1e-3, 0.05);
    expectPoseNear(tr.lastGoodPose(), T_b, 1e-3, 0.05);
  }
  {  // a frame the first model supports never asks for the denser one
    IcpTracker tr;
    tr.reset(kRoomPose);
    const TrackingResult r = tr.track(p.pyr_b, modelOf(*p.model, kRoomPose), {}, nullptr, dense);
    EXPECT_EQ(calls, 1);
    EXPECT_TRUE(r.ok);
    EXPECT_FALSE(r.denser_model);
  }
  {  // no denser model to offer (nullopt): the first result stands
    IcpTracker tr;
    tr.reset(kRoomPose);
    const TrackingResult r = tr.track(p.pyr_b, modelOf(sparse, kRoomPose), {}, nullptr,
                                      [] { return std::optional<ModelMaps>(); });
    EXPECT_EQ(r.status, TrackingStatus::TooFewInliers);
    EXPECT_FALSE(r.denser_model);
  }
  {  // a denser model that does not agree either (the room seen from elsewhere) changes nothing
    const Eigen::Isometry3d T_other = lookAt({-1.5, 1.5, 1.0}, {1.0, -1.0, 0.3});
    const WorldMaps other(pyramidOf(Scene::room().render(K, T_other))[0], T_other);
    IcpTracker tr;
    tr.reset(kRoomPose);
    const TrackingResult r = tr.track(p.pyr_b, modelOf(sparse, kRoomPose), {}, nullptr,
                                      [&] { return std::optional(modelOf(other, kRoomPose)); });
    EXPECT_FALSE(r.ok) << toString(r.status);
    EXPECT_FALSE(r.denser_model);
  }
}

// Without a prior, a retry that comes back degenerate is not taken: the denser model gives the
// frame the inliers a degenerate frame needs, not the directions it lacks (a camera before a
// single wall, sliding along it). With a prior, which holds those directions, it is.
TEST(IcpTracker, DegenerateRetryIsTakenOnlyWithAPrior) {
  const Eigen::Isometry3d T_a = lookAt({0.3, 0, 1.3}, {0.5, 2, 1.0});
  const Eigen::Isometry3d T_b = T_a * motion({0.01, 0.0, 0.01}, {0, 1, 0}, 0.5);
  const Pair p(Scene::wall(), T_a, T_b);
  ASSERT_TRUE(IcpTracker().align(p.pyr_b, modelOf(*p.model, T_a), T_a).ok)
      << "against the whole wall the frame is accepted as degenerate (SingleWallIsDegenerate)";
  WorldMaps sparse = *p.model;
  const Vec3f nan = Vec3f::Constant(std::numeric_limits<float>::quiet_NaN());
  for (int y = 0; y < K.height; ++y)
    for (int x = 0; x < K.width; ++x)
      if (std::abs(x - K.width / 2) >= 20 || std::abs(y - K.height / 2) >= 20)
        sparse.vertex(x, y) = sparse.normal(x, y) = nan;
  const IcpTracker::DenserModel dense = [&] { return std::optional(modelOf(*p.model, T_a)); };

  IcpTracker tr;
  tr.reset(T_a);
  const TrackingResult r = tr.track(p.pyr_b, modelOf(sparse, T_a), {}, nullptr, dense);
  EXPECT_FALSE(r.ok);
  EXPECT_EQ(r.status, TrackingStatus::TooFewInliers) << toString(r.status);
  EXPECT_FALSE(r.denser_model);

  // A prior at the true pose, 1 cm / 1 deg: the degenerate retry stands, at the true pose.
  const MotionPrior prior =
      MotionPrior::fromStdDevs(T_b, Eigen::Matrix3d::Identity(), Eigen::Vector3d::Constant(0.01),
                               Eigen::Vector3d::Constant(kDeg));
  IcpTracker tp;
  tp.reset(T_a);
  const TrackingResult rp = tp.track(p.pyr_b, modelOf(sparse, T_a), {}, &prior, dense);
  EXPECT_TRUE(rp.ok) << toString(rp.status);
  EXPECT_EQ(rp.status, TrackingStatus::Degenerate);
  EXPECT_TRUE(rp.denser_model);
  expectPoseNear(rp.T_world_cam, T_b, 2e-3, 0.1);
}

// Loop closure trusts a registration only along the directions its data hold well: the move
// from the tracked pose is kept along eigen-directions at or above the bar and dropped along the
// others (translations in metres, rotations about the camera centre scaled by the mean depth).
TEST(IcpTracker, MoveIsKeptOnlyAlongHeldDirections) {
  const Eigen::Isometry3d T_from = lookAt({2.0, 1.0, 0.5}, {4.0, 1.5, 0.3});
  // Registered: 3 cm along world x, 2 cm along y, -1 cm along z, and 0.5 deg about world z
  // through the camera centre.
  Eigen::Isometry3d T_reg = T_from;
  T_reg.linear() = Eigen::AngleAxisd(0.5 * kDeg, Eigen::Vector3d::UnitZ()) * T_from.linear();
  T_reg.translation() += Eigen::Vector3d(0.03, 0.02, -0.01);
  TrackingResult r;
  r.T_world_cam = T_reg;
  r.eigen_mean_depth_m = 2.5;
  r.eigenvectors.setIdentity();  // [tx ty tz rx ry rz] in the analysis' coordinates
  r.eigenvalues << 1e-3, 0.5, 0.5, 0.5, 0.5, 0.5;

  // World x is weak: the camera stays at T_from's x, the rest of the move is kept.
  const Eigen::Isometry3d kept = moveAlongHeldDirections(r, T_from, 1e-2);
  EXPECT_NEAR(kept.translation().x(), T_from.translation().x(), 1e-9);
  EXPECT_NEAR(kept.translation().y(), T_reg.translation().y(), 1e-9);
  EXPECT_NEAR(kept.translation().z(), T_reg.translation().z(), 1e-9);
  EXPECT_NEAR(rotationAngle(kept, T_reg), 0.0, 1e-9);
  // No bar: the registration as it is.
  EXPECT_LT(translationDistance(moveAlongHeldDirections(r, T_from, 0.0), T_reg), 1e-12);

  // The rotation about world z weak instead (its column scaled by the mean depth does not change
  // which direction it is): the orientation stays at T_from's, the translation moves.
  r.eigenvalues << 0.5, 0.5, 0.5, 0.5, 0.5, 1e-3;
  const Eigen::Isometry3d turned_back = moveAlongHeldDirections(r, T_from, 1e-2);
  EXPECT_NEAR(rotationAngle(turned_back, T_from), 0.0, 1e-9);
  EXPECT_LT(translationDistance(turned_back, T_reg), 1e-9);

  // An eigenvector mixing x and y: only the component of the move along the held one remains.
  r.eigenvectors.setIdentity();
  const double c = std::sqrt(0.5);
  r.eigenvectors.block<2, 2>(0, 0) << c, -c, c, c;  // (x + y)/sqrt2 weak, (-x + y)/sqrt2 held
  r.eigenvalues << 1e-3, 0.5, 0.5, 0.5, 0.5, 0.5;
  const Eigen::Vector3d moved =
      moveAlongHeldDirections(r, T_from, 1e-2).translation() - T_from.translation();
  // The move (0.03, 0.02) has -0.01/sqrt2 along (-x + y)/sqrt2: (0.005, -0.005) remains.
  EXPECT_NEAR(moved.x(), 0.005, 1e-9);
  EXPECT_NEAR(moved.y(), -0.005, 1e-9);
  EXPECT_NEAR(moved.z(), -0.01, 1e-9);
}

// A relocalised robot pose is checked against the odometry like a tracked one: distances count
// in the odometry's sigmas along the floor and about its normal, and not at all in height.
TEST(IcpTracker, OdometrySigmasMeasureAlongTheFloorOnly) {
  const Eigen::Isometry3d T = lookAt({1.0, 2.0, 0.5}, {3.0, 2.5, 0.4});
  MotionPrior prior;
  prior.T_world_cam = T;
  prior.odometry_information =
      MotionPrior::planarInformation(Eigen::Matrix3d::Identity(), 0.01, 0.5 * kDeg);
  Eigen::Isometry3d moved = T;
  moved.translation() += Eigen::Vector3d(0.03, 0.0, 0.0);
  EXPECT_NEAR(odometrySigmas(moved, prior), 3.0, 1e-6);
  moved = T;
  moved.translation() += Eigen::Vector3d(0.0, 0.0, 0.05);  // height: not the odometry's
  EXPECT_NEAR(odometrySigmas(moved, prior), 0.0, 1e-6);
  moved = T;
  moved.linear() = Eigen::AngleAxisd(1.0 * kDeg, Eigen::Vector3d::UnitZ()) * T.linear();
  EXPECT_NEAR(odometrySigmas(moved, prior), 2.0, 1e-6);  // 1 deg of yaw at 0.5 deg
  EXPECT_EQ(odometrySigmas(moved, MotionPrior()), 0.0);  // no odometry, no distance
}
