// Vertex/normal maps (II-A) and the depth pyramid on analytic scenes.
#include <gtest/gtest.h>

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstring>

#include "rasm/compute/Device.h"
#include "rasm/core/FrameProcessing.h"
#include "rasm/core/RgbdFrame.h"
#include "rasm/core/SurfelMath.h"
#include "rasm/core/kernels/FrameKernels.h"

using namespace rasm;

namespace {
const CameraIntrinsics kK(525.0, 525.0, 319.5, 239.5, 640, 480);

/// Depth image of the plane n . p = d (camera frame) by exact ray intersection.
Image<float> planeDepth(const Eigen::Vector3d& n, double d, const CameraIntrinsics& K) {
  Image<float> depth(K.width, K.height, 0.0f);
  for (int y = 0; y < K.height; ++y)
    for (int x = 0; x < K.width; ++x) {
      const Eigen::Vector3d ray((x - K.cx) / K.fx, (y - K.cy) / K.fy, 1.0);
      const double t = d / n.dot(ray);  // point = t * ray, z = t
      depth(x, y) = t > 0 ? float(t) : 0.0f;
    }
  return depth;
}
}  // namespace

TEST(VertexMap, BackProjectionMatchesPinhole) {
  Image<float> depth(kK.width, kK.height, 2.0f);
  depth(10, 20) = 0.0f;   // invalid
  depth(11, 20) = 50.0f;  // beyond max range
  Image<Vec3f> v;
  computeVertexMap(depth, kK, v);
  const Vec3f p = v(100, 200);
  EXPECT_NEAR(p.z(), 2.0f, 1e-6);
  EXPECT_NEAR(p.x(), (100 - 319.5) / 525.0 * 2.0, 1e-6);
  EXPECT_NEAR(p.y(), (200 - 239.5) / 525.0 * 2.0, 1e-6);
  // Re-projection returns the pixel exactly.
  const Vec2f uv = kK.plain().project(p);
  EXPECT_NEAR(uv.x(), 100.0f, 1e-3);
  EXPECT_NEAR(uv.y(), 200.0f, 1e-3);
  EXPECT_FALSE(kernels::validVec(v(10, 20)));
  EXPECT_FALSE(kernels::validVec(v(11, 20)));
}

TEST(NormalMap, TiltedPlaneNormalIsExactAndFacesCamera) {
  // Plane tilted 30 deg about x, 1.5 m away along the optical axis.
  const double a = 30.0 * M_PI / 180.0;
  const Eigen::Vector3d n(0.0, std::sin(a), -std::cos(a));  // facing the camera (n . z < 0)
  const double d = n.dot(Eigen::Vector3d(0, 0, 1.5));
  const Image<float> depth = planeDepth(n, d, kK);
  Image<Vec3f> v, nm;
  computeVertexMap(depth, kK, v);
  computeNormalMap(v, nm);
  int valid = 0;
  double max_err_deg = 0;
  for (int y = 0; y < kK.height; ++y)
    for (int x = 0; x < kK.width; ++x) {
      const bool border = x == 0 || y == 0 || x == kK.width - 1 || y == kK.height - 1;
      if (border) {
        EXPECT_FALSE(kernels::validVec(nm(x, y))) << x << "," << y;
        continue;
      }
      ASSERT_TRUE(kernels::validVec(nm(x, y)));
      ++valid;
      const double c = std::min(1.0, double(nm(x, y).cast<double>().dot(n)));
      max_err_deg = std::max(max_err_deg, std::acos(c) * 180 / M_PI);
      // Points lie on the plane: float back-projection error only.
      EXPECT_NEAR(v(x, y).cast<double>().dot(n), d, 1e-5);
    }
  EXPECT_EQ(valid, (kK.width - 2) * (kK.height - 2));
  // A plane is exactly planar, so the cross product of central differences is exact up to float
  // rounding: ~1e-3 deg.
  EXPECT_LT(max_err_deg, 0.05);
}

