#pragma once
// Structured-light (Kinect v1 class) depth sensor model, applied to exact ray-cast depth.
//  - Axial noise: sigma_z(z, theta) of Nguyen, Izadi & Lovell 2012
//  (core/kernels/DepthNoiseModel.h),
//    theta the angle between the surface normal and the viewing ray.
//  - Lateral noise (same paper, eq. 2): sigma_L(theta) = 0.8 + 0.035 theta / (pi/2 - theta) pixels;
//    where the ray through u + N(0, sigma_L^2) meets another surface than the ray through u (a
//    depth edge between them), pixel u measures that surface's depth, so edges become ragged; on
//    one smooth surface the offset changes nothing (the axial model holds a plane's noise).
//  - Disparity quantization: depth comes from disparity d = f b / z quantized to 1/subpixel px
//    (Kinect v1: 1/8 px, b = 0.075 m, f = 580 px), so the depth step is z^2 / (f b) / subpixel.
//  - Missing data: outside [min_depth_m, max_depth_m], at grazing angles (theta > max), and in the
//    projector's shadow: pixels that the IR projector, offset by projector_offset_m along the
//    camera x axis, does not see (found with an epipolar scan of each row, ProjectorShadowRows).
// Plain header: compute/ and Eigen only.

#include <cmath>
#include <cstdint>

#include "rasm/compute/ImageView.h"
#include "rasm/core/kernels/DepthNoiseModel.h"
#include "rasm/sim/kernels/CounterRng.h"

namespace rasm::sim {

struct DepthModelParams {
  bool axial_noise = true;
  bool lateral_noise = true;
  sensor::AxialNoiseModel axial;        ///< Nguyen et al.'s sigma_z and its constants
  float lateral_px = 0.8f;              ///< Nguyen et al.: sigma_L at theta = 0
  float lateral_angle = 0.035f;         ///< Nguyen et al.: angle term of sigma_L (px)
  float disparity_fb = 580.f * 0.075f;  ///< f * b (px m); depth = fb / disparity
  float disparity_subpixel = 8.f;       ///< quantization 1/subpixel px; 0 = no quantization
  float min_depth_m = 0.4f;
  float max_depth_m = 4.5f;
  float max_incidence_rad =
      80.f * 3.14159265f / 180.f;  ///< larger theta = missing; >= pi/2 disables
  /// Lateral resampling uses bilinear interpolation only when the 4 neighbours agree within this
  /// fraction of the depth (same surface); nearest neighbour otherwise.
  float smooth_rel_tol = 0.02f;
};

using sensor::fastAcos01;
using sensor::incidenceAngleFactor;

/// sigma_z(z, theta) of Nguyen et al. (metres).
RASM_HD_INLINE float axialSigma(const DepthModelParams& p, float z, float theta) {
  return p.axial.sigma(z, theta);
}

/// sigma_L(theta) of Nguyen et al. (pixels).
RASM_HD_INLINE float lateralSigmaPx(const DepthModelParams& p, float theta) {
  return p.lateral_px + p.lateral_angle * incidenceAngleFactor(theta);
}

/// Depth after rounding the disparity f b / z to 1/subpixel px (identity when subpixel <= 0).
RASM_HD_INLINE float quantizeDepth(const DepthModelParams& p, float z) {
  if (p.disparity_subpixel <= 0.f || z <= 0.f) return z;
  const float d =
      std::floor(p.disparity_fb / z * p.disparity_subpixel + 0.5f) / p.disparity_subpixel;
  return d > 0.f ? p.disparity_fb / d : 0.f;
}

/// Depth step of the quantization at depth z: z^2 / (f b) / subpixel.
RASM_HD_INLINE float quantizationStep(const DepthModelParams& p, float z) {
  return p.disparity_subpixel > 0.f ? z * z / p.disparity_fb / p.disparity_subpixel : 0.f;
}

/// Marks pixels the projector cannot see. The projector has the camera's orientation and sits at
/// x = offset_m in the camera frame, so a point at column u and depth z lies on projector column
/// u_p = u - fx * offset / z of the same row (the epipolar line). Seen from the projector, points
/// keep their left-to-right order unless one hides another: scanning away from the projector
/// (right to left for offset > 0), a pixel whose u_p is not below the running minimum of the u_p
/// already passed is hidden from it. Run per row.
struct ProjectorShadowRows {
  ImageView<const float> z_exact;    ///< 0 = no surface
  ImageView<std::uint8_t> shadow;    ///< out: 1 = not lit by the projector
  float fx_offset = 580.f * 0.075f;  ///< fx * offset_m (px m), signed

