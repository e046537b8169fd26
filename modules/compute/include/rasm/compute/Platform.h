#pragma once
// RASM_HD marks functions that run on both backends: __host__ __device__ under nvcc, nothing on
// the CPU. Kernel bodies are written once with it (DESIGN.md "Compute: one kernel, two backends").

#if defined(__CUDACC__)
#define RASM_HD __host__ __device__
#define RASM_HD_INLINE __host__ __device__ __forceinline__
#define RASM_DEVICE_CODE 1
#else
#define RASM_HD
#define RASM_HD_INLINE inline
#endif

#include <cstdint>

namespace rasm::compute {

/// Quiet NaN usable in device code; invalid vertices and normals hold it in x.
RASM_HD_INLINE float invalidFloat() {
  return __builtin_nanf("");
}
/// std::lround for |x| < 2^23 (halves away from zero), inline: x - trunc(x) is exact there, so
/// the result equals lround's (libm's out-of-line lroundf cost ~1% of a 7-Scenes run).
RASM_HD_INLINE int roundHalfAway(float x) {
  const float t = __builtin_truncf(x);
  const float f = x - t;
  return int(t) + (f >= 0.5f ? 1 : (f <= -0.5f ? -1 : 0));
}

}  // namespace rasm::compute