TEST(NormalMap, SphereNormalsAreRadial) {
  const Eigen::Vector3d c(0.1, -0.05, 2.0);
  const double R = 0.5;
  Image<float> depth(kK.width, kK.height, 0.0f);
  for (int y = 0; y < kK.height; ++y)
    for (int x = 0; x < kK.width; ++x) {
      const Eigen::Vector3d r =
          Eigen::Vector3d((x - kK.cx) / kK.fx, (y - kK.cy) / kK.fy, 1.0).normalized();
      const double b = r.dot(c), disc = b * b - (c.squaredNorm() - R * R);
      if (disc < 0) continue;
      const double t = b - std::sqrt(disc);
      depth(x, y) = float(t * r.z());
    }
  Image<Vec3f> v, nm;
  computeVertexMap(depth, kK, v);
  computeNormalMap(v, nm);
  int checked = 0;
  for (int y = 1; y < kK.height - 1; ++y)
    for (int x = 1; x < kK.width - 1; ++x) {
      if (!kernels::validVec(nm(x, y))) continue;
      const Eigen::Vector3d p = v(x, y).cast<double>();
      const Eigen::Vector3d expect = (p - c).normalized();
      const double ang = std::acos(std::min(1.0, nm(x, y).cast<double>().dot(expect))) * 180 / M_PI;
      // Only well-conditioned pixels: where the surface faces the camera within 60 deg the
      // central difference spans ~2 mm on a 0.5 m sphere, so the chord error is < 0.5 deg.
      if (-expect.dot(p.normalized()) > 0.5) {
        EXPECT_LT(ang, 0.5) << x << "," << y;
        ++checked;
      }
    }
  // The sphere covers pi (f R / z)^2 ~ 54k pixels; the facing part is most of it.
  EXPECT_GT(checked, 30000);
}

TEST(NormalMap, DepthDiscontinuityIsInvalid) {
  Image<float> depth(64, 48, 1.0f);
  for (int y = 0; y < 48; ++y)
    for (int x = 32; x < 64; ++x) depth(x, y) = 2.0f;
  const CameraIntrinsics K(50, 50, 31.5, 23.5, 64, 48);
  Image<Vec3f> v, nm;
  computeVertexMap(depth, K, v);
  computeNormalMap(v, nm);
  EXPECT_FALSE(kernels::validVec(nm(31, 20)));
  EXPECT_FALSE(kernels::validVec(nm(32, 20)));
  EXPECT_TRUE(kernels::validVec(nm(20, 20)));
  EXPECT_TRUE(kernels::validVec(nm(40, 20)));
}

TEST(Pyramid, InvalidAwareAveraging) {
  Image<float> d(4, 2, 0.0f);
  // Block 0: two valid (1.0, 1.02) and two invalid -> mean of the valid ones.
  d(0, 0) = 1.0f;
  d(1, 1) = 1.02f;
  // Block 1: foreground 1.0 and background 3.0: background is excluded, not averaged in.
  d(2, 0) = 1.0f;
  d(3, 0) = 3.0f;
  d(2, 1) = 3.0f;
  Image<float> h;
  downsampleDepth(d, h);
  ASSERT_EQ(h.width(), 2);
  ASSERT_EQ(h.height(), 1);
  EXPECT_NEAR(h(0, 0), 1.01f, 1e-6);
  EXPECT_NEAR(h(1, 0), 1.0f, 1e-6);
  Image<float> none(2, 2, 0.0f), hn;
  downsampleDepth(none, hn);
  EXPECT_EQ(hn(0, 0), 0.0f);
}

TEST(Pyramid, LevelIntrinsicsKeepGeometry) {
  // A fronto-parallel plane at 2 m stays at 2 m at every level, and each level's vertex map
  // re-projects with that level's intrinsics.
  Image<float> depth(kK.width, kK.height, 2.0f);
  std::vector<FrameLevel> pyr;
  buildFramePyramid(depth, kK, 3, pyr);
  ASSERT_EQ(pyr.size(), 3u);
  EXPECT_EQ(pyr[2].depth_m.width(), 160);
  EXPECT_EQ(pyr[2].depth_m.height(), 120);
  EXPECT_NEAR(pyr[2].K.fx, 525.0 / 4, 1e-9);
  // Pixel (x,y) at level 2 covers level-0 pixels 4x..4x+3: its centre is 4x + 1.5.
  const Vec3f p2 = pyr[2].vertex(10, 20);
  const Vec3f p0 = Eigen::Vector3f((4 * 10 + 1.5f - 319.5f) / 525.0f * 2.0f,
                                   (4 * 20 + 1.5f - 239.5f) / 525.0f * 2.0f, 2.0f);
  EXPECT_LT((p2 - p0).norm(), 1e-5);
}

