// Splat / point rendering (II-A) and the 4x index map (II-D) against brute-force projection,
// frustum culling by block counts, rendered plane depth, determinism across thread counts.

#include "rasm/surfel_map/SurfelRenderer.h"

#include <gtest/gtest.h>

#include <omp.h>
#include "rasm/core/ComputeOptions.h"

#include <algorithm>
#include <cmath>
#include <random>

#include "rasm/compute/Device.h"
#include "rasm/surfel_map/kernels/RenderKernels.h"

using namespace rasm;
using namespace rasm::maps;

namespace {

const CameraIntrinsics kSmallK(70.0, 70.0, 39.5, 29.5, 80, 60);

Eigen::Isometry3d lookPose() {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitY()).toRotationMatrix() *
               Eigen::AngleAxisd(-0.2, Eigen::Vector3d::UnitX()).toRotationMatrix();
  T.translation() = Eigen::Vector3d(0.2, -0.1, 0.3);
  return T;
}

/// Random surfels in front of the camera T_world_cam (camera-frame depth 1-4 m), random normals
/// facing the camera, radii 5-30 mm times radius_scale.
SurfelStore randomMapInView(const Eigen::Isometry3d& T_world_cam, const CameraIntrinsics& K, int n,
                            unsigned seed, float radius_scale = 1.0f) {
  SurfelStore store;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u01(0.0f, 1.0f);
  for (int i = 0; i < n; ++i) {
    const float z = 1.0f + 3.0f * u01(rng);
    const float u = -5.0f + (K.width + 10.0f) * u01(rng), v = -5.0f + (K.height + 10.0f) * u01(rng);
    const Eigen::Vector3d pc((u - K.cx) / K.fx * z, (v - K.cy) / K.fy * z, z);
    Eigen::Vector3d nc(u01(rng) - 0.5, u01(rng) - 0.5, -1.0);
    nc.normalize();
    Surfel s;
    s.position = (T_world_cam * pc).cast<float>();
    s.normal = (T_world_cam.linear() * nc).cast<float>();
    s.radius = (0.005f + 0.025f * u01(rng)) * radius_scale;
    s.confidence = 20.0f * u01(rng);
    s.stable = s.confidence > 10.0f;
    s.segment = 1 + i;
    s.colour = Bgr8{std::uint8_t(i & 255), 0, 0};
    store.append(s);
  }
  return store;
}

/// Brute force over ALL surfels (no culling) with the kernels' arithmetic: (depth, index) min.
Image<std::uint64_t> bruteForcePoints(const SurfelStore& store,
                                      const Eigen::Isometry3d& T_world_cam,
                                      const CameraIntrinsics& K, int scale,
                                      const RenderOptions& opt) {
  Image<std::uint64_t> out(K.width * scale, K.height * scale, kernels::kEmptyPacked);
  const RigidF T_cw = RigidF::fromMatrix(T_world_cam.inverse().matrix().cast<float>());
  const PinholeF Kp = K.plain();
  const SurfelArrays a = store.arrays();
  for (int i = 0; i < a.size; ++i) {
    if (opt.stable_only && !a.stable(i)) continue;
    if (a.confidence(i) < opt.min_confidence) continue;
    const Vec3f pc = T_cw.apply(a.position(i));
    if (!(pc.z() >= opt.min_depth_m && pc.z() <= opt.max_depth_m)) continue;
    const float u = Kp.fx * pc.x() / pc.z() + Kp.cx, v = Kp.fy * pc.y() / pc.z() + Kp.cy;
    const int sx = int(std::floor(scale * (u + 0.5f))), sy = int(std::floor(scale * (v + 0.5f)));
    if (sx < 0 || sy < 0 || sx >= out.width() || sy >= out.height()) continue;
    out(sx, sy) = std::min(out(sx, sy), kernels::packDepthIndex(pc.z(), i));
  }
  return out;
}

}  // namespace

