// The SSE CPU launchers of fusion (FusionCpu.h) against the kernels themselves, bit for bit.

#include "rasm/fusion/FusionCpu.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <vector>

#include "rasm/core/CameraIntrinsics.h"
#include "rasm/core/Image.h"
#include "rasm/surfel_map/SurfelStore.h"
#include "rasm/surfel_map/kernels/ViewBins.h"

using namespace rasm;
using namespace rasm::fusion;

namespace {

template <typename T>
bool sameBytes(const T* a, const T* b, std::size_t n) {
  return std::memcmp(a, b, n * sizeof(T)) == 0;
}

/// Rows of two images byte-equal (one expectation per row, naming it).
template <typename T>
void expectSameRows(const Image<T>& a, const Image<T>& b) {
  for (int y = 0; y < a.height(); ++y)
    EXPECT_TRUE(sameBytes(a.row(y), b.row(y), std::size_t(a.width()))) << "row " << y;
}

/// Candidate lists in SurfelRenderer::renderCandidates4x's layout, every entry a candidate:
/// build(W, H, pixel) calls pixel(x, y, out) in row order, which appends pixel (x, y)'s entries.
struct TestLists {
  std::vector<maps::kernels::CameraPoint> entries;
  std::vector<std::uint32_t> first;
  std::vector<std::uint8_t> count;

  template <typename F>
  static TestLists build(int w, int h, F&& pixel) {
    TestLists l;
    std::vector<maps::kernels::CameraPoint> out;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        out.clear();
        pixel(x, y, out);
        l.first.push_back(std::uint32_t(l.entries.size()));
        l.entries.insert(l.entries.end(), out.begin(), out.end());
        l.count.push_back(std::uint8_t(out.size()));
      }
    l.first.push_back(std::uint32_t(l.entries.size()));
    return l;
  }
};

/// An AssociateKernel over a frame (vertex, normal, weight images; focal length 30 px) and the
/// candidate lists of the surfels in `store` (world = camera frame).
kernels::AssociateKernel<kernels::ListCandidates> listAssociateKernel(
    const Image<Vec3f>& vertex, const Image<Vec3f>& normal, const Image<float>& weight,
    const CameraIntrinsics& K, const TestLists& lists, const maps::SurfelStore& store) {
  kernels::AssociateKernel<kernels::ListCandidates> k;
  k.frame.vertex_cam = vertex.cview();
  k.frame.normal_cam = normal.cview();
  k.frame.weight = weight.cview();
  k.frame.K = K.plain();
  k.frame.focal_px = 30.0f;
  k.candidates.entries = lists.entries.data();
  k.candidates.first = lists.first.data();
  k.candidates.count = lists.count.data();
  k.candidates.width = K.width;
  k.candidates.height = K.height;
  k.s = store.arrays();
  return k;
}

}  // namespace

/// View-bin layouts (azimuth sectors, elevation rings): the comparison-decided ones and one
/// through fastAtan2 (12 x 5), all on the update's four lanes.
class UpdateCpu : public ::testing::TestWithParam<std::pair<int, int>> {};
INSTANTIATE_TEST_SUITE_P(ViewBinLayouts, UpdateCpu,
                         ::testing::Values(std::make_pair(8, 2), std::make_pair(8, 1),
                                           std::make_pair(8, 4), std::make_pair(12, 5)),
                         [](const auto& info) {
                           return std::to_string(info.param.first) + "x" +
                                  std::to_string(info.param.second);
                         });

