// ICP kernels of II-C on tiny synthetic maps: residuals and Jacobians against hand-computed values
// and finite differences, the model downsampling rule, and the CUDA launcher against the CPU.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "rasm/compute/Device.h"
#include "rasm/compute/Parallel.h"
#include "rasm/core/CameraIntrinsics.h"
#include "rasm/core/FrameProcessing.h"
#include "rasm/core/Image.h"
#include "rasm/core/SE3.h"
#include "rasm/tracking/IcpCuda.h"
#include "rasm/tracking/kernels/IcpKernels.h"
#include "tracking/SyntheticScene.h"

using namespace rasm;
using namespace rasm::tracking;
using kernels::IcpAccumulator;
using kernels::IcpReduceKernel;

namespace {

const CameraIntrinsics K(80.0, 80.0, 39.5, 29.5, 80, 60);

RigidF rigid(const Eigen::Isometry3d& T) {
  return RigidF::fromMatrix(T.matrix().cast<float>());
}

/// Kernel aligning `frame` (camera frame at T_world_cam) with `model` (world, rendered at
/// T_world_model).
IcpReduceKernel makeKernel(const FrameLevel& frame, const Image<Vec3f>& mv, const Image<Vec3f>& mn,
                           const Eigen::Isometry3d& T_world_cam,
                           const Eigen::Isometry3d& T_world_model,
                           const CameraIntrinsics& K_model = K) {
  IcpReduceKernel k;
  k.frame_vertex = frame.vertex.view();
  k.frame_normal = frame.normal.view();
  k.model_vertex = mv.view();
  k.model_normal = mn.view();
  k.K_model = K_model.plain();
  k.T_world_cam = rigid(T_world_cam);
  k.T_model_cam = rigid(T_world_model.inverse() * T_world_cam);
  k.pivot_world = T_world_cam.translation().cast<float>();
  k.max_dist_m = 0.1f;
  k.min_normal_cos = 0.8f;
  return k;
}

FrameLevel frameOf(const Image<float>& depth) {
  std::vector<FrameLevel> pyr;
  buildFramePyramid(depth, K, 1, pyr);
  return pyr[0];
}

}  // namespace

TEST(IcpKernels, PlaneOffsetAlongNormal) {
  // Frame: wall at z = 2 m in front of the camera. Model: the same wall 1 cm further away.
  // Every valid interior pixel is an inlier with r = n . (p - q) = (-z) . (-0.01 z) = 0.01 and
  // J = [n, (p - c) x n]; the translation part of J^T J is N n n^T.
  const Image<float> d_frame(K.width, K.height, 2.0f), d_model(K.width, K.height, 2.01f);
  const FrameLevel F = frameOf(d_frame), M = frameOf(d_model);
  const Eigen::Isometry3d I = Eigen::Isometry3d::Identity();
  const IcpReduceKernel k = makeKernel(F, M.vertex, M.normal, I, I);
  const IcpAccumulator a = compute::reduce1D<IcpAccumulator>(k.items(), k);
  const double n_valid = double((K.width - 2) * (K.height - 2));  // border normals are invalid
  EXPECT_EQ(a.valid(), n_valid);
  EXPECT_EQ(a.inliers(), n_valid);
  EXPECT_NEAR(a.s[IcpAccumulator::kR2] / a.inliers(), 1e-4, 1e-7);
  EXPECT_NEAR(a.s[IcpAccumulator::kJtJ + 11], n_valid, 1e-3);  // (2,2): n_z^2
  EXPECT_NEAR(a.s[IcpAccumulator::kJtJ + 0], 0.0, 1e-6);       // (0,0): n_x^2
  EXPECT_NEAR(a.s[IcpAccumulator::kJtr + 2], -0.01 * n_valid, 1e-3 * n_valid * 1e-2);
  EXPECT_NEAR(a.s[IcpAccumulator::kDepth] / a.inliers(), 2.0, 1e-5);
  // Rotation about the optical axis does not move a fronto-parallel wall: (5,5) = 0.
  EXPECT_NEAR(a.s[IcpAccumulator::kJtJ + 20], 0.0, 1e-6);

  // Beyond the distance limit nothing is an inlier.
  IcpReduceKernel far = k;
  far.max_dist_m = 0.005f;
  const IcpAccumulator b = compute::reduce1D<IcpAccumulator>(far.items(), far);
  EXPECT_EQ(b.inliers(), 0);
  EXPECT_EQ(b.valid(), n_valid);
}

