#pragma once
// SSE helpers of the CPU launchers (FusionCpu, SurfelRenderer): four lanes that each run the scalar
// kernel's float operations in the same order, so that the launchers are bit-identical to their
// kernels. Orders: Eigen sums three terms (dot, squaredNorm of a Vector3f) as a0 + (a1 + a2);
// RigidF::apply / rotate as ((m0 x + m1 y) + m2 z) + m3; Eigen's cross as
// (a1 b2 - a2 b1, a2 b0 - a0 b2, a0 b1 - a1 b0). Host only (x86-64-v2: SSE4.1).

#include <immintrin.h>

#include "rasm/compute/Types.h"

namespace rasm::sse {

/// a0 + (a1 + a2), as Eigen sums three terms.
inline __m128 sum3(__m128 a0, __m128 a1, __m128 a2) {
  return _mm_add_ps(a0, _mm_add_ps(a1, a2));
}

/// Row m[0..3] of a RigidF over four lanes: ((m0 x + m1 y) + m2 z) (+ m3 when `affine`, as
/// RigidF::apply; without, as RigidF::rotate).
inline __m128 rigidRow(const float* m, __m128 x, __m128 y, __m128 z, bool affine = true) {
  const __m128 r =
      _mm_add_ps(_mm_add_ps(_mm_mul_ps(_mm_set1_ps(m[0]), x), _mm_mul_ps(_mm_set1_ps(m[1]), y)),
                 _mm_mul_ps(_mm_set1_ps(m[2]), z));
  return affine ? _mm_add_ps(r, _mm_set1_ps(m[3])) : r;
}

/// mask ? a : b, per lane.
inline __m128 select(__m128 mask, __m128 a, __m128 b) {
  return _mm_or_ps(_mm_and_ps(mask, a), _mm_andnot_ps(mask, b));
}

/// c = a x b per lane, as Eigen's cross.
inline void cross(__m128 ax, __m128 ay, __m128 az, __m128 bx, __m128 by, __m128 bz, __m128& cx,
                  __m128& cy, __m128& cz) {
  cx = _mm_sub_ps(_mm_mul_ps(ay, bz), _mm_mul_ps(az, by));
  cy = _mm_sub_ps(_mm_mul_ps(az, bx), _mm_mul_ps(ax, bz));
  cz = _mm_sub_ps(_mm_mul_ps(ax, by), _mm_mul_ps(ay, bx));
}

/// (x, y, z, *) of a Vec3f with one unaligned load, which reads the 4 bytes after the element:
/// pass `last` = true for an element with nothing after it (the last of an image or array).
inline __m128 loadVec3(const Vec3f& p, bool last) {
  return last ? _mm_setr_ps(p.x(), p.y(), p.z(), 0.0f) : _mm_loadu_ps(p.data());
}

/// x, y, z planes of four Vec3f (loadVec3 each, then a transpose: no lane buffer filled one
/// float at a time, whose reload as a vector would stall on store forwarding).
inline void gather3(const Vec3f& a, const Vec3f& b, const Vec3f& c, const Vec3f& d, bool last_a,
                    bool last_b, bool last_c, bool last_d, __m128& x, __m128& y, __m128& z) {
  __m128 r0 = loadVec3(a, last_a), r1 = loadVec3(b, last_b), r2 = loadVec3(c, last_c),
         r3 = loadVec3(d, last_d);
  _MM_TRANSPOSE4_PS(r0, r1, r2, r3);
  x = r0;
  y = r1;
  z = r2;
}

}  // namespace rasm::sse