TEST_P(UpdateCpu, BitIdenticalToTheKernel) {
  const auto [n_azimuth, n_elevation] = GetParam();
  // 37x6 pixels (partial lane groups), every pixel measured, ~80% associated with distinct
  // surfels in shuffled order (the last surfel too: its basis is read without the vector load).
  // The surfels cover every branch: geometry averaged or not (radius rule), radius shrunk or not,
  // becoming stable, already stable, basis parallel to the normal (anyPerpendicular fallback),
  // crossing a block border, labels that accumulate, erode and relabel, view bins, carving.
  const int W = 37, H = 6;
  const CameraIntrinsics K(30.0, 30.0, 18.0, 2.5, W, H);
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f), u01(0.0f, 1.0f);

  Image<Vec3f> vertex(W, H), normal(W, H);
  Image<Bgr8> colour(W, H);
  Image<std::uint32_t> labels(W, H);
  Image<float> depth(W, H);
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const float z = 1.0f + 2.0f * u01(rng);
      const Vec3f v((float(x) - K.cx) / K.fx * z, (float(y) - K.cy) / K.fy * z, z);
      vertex(x, y) = v;
      normal(x, y) = (-v.normalized() + 0.3f * Vec3f(u(rng), u(rng), u(rng))).normalized();
      colour(x, y) =
          Bgr8{std::uint8_t(rng() & 255), std::uint8_t(rng() & 255), std::uint8_t(rng() & 255)};
      labels(x, y) = rng() % 4;                      // 0 = none
      depth(x, y) = u01(rng) < 0.2f ? z + 0.5f : z;  // some measurements far behind the surfels
    }

  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() =
      Eigen::AngleAxisd(0.3, Eigen::Vector3d(0.2, 1.0, 0.1).normalized()).toRotationMatrix();
  T.translation() = Eigen::Vector3d(0.1, -0.2, 0.05);
  const RigidF T_wc = RigidF::fromMatrix(T.matrix().cast<float>());

  const int n_surfels = W * H + 5;
  std::vector<int> order(n_surfels);
  for (int i = 0; i < n_surfels; ++i) order[i] = n_surfels - 1 - i;
  std::shuffle(order.begin() + 1, order.end(), rng);  // order[0] = the last surfel
  Image<std::int32_t> pixel_surfel(W, H);
  Image<std::uint16_t> flags_ref(W, H), flags_sse(W, H);
  std::vector<Vec3f> near(n_surfels, Vec3f(0.5f, 0.2f, 2.0f));  // camera frame, unassigned ones
  int next = 0, associated = 0;
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const bool take = u01(rng) < 0.8f;
      pixel_surfel(x, y) = take ? order[next++] : -1;
      associated += take;
      flags_ref(x, y) = flags_sse(x, y) =
          take ? std::uint16_t(kernels::kPixValid | kernels::kPixAssociated) : 0;
      // On the pixel's ray, from well in front of the measurement to just behind it.
      if (take) near[pixel_surfel(x, y)] = vertex(x, y) * (0.6f + 0.45f * u01(rng));
    }
  ASSERT_GT(associated, 100);

  maps::SurfelStoreOptions layout;
  layout.view_bins_azimuth = n_azimuth;
  layout.view_bins_elevation = n_elevation;
  maps::SurfelStore store(layout);
  store.allocate(n_surfels);
  {
    const maps::SurfelArrays a = store.arrays();
    for (int i = 0; i < n_surfels; ++i) {
      const Vec3f n = Vec3f(u(rng), u(rng), u(rng)).normalized();
      const float conf = 20.0f * u01(rng);
      const Vec3f p = T_wc.apply(near[i]);
      // Radii around the measurement's (z / (sqrt2 f n_z) ~ 0.02-0.1 m here): the radius rule
      // (r <= 1.5 r_s) passes for about half of them.
      a.pos_conf[i] = Vec4f(p.x(), p.y(), p.z(), conf);
      a.normal_radius[i] = Vec4f(n.x(), n.y(), n.z(), 0.01f + 0.1f * u01(rng));
      a.basis[i] = i % 11 == 0 ? n : maps::kernels::anyPerpendicular(n);
      a.colour_flags[i] = (rng() & 0xffffffu) | (conf >= 10.0f ? maps::kSurfelStable : 0u);
      a.t_init[i] = 0.0f;
      a.t_last[i] = 0.1f;
      a.segment[i] = rng() % 4;
      a.segment_w[i] = 3.0f * u01(rng);
      for (int b = 0; b < a.n_view_bins; ++b)
        a.viewRow(i)[b] = std::uint8_t(rng() % 3 == 0 ? 255 : rng() & 255);
    }
  }

  maps::SurfelStore ref = store, sse = store;
  kernels::UpdateKernel k;
  k.frame.colour = colour.cview();
  k.frame.vertex_cam = vertex.cview();
  k.frame.normal_cam = normal.cview();
  k.frame.labels = labels.cview();
  k.frame.K = K.plain();
  k.frame.focal_px = 30.0f;
  k.prm.max_depth_m = 5.0f;
  k.prm.n_azimuth = n_azimuth;
  k.prm.n_elevation = n_elevation;
  k.prm.inv_block_size = 8.0f;  // 12.5 cm blocks: some updates cross a border
  k.T_world_cam = T_wc;
  k.T_cam_world = RigidF::fromMatrix(T.inverse().matrix().cast<float>());
  k.now = 0.5f;
  k.pixel_surfel = pixel_surfel.cview();
  k.carve = true;
  k.carve_test.depth_m = depth.cview();
  k.carve_test.K = K.plain();

  // The kernel, pixel by pixel.
  kernels::UpdateKernel kr = k;
  kr.s = ref.arrays();
  kr.flags = flags_ref.view();
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) kr(x, y);

  // The launcher, with the measurements an association keeps.
  kernels::UpdateKernel ks = k;
  ViewInfoThresholds ic;  // surfels 1-3 m away: IC 1-0.37, bins of random values raised or not
  ic.build(k.prm.ic_lambda1, k.prm.ic_d_min_m);
  ks.s = sse.arrays();
  ks.flags = flags_sse.view();
  std::vector<KeptMeasurement> kept(W);
  int fused = 0, shrunk = 0, fallback = 0;
  for (int y = 0; y < H; ++y) {
    for (int x = 0; x < W; ++x) {
      Vec3f v, n;
      float w = 0.f, r = 0.f;
      ASSERT_TRUE(k.frame.measure(x, y, k.prm, v, n, w, r)) << x << "," << y;
      kept[x] = KeptMeasurement{v, k.T_world_cam.rotate(n), w, r};
      const int i = pixel_surfel(x, y);
      if (i >= 0) {
        const float rs = store.arrays().normal_radius[i].w();
        fused += r <= k.prm.radius_update_ratio * rs;
        shrunk += r < rs;
        fallback += i % 11 == 0 && r <= k.prm.radius_update_ratio * rs;
      }
    }
    // (odd rows with the view-bin thresholds, even rows without: both must be the kernel's)
    updateRowCpu(ks, y, kept.data(), true, true, y % 2 ? &ic : nullptr);
  }
  EXPECT_GT(fused, 20);
  EXPECT_GT(associated - fused, 20);
  EXPECT_GT(shrunk, 10);
  EXPECT_GT(fallback, 2);

  int flag_kinds = 0;
  for (std::uint16_t bit : {kernels::kPixFused, kernels::kPixBecameStable, kernels::kPixRelabelled,
                            kernels::kPixCrossedBlock}) {
    int with = 0;
    for (int y = 0; y < H; ++y)
      for (int x = 0; x < W; ++x) with += (flags_ref(x, y) & bit) != 0;
    flag_kinds += with > 0;
  }
  EXPECT_EQ(flag_kinds, 4) << "every outcome must occur";
  int carved = 0;
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) carved += (flags_ref(x, y) >> kernels::kPixCarveShift) != 0;
  EXPECT_GT(carved, 0);

  const maps::SurfelArrays a = ref.arrays(), b = sse.arrays();
  const std::size_t n = std::size_t(n_surfels);
  EXPECT_TRUE(sameBytes(a.pos_conf, b.pos_conf, n));
  EXPECT_TRUE(sameBytes(a.normal_radius, b.normal_radius, n));
  EXPECT_TRUE(sameBytes(a.basis, b.basis, n));
  EXPECT_TRUE(sameBytes(a.colour_flags, b.colour_flags, n));
  EXPECT_TRUE(sameBytes(a.t_last, b.t_last, n));
  EXPECT_TRUE(sameBytes(a.segment, b.segment, n));
  EXPECT_TRUE(sameBytes(a.segment_w, b.segment_w, n));
  EXPECT_TRUE(sameBytes(a.view_ic, b.view_ic, n * std::size_t(a.n_view_bins)));
  expectSameRows(flags_ref, flags_sse);
}