TEST(SurfelMath, ConfidenceAndRadius) {
  const PinholeF K = kK.plain();
  EXPECT_NEAR(normalizedRadialDistance(319.5f, 239.5f, K), 0.0f, 1e-6);
  EXPECT_NEAR(normalizedRadialDistance(0.0f, 0.0f, K), 1.0f, 1e-6);
  EXPECT_NEAR(confidenceWeight(0.0f), 1.0f, 1e-7);
  // gamma = sigma -> exp(-1/2).
  EXPECT_NEAR(confidenceWeight(0.6f), std::exp(-0.5f), 1e-6);
  // r = z / (sqrt(2) f n_z): at 2 m, f = 525, facing the camera: 2.694 mm.
  EXPECT_NEAR(surfelRadius(2.0f, -1.0f, 525.0f), 2.0 / (std::sqrt(2.0) * 525.0), 1e-7);
  EXPECT_NEAR(surfelRadius(2.0f, 0.5f, 525.0f), 2.0 / (std::sqrt(2.0) * 525.0 * 0.5), 1e-7);
  EXPECT_NEAR(surfelRadius(2.0f, 0.01f, 525.0f, 0.2f), 2.0 / (std::sqrt(2.0) * 525.0 * 0.2), 1e-7);
}

TEST(Cuda, VertexNormalMatchCpu) {
  const auto avail = compute::cudaAvailability();
  if (!avail.available) GTEST_SKIP() << avail.reason;
  const double a = 20.0 * M_PI / 180.0;
  const Eigen::Vector3d n(std::sin(a), 0.0, -std::cos(a));
  const Image<float> depth = planeDepth(n, n.dot(Eigen::Vector3d(0, 0, 1.2)), kK);
  Image<Vec3f> vc, nc, vg, ng;
  computeVertexMap(depth, kK, vc, {}, compute::Backend::Cpu);
  computeNormalMap(vc, nc, 0.05f, compute::Backend::Cpu);
  computeVertexMap(depth, kK, vg, {}, compute::Backend::Cuda);
  computeNormalMap(vg, ng, 0.05f, compute::Backend::Cuda);
  for (int y = 1; y < kK.height - 1; y += 7)
    for (int x = 1; x < kK.width - 1; x += 5) {
      EXPECT_LT((vc(x, y) - vg(x, y)).norm(), 1e-6);
      EXPECT_LT((nc(x, y) - ng(x, y)).norm(), 1e-5);
    }
}

TEST(Bilateral, SmoothsNoiseKeepsEdgesAndInvalid) {
  // Two fronto-parallel planes (1.0 m | 2.0 m) with +-2 mm alternating noise and a hole.
  Image<float> d(64, 48);
  for (int y = 0; y < 48; ++y)
    for (int x = 0; x < 64; ++x)
      d(x, y) = (x < 32 ? 1.0f : 2.0f) + (((x + y) % 2) ? 0.002f : -0.002f);
  d(10, 10) = 0.0f;
  Image<float> f;
  bilateralFilterDepth(d, f, 2, 4.5f, 0.03f);
  EXPECT_EQ(f(10, 10), 0.0f);             // invalid stays invalid
  EXPECT_NEAR(f(11, 10), 1.0f, 0.0015f);  // a hole does not pull depth towards 0
  EXPECT_NEAR(f(20, 20), 1.0f, 0.0008f);  // noise averaged down (5x5 of +-2 mm)
  EXPECT_NEAR(f(31, 20), 1.0f, 0.0015f);  // the 1 m edge is not blended with 2 m
  EXPECT_NEAR(f(32, 20), 2.0f, 0.0015f);
}