TEST(IcpKernels, NoiseAndConfidenceWeights) {
  // The wall of PlaneOffsetAlongNormal. Depth-noise weighting scales every term at z = 2 m by
  // (sigma(1 m) / sigma(2 m))^2; a model confidence of 4 with confidence_full = 10 by 0.4. The
  // Gauss-Newton step -J^T W r / J^T W J along the normal stays 1 cm either way.
  const Image<float> d_frame(K.width, K.height, 2.0f), d_model(K.width, K.height, 2.01f);
  const FrameLevel F = frameOf(d_frame), M = frameOf(d_model);
  const Eigen::Isometry3d I = Eigen::Isometry3d::Identity();
  const IcpReduceKernel plain = makeKernel(F, M.vertex, M.normal, I, I);
  const IcpAccumulator a0 = compute::reduce1D<IcpAccumulator>(plain.items(), plain);
  EXPECT_NEAR(a0.s[IcpAccumulator::kW], a0.inliers(), 1e-6);
  EXPECT_NEAR(a0.s[IcpAccumulator::kWR2], 1e-4 * a0.inliers(), 1e-6 * a0.inliers());

  const double s = kernels::depthNoiseSigma(1.0f) / kernels::depthNoiseSigma(2.0f);
  EXPECT_NEAR(kernels::depthNoiseSigma(2.0f), 0.0012 + 0.0019 * 1.6 * 1.6, 1e-7);
  IcpReduceKernel k = plain;
  k.depth_noise_weighting = true;
  const Image<float> conf(K.width, K.height, 4.0f);
  k.model_confidence = conf.cview();
  k.confidence_full = 10.0f;
  const IcpAccumulator a = compute::reduce1D<IcpAccumulator>(k.items(), k);
  const double w = s * s * 0.4;
  EXPECT_EQ(a.inliers(), a0.inliers());
  EXPECT_NEAR(a.s[IcpAccumulator::kW], w * a0.inliers(), 1e-4 * a0.inliers());
  EXPECT_NEAR(a.s[IcpAccumulator::kJtJ + 11], w * a0.s[IcpAccumulator::kJtJ + 11],
              1e-4 * a0.inliers());
  EXPECT_NEAR(-a.s[IcpAccumulator::kJtr + 2] / a.s[IcpAccumulator::kJtJ + 11], 0.01, 1e-5);
  EXPECT_NEAR(a.s[IcpAccumulator::kR2], a0.s[IcpAccumulator::kR2],
              1e-9 * a0.inliers());  // unweighted
}

TEST(IcpKernels, IncidenceWeightingCountsAGrazingPlaneForItsNoise) {
  // A plane through (0, 0, 2 m) whose normal makes 70 deg with the optical axis: the centre
  // pixel sees it at depth 2 m and incidence 70 deg. Nguyen et al.'s sigma_z there is
  // 0.0012 + 0.0019 * 1.6^2 + 0.0001 / sqrt(2) * g^2, g = theta / (pi/2 - theta) = 3.5 (6.93 mm)
  // against 6.06 mm head-on, so with the incidence term its weight falls to (6.06 / 6.93)^2.
  const double phi = 70.0 * M_PI / 180.0;
  const Eigen::Vector3d n(0.0, std::sin(phi), -std::cos(phi)), p0(0.0, 0.0, 2.0);
  Image<float> depth(K.width, K.height, 0.0f), model_depth(K.width, K.height, 0.0f);
  for (int y = 0; y < K.height; ++y)
    for (int x = 0; x < K.width; ++x) {
      const Eigen::Vector3d d((x - K.cx) / K.fx, (y - K.cy) / K.fy, 1.0);
      const double z = n.dot(p0) / n.dot(d);
      depth(x, y) = z > 0.5 && z < 8.0 ? float(z) : 0.0f;
      const double zm = n.dot(p0 - 0.005 * n) / n.dot(d);  // the model 5 mm along the normal
      model_depth(x, y) = zm > 0.5 && zm < 8.0 ? float(zm) : 0.0f;
    }
  const FrameLevel F = frameOf(depth), M = frameOf(model_depth);
  const Eigen::Isometry3d I = Eigen::Isometry3d::Identity();
  IcpReduceKernel k = makeKernel(F, M.vertex, M.normal, I, I);
  k.depth_noise_weighting = true;
  const int cx = int(K.cx), cy = int(K.cy);
  float J[6], r, w_depth, w_incidence, depth_m;
  ASSERT_EQ(k.pixel(cx, cy, J, r, w_depth, depth_m), tracking::kernels::kIcpInlier);
  k.depth_noise_incidence = true;
  ASSERT_EQ(k.pixel(cx, cy, J, r, w_incidence, depth_m), tracking::kernels::kIcpInlier);
  auto sigma = [](double z, double theta) {
    const double g = theta / (M_PI / 2 - theta);
    return 0.0012 + 0.0019 * (z - 0.4) * (z - 0.4) + 0.0001 / std::sqrt(z) * g * g;
  };
  const double zc = depth(cx, cy);  // pixel centre (39, 29), a little off the optical axis
  const Eigen::Vector3d ray((cx - K.cx) / K.fx, (cy - K.cy) / K.fy, 1.0);
  const double theta = std::acos(std::abs(n.dot(ray)) / ray.norm());
  EXPECT_NEAR(theta * 180.0 / M_PI, 70.0, 1.0);
  EXPECT_NEAR(w_incidence / w_depth, std::pow(sigma(zc, 0.0) / sigma(zc, theta), 2), 0.01);
  EXPECT_LT(w_incidence / w_depth, 0.8);
}