TEST(AssociateCpu, BitIdenticalToTheKernel) {
  // 37x5 pixels: invalid vertices and normals, depths outside the range, grazing normals, and
  // 0-6 candidates per pixel around the pixel ray (some outside the depth or normal gates); the
  // launcher must give the kernel's matches, flags and kept measurements.
  const int W = 37, H = 5;
  const CameraIntrinsics K(30.0, 30.0, 18.0, 2.5, W, H);
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f), u01(0.0f, 1.0f);
  const float nan = std::nanf("");
  Image<Vec3f> vertex(W, H), normal(W, H);
  Image<float> weight(W, H);
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const float z = 0.05f + 6.0f * u01(rng);  // some outside [0.1, 5]
      const Vec3f v((float(x) - K.cx) / K.fx * z, (float(y) - K.cy) / K.fy * z, z);
      vertex(x, y) = u01(rng) < 0.05f ? Vec3f(nan, nan, nan) : v;
      const float tilt = u01(rng) < 0.15f ? 3.0f : 0.3f;  // some grazing
      normal(x, y) = u01(rng) < 0.05f
                         ? Vec3f(nan, nan, nan)
                         : (-v.normalized() + tilt * Vec3f(u(rng), u(rng), u(rng))).normalized();
      weight(x, y) = u01(rng);
    }
  vertex(W - 1, H - 1) = Vec3f(0.1f, 0.05f, 1.0f);  // the last element is measured
  normal(W - 1, H - 1) = Vec3f(0.0f, 0.0f, -1.0f);

  maps::SurfelStore store;
  const TestLists lists =
      TestLists::build(W, H, [&](int x, int y, std::vector<maps::kernels::CameraPoint>& pixel) {
        const int n = int(rng() % 7);  // 0-6: one or two groups of four in the SSE launcher
        const Vec3f v = vertex(x, y).x() == vertex(x, y).x() ? vertex(x, y) : Vec3f(0, 0, 1);
        for (int c = 0; c < n; ++c) {
          maps::Surfel s;
          const Vec3f pc = v * (1.0f + 0.03f * u(rng)) + 0.01f * Vec3f(u(rng), u(rng), u(rng));
          s.position = pc;  // world = camera frame here
          const Vec3f nn = normal(x, y).x() == normal(x, y).x() ? normal(x, y) : Vec3f(0, 0, -1);
          s.normal = (nn + 0.6f * Vec3f(u(rng), u(rng), u(rng))).normalized();
          s.radius = 0.005f + 0.05f * u01(rng);
          s.confidence = 1.0f;
          pixel.push_back(maps::kernels::CameraPoint{pc, store.append(s)});
          // Some exact twins (another index): equal costs, the lower index must win.
          if (u01(rng) < 0.4f) pixel.push_back(maps::kernels::CameraPoint{pc, store.append(s)});
        }
        std::shuffle(pixel.begin(), pixel.end(), rng);
      });

  kernels::AssociateKernel<kernels::ListCandidates> k =
      listAssociateKernel(vertex, normal, weight, K, lists, store);
  k.prm.min_cos_normal = 0.9f;
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() =
      Eigen::AngleAxisd(0.2, Eigen::Vector3d(1.0, 0.3, 0.0).normalized()).toRotationMatrix();
  k.T_world_cam = RigidF::fromMatrix(T.matrix().cast<float>());  // (normals compared in this frame)

  Image<std::int32_t> ps_ref(W, H), ps_sse(W, H);
  Image<std::uint16_t> fl_ref(W, H), fl_sse(W, H);
  std::vector<KeptMeasurement> kept_ref(std::size_t(W * H)), kept_sse(std::size_t(W * H));
  std::memset(static_cast<void*>(kept_ref.data()), 0, kept_ref.size() * sizeof(KeptMeasurement));
  std::memset(static_cast<void*>(kept_sse.data()), 0, kept_sse.size() * sizeof(KeptMeasurement));
  kernels::AssociateKernel<kernels::ListCandidates> kr = k, ks = k;
  kr.pixel_surfel = ps_ref.view();
  kr.flags = fl_ref.view();
  ks.pixel_surfel = ps_sse.view();
  ks.flags = fl_sse.view();
  int outcome[3] = {0, 0, 0};  // none, new, associated
  for (int y = 0; y < H; ++y) {
    for (int x = 0; x < W; ++x) {
      kernels::PixelMeasurement m;
      const int best = kr.associate(x, y, m);
      ++outcome[best >= 0 ? 2 : -best - 1];
      if (best != -1) kept_ref[std::size_t(y * W + x)] = KeptMeasurement{m.v, m.n_world, m.w, m.r};
    }
    associateRowCpu(ks, y, kept_sse.data() + std::size_t(y) * W);
  }
  EXPECT_GT(outcome[0], 10);
  EXPECT_GT(outcome[1], 10);
  EXPECT_GT(outcome[2], 10);
  EXPECT_GE(ps_ref(W - 1, H - 1), -2);  // the last element was measured
  expectSameRows(ps_ref, ps_sse);
  expectSameRows(fl_ref, fl_sse);
  EXPECT_TRUE(sameBytes(reinterpret_cast<const char*>(kept_ref.data()),
                        reinterpret_cast<const char*>(kept_sse.data()),
                        kept_ref.size() * sizeof(KeptMeasurement)));
}

