#pragma once
// View-information bins and the in-plane basis of section V-B, shared by fusion (update) and
// exploration (predicted IC maps). Plain header: compute/ and Eigen only.

#include <cmath>

#include "rasm/compute/Lanes.h"
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
/// Over lanes (compute/Lanes.h); 0 where x = y = 0.
template <class F>
RASM_HD_INLINE F fastAtan2(const F& y, const F& x) {
  using lanes::select;
  const F ax = lanes::absL(x), ay = lanes::absL(y);
  const F mx = select(ax > ay, ax, ay), mn = select(ax > ay, ay, ax);
  const F a = mn / mx, s = a * a;
  // Minimax polynomial of atan on [0, 1] (odd, degree 11), |error| < 1e-5 rad.
  F r = a * (0.99997726f +
             s * (-0.33262347f +
                  s * (0.19354346f + s * (-0.11643287f + s * (0.05265332f - s * 0.01172120f)))));
  r = select(ay > ax, 1.57079637f - r, r);
  r = select(x < 0.0f, 3.14159274f - r, r);
  r = select(y < 0.0f, -r, r);
  return select(mx == 0.0f, F(0.0f), r);
}

/// Elevation ring borders (sines of k pi / (2 n)) of the view bins for n = 2, 3, 4 rings.
constexpr float kSinPi8 = 0.38268343f, kSinPi6 = 0.5f, kSinPi4 = 0.70710678f, kSinPi3 = 0.86602540f,
                kSin3Pi8 = 0.92387953f;

/// 1 where s >= border, else 0 (float lanes).
template <class F>
RASM_HD_INLINE F atOrAbove(const F& s, float border) {
  return lanes::select(s >= border, F(1.0f), F(0.0f));
}

/// Bin of the camera direction `d` (unit, from the surfel towards the camera centre) in the
/// surfel frame (b, n x b, n) (V-B), as a float: azimuth atan2(d.(n x b), d.b) in [-pi, pi) over
/// n_azimuth equal sectors, elevation asin(d.n) in [0, pi/2] over n_elevation equal rings
/// (back-facing directions clamp to elevation 0). Bin = elevation_ring * n_azimuth + sector.
/// The common layouts (up to 4 rings, 8 sectors) are decided by comparisons against the ring and
/// sector borders (no trigonometry); others by fastAtan2 (they agree but within 1e-5 rad of a
/// border). Over lanes (compute/Lanes.h): fusion's CPU update runs it on four surfels at once.
template <class F>
RASM_HD_INLINE F viewBinOfDirection(const lanes::LaneVec3<F>& n, const lanes::LaneVec3<F>& b,
                                    const lanes::LaneVec3<F>& d, int n_azimuth, int n_elevation) {
  using lanes::select;
  const float kPi = 3.14159265358979f;
  const lanes::LaneVec3<F> c = lanes::cross(n, b);
  F s = lanes::dot(d, n);
  s = select(s < 0.0f, F(0.0f), select(s > 1.0f, F(1.0f), s));
  F el(0.0f);
  if (n_elevation == 2) {  // ring border asin(s) = pi/4
    el = atOrAbove(s, kSinPi4);
  } else if (n_elevation == 3) {  // pi/6, pi/3
    el = atOrAbove(s, kSinPi6) + atOrAbove(s, kSinPi3);
  } else if (n_elevation == 4) {  // pi/8, pi/4, 3 pi/8
    el = atOrAbove(s, kSinPi8) + atOrAbove(s, kSinPi4) + atOrAbove(s, kSin3Pi8);
  } else if (n_elevation > 4) {
    const F cos_el = lanes::sqrtL(1.0f - s * s);
    el = lanes::truncL(fastAtan2(s, cos_el) * (2.0f / kPi) * float(n_elevation));  // asin(s)
    el = select(el >= float(n_elevation), F(float(n_elevation - 1)), el);
  }
  const F x = lanes::dot(d, b), y = lanes::dot(d, c);
  F sector;
  if (n_azimuth == 8) {  // sector borders every pi/4 from -pi; y = +-0 counts as the upper half
    const F ax = lanes::absL(x), ay = lanes::absL(y);
    const F upper =
        select(x > 0.0f, select(y < x, F(4.0f), F(5.0f)), select(y > -x, F(6.0f), F(7.0f)));
    const F lower =
        select(x < 0.0f, select(ay < ax, F(0.0f), F(1.0f)), select(ay > x, F(2.0f), F(3.0f)));
    sector = select(y >= 0.0f, upper, lower);
  } else {
    const F az = fastAtan2(y, x);  // (-pi, pi]
    sector = lanes::truncL((az + kPi) * (0.5f / kPi) * float(n_azimuth));
    sector = select(sector >= float(n_azimuth), F(float(n_azimuth - 1)), sector);
    sector = select(sector < 0.0f, F(0.0f), sector);
  }
  return el * float(n_azimuth) + sector;
}

/// viewBinOfDirection of one surfel.
RASM_HD_INLINE int viewBinIndex(const Vec3f& n, const Vec3f& b, const Vec3f& dir_to_camera,
                                int n_azimuth, int n_elevation) {
  return int(viewBinOfDirection(lanes::lanesOf(n), lanes::lanesOf(b), lanes::lanesOf(dir_to_camera),
                                n_azimuth, n_elevation));
}

/// The view bin (viewBinOfDirection) in which a surfel at p with normal n and basis b sees the
/// camera centre, and the camera's distance `dist`; bin -1 where the camera sits on the surfel
/// (!(dist > 0)). Fusion's update of V-B, on one surfel (updateViewBin) or four (FusionCpu).
template <class F>
RASM_HD_INLINE F viewBinOfCamera(const lanes::LaneVec3<F>& p, const lanes::LaneVec3<F>& n,
                                 const lanes::LaneVec3<F>& b, const Vec3f& camera_centre,
                                 int n_azimuth, int n_elevation, F& dist) {
  const lanes::LaneVec3<F> d{camera_centre.x() - p.x, camera_centre.y() - p.y,
                             camera_centre.z() - p.z};
  dist = lanes::sqrtL(lanes::dot(d, d));
  const F inv = 1.0f / dist;
  const F bin = viewBinOfDirection(n, b, lanes::LaneVec3<F>{d.x * inv, d.y * inv, d.z * inv},
                                   n_azimuth, n_elevation);
  return lanes::select(dist > 0.0f, bin, F(-1.0f));
}

}  // namespace rasm::maps::kernels