TEST(IcpKernels, JacobianMatchesFiniteDifferences) {
  // One pixel of a sphere-and-planes scene: the residual n . (T(xi) v - q) with the association
  // held fixed, differentiated numerically w.r.t. xi (left increment about the pivot).
  test::Scene scene = test::Scene::room();
  const Eigen::Isometry3d T_model = test::lookAt({0.3, -1.5, 1.3}, {-0.2, 0.8, 0.5});
  const Eigen::Isometry3d T_cam = T_model * test::motion({0.01, -0.005, 0.01}, {0.2, 1, 0.1}, 0.7);
  const FrameLevel F = frameOf(scene.render(K, T_cam)), M = frameOf(scene.render(K, T_model));
  const test::WorldMaps W(M, T_model);
  const IcpReduceKernel k = makeKernel(F, W.vertex, W.normal, T_cam, T_model);
  int checked = 0;
  for (int y = 5; y < K.height - 5; y += 7)
    for (int x = 5; x < K.width - 5; x += 9) {
      float J[6], r, w, depth;
      if (k.pixel(x, y, J, r, w, depth) != kernels::kIcpInlier) continue;
      // The associated model point q and normal n (recomputed as the kernel does).
      const Vec3f pm = k.T_model_cam.apply(F.vertex(x, y));
      const int u = int(K.fx * pm.x() / pm.z() + K.cx + 0.5),
                v = int(K.fy * pm.y() / pm.z() + K.cy + 0.5);
      const Eigen::Vector3d q = W.vertex(u, v).cast<double>(), n = W.normal(u, v).cast<double>();
      const Eigen::Vector3d pc = F.vertex(x, y).cast<double>(), c = T_cam.translation();
      auto residual = [&](const Vector6d& xi) {
        Eigen::Isometry3d P = Eigen::Isometry3d::Identity();
        P.translation() = c;
        return n.dot(P * se3Exp(xi) * P.inverse() * T_cam * pc - q);
      };
      EXPECT_NEAR(r, residual(Vector6d::Zero()), 1e-5);
      for (int i = 0; i < 6; ++i) {
        Vector6d e = Vector6d::Zero();
        e(i) = 1e-6;
        const double num = (residual(e) - residual(-e)) / 2e-6;
        EXPECT_NEAR(J[i], num, 2e-3 * (1.0 + std::abs(num)))
            << "pixel " << x << "," << y << " dof " << i;
      }
      ++checked;
    }
  EXPECT_GT(checked, 20);
}