TEST(SurfelRenderer, PointModeIndexMapEqualsBruteForce) {
  const Eigen::Isometry3d T = lookPose();
  const SurfelStore store = randomMapInView(T, kSmallK, 3000, 11);
  for (bool stable_only : {false, true}) {
    RenderOptions opt;
    opt.splat = false;
    opt.stable_only = stable_only;
    SurfelRenderer r;
    RenderedMaps m;
    RenderStats st;
    r.render(store, T, kSmallK, opt, m, &st);
    const Image<std::uint64_t> bf = bruteForcePoints(store, T, kSmallK, 1, opt);
    int drawn = 0;
    for (int y = 0; y < kSmallK.height; ++y)
      for (int x = 0; x < kSmallK.width; ++x) {
        ASSERT_EQ(m.index(x, y), kernels::unpackIndex(bf(x, y))) << "pixel " << x << "," << y;
        drawn += m.index(x, y) >= 0;
        if (m.index(x, y) >= 0) {
          EXPECT_EQ(m.segment(x, y), store.arrays().segment[m.index(x, y)]);
          EXPECT_EQ(m.vertex_world(x, y),
                    store.arrays().position(m.index(x, y)));  // point mode: centre
        }
      }
    EXPECT_GT(drawn, 500);
    EXPECT_EQ(st.pixels_drawn, drawn);
  }
}

TEST(SurfelRenderer, IndexMap4xEqualsBruteForceAndSparseClearWorks) {
  const Eigen::Isometry3d T = lookPose();
  SurfelRenderer r;
  IndexMap4x map4;
  for (unsigned seed : {21u, 22u}) {  // the second render reuses (sparse-clears) the buffer
    const SurfelStore store = randomMapInView(T, kSmallK, 4000, seed);
    RenderOptions opt;
    r.renderIndexMap4x(store, T, kSmallK, opt, map4);
    const Image<std::uint64_t> bf = bruteForcePoints(store, T, kSmallK, 4, opt);
    for (int y = 0; y < bf.height(); ++y)
      for (int x = 0; x < bf.width(); ++x)
        ASSERT_EQ(map4.index(x, y), kernels::unpackIndex(bf(x, y)));
  }
}

TEST(SurfelRenderer, CompactCandidatesEqualTheIndexMap4x) {
  // renderCandidates4x (fusion's CPU path) lists, per frame pixel, exactly the surfels of the 4x
  // map's 4x4 block, with their camera-frame centres; with the hidden ones it lists every visible
  // surfel once. Many surfels per pixel so that sub-pixels collide; several thread counts.
  const Eigen::Isometry3d T = lookPose();
  const RigidF T_cw = RigidF::fromMatrix(T.inverse().matrix().cast<float>());
  const int nt = omp_get_max_threads();
  for (int threads : {1, std::max(2, nt)}) {
    omp_set_num_threads(threads);
    for (unsigned seed : {31u, 32u}) {
      const SurfelStore store = randomMapInView(T, kSmallK, 30000, seed);
      RenderOptions opt;
      opt.max_depth_m = 3.5f;  // some surfels beyond the range: visible, but not candidates
      SurfelRenderer r;
      IndexMap4x map4;
      r.renderIndexMap4x(store, T, kSmallK, opt, map4);
      PointCandidates4x cand;
      r.renderCandidates4x(store, T, kSmallK, opt, cand);
      ASSERT_EQ(cand.first.size(), std::size_t(kSmallK.width * kSmallK.height + 1));
      std::vector<int> listed;
      int candidates = 0;
      for (int y = 0; y < kSmallK.height; ++y)
        for (int x = 0; x < kSmallK.width; ++x) {
          const int p = y * kSmallK.width + x;
          std::vector<int> expect, got;
          for (int sy = 4 * y; sy < 4 * y + 4; ++sy)
            for (int sx = 4 * x; sx < 4 * x + 4; ++sx)
              if (map4.index(sx, sy) >= 0) expect.push_back(map4.index(sx, sy));
          for (std::uint32_t q = cand.first[p]; q < cand.first[p + 1]; ++q) {
            const kernels::CameraPoint& c = cand.entries[q];
            EXPECT_EQ(c.pc, T_cw.apply(store.arrays().position(c.index)));
            if (q < cand.first[p] + cand.count[p]) got.push_back(c.index);
            listed.push_back(c.index);
          }
          std::sort(expect.begin(), expect.end());
          std::sort(got.begin(), got.end());
          ASSERT_EQ(got, expect) << "pixel " << x << "," << y;
          candidates += int(got.size());
        }
      for (const kernels::CameraPoint& c : cand.others) listed.push_back(c.index);
      std::vector<int> visible;
      r.collectVisible(store, T, kSmallK, opt, 0.5f, visible);
      std::sort(listed.begin(), listed.end());
      std::sort(visible.begin(), visible.end());
      EXPECT_EQ(listed, visible);
      EXPECT_GT(candidates, 2000);
      EXPECT_LT(candidates, int(visible.size()));  // collisions happened
    }
  }
  omp_set_num_threads(nt);
}

