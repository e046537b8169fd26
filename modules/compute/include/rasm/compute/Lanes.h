#pragma once
// Lanes: one kernel body for one element and for four at once. A body written as a template over
// a lane type F runs as F = float (the CUDA kernels and the scalar CPU path) and, on the CPU, as
// F = lanes::F4 (four floats in one SSE register: std::experimental::simd, GCC's <experimental/
// simd>, with the 16-byte ABI of -march=x86-64-v2). Such a body uses only what both have:
// arithmetic and comparisons with float constants, && || ! on masks, select(), sqrtL(), absL(),
// truncL(), floorL(), ceilL(), rintL(), pow2OfIntegral(), minL() / maxL() (minF / maxF's a < b ? a
// : b) and LaneVec3 (dot, cross, blend, scaled, RigidF's rotate and apply) with Eigen's and
// RigidF's order of operations (dot: a0 b0 + (a1 b1 + a2 b2); cross: (a1 b2 - a2 b1, a2 b0 - a0 b2,
// a0 b1 - a1 b0)), so that both instantiations give the bits of the Eigen code they replace. Small
// integers (bins, counts) are carried as floats (exact below 2^24) and converted once at the end,
// so that no integer mask is needed.

#include <cmath>
#include <cstdint>
#include <cstring>

#include "rasm/compute/Platform.h"
#include "rasm/compute/Types.h"

#if !defined(__CUDACC__)
#include <immintrin.h>

#include <experimental/simd>
#endif

