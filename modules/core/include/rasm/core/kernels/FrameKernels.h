#pragma once
// Per-pixel kernels of section II-A and the depth pyramid, written once for both backends.
// Plain header: only compute/ and Eigen, so .cu files include it.
// Invalid vertices/normals have x = NaN (compute::invalidFloat()); invalid depth is 0.

#include "rasm/compute/ImageView.h"
#include "rasm/compute/Lanes.h"
#include "rasm/compute/Types.h"

namespace rasm::kernels {

RASM_HD_INLINE bool validVec(const Vec3f& v) {
  return v.x() == v.x();
}
RASM_HD_INLINE Vec3f invalidVec() {
  return Vec3f(compute::invalidFloat(), compute::invalidFloat(), compute::invalidFloat());
}

/// V_t(u) = D_t(u) K^-1 u^H (II-A). Depth outside [min_depth_m, max_depth_m] is invalid.
struct VertexMapKernel {
  ImageView<const float> depth_m;
  ImageView<Vec3f> vertex;
  PinholeF K;
  float min_depth_m = 0.1f;
  float max_depth_m = 10.0f;

  RASM_HD_INLINE void operator()(int x, int y) const {
    const float z = depth_m(x, y);
    vertex(x, y) = (z >= min_depth_m && z <= max_depth_m) ? K.backProject(float(x), float(y), z)
                                                          : invalidVec();
  }
};

/// N_t(u) = (V(u+1,v) - V(u-1,v)) x (V(u,v+1) - V(u,v-1)), normalised (II-A). Border pixels and
/// pixels with an invalid neighbour are invalid. The result is oriented towards the camera
/// (n . v < 0), which the central-difference cross product gives for image axes x right, y down.
/// A neighbour further than `max_jump_m` (relative to depth) from the centre marks a depth
/// discontinuity: the normal would straddle two surfaces and is invalid.
struct NormalMapKernel {
  ImageView<const Vec3f> vertex;
  ImageView<Vec3f> normal;
  float max_jump_rel = 0.05f;  ///< max |dz| of a neighbour as a fraction of the centre depth

  RASM_HD_INLINE void operator()(int x, int y) const {
    if (x <= 0 || y <= 0 || x >= vertex.width - 1 || y >= vertex.height - 1) {
      normal(x, y) = invalidVec();
      return;
    }
    const Vec3f c = vertex(x, y), l = vertex(x - 1, y), r = vertex(x + 1, y), u = vertex(x, y - 1),
                d = vertex(x, y + 1);
    if (!validVec(c) || !validVec(l) || !validVec(r) || !validVec(u) || !validVec(d)) {
      normal(x, y) = invalidVec();
      return;
    }
    const float lim = max_jump_rel * c.z();
    if (fabsf(l.z() - c.z()) > lim || fabsf(r.z() - c.z()) > lim || fabsf(u.z() - c.z()) > lim ||
        fabsf(d.z() - c.z()) > lim) {
      normal(x, y) = invalidVec();
      return;
    }
    Vec3f n = (r - l).cross(d - u);
    const float len = n.norm();
    if (!(len > 0.0f)) {
      normal(x, y) = invalidVec();
      return;
    }
    n /= len;
    if (n.dot(c) > 0.0f) n = -n;
    normal(x, y) = n;
  }
};

/// Half-resolution depth: the mean of the valid depths of the 2x2 block that lie within
/// `max_diff_m` of the block's nearest valid depth (so averaging never mixes foreground and
/// background across a discontinuity); 0 if the block has no valid depth.
struct DepthDownsampleKernel {
  ImageView<const float> in;
  ImageView<float> out;
  float max_diff_m = 0.03f;

