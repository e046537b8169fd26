#pragma once
// View-information bins and the in-plane basis of section V-B, shared by fusion (update) and
// exploration (predicted IC maps). Plain header: compute/ and Eigen only.

#include <cmath>

#include "rasm/compute/Types.h"

namespace rasm::maps::kernels {

/// IC(s) = exp(-lambda1 (max(||p - t||, d_min) - d_min)) (V-B): 1 up to d_min, then decaying.
RASM_HD_INLINE float informationContent(float distance_m, float lambda1, float d_min_m) {
  return distance_m > d_min_m ? expf(-lambda1 * (distance_m - d_min_m)) : 1.0f;
}

/// A unit vector perpendicular to the unit vector n (initial basis b of a new surfel, II-B / V-B).
RASM_HD_INLINE Vec3f anyPerpendicular(const Vec3f& n) {
  // Cross with the axis least aligned with n: well conditioned for every n.
  const float ax = fabsf(n.x()), ay = fabsf(n.y()), az = fabsf(n.z());
  const Vec3f a =
      (ax <= ay && ax <= az) ? Vec3f(1, 0, 0) : (ay <= az ? Vec3f(0, 1, 0) : Vec3f(0, 0, 1));
  return n.cross(a).normalized();
}

/// b <- -n x (n x b), normalised (V-B): the projection of b onto the plane of the (updated) normal,
/// so b stays in the surfel plane and turns with it. Falls back to anyPerpendicular(n) when b is
/// (nearly) parallel to n.
RASM_HD_INLINE Vec3f updateBasis(const Vec3f& n, const Vec3f& b) {
  const Vec3f nb = -n.cross(n.cross(b));
  const float len = nb.norm();
  return len > 1e-4f ? Vec3f(nb * (1.0f / len)) : anyPerpendicular(n);
}

/// atan2 with |error| < 1e-5 rad (polynomial on [0, 1] plus octant folding): the bins
/// are tens of degrees wide, and libm's atan2f/asinf dominated the per-surfel update cost.
RASM_HD_INLINE float fastAtan2(float y, float x) {
  const float ax = fabsf(x), ay = fabsf(y);
  const float mx = ax > ay ? ax : ay, mn = ax > ay ? ay : ax;
  if (mx == 0.0f) return 0.0f;
  const float a = mn / mx, s = a * a;
  // Minimax polynomial of atan on [0, 1] (odd, degree 11), |error| < 1e-5 rad.
  float r =
      a * (0.99997726f +
           s * (-0.33262347f +
                s * (0.19354346f + s * (-0.11643287f + s * (0.05265332f - s * 0.01172120f)))));
  if (ay > ax) r = 1.57079637f - r;
  if (x < 0.0f) r = 3.14159274f - r;
  return y < 0.0f ? -r : r;
}

/// Elevation ring borders (sines of k pi / (2 n)) of the view bins for n = 2, 3, 4 rings (the SSE
/// copy in fusion's FusionCpu.cpp uses these).
constexpr float kSinPi8 = 0.38268343f, kSinPi6 = 0.5f, kSinPi4 = 0.70710678f, kSinPi3 = 0.86602540f,
                kSin3Pi8 = 0.92387953f;

/// Bin of the camera direction `dir_to_camera` (unit, from the surfel towards the camera centre)
/// in the surfel frame (b, n x b, n) (V-B): azimuth atan2(d.(n x b), d.b) in [-pi, pi) over
/// n_azimuth equal sectors, elevation asin(d.n) in [0, pi/2] over n_elevation equal rings
/// (back-facing directions clamp to elevation 0). Bin = elevation_ring * n_azimuth + sector.
/// The common layouts (up to 4 rings, 8 sectors) are decided by comparisons against the ring and
/// sector borders (no trigonometry); others by fastAtan2 (they agree but within 1e-5 rad of a
/// border).
RASM_HD_INLINE int viewBinIndex(const Vec3f& n, const Vec3f& b, const Vec3f& dir_to_camera,
                                int n_azimuth, int n_elevation) {
  const float kPi = 3.14159265358979f;
  const Vec3f c = n.cross(b);
  float s = dir_to_camera.dot(n);
  s = s < 0.0f ? 0.0f : (s > 1.0f ? 1.0f : s);
  int el;
  if (n_elevation == 1) {
    el = 0;
  } else if (n_elevation == 2) {  // ring border asin(s) = pi/4
    el = s >= kSinPi4 ? 1 : 0;
  } else if (n_elevation == 3) {  // pi/6, pi/3
    el = (s >= kSinPi6 ? 1 : 0) + (s >= kSinPi3 ? 1 : 0);
  } else if (n_elevation == 4) {  // pi/8, pi/4, 3 pi/8
    el = (s >= kSinPi8 ? 1 : 0) + (s >= kSinPi4 ? 1 : 0) + (s >= kSin3Pi8 ? 1 : 0);
  } else {
    const float cos_el = sqrtf(1.0f - s * s);
    el = int(fastAtan2(s, cos_el) * (2.0f / kPi) * float(n_elevation));  // asin(s)
    if (el >= n_elevation) el = n_elevation - 1;
  }
  const float x = dir_to_camera.dot(b), y = dir_to_camera.dot(c);
  int sector;
  if (n_azimuth == 8) {  // sector borders every pi/4 from -pi; y = +-0 counts as the upper half
    const float ax = fabsf(x), ay = fabsf(y);
    if (y >= 0.0f)
      sector = x > 0.0f ? (y < x ? 4 : 5) : (y > -x ? 6 : 7);
    else
      sector = x < 0.0f ? (ay < ax ? 0 : 1) : (ay > x ? 2 : 3);
  } else {
    const float az = fastAtan2(y, x);  // (-pi, pi]
    sector = int((az + kPi) * (0.5f / kPi) * float(n_azimuth));
    if (sector >= n_azimuth) sector = n_azimuth - 1;
    if (sector < 0) sector = 0;
  }
  return el * n_azimuth + sector;
}

}  // namespace rasm::maps::kernels