TEST(IcpKernels, ModelDownsampleKeepsForeground) {
  // A 2x2 block with two foreground samples (z = 1) and two background ones (z = 3): the coarse
  // pixel averages the foreground only, normals renormalised; an all-invalid block stays invalid.
  const float nan = std::numeric_limits<float>::quiet_NaN();
  Image<Vec3f> v(4, 2, Vec3f(nan, nan, nan)), n(4, 2, Vec3f(nan, nan, nan));
  v(0, 0) = Vec3f(0.0f, 0.0f, 1.0f);
  v(1, 0) = Vec3f(0.02f, 0.0f, 1.01f);
  v(0, 1) = Vec3f(0.0f, 0.1f, 3.0f);
  v(1, 1) = Vec3f(0.1f, 0.1f, 3.0f);
  n(0, 0) = Vec3f(0, 0, -1);
  n(1, 0) = Vec3f(0.6f, 0, -0.8f);
  n(0, 1) = n(1, 1) = Vec3f(1, 0, 0);
  Image<Vec3f> ov(2, 1), on(2, 1);
  kernels::ModelDownsampleKernel k;
  k.in_vertex = v.view();
  k.in_normal = n.view();
  k.out_vertex = ov.view();
  k.out_normal = on.view();
  k.max_diff_m = 0.03f;
  // Intensity and confidence follow the same samples (the foreground pair).
  Image<float> in_i(4, 2, nan), in_c(4, 2, 0.0f), out_i(2, 1), out_c(2, 1);
  in_i(0, 0) = 0.2f;
  in_i(1, 0) = 0.4f;
  in_i(0, 1) = in_i(1, 1) = 0.9f;
  in_c(0, 0) = 3.0f;
  in_c(1, 0) = 7.0f;
  in_c(0, 1) = in_c(1, 1) = 50.0f;
  k.in_intensity = in_i.cview();
  k.out_intensity = out_i.view();
  k.in_confidence = in_c.cview();
  k.out_confidence = out_c.view();
  compute::forEach2D(2, 1, k);
  EXPECT_NEAR(out_i(0, 0), 0.3f, 1e-6);
  EXPECT_NEAR(out_c(0, 0), 5.0f, 1e-6);
  EXPECT_TRUE(std::isnan(out_i(1, 0)));
  EXPECT_EQ(out_c(1, 0), 0.0f);
  EXPECT_NEAR(ov(0, 0).z(), 1.005f, 1e-6);
  EXPECT_NEAR(ov(0, 0).x(), 0.01f, 1e-6);
  EXPECT_NEAR(on(0, 0).norm(), 1.0f, 1e-6);
  EXPECT_NEAR(on(0, 0).x(), 0.3f / std::sqrt(0.09f + 0.81f), 1e-5);
  EXPECT_TRUE(std::isnan(ov(1, 0).x()));
  EXPECT_TRUE(std::isnan(on(1, 0).x()));
}

TEST(IcpKernels, CudaMatchesCpu) {
  const auto avail = compute::cudaAvailability();
  if (!avail.available) GTEST_SKIP() << avail.reason;
  ASSERT_TRUE(tracking::cuda::built());
  test::Scene scene = test::Scene::room();
  const CameraIntrinsics K640 = CameraIntrinsics::preset("kinect_v1");
  const Eigen::Isometry3d T_model = test::lookAt({0.3, -1.5, 1.3}, {-0.2, 0.8, 0.5});
  const Eigen::Isometry3d T_cam = T_model * test::motion({0.02, -0.01, 0.02}, {0.2, 1, 0.1}, 1.5);
  std::vector<FrameLevel> pf, pm;
  buildFramePyramid(scene.render(K640, T_cam), K640, 1, pf);
  buildFramePyramid(scene.render(K640, T_model), K640, 1, pm);
  const test::WorldMaps W(pm[0], T_model);
  for (int stride : {1, 2}) {
    IcpReduceKernel k;
    k.frame_vertex = pf[0].vertex.view();
    k.frame_normal = pf[0].normal.view();
    k.model_vertex = W.vertex.view();
    k.model_normal = W.normal.view();
    k.K_model = K640.plain();
    k.T_world_cam = rigid(T_cam);
    k.T_model_cam = rigid(T_model.inverse() * T_cam);
    k.pivot_world = T_cam.translation().cast<float>();
    k.huber_delta_m = 0.01f;
    k.stride = stride;
    const IcpAccumulator cpu = compute::reduce1D<IcpAccumulator>(k.items(), k);
    const IcpAccumulator gpu = tracking::cuda::reduceIcp(k);
    EXPECT_EQ(cpu.valid(), gpu.valid());
    EXPECT_NEAR(cpu.inliers(), gpu.inliers(),
                1e-4 * cpu.inliers() + 2);  // fast-math rounding at limits
    for (int i = 0; i < IcpAccumulator::kSize; ++i)
      EXPECT_NEAR(cpu.s[i], gpu.s[i], 1e-3 * (1.0 + std::abs(cpu.s[i]))) << "entry " << i;
  }
}