TEST(AssociateCpu, MeasurementsBitIdenticalToTheKernel) {
  // Every field of the association's measurement (FrameView::measure, measureForAssociation) on
  // four lanes, for valid, invalid, out-of-range and grazing pixels, the last one of the image too.
  const int W = 23, H = 4;
  const CameraIntrinsics K(30.0, 28.0, 11.0, 1.5, W, H);
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f), u01(0.0f, 1.0f);
  Image<Vec3f> vertex(W, H), normal(W, H);
  Image<float> weight(W, H);
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const float z = 0.05f + 6.0f * u01(rng);
      const Vec3f v((float(x) - K.cx) / K.fx * z, (float(y) - K.cy) / K.fy * z, z);
      vertex(x, y) = u01(rng) < 0.05f ? Vec3f(std::nanf(""), 0, 0) : v;
      normal(x, y) =
          (-v.normalized() + (u01(rng) < 0.2f ? 3.0f : 0.4f) * Vec3f(u(rng), u(rng), u(rng)))
              .normalized();
      weight(x, y) = u01(rng);
    }
  vertex(W - 1, H - 1) = Vec3f(0.1f, 0.05f, 1.0f);
  normal(W - 1, H - 1) = Vec3f(0.1f, 0.0f, -1.0f).normalized();
  kernels::FrameView fv;
  fv.vertex_cam = vertex.cview();
  fv.normal_cam = normal.cview();
  fv.weight = weight.cview();
  fv.K = K.plain();
  fv.focal_px = 29.0f;
  kernels::FusionKernelParams prm;
  prm.assoc_dz_rel = 0.012f;
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() =
      Eigen::AngleAxisd(0.7, Eigen::Vector3d(0.3, 1.0, 0.2).normalized()).toRotationMatrix();
  const RigidF R = RigidF::fromMatrix(T.matrix().cast<float>());
  int valid = 0, invalid = 0;
  for (int y = 0; y < H; ++y)
    for (int x0 = 0; x0 < W; x0 += 4) {
      const int nl = std::min(4, W - x0);
      int xs[4];
      for (int l = 0; l < 4; ++l) xs[l] = x0 + (l < nl ? l : 0);
      kernels::PixelMeasurement m[4];
      const int mask = measureFour(fv, prm, R, y, xs, nl, m);
      for (int l = 0; l < nl; ++l) {
        kernels::PixelMeasurement ref;
        const bool ok = kernels::measureForAssociation(fv, x0 + l, y, prm, R, ref);
        ASSERT_EQ(ok, ((mask >> l) & 1) != 0) << x0 + l << "," << y;
        valid += ok;
        invalid += !ok;
        if (ok) {
          EXPECT_EQ(0, std::memcmp(&ref, &m[l], sizeof ref)) << x0 + l << "," << y;
        }
      }
    }
  EXPECT_GT(valid, 20);
  EXPECT_GT(invalid, 10);
}

