#pragma once
// Per-measurement quantities of section II-B, shared by fusion and tracking on both backends.

#include <cmath>

#include "rasm/compute/Lanes.h"
#include "rasm/compute/Types.h"

namespace rasm {

/// Paper default sigma of the confidence weight (II-B).
constexpr float kConfidenceSigma = 0.6f;

/// gamma: radial distance of pixel (u,v) from the image centre (cx, cy), normalised so that the
/// image corner at the largest distance is 1 (as in ElasticFusion / Keller et al. 2013).
RASM_HD_INLINE float normalizedRadialDistance(float u, float v, const PinholeF& K) {
  const float dx = u - K.cx, dy = v - K.cy;
  const float mx = K.cx > K.width - 1 - K.cx ? K.cx : K.width - 1 - K.cx;
  const float my = K.cy > K.height - 1 - K.cy ? K.cy : K.height - 1 - K.cy;
  return sqrtf((dx * dx + dy * dy) / (mx * mx + my * my));
}

/// w = exp(-gamma^2 / (2 sigma^2)) (II-B, after Nguyen et al. [29]).
RASM_HD_INLINE float confidenceWeight(float gamma, float sigma = kConfidenceSigma) {
  return expf(-gamma * gamma / (2.0f * sigma * sigma));
}

/// sqrt(2): the circle circumscribing a pixel (surfelRadius).
constexpr float kSqrt2 = 1.41421356f;
/// surfelRadius's default lower bound of |n_z|.
constexpr float kMinAbsNormalZ = 0.2f;

/// r = V(u)_z / (sqrt(2) f N(u)_z) (II-B): the back-projected circle circumscribing the pixel.
/// |n_z| is clamped below by `min_abs_nz` so grazing surfels do not get unbounded radii.
/// Over lanes (compute/Lanes.h): fusion's CPU association measures four pixels at once.
template <class F>
RASM_HD_INLINE F surfelRadiusOf(const F& depth_m, const F& normal_z, float focal_px,
                                float min_abs_nz = kMinAbsNormalZ) {
  F nz = lanes::absL(normal_z);
  nz = lanes::select(nz < min_abs_nz, F(min_abs_nz), nz);
  return depth_m / (kSqrt2 * focal_px * nz);
}
RASM_HD_INLINE float surfelRadius(float depth_m, float normal_z, float focal_px,
                                  float min_abs_nz = kMinAbsNormalZ) {
  return surfelRadiusOf(depth_m, normal_z, focal_px, min_abs_nz);
}

}  // namespace rasm
