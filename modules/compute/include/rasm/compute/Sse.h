#pragma once
// SSE data movement of the CPU launchers (FusionCpu): loading four Vec3f into x, y, z lanes. The
// arithmetic runs as one body over lanes (compute/Lanes.h). Host only (x86-64-v2: SSE4.1).

#include <immintrin.h>

#include "rasm/compute/Types.h"

namespace rasm::sse {

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