TEST(Bilateral, PairWeightIsOneBodyOnOneAndFourLanes) {
  // kernels::bilateralWeight is the kernel's weight and the SSE launcher's: both instantiations
  // give the same bits, within 3e-6 relative of exp2 (exp2NonPositive's polynomial bound).
  const float depth_log2 = kernels::bilateralDepthLog2(0.03f);
  int checked = 0;
  for (int d2 = 0; d2 <= 18; ++d2) {
    const float space = kernels::bilateralSpaceLog2(d2, 4.5f);
    for (int k = -200; k <= 200; k += 3) {
      const float dz[4] = {k * 1e-4f, k * 7e-4f, k * 3.1e-3f, -k * 1.3e-2f};
      float four[4];
      lanes::store(four, kernels::bilateralWeight(lanes::F4(space),
                                                  lanes::F4(dz, lanes::stdx::element_aligned),
                                                  lanes::F4(depth_log2)));
      for (int l = 0; l < 4; ++l) {
        const float one = kernels::bilateralWeight(space, dz[l], depth_log2);
        ASSERT_EQ(std::memcmp(&one, &four[l], sizeof one), 0) << d2 << " dz " << dz[l];
        // (against 2^t of the float exponent the weight is computed from: the polynomial's error)
        const float t = std::max(-126.0f, space - dz[l] * dz[l] * depth_log2);
        ASSERT_NEAR(one / std::exp2(double(t)), 1.0, 3e-6) << d2 << " dz " << dz[l];
        ++checked;
      }
    }
  }
  EXPECT_EQ(checked, 19 * 134 * 4);
  EXPECT_EQ(kernels::bilateralWeight(0.0f, 0.0f, depth_log2), 1.0f);  // the centre tap: exactly 1
  EXPECT_EQ(kernels::exp2NonPositive(-500.0f), std::ldexp(1.0f, -126));  // clamped, not 0
}

TEST(Bilateral, CpuLauncherComputesTheKernelsFilter) {
  // A tilted plane with pseudo-random +-3 mm noise, a 40 cm step and scattered holes: the SSE CPU
  // path must give BilateralDepthKernel's values (same window and invalid handling, the same
  // weights bit for bit: PairWeightIsOneBodyOnOneAndFourLanes; only the order of the sums
  // differs, so depths agree to ~1e-6 m).
  const int w = 97, h = 61;  // not a multiple of 4: scalar tails and borders are exercised
  Image<float> d(w, h);
  std::uint32_t s = 12345u;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      s = s * 1664525u + 1013904223u;
      const float noise = (float(s >> 8) / float(1u << 24) - 0.5f) * 0.006f;
      d(x, y) = 1.2f + 0.004f * x + 0.002f * y + (x > 50 ? 0.4f : 0.0f) + noise;
      if ((s >> 4) % 17 == 0) d(x, y) = 0.0f;
    }
  for (int radius = 0; radius <= 3; ++radius) {  // every window the launcher supports
    Image<float> cpu, ref(w, h);
    bilateralFilterDepth(d, cpu, radius, 4.5f, 0.03f);
    kernels::BilateralDepthKernel k{d.cview(), ref.view(), radius, 4.5f, 0.03f};
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) k(x, y);
    int invalid = 0;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        if (d(x, y) == 0.0f) {
          ++invalid;
          ASSERT_EQ(cpu(x, y), 0.0f) << x << "," << y << " radius " << radius;
          continue;
        }
        ASSERT_NEAR(cpu(x, y), ref(x, y), 2e-6f) << x << "," << y << " radius " << radius;
      }
    EXPECT_GT(invalid, 100);
  }
  Image<float> out;
  EXPECT_THROW(bilateralFilterDepth(d, out, 4, 4.5f, 0.03f), std::invalid_argument);
  Image<float> tiny(3, 2, 1.0f);  // narrower than one group of four pixels
  bilateralFilterDepth(tiny, out, 2, 4.5f, 0.03f);
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 3; ++x) EXPECT_FLOAT_EQ(out(x, y), 1.0f);
}