TEST(CarveTest, UpdatedSurfelSkipNeverHidesAViolation) {
  // CarveTest::updatedMayViolate lets the update skip the carving projection of a surfel it just
  // averaged with pixel (x, y)'s measurement. Random updates (old centre inside the pixel's square
  // within the association gate of the measured depth z, averaged with the measured point on the
  // pixel ray) over a raw depth image that differs from z by up to +-15 cm (the filtered depth
  // near edges): whenever the full test says "violates", the skip test must say "may violate".
  const CameraIntrinsics K(131.25, 131.25, 79.5, 59.5, 160, 120);
  const PinholeF Kp = K.plain();
  Image<float> raw(K.width, K.height);
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> uni(0.0f, 1.0f);
  for (int y = 0; y < K.height; ++y)
    for (int x = 0; x < K.width; ++x) raw(x, y) = 0.6f + 3.2f * float((x / 9 + y / 7) % 5) / 4.0f;
  kernels::CarveTest t;
  t.depth_m = raw.cview();
  t.K = Kp;
  t.min_depth_m = 0.3f;
  t.max_depth_m = 4.5f;
  const float gate_abs = 0.03f, gate_rel = 0.01f;  // TFusionParams' association gate
  int violations = 0, skipped = 0;
  for (int k = 0; k < 200000; ++k) {
    const int x = 1 + int(uni(rng) * float(K.width - 2)),
              y = 1 + int(uni(rng) * float(K.height - 2));
    const float z = raw(x, y) + (uni(rng) - 0.5f) * 0.3f;
    const float dz = std::max(gate_abs, gate_rel * z);
    const float z_old = z + (2.0f * uni(rng) - 1.0f) * dz;
    // Old centre anywhere in the pixel's square at depth z_old; measured point on the pixel ray.
    const float u = float(x) - 0.5f + uni(rng), v = float(y) - 0.5f + uni(rng);
    const Vec3f p_old((u - Kp.cx) / Kp.fx * z_old, (v - Kp.cy) / Kp.fy * z_old, z_old);
    const Vec3f p_meas((float(x) - Kp.cx) / Kp.fx * z, (float(y) - Kp.cy) / Kp.fy * z, z);
    const float a1 = uni(rng);
    const Vec3f p = (1.0f - a1) * p_old + a1 * p_meas;
    const bool violates = t.violates(p), may = t.updatedMayViolate(x, y, z, dz);
    violations += violates;
    skipped += !may;
    if (violates) {
      ASSERT_TRUE(may) << x << "," << y << " z " << z << " z_old " << z_old;
    }
  }
  EXPECT_GT(violations, 100);  // the case the skip must not hide occurs
  EXPECT_GT(skipped, 100000);  // and the skip is taken where the depths agree
}