  RASM_HD void operator()(int y) const {
    const float* z = z_exact.row(y);
    std::uint8_t* s = shadow.row(y);
    const int w = z_exact.width;
    if (fx_offset == 0.f) {
      for (int x = 0; x < w; ++x) s[x] = 0;
      return;
    }
    const bool right = fx_offset > 0.f;  // projector to the right: scan right to left
    float extreme = right ? 3.0e38f : -3.0e38f;
    for (int i = 0; i < w; ++i) {
      const int x = right ? w - 1 - i : i;
      if (z[x] <= 0.f) {
        s[x] = 0;
        continue;
      }
      const float up = float(x) - fx_offset / z[x];
      const bool hidden = right ? up >= extreme : up <= extreme;
      s[x] = hidden ? 1 : 0;
      if (!hidden) extreme = up;
    }
  }
};

/// The three independent standard normal variates of pixel `pix` (lateral du, dv and axial):
/// counter = pixel index, so they do not depend on the order pixels are processed in.
RASM_HD_INLINE void pixelNormals(const CounterRng& rng, std::uint32_t pix, float& du, float& dv,
                                 float& dz) {
  float unused;
  rng.gaussian2(pix, 0, du, dv);
  rng.gaussian2(pix, 1, dz, unused);
}

/// Measured depth per pixel from exact depth, incidence angle and projector shadow mask.
/// operator()(x, y) is the per-pixel kernel (any backend); operator()(y) runs a row on the CPU,
/// drawing the row's normal variates first in chunks (a branch-free loop the compiler vectorizes).
struct DepthMeasurementKernel {
  ImageView<const float> z_exact;        ///< exact z (m), 0 = no surface
  ImageView<const float> cos_incidence;  ///< cos theta, theta between normal and viewing ray
  ImageView<const std::uint8_t> shadow;  ///< may be empty (no shadows)
  ImageView<float> depth_out;
  DepthModelParams p;
  CounterRng rng;
  bool dropouts = true;  ///< grazing-angle and shadow dropouts

  /// Depth of the ray through (u, v), bilinear when its 4 neighbours are one smooth surface.
  /// Samples beyond the image border are clamped to it.
  RASM_HD float sampleDepth(float u, float v) const {
    const int w = z_exact.width, h = z_exact.height;
    u = u < 0.f ? 0.f : (u > float(w - 1) ? float(w - 1) : u);
    v = v < 0.f ? 0.f : (v > float(h - 1) ? float(h - 1) : v);
    const int x0 = int(u), y0 = int(v);
    const int x1 = x0 + 1 < w ? x0 + 1 : x0, y1 = y0 + 1 < h ? y0 + 1 : y0;
    const float a = z_exact(x0, y0), b = z_exact(x1, y0), c = z_exact(x0, y1), d = z_exact(x1, y1);
    const float tx = u - float(x0), ty = v - float(y0);
    auto mn = [](float p0, float p1) { return p1 < p0 ? p1 : p0; };  // minss / maxss, no branches
    auto mx = [](float p0, float p1) { return p1 > p0 ? p1 : p0; };
    const float lo = mn(mn(a, b), mn(c, d)), hi = mx(mx(a, b), mx(c, d));
    if (lo > 0.f && hi - lo <= p.smooth_rel_tol * lo)
      return (a * (1.f - tx) + b * tx) * (1.f - ty) + (c * (1.f - tx) + d * tx) * ty;
    const int xn = tx < 0.5f ? x0 : x1, yn = ty < 0.5f ? y0 : y1;
    return z_exact(xn, yn);
  }