TEST(VertexMap, CpuLauncherBitIdenticalToTheKernel) {
  // 103x7 (a tail of 3 columns per row): depths in and out of [min, max], zeros and NaNs; the
  // SSE launcher must write the kernel's vertices bit for bit (invalid ones as its NaN triple).
  const int w = 103, h = 7;
  const CameraIntrinsics K(52.5, 51.0, 51.3, 3.1, w, h);
  Image<float> d(w, h);
  std::uint32_t s = 99u;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      s = s * 1664525u + 1013904223u;
      const int kind = int((s >> 20) % 10);
      d(x, y) = kind == 0   ? 0.0f
                : kind == 1 ? std::nanf("")
                : kind == 2 ? 0.05f
                : kind == 3 ? 12.0f
                            : 0.3f + float(s >> 8) / float(1u << 24) * 5.0f;
    }
  VertexMapOptions opt;
  opt.min_depth_m = 0.1f;
  opt.max_depth_m = 8.0f;
  Image<Vec3f> cpu, ref(w, h);
  computeVertexMap(d, K, cpu, opt, compute::Backend::Cpu);
  const kernels::VertexMapKernel k{d.cview(), ref.view(), K.plain(), opt.min_depth_m,
                                   opt.max_depth_m};
  int valid = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      k(x, y);
      valid += ref(x, y).x() == ref(x, y).x();
    }
  for (int y = 0; y < h; ++y)
    ASSERT_EQ(std::memcmp(cpu.row(y), ref.row(y), sizeof(Vec3f) * w), 0) << "row " << y;
  EXPECT_GT(valid, w * h / 2);
  EXPECT_LT(valid, w * h);
}

TEST(Bilateral, CpuLauncherIsIndependentOfThreadCount) {
  // The launcher splits rows into bands by thread count and adds each pair's weight to both
  // pixels: the sums' order must not depend on the split (bit-identical outputs).
  const int w = 131, h = 77;
  Image<float> d(w, h);
  std::uint32_t s = 777u;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      s = s * 1664525u + 1013904223u;
      d(x, y) = 0.8f + 0.01f * float(x % 13) + (float(s >> 8) / float(1u << 24)) * 0.01f;
      if ((s >> 4) % 11 == 0) d(x, y) = (s >> 9) % 2 ? 0.0f : std::nanf("");
    }
  const int nt = omp_get_max_threads();
  Image<float> one, many;
  omp_set_num_threads(1);
  bilateralFilterDepth(d, one, 2, 4.5f, 0.03f);
  omp_set_num_threads(std::max(3, nt));
  bilateralFilterDepth(d, many, 2, 4.5f, 0.03f);
  omp_set_num_threads(nt);
  for (int y = 0; y < h; ++y)
    ASSERT_EQ(std::memcmp(one.row(y), many.row(y), sizeof(float) * w), 0) << "row " << y;
}

// ---- compute::reduce1D: fixed chunks summed in order ----

#include "rasm/compute/Parallel.h"
#ifdef _OPENMP
#include <omp.h>
#endif

namespace {
struct SumAcc {
  float f = 0.0f;  // float: a different grouping of the terms would change the bits
  long long n = 0;
  SumAcc& operator+=(const SumAcc& o) {
    f += o.f;
    n += o.n;
    return *this;
  }
};
}  // namespace

TEST(Reduce1D, SameBitsForAnyThreadCount) {
  const int n = 100003;
  const auto term = [](int i, SumAcc& a) {
    a.f += 1.0f / float(1 + i % 977) + (i % 3 == 0 ? 1e3f : 1e-3f);
    ++a.n;
  };
  std::vector<SumAcc> results;
  const int team = compute::maxThreads();
  for (int threads : {1, 2, 3, 5}) {
#ifdef _OPENMP
    omp_set_num_threads(threads);
#else
    (void)threads;
#endif
    results.push_back(compute::reduce1D<SumAcc>(n, term));
  }
#ifdef _OPENMP
  omp_set_num_threads(team);
#else
  (void)team;
#endif
  for (const SumAcc& r : results) {
    EXPECT_EQ(r.n, n);
    EXPECT_EQ(r.f, results[0].f);  // bitwise: the chunking does not depend on the team
  }
  // And it is the sum (float rounding over 1e5 terms: ~1e-4 relative).
  double exact = 0.0;
  for (int i = 0; i < n; ++i) exact += 1.0 / (1 + i % 977) + (i % 3 == 0 ? 1e3 : 1e-3);
  EXPECT_NEAR(results[0].f, exact, 1e-4 * exact);
}