TEST(CoverCpu, BitIdenticalToTheKernel) {
  // A noisy plane 1 m ahead seen by 37x5 pixels; every third pixel has no candidate (new), the
  // others 1-2 surfels near their ray with radii of 0.1-1.2 pixel footprints: coverRowCpu, with the
  // association's kept measurements, must drop exactly the new pixels the kernel drops.
  const int W = 37, H = 5;
  const CameraIntrinsics K(30.0, 30.0, 18.0, 2.5, W, H);
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f), u01(0.0f, 1.0f);
  Image<Vec3f> vertex(W, H), normal(W, H);
  Image<float> weight(W, H);
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const float z = 1.0f + 0.005f * u(rng);
      vertex(x, y) = Vec3f((float(x) - K.cx) / K.fx * z, (float(y) - K.cy) / K.fy * z, z);
      normal(x, y) = (Vec3f(0, 0, -1) + 0.05f * Vec3f(u(rng), u(rng), u(rng))).normalized();
      weight(x, y) = 0.2f + 0.8f * u01(rng);
    }
  maps::SurfelStore store;
  const TestLists lists =
      TestLists::build(W, H, [&](int x, int y, std::vector<maps::kernels::CameraPoint>& pixel) {
        const int n = (x + 2 * y) % 3 == 0 ? 0 : 1 + int(rng() % 2);
        for (int c = 0; c < n; ++c) {
          maps::Surfel s;
          const Vec3f pc = vertex(x, y) + Vec3f(0.012f * u(rng), 0.012f * u(rng), 0.005f * u(rng));
          s.position = pc;  // world = camera frame
          s.normal = (Vec3f(0, 0, -1) + 0.05f * Vec3f(u(rng), u(rng), u(rng))).normalized();
          s.radius = (0.1f + 1.1f * u01(rng)) / 30.0f;
          s.confidence = 1.0f;
          pixel.push_back(maps::kernels::CameraPoint{pc, store.append(s)});
        }
      });

  kernels::AssociateKernel<kernels::ListCandidates> ka =
      listAssociateKernel(vertex, normal, weight, K, lists, store);
  Image<std::int32_t> ps_ref(W, H), ps_cpu(W, H);
  Image<std::uint16_t> fl_ref(W, H), fl_cpu(W, H);
  std::vector<KeptMeasurement> kept(std::size_t(W * H));
  ka.pixel_surfel = ps_cpu.view();
  ka.flags = fl_cpu.view();
  for (int y = 0; y < H; ++y) associateRowCpu(ka, y, kept.data() + std::size_t(y) * W);
  for (int y = 0; y < H; ++y) {
    std::memcpy(ps_ref.row(y), ps_cpu.row(y), sizeof(std::int32_t) * W);
    std::memcpy(fl_ref.row(y), fl_cpu.row(y), sizeof(std::uint16_t) * W);
  }

  kernels::CoverageKernel<kernels::ListCandidates> cr;
  cr.frame = ka.frame;
  cr.prm = ka.prm;
  cr.candidates = ka.candidates;
  cr.s = ka.s;
  kernels::CoverageKernel<kernels::ListCandidates> cc = cr;
  cr.pixel_surfel = ps_ref.view();
  cr.flags = fl_ref.view();
  cc.pixel_surfel = ps_cpu.view();
  cc.flags = fl_cpu.view();
  for (int y = 0; y < H; ++y) {
    for (int x = 0; x < W; ++x) cr(x, y);
    coverRowCpu(cc, y, kept.data() + std::size_t(y) * W);
  }
  int covered = 0, still_new = 0;
  expectSameRows(ps_ref, ps_cpu);
  expectSameRows(fl_ref, fl_cpu);
  for (int y = 0; y < H; ++y) {
    for (int x = 0; x < W; ++x) {
      covered += (fl_ref(x, y) & kernels::kPixCovered) != 0;
      still_new += (fl_ref(x, y) & kernels::kPixNew) != 0;
    }
  }
  EXPECT_GT(covered, 5);
  EXPECT_GT(still_new, 5);
}