namespace rasm::lanes {

RASM_HD_INLINE float select(bool m, float a, float b) {
  return m ? a : b;
}
RASM_HD_INLINE float sqrtL(float x) {
  return sqrtf(x);
}
RASM_HD_INLINE float absL(float x) {
  return fabsf(x);
}
RASM_HD_INLINE float truncL(float x) {
  return truncf(x);
}
RASM_HD_INLINE float floorL(float x) {
  return floorf(x);
}
RASM_HD_INLINE float ceilL(float x) {
  return ceilf(x);
}
/// Nearest integer, ties to even (the default rounding mode; roundps' nearest).
RASM_HD_INLINE float rintL(float x) {
  return rintf(x);
}
/// 2^n for an integer-valued n in [-126, 127]: the exponent field set directly.
RASM_HD_INLINE float pow2OfIntegral(float n) {
  const std::int32_t e = (std::int32_t(n) + 127) << 23;
#if defined(__CUDA_ARCH__)
  return __int_as_float(e);
#else
  float f;
  std::memcpy(&f, &e, sizeof f);
  return f;
#endif
}

#if !defined(__CUDACC__)
namespace stdx = std::experimental;
/// Four float lanes in one SSE register (convertible from and to __m128).
using F4 = stdx::simd<float, stdx::simd_abi::deduce_t<float, 4>>;
using I4 = stdx::simd<int, stdx::simd_abi::deduce_t<int, 4>>;
static_assert(F4::size() == 4 && sizeof(F4) == 16, "F4 must be one SSE register");

inline F4 select(const F4::mask_type& m, const F4& a, F4 b) {
  stdx::where(m, b) = a;
  return b;
}
inline F4 sqrtL(const F4& x) {
  return stdx::sqrt(x);
}
inline F4 absL(const F4& x) {
  return stdx::abs(x);
}
inline F4 truncL(const F4& x) {
  return stdx::trunc(x);
}
inline F4 floorL(const F4& x) {
  return stdx::floor(x);
}
inline F4 ceilL(const F4& x) {
  return stdx::ceil(x);
}
inline F4 rintL(const F4& x) {
  return F4(_mm_round_ps(static_cast<__m128>(x), _MM_FROUND_TO_NEAREST_INT | _MM_FROUND_NO_EXC));
}
inline F4 pow2OfIntegral(const F4& n) {
  const __m128i e = _mm_slli_epi32(
      _mm_add_epi32(_mm_cvtps_epi32(static_cast<__m128>(n)), _mm_set1_epi32(127)), 23);
  return F4(_mm_castsi128_ps(e));
}
/// Lane l of the mask as bit l.
inline int bits(const F4::mask_type& m) {
  return _mm_movemask_ps(static_cast<__m128>(select(m, F4(-1.0f), F4(0.0f))));
}
/// Integer-valued float lanes to int lanes (truncation, as int(float)).
inline __m128i toInt(const F4& x) {
  return static_cast<__m128i>(stdx::static_simd_cast<I4>(x));
}
/// The four lanes to to[0..3] (as floats; as ints truncated, toInt).
inline void store(float* to, const F4& x) {
  x.copy_to(to, stdx::element_aligned);
}
inline void storeInt(int* to, const F4& x) {
  _mm_storeu_si128(reinterpret_cast<__m128i*>(to), toInt(x));
}
#endif

/// The mask of a lane type (bool for float).
template <class F>
using MaskOf = decltype(F() < F());

/// a < b ? a : b and a > b ? a : b per lane (minps / maxps: b where either is NaN).
template <class F>
RASM_HD_INLINE F minL(const F& a, const F& b) {
  return select(a < b, a, b);
}
template <class F>
RASM_HD_INLINE F maxL(const F& a, const F& b) {
  return select(a > b, a, b);
}

/// A 3-vector of lanes: component k of lane l is the l-th element of a vector's k-th coordinate.
template <class F>
struct LaneVec3 {
  F x, y, z;
};

template <class F>
RASM_HD_INLINE LaneVec3<F> select(const MaskOf<F>& m, const LaneVec3<F>& a, const LaneVec3<F>& b) {
  return {select(m, a.x, b.x), select(m, a.y, b.y), select(m, a.z, b.z)};
}
/// a x + b y per coordinate (a blend of two vectors).
template <class F>
RASM_HD_INLINE LaneVec3<F> blend(const F& a, const LaneVec3<F>& x, const F& b,
                                 const LaneVec3<F>& y) {
  return {a * x.x + b * y.x, a * x.y + b * y.y, a * x.z + b * y.z};
}
template <class F>
RASM_HD_INLINE LaneVec3<F> scaled(const LaneVec3<F>& v, const F& k) {
  return {v.x * k, v.y * k, v.z * k};
}
/// RigidF::rotate over lanes: (m0 x + m1 y) + m2 z per row.
template <class F>
RASM_HD_INLINE LaneVec3<F> rotate(const RigidF& T, const LaneVec3<F>& v) {
  const float* m = T.m;
  return {m[0] * v.x + m[1] * v.y + m[2] * v.z, m[4] * v.x + m[5] * v.y + m[6] * v.z,
          m[8] * v.x + m[9] * v.y + m[10] * v.z};
}
/// RigidF::apply over lanes: ((m0 x + m1 y) + m2 z) + m3 per row.
template <class F>
RASM_HD_INLINE LaneVec3<F> apply(const RigidF& T, const LaneVec3<F>& p) {
  const float* m = T.m;
  return {m[0] * p.x + m[1] * p.y + m[2] * p.z + m[3], m[4] * p.x + m[5] * p.y + m[6] * p.z + m[7],
          m[8] * p.x + m[9] * p.y + m[10] * p.z + m[11]};
}

/// Lanes of a Vec3f (float lanes: the vector itself).
RASM_HD_INLINE LaneVec3<float> lanesOf(const Vec3f& v) {
  return {v.x(), v.y(), v.z()};
}

template <class F>
RASM_HD_INLINE F dot(const LaneVec3<F>& a, const LaneVec3<F>& b) {
  return a.x * b.x + (a.y * b.y + a.z * b.z);
}
template <class F>
RASM_HD_INLINE LaneVec3<F> cross(const LaneVec3<F>& a, const LaneVec3<F>& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}

}  // namespace rasm::lanes
