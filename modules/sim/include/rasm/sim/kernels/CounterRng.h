#pragma once
// Counter-based random numbers for per-pixel sensor noise. Every pixel's variates are a
// stateless hash of (frame key, pixel index, stream), so a frame's noise is identical whatever
// the number of threads or the order pixels are processed in (and on the GPU). The frame key
// itself comes from a std::mt19937 seeded with (seed, frame index) on the host (RgbdSensor).
// Everything is branch-free 32-bit integer and float arithmetic, so the row loops vectorize.
// Plain header: compute/ and Eigen only.

#include <cmath>
#include <cstdint>
#include <cstring>

#include "rasm/compute/Platform.h"

namespace rasm::sim {

/// SplitMix64 finalizer (Steele, Lea & Flood 2014): a bijective 64-bit mix with full avalanche.
RASM_HD_INLINE std::uint64_t splitMix64(std::uint64_t z) {
  z += 0x9E3779B97F4A7C15ull;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

/// 32-bit integer hash with good avalanche (Wellons' "lowbias32").
RASM_HD_INLINE std::uint32_t hash32(std::uint32_t x) {
  x ^= x >> 16;
  x *= 0x7FEB352Du;
  x ^= x >> 15;
  x *= 0x846CA68Bu;
  x ^= x >> 16;
  return x;
}

/// Natural log for normal positive floats (|error| < 2e-6): exponent from the bits, log of the
/// mantissa m in [1, 2) by the atanh series 2 (t + t^3/3 + ...), t = (m - 1) / (m + 1).
RASM_HD_INLINE float fastLog(float x) {
  std::uint32_t b;
  std::memcpy(&b, &x, sizeof b);
  const int e = int((b >> 23) & 255u) - 127;
  b = (b & 0x007FFFFFu) | 0x3F800000u;
  float m;
  std::memcpy(&m, &b, sizeof m);
  const float t = (m - 1.f) / (m + 1.f), t2 = t * t;
  return float(e) * 0.693147181f +
         2.f * t *
             (1.f + t2 * (0.333333333f + t2 * (0.2f + t2 * (0.142857143f + t2 * 0.111111111f))));
}

/// sin and cos of 2 pi (u - 1/2) for u in [0, 1) (|error| < 1e-5): Taylor polynomials of the
/// half angle h in [-pi/2, pi/2), then the double-angle formulas.
RASM_HD_INLINE void fastSinCosTurn(float u, float& s, float& c) {
  const float h = 3.14159265f * (u - 0.5f), h2 = h * h;
  const float sh =
      h * (1.f - h2 * (1.f / 6 - h2 * (1.f / 120 - h2 * (1.f / 5040 - h2 * (1.f / 362880)))));
  const float ch =
      1.f -
      h2 * (0.5f - h2 * (1.f / 24 - h2 * (1.f / 720 - h2 * (1.f / 40320 - h2 * (1.f / 3628800)))));
  s = 2.f * sh * ch;
  c = ch * ch - sh * sh;
}

/// Uniform in (0, 1] from the top 24 bits (never 0, so log() is safe).
RASM_HD_INLINE float uniformOpen0(std::uint32_t bits) {
  return float((bits >> 8) + 1u) * (1.0f / 16777216.0f);
}
/// Uniform in [0, 1) from the top 24 bits.
RASM_HD_INLINE float uniform01(std::uint32_t bits) {
  return float(bits >> 8) * (1.0f / 16777216.0f);
}

struct CounterRng {
  std::uint64_t key = 0;

  /// 32 random bits for (counter, stream): a double hash keyed by both halves of the key.
  RASM_HD_INLINE std::uint32_t bits(std::uint32_t counter, std::uint32_t stream) const {
    return hash32(std::uint32_t(key) ^
                  hash32(counter * 0x9E3779B9u + stream * 0x632BE5ABu + std::uint32_t(key >> 32)));
  }
  RASM_HD_INLINE float uniform(std::uint32_t counter, std::uint32_t stream) const {
    return uniformOpen0(bits(counter, stream));
  }
  /// Two independent standard normal variates (Box-Muller; tails reach 5.8 sigma).
  RASM_HD_INLINE void gaussian2(std::uint32_t counter, std::uint32_t stream, float& g0,
                                float& g1) const {
    const float r = std::sqrt(-2.f * fastLog(uniformOpen0(bits(counter, 2 * stream))));
    float s, c;
    fastSinCosTurn(uniform01(bits(counter, 2 * stream + 1)), s, c);
    g0 = r * c;
    g1 = r * s;
  }
};

}  // namespace rasm::sim