TEST(SurfelRenderer, SplatPixelsHoldTheNearestCoveringSurfel) {
  const Eigen::Isometry3d T = lookPose();
  const SurfelStore store = randomMapInView(T, kSmallK, 400, 5, 4.0f);  // 2-12 cm discs
  RenderOptions opt;
  opt.max_splat_radius_px = 1000.0f;  // no clamp: every covering surfel must compete
  SurfelRenderer r;
  RenderedMaps m;
  RenderStats st;
  r.render(store, T, kSmallK, opt, m, &st);

  // Brute force, written independently in double precision: a surfel covers pixel (x, y) when the
  // pixel ray meets its disc, or when its centre projects into the pixel.
  const Eigen::Isometry3d T_cw = T.inverse();
  const SurfelArrays a = store.arrays();
  int covered = 0;
  for (int y = 0; y < kSmallK.height; ++y)
    for (int x = 0; x < kSmallK.width; ++x) {
      const Eigen::Vector3d d((x - kSmallK.cx) / kSmallK.fx, (y - kSmallK.cy) / kSmallK.fy, 1.0);
      double best_t = 1e30;
      for (int i = 0; i < a.size; ++i) {
        const Eigen::Vector3d p = T_cw * a.position(i).cast<double>();
        const Eigen::Vector3d n = T_cw.linear() * a.normal(i).cast<double>();
        const double r = a.radius(i);
        const double u = kSmallK.fx * p.x() / p.z() + kSmallK.cx,
                     v = kSmallK.fy * p.y() / p.z() + kSmallK.cy;
        const bool own = std::floor(u + 0.5) == x && std::floor(v + 0.5) == y;
        const double denom = n.dot(d);
        double t = std::abs(denom) > 1e-6 ? n.dot(p) / denom : -1.0;
        if (own) {
          if (!(t > 0) || std::abs(t - p.z()) > r) t = p.z();
        } else if (!(t > 0) || (t * d - p).norm() > r) {
          continue;
        }
        best_t = std::min(best_t, t);
      }
      const int idx = m.index(x, y);
      if (best_t > 1e29) {
        EXPECT_EQ(idx, -1) << "pixel " << x << "," << y;
        continue;
      }
      ++covered;
      ASSERT_GE(idx, 0) << "pixel " << x << "," << y;
      // Same nearest depth (float vs double arithmetic: 1e-4 relative).
      EXPECT_NEAR(m.depth_m(x, y), best_t, 1e-4 * best_t) << "pixel " << x << "," << y;
    }
  EXPECT_GT(covered, kSmallK.width * kSmallK.height / 2);
  EXPECT_EQ(st.pixels_drawn, covered);
}