TEST(ViewInfoThresholds, SkipOnlyWhereTheBinCannotRise) {
  // Every float distance in [0.5, 12] m, default IC parameters and another set: the bin value v
  // may be skipped (distance >= below[v]) only when the quantised IC is <= v, i.e. for every
  // distance, below[q - 1] > distance where q is its quantised IC (below is non-increasing).
  for (const auto& [l1, dm] : {std::pair<float, float>{0.5f, 1.0f}, {1.3f, 0.4f}}) {
    ViewInfoThresholds t;
    t.build(l1, dm);
    ASSERT_TRUE(t.builtFor(l1, dm));
    for (int v = 1; v < 255; ++v) ASSERT_LE(t.below[v], t.below[v - 1]) << v;
    EXPECT_GT(t.below[0], dm);
    EXPECT_GT(t.below[254], dm);
    std::uint32_t b0, b1;
    const float lo = 0.5f, hi = 12.0f;
    std::memcpy(&b0, &lo, 4);
    std::memcpy(&b1, &hi, 4);
    long long skipped = 0, checked = 0;
    for (std::uint32_t b = b0; b <= b1; b += 7) {  // every 7th float: ~2.8M distances
      float d;
      std::memcpy(&d, &b, 4);
      const int q = maps::quantizeUnit(maps::kernels::informationContent(d, l1, dm));
      ++checked;
      if (q > 0) {
        ASSERT_GT(t.below[q - 1], d) << "distance " << d << " IC level " << q;
      }
      skipped += q < 255 && d >= t.below[q];  // a bin already at q is skipped there
    }
    EXPECT_GT(skipped, checked / 2);
  }
}