TEST(NormalMap, CpuLauncherIsBitIdenticalToTheKernel) {
  // Noisy depth with holes, a depth step (normals invalid across it) and a width that is not a
  // multiple of 4 (the SSE path, its scalar row ends and the borders all run).
  const int w = 83, h = 37;
  const CameraIntrinsics K(80.0, 80.0, 41.0, 18.0, w, h);
  Image<float> d(w, h);
  std::uint32_t s = 777u;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      s = s * 1664525u + 1013904223u;
      d(x, y) = 1.0f + 0.01f * x - 0.005f * y + (x > 40 ? 0.3f : 0.0f) +
                (float(s >> 8) / float(1u << 24) - 0.5f) * 0.004f;
      if ((s >> 4) % 13 == 0) d(x, y) = 0.0f;
    }
  Image<Vec3f> v, n, ref(w, h);
  computeVertexMap(d, K, v);
  computeNormalMap(v, n, 0.05f);
  const kernels::NormalMapKernel k{v.cview(), ref.view(), 0.05f};
  int valid = 0, invalid = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      k(x, y);
      if (kernels::validVec(ref(x, y))) {
        ++valid;
        ASSERT_EQ(0, std::memcmp(n(x, y).data(), ref(x, y).data(), sizeof(Vec3f))) << x << "," << y;
      } else {
        ++invalid;
        ASSERT_FALSE(kernels::validVec(n(x, y))) << x << "," << y;
      }
    }
  EXPECT_GT(valid, 1000);
  EXPECT_GT(invalid, 500);
}

TEST(RoundHalfAway, EqualsLround) {
  const float edge = std::nextafter(0.5f, 0.0f);  // 0.49999997: x + 0.5 would round up to 1
  for (float x : {0.0f, -0.0f, 0.5f, -0.5f, 1.5f, -1.5f, 2.5f, -2.5f, edge, -edge, 0.7f, -0.7f,
                  319.49998f, 639.5f, -3.2f, 1e6f + 0.5f})
    EXPECT_EQ(compute::roundHalfAway(x), int(std::lround(x))) << x;
  std::uint32_t s = 99u;
  for (int k = 0; k < 100000; ++k) {
    s = s * 1664525u + 1013904223u;
    const float x = (float(s >> 8) / float(1u << 24) - 0.5f) * 2000.0f;
    ASSERT_EQ(compute::roundHalfAway(x), int(std::lround(x))) << x;
  }
}

// Colour registration's projection (fuzz_rawlog found a NaN converted to int under UBSan): a
// point in front projects to its rounded pixel; NaN, huge, behind-camera and outside points give
// no pixel.
TEST(NearestPixel, RoundsInsideAndRefusesNanHugeBehindAndOutside) {
  const rasm::PinholeF K{500.0f, 500.0f, 319.5f, 239.5f, 640, 480};
  int u = -1, v = -1;
  ASSERT_TRUE(rasm::nearestPixel(K, Eigen::Vector3f(0.0f, 0.0f, 2.0f), 640, 480, u, v));
  EXPECT_EQ(u, 320);  // 319.5 rounds half away from zero
  EXPECT_EQ(v, 240);
  ASSERT_TRUE(rasm::nearestPixel(K, Eigen::Vector3f(-1.2772f, -0.9572f, 2.0f), 640, 480, u, v));
  EXPECT_EQ(u, 0);
  EXPECT_EQ(v, 0);
  const float nan = std::nanf(""), huge = 1e30f;
  for (const Eigen::Vector3f& p :
       {Eigen::Vector3f(nan, 0, 1), Eigen::Vector3f(0, 0, nan), Eigen::Vector3f(huge, 0, 1),
        Eigen::Vector3f(0, -huge, 1), Eigen::Vector3f(0, 0, -1), Eigen::Vector3f(0, 0, 0),
        Eigen::Vector3f(2.0f, 0, 1)})
    EXPECT_FALSE(rasm::nearestPixel(K, p, 640, 480, u, v)) << p.transpose();
}