TEST(SurfelRenderer, CpuSplatEqualsTheKernelBitForBit) {
  // The CPU launcher (SSE footprints, band binning, row and two-row SSE rasterisation) against
  // SplatKernel's own footprint + rasterize over every surfel: the same index and depth bits in
  // every pixel. Radii from sub-pixel to several pixels, so that 1x1, 1x2, 2x2 and larger
  // footprints all occur, also across the image borders and the band borders.
  const Eigen::Isometry3d T = lookPose();
  int two_rows = 0;
  for (float scale : {0.3f, 1.0f, 4.0f}) {
    const SurfelStore store = randomMapInView(T, kSmallK, 3000, 9, scale);
    RenderOptions opt;
    opt.outputs = kRenderDepth;
    SurfelRenderer r;
    RenderedMaps m;
    r.render(store, T, kSmallK, opt, m);

    Image<std::uint64_t> ref(kSmallK.width, kSmallK.height, kernels::kEmptyPacked);
    const kernels::SplatKernel k{store.arrays(),
                                 nullptr,
                                 RigidF::fromMatrix(T.inverse().matrix().cast<float>()),
                                 kSmallK.plain(),
                                 opt.min_depth_m,
                                 opt.max_depth_m,
                                 opt.max_splat_radius_px,
                                 ref.view()};
    for (int i = 0; i < store.size(); ++i) {
      kernels::SplatFootprint f;
      if (!k.footprintOf(i, f)) continue;
      two_rows += f.y1 == f.y0 + 1 && f.x1 <= f.x0 + 1;
      k.rasterize(f, f.y0, f.y1, false);
    }
    for (int y = 0; y < kSmallK.height; ++y)
      for (int x = 0; x < kSmallK.width; ++x) {
        ASSERT_EQ(m.index(x, y), kernels::unpackIndex(ref(x, y))) << scale << ": " << x << "," << y;
        if (m.index(x, y) >= 0) {
          ASSERT_EQ(kernels::floatBits(m.depth_m(x, y)), std::uint32_t(ref(x, y) >> 32))
              << scale << ": " << x << "," << y;
        }
      }
  }
  EXPECT_GT(two_rows, 300);  // footprints of the two-row path
}

TEST(SurfelRenderer, KernelOnlyModeRendersTheSameMaps) {
  // [compute] simd = false renders through SplatKernel + ResolveKernel alone: the same index,
  // depth, vertex and normal bits as the SSE launcher.
  const Eigen::Isometry3d T = lookPose();
  const SurfelStore store = randomMapInView(T, kSmallK, 3000, 9, 1.0f);
  RenderOptions opt;
  opt.outputs = kRenderDepth | kRenderVertex | kRenderNormal;
  SurfelRenderer r;
  RenderedMaps sse, kern;
  RenderStats s1, s2;
  r.render(store, T, kSmallK, opt, sse, &s1);
  compute::setSimdEnabled(false);
  r.render(store, T, kSmallK, opt, kern, &s2);
  compute::setSimdEnabled(true);
  EXPECT_EQ(s1.pixels_drawn, s2.pixels_drawn);
  ASSERT_GT(s1.pixels_drawn, 1000);
  for (int y = 0; y < kSmallK.height; ++y)
    for (int x = 0; x < kSmallK.width; ++x) {
      ASSERT_EQ(sse.index(x, y), kern.index(x, y)) << x << "," << y;
      if (sse.index(x, y) < 0) continue;
      ASSERT_EQ(kernels::floatBits(sse.depth_m(x, y)), kernels::floatBits(kern.depth_m(x, y)));
      ASSERT_EQ(sse.vertex_world(x, y), kern.vertex_world(x, y));
      ASSERT_EQ(sse.normal_world(x, y), kern.normal_world(x, y));
    }
}