TEST(IcpKernels, IntensityGradientOfRamp) {
  // I = 0.01 x + 0.002 y: Sobel / 8 gives the exact slope per pixel in the interior.
  Image<float> I(12, 9);
  for (int y = 0; y < I.height(); ++y)
    for (int x = 0; x < I.width(); ++x) I(x, y) = 0.01f * x + 0.002f * y;
  Image<Vec3f> g(12, 9);
  compute::forEach2D(12, 9, kernels::IntensityGradientKernel{I.cview(), g.view()});
  EXPECT_NEAR(g(5, 4).x(), 0.058f, 1e-6);
  EXPECT_NEAR(g(5, 4).y(), 0.01f, 1e-6);
  EXPECT_NEAR(g(5, 4).z(), 0.002f, 1e-6);
  EXPECT_EQ(g(0, 4).y(), 0.0f);  // border: no gradient
  // Luma of pure channels (BT.601).
  EXPECT_NEAR(kernels::luma(Bgr8{0, 0, 255}), 0.299f, 1e-6);
  EXPECT_NEAR(kernels::luma(Bgr8{255, 255, 255}), 1.0f, 1e-6);
}

TEST(IcpKernels, PhotometricJacobianMatchesFiniteDifferences) {
  // Room geometry; the frame's intensity a smooth quadratic of the pixel coordinates, so the
  // Sobel gradient (exact up to the quadratic's second differences) and the bilinear
  // interpolation both follow the true derivative closely. The residual of a model pixel warped
  // into the frame is differentiated numerically w.r.t. xi (left increment about the pivot) by
  // re-running the kernel at the perturbed pose.
  const test::Scene scene = test::Scene::room();
  const Eigen::Isometry3d T_model = test::lookAt({0.3, -1.5, 1.3}, {-0.2, 0.8, 0.5});
  const Eigen::Isometry3d T_cam = T_model * test::motion({0.01, -0.005, 0.01}, {0.2, 1, 0.1}, 0.7);
  const FrameLevel F = frameOf(scene.render(K, T_cam)), M = frameOf(scene.render(K, T_model));
  const test::WorldMaps W(M, T_model);
  Image<float> If(K.width, K.height), Im(K.width, K.height, 0.4f);
  for (int y = 0; y < K.height; ++y)
    for (int x = 0; x < K.width; ++x) If(x, y) = 0.2f + 0.006f * x + 0.004f * y + 1e-5f * x * y;
  Image<Vec3f> G(K.width, K.height);
  compute::forEach2D(K.width, K.height, kernels::IntensityGradientKernel{If.cview(), G.view()});

  kernels::PhotometricReduceKernel k;
  k.model_vertex = W.vertex.cview();
  k.model_intensity = Im.cview();
  k.frame_igrad = G.cview();
  k.frame_depth_m = F.depth_m.cview();
  k.K_frame = K.plain();
  const Eigen::Vector3d c = T_cam.translation();
  auto at = [&](const Vector6d& xi) {
    Eigen::Isometry3d P = Eigen::Isometry3d::Identity();
    P.translation() = c;
    const Eigen::Isometry3d T = P * se3Exp(xi) * P.inverse() * T_cam;
    kernels::PhotometricReduceKernel kk = k;
    kk.T_world_cam = rigid(T);
    kk.T_cam_world = rigid(T.inverse());
    kk.pivot_world = c.cast<float>();
    return kk;
  };
  const kernels::PhotometricReduceKernel k0 = at(Vector6d::Zero());
  int checked = 0;
  for (int y = 3; y < K.height - 3; y += 5)
    for (int x = 3; x < K.width - 3; x += 7) {
      float J[6], r, w, depth;
      if (k0.pixel(x, y, J, r, w, depth) != kernels::kIcpInlier) continue;
      // The residual at xi = 0: the quadratic at the warped point minus the model intensity.
      const Vec3f p = k0.T_cam_world.apply(W.vertex(x, y));
      const double u = K.fx * p.x() / p.z() + K.cx, v = K.fy * p.y() / p.z() + K.cy;
      EXPECT_NEAR(r, 0.2 + 0.006 * u + 0.004 * v + 1e-5 * u * v - 0.4, 2e-4);
      for (int i = 0; i < 6; ++i) {
        Vector6d e = Vector6d::Zero();
        e(i) = 1e-3;
        float Jp[6], Jm[6], rp, rm, wp, wm, dp, dm;
        ASSERT_EQ(at(e).pixel(x, y, Jp, rp, wp, dp), kernels::kIcpInlier);
        ASSERT_EQ(at(-e).pixel(x, y, Jm, rm, wm, dm), kernels::kIcpInlier);
        const double num = (rp - rm) / 2e-3;
        EXPECT_NEAR(J[i], num, 0.02 * (0.1 + std::abs(num)))
            << "pixel " << x << "," << y << " dof " << i;
      }
      ++checked;
    }
  EXPECT_GT(checked, 20);
}