  /// Whether the depths at a pixel, half-way to a sample and at the sample lie on one smooth
  /// surface: the second difference is within smooth_rel_tol of the depth (a step edge between
  /// them puts half its height into it; a floor's curvature in depth over a few pixels is 50x
  /// smaller than the tolerance at 4 m).
  RASM_HD_INLINE bool onOneSmoothSurface(float z_pixel, float z_mid, float z_sample) const {
    if (!(z_mid > 0.f) || !(z_sample > 0.f)) return false;
    const float second_difference = 2.f * z_mid - z_pixel - z_sample;
    return fabsf(second_difference) <= p.smooth_rel_tol * z_pixel;
  }

  RASM_HD void operator()(int x, int y) const {
    float du = 0.f, dv = 0.f, dz = 0.f;
    if (p.lateral_noise || p.axial_noise)
      pixelNormals(rng, std::uint32_t(y) * std::uint32_t(z_exact.width) + std::uint32_t(x), du, dv,
                   dz);
    measure(x, y, du, dv, dz);
  }

  void operator()(int y) const {
    constexpr int kChunk = 64;
    float du[kChunk], dv[kChunk], dz[kChunk];
    const int w = z_exact.width;
    const bool noisy = p.lateral_noise || p.axial_noise;
    for (int x0 = 0; x0 < w; x0 += kChunk) {
      const int n = w - x0 < kChunk ? w - x0 : kChunk;
      const std::uint32_t base = std::uint32_t(y) * std::uint32_t(w) + std::uint32_t(x0);
      if (noisy)
        for (int i = 0; i < n; ++i) pixelNormals(rng, base + std::uint32_t(i), du[i], dv[i], dz[i]);
      for (int i = 0; i < n; ++i)
        measure(x0 + i, y, noisy ? du[i] : 0.f, noisy ? dv[i] : 0.f, noisy ? dz[i] : 0.f);
    }
  }

  /// Pixel (x, y) with its normal variates.
  RASM_HD void measure(int x, int y, float noise_du, float noise_dv, float noise_z) const {
    float z = z_exact(x, y);
    float& out = depth_out(x, y);
    if (z <= 0.f) {
      out = 0.f;
      return;
    }
    const float theta = fastAcos01(cos_incidence(x, y));
    if (dropouts && (theta > p.max_incidence_rad || (!shadow.empty() && shadow(x, y)))) {
      out = 0.f;
      return;
    }
    const float g = incidenceAngleFactor(theta);
    if (p.lateral_noise) {
      // Nguyen et al. measured sigma_L on the edges of a planar target, and sigma_z on the
      // residuals of planes at known angles, so sigma_z already holds all the noise a smooth
      // surface shows: the lateral offset moves depth edges, not a smooth surface's depth.
      // (Applied on smooth surfaces too, it doubled the noise of a far floor and biased it by
      // +1 mm at 3.5-4 m, the depth being convex in the row: docs/sim.md "Depth error on a floor".)
      const float sl = p.lateral_px + p.lateral_angle * g;
      const float du = sl * noise_du, dv = sl * noise_dv;
      const float z_sample = sampleDepth(float(x) + du, float(y) + dv);
      const float z_mid = sampleDepth(float(x) + 0.5f * du, float(y) + 0.5f * dv);
      if (!onOneSmoothSurface(z, z_mid, z_sample)) z = z_sample;
      if (z <= 0.f) {
        out = 0.f;
        return;
      }
    }
    if (p.axial_noise) z += p.axial.sigmaG(z, g) * noise_z;
    z = quantizeDepth(p, z);
    out = (z >= p.min_depth_m && z <= p.max_depth_m) ? z : 0.f;
  }
};

}  // namespace rasm::sim