TEST(SurfelRenderer, PlaneAtKnownDistanceRendersWithinOneMillimetre) {
  const CameraIntrinsics K(262.5, 262.5, 159.5, 119.5, 320, 240);
  for (double tilt_deg : {0.0, 35.0}) {
    // A plane through (0, 0, 2) (camera frame = world) tilted about the x axis, tiled with surfels
    // on a 7 mm grid with 6 mm radius (> 7 / sqrt 2: overlapping discs, as fusion produces).
    const double tilt = tilt_deg * M_PI / 180.0;
    const Eigen::Vector3d n(0.0, std::sin(tilt), -std::cos(tilt));
    const Eigen::Vector3d e1(1, 0, 0), e2 = n.cross(e1).normalized();
    const Eigen::Vector3d p0(0, 0, 2);
    SurfelStore store;
    for (double a = -1.9; a <= 1.9; a += 0.007)
      for (double b = -1.7; b <= 1.7; b += 0.007) {
        Surfel s;
        s.position = (p0 + a * e1 + b * e2).cast<float>();
        s.normal = n.cast<float>();
        s.radius = 0.006f;
        s.confidence = 15.0f;
        s.stable = true;
        store.append(s);
      }
    SurfelRenderer r;
    RenderedMaps m;
    RenderOptions opt;
    r.render(store, Eigen::Isometry3d::Identity(), K, opt, m);
    int checked = 0;
    for (int y = 0; y < K.height; ++y)
      for (int x = 0; x < K.width; ++x) {
        const Eigen::Vector3d d((x - K.cx) / K.fx, (y - K.cy) / K.fy, 1.0);
        const double t = n.dot(p0) / n.dot(d);  // analytic depth of the plane on this ray
        ASSERT_GT(m.depth_m(x, y), 0.0f) << "hole at " << x << "," << y << " tilt " << tilt_deg;
        EXPECT_NEAR(m.depth_m(x, y), t, 1e-3) << x << "," << y << " tilt " << tilt_deg;
        EXPECT_NEAR((m.vertex_world(x, y).cast<double>() - t * d).norm(), 0.0, 1.5e-3);
        EXPECT_NEAR(m.normal_world(x, y).cast<double>().dot(n), 1.0, 1e-5);
        ++checked;
      }
    EXPECT_EQ(checked, K.width * K.height);
  }
}

TEST(SurfelRenderer, FrustumCullingVisitsOnlyBlocksInView) {
  // A 10 x 10 x 3 m room (walls, floor, ceiling) sampled every 5 cm, camera in the middle looking
  // along +x with a 4 m range: most blocks are out of view.
  SurfelStore store;
  auto add = [&](const Eigen::Vector3f& p, const Eigen::Vector3f& n) {
    Surfel s;
    s.position = p;
    s.normal = n;
    s.radius = 0.03f;
    s.confidence = 1.0f;
    store.append(s);
  };
  for (float a = -5.0f; a <= 5.0f; a += 0.05f)
    for (float h = 0.0f; h <= 3.0f; h += 0.05f) {
      add({a, -5.0f, h}, {0, 1, 0});
      add({a, 5.0f, h}, {0, -1, 0});
      add({-5.0f, a, h}, {1, 0, 0});
      add({5.0f, a, h}, {-1, 0, 0});
    }
  for (float a = -5.0f; a <= 5.0f; a += 0.05f)
    for (float b = -5.0f; b <= 5.0f; b += 0.05f) {
      add({a, b, 0.0f}, {0, 0, 1});
      add({a, b, 3.0f}, {0, 0, -1});
    }
  // Optical camera at (0, 0, 1.5) looking along world +x (z_cam = x_world, x_cam = -y_world,
  // y_cam = -z_world).
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() << 0, 0, 1, -1, 0, 0, 0, -1, 0;
  T.translation() = Eigen::Vector3d(0, 0, 1.5);
  const CameraIntrinsics K(131.25, 131.25, 79.5, 59.5, 160, 120);
  RenderOptions opt;
  opt.max_depth_m = 4.0f;
  opt.splat = false;
  SurfelRenderer r;
  RenderedMaps m;
  RenderStats st;
  r.render(store, T, K, opt, m, &st);

  EXPECT_EQ(st.blocks_total, store.spatialIndex().numBlocks());
  // In view: a wedge of ~63 deg x 4 m: the floor/ceiling/wall blocks within it. Out of view: the
  // rest of the 10 x 10 room. Counts, not time.
  EXPECT_LT(st.blocks_visited, st.blocks_total / 4);
  EXPECT_LT(st.surfels_tested, store.size() / 4);
  EXPECT_GT(st.surfels_drawn, 1000);
  // Culling dropped nothing that brute force over the whole map draws.
  const Image<std::uint64_t> bf = bruteForcePoints(store, T, K, 1, opt);
  for (int y = 0; y < K.height; ++y)
    for (int x = 0; x < K.width; ++x) ASSERT_EQ(m.index(x, y), kernels::unpackIndex(bf(x, y)));
}

