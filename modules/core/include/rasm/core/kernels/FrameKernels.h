#pragma once
// Per-pixel kernels of section II-A and the depth pyramid, written once for both backends.
// Plain header: only compute/ and Eigen, so .cu files include it.
// Invalid vertices/normals have x = NaN (compute::invalidFloat()); invalid depth is 0.

#include "rasm/compute/ImageView.h"
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

/// Edge-preserving bilateral filter of depth (optional preprocessing, as in KinectFusion): the
/// weighted mean of the valid depths of the circular window dx^2 + dy^2 <= radius^2 (13 taps at
/// radius 2, OpenCV's bilateralFilter window) inside the image, weights exp(-(dx^2 + dy^2) /
/// 2 sigma_s^2 - dz^2 / 2 sigma_d^2). The CPU launcher (bilateralFilterDepth) computes the same
/// filter four pixels at a time.
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
    const float is2 = 1.0f / (2.0f * sigma_space_px * sigma_space_px);
    const float id2 = 1.0f / (2.0f * sigma_depth_m * sigma_depth_m);
    for (int dy = -radius; dy <= radius; ++dy)
      for (int dx = -radius; dx <= radius; ++dx) {
        const int sx = x + dx, sy = y + dy;
        if (dx * dx + dy * dy > radius * radius || !in.inside(sx, sy)) continue;
        const float z = in(sx, sy);
        if (!(z > 0.0f)) continue;
        const float dz = z - c;
        const float w = expf(-float(dx * dx + dy * dy) * is2 - dz * dz * id2);
        sum += w * z;
        wsum += w;
      }
    out(x, y) = sum / wsum;
  }
};

}  // namespace rasm::kernels