  RASM_HD_INLINE void operator()(int x, int y) const {
    float d[4];
    int n = 0;
    float nearest = 1e30f;
    for (int dy = 0; dy < 2; ++dy)
      for (int dx = 0; dx < 2; ++dx) {
        const int sx = 2 * x + dx, sy = 2 * y + dy;
        if (sx >= in.width || sy >= in.height) continue;
        const float z = in(sx, sy);
        if (z > 0.0f) {
          d[n++] = z;
          if (z < nearest) nearest = z;
        }
      }
    if (n == 0) {
      out(x, y) = 0.0f;
      return;
    }
    float sum = 0.0f;
    int cnt = 0;
    for (int i = 0; i < n; ++i)
      if (d[i] - nearest <= max_diff_m) {
        sum += d[i];
        ++cnt;
      }
    out(x, y) = sum / float(cnt);
  }
};

/// 2^t for t <= 0 over lanes (float or lanes::F4, the same bits): t = n + f with n = rint(t),
/// f in [-0.5, 0.5], 2^f by its degree-6 Taylor polynomial (relative error < 3e-6, plenty for
/// filter weights); t below -126 gives 2^-126, not 0.
template <class F>
RASM_HD_INLINE F exp2NonPositive(F t) {
  t = lanes::maxL(t, F(-126.0f));
  const F n = lanes::rintL(t);
  const F f = t - n;
  // 2^f = sum a_k f^k, k <= 6, by Estrin's scheme (half Horner's dependency chain):
  // (a0 + a1 f) + f^2 (a2 + a3 f) + f^4 ((a4 + a5 f) + f^2 a6).
  const F f2 = f * f, f4 = f2 * f2;
  const F p01 = F(6.9314718e-1f) * f + F(1.0f);
  const F p23 = F(5.5504109e-2f) * f + F(2.4022651e-1f);
  const F p45 = F(1.3333558e-3f) * f + F(9.6181291e-3f);
  const F p46 = p45 + f2 * F(1.5403530e-4f);
  const F p = (p01 + f2 * p23) + f4 * p46;
  return p * lanes::pow2OfIntegral(n);
}

/// The bilateral filter's weights in log2 units: the spatial term -(dx^2 + dy^2) / 2 sigma_s^2
/// of a tap at squared distance d2 (px^2), and the depth factor 1 / 2 sigma_d^2 (1/m^2).
constexpr double kLog2e = 1.4426950408889634;
RASM_HD_INLINE float bilateralSpaceLog2(int d2, float sigma_space_px) {
  return -float(double(d2) / (2.0 * double(sigma_space_px) * sigma_space_px) * kLog2e);
}
RASM_HD_INLINE float bilateralDepthLog2(float sigma_depth_m) {
  return float(kLog2e / (2.0 * double(sigma_depth_m) * sigma_depth_m));
}
/// The weight of a pair of pixels at depth difference dz (m): exp(-(dx^2 + dy^2) / 2 sigma_s^2 -
/// dz^2 / 2 sigma_d^2) = 2^(space_log2 - dz^2 depth_log2). One body for the kernel and the CPU
/// launcher's four pixels.
template <class F>
RASM_HD_INLINE F bilateralWeight(const F& space_log2, const F& dz, const F& depth_log2) {
  return exp2NonPositive(space_log2 - dz * dz * depth_log2);
}

/// Edge-preserving bilateral filter of depth (optional preprocessing, as in KinectFusion): the
/// weighted mean of the valid depths of the circular window dx^2 + dy^2 <= radius^2 (13 taps at
/// radius 2, OpenCV's bilateralFilter window) inside the image, weights bilateralWeight(). The
/// CPU launcher (bilateralFilterDepth) computes the same filter four pixels at a time, each
/// pair's weight once for both pixels.
struct BilateralDepthKernel {
  ImageView<const float> in;
  ImageView<float> out;
  int radius = 2;
  float sigma_space_px = 4.5f;
  float sigma_depth_m = 0.03f;

  RASM_HD_INLINE void operator()(int x, int y) const {
    const float c = in(x, y);
    if (!(c > 0.0f)) {
      out(x, y) = 0.0f;
      return;
    }
    float sum = 0.0f, wsum = 0.0f;
    const float depth_log2 = bilateralDepthLog2(sigma_depth_m);
    for (int dy = -radius; dy <= radius; ++dy)
      for (int dx = -radius; dx <= radius; ++dx) {
        const int sx = x + dx, sy = y + dy;
        if (dx * dx + dy * dy > radius * radius || !in.inside(sx, sy)) continue;
        const float z = in(sx, sy);
        if (!(z > 0.0f)) continue;
        const float w = bilateralWeight(bilateralSpaceLog2(dx * dx + dy * dy, sigma_space_px),
                                        z - c, depth_log2);
        sum += w * z;
        wsum += w;
      }
    out(x, y) = sum / wsum;
  }
};

}  // namespace rasm::kernels