TEST(SurfelRenderer, ResultIsIndependentOfThreadCount) {
  const Eigen::Isometry3d T = lookPose();
  const SurfelStore store = randomMapInView(T, kSmallK, 5000, 9);
  RenderOptions opt;
  SurfelRenderer r;
  RenderedMaps m1, m2;
  const int nt = omp_get_max_threads();
  omp_set_num_threads(1);
  r.render(store, T, kSmallK, opt, m1);
  omp_set_num_threads(std::max(nt, 4));
  r.render(store, T, kSmallK, opt, m2);
  omp_set_num_threads(nt);
  for (int y = 0; y < kSmallK.height; ++y)
    for (int x = 0; x < kSmallK.width; ++x) {
      ASSERT_EQ(m1.index(x, y), m2.index(x, y));
      ASSERT_EQ(m1.depth_m(x, y), m2.depth_m(x, y));
    }
}

TEST(SurfelRenderer, FiltersAndInvalidPixels) {
  const Eigen::Isometry3d T = lookPose();
  SurfelStore store = randomMapInView(T, kSmallK, 2000, 3);
  RenderOptions opt;
  opt.min_confidence = 5.0f;
  opt.outputs = kRenderDepth | kRenderConfidence;
  SurfelRenderer r;
  RenderedMaps m;
  r.render(store, T, kSmallK, opt, m);
  EXPECT_TRUE(m.vertex_world.empty());  // not requested
  for (int y = 0; y < kSmallK.height; ++y)
    for (int x = 0; x < kSmallK.width; ++x) {
      if (m.index(x, y) < 0) {
        EXPECT_EQ(m.depth_m(x, y), 0.0f);
        EXPECT_EQ(m.confidence(x, y), 0.0f);
      } else {
        EXPECT_GE(m.confidence(x, y), 5.0f);
      }
    }
  // Time window: only surfels fused in the last second.
  const SurfelArrays a = store.arrays();
  for (int i = 0; i < a.size; ++i) a.t_last[i] = (i % 2) ? 10.0f : 1.0f;
  store.setTimeOrigin(100.0);
  RenderOptions tw;
  tw.splat = false;
  tw.now_s = 110.5;
  tw.time_window_s = 1.0;
  r.render(store, T, kSmallK, tw, m);
  for (int y = 0; y < kSmallK.height; ++y)
    for (int x = 0; x < kSmallK.width; ++x)
      if (m.index(x, y) >= 0) {
        EXPECT_EQ(m.index(x, y) % 2, 1);
      }
}

TEST(SurfelRendererCuda, MatchesCpu) {
  const auto avail = compute::cudaAvailability();
  if (!avail.available) GTEST_SKIP() << avail.reason;
  const Eigen::Isometry3d T = lookPose();
  const SurfelStore store = randomMapInView(T, kSmallK, 3000, 17, 2.0f);
  SurfelRenderer cpu(compute::Backend::Cpu), gpu(compute::Backend::Cuda);
  for (bool splat : {true, false}) {
    RenderOptions opt;
    opt.splat = splat;
    RenderedMaps a, b;
    cpu.render(store, T, kSmallK, opt, a);
    gpu.render(store, T, kSmallK, opt, b);
    for (int y = 0; y < kSmallK.height; ++y)
      for (int x = 0; x < kSmallK.width; ++x) {
        ASSERT_EQ(a.index(x, y), b.index(x, y)) << x << "," << y << " splat " << splat;
        ASSERT_EQ(a.depth_m(x, y), b.depth_m(x, y));
      }
  }
  IndexMap4x a4, b4;
  cpu.renderIndexMap4x(store, T, kSmallK, RenderOptions(), a4);
  gpu.renderIndexMap4x(store, T, kSmallK, RenderOptions(), b4);
  for (int y = 0; y < a4.packed.height(); ++y)
    for (int x = 0; x < a4.packed.width(); ++x) ASSERT_EQ(a4.index(x, y), b4.index(x, y));
}
