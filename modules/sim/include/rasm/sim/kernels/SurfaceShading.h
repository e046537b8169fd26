#pragma once
// Colour of a simulated surface point: albedo from a procedural pattern (3-D checker and stripes,
// planar value noise) evaluated in the object's frame, lit by one directional light with Lambertian
// diffuse reflection plus ambient:  c = albedo * (ambient + diffuse * max(0, -n . l)).
// Plain header: compute/ and Eigen only.

#include <cmath>
#include <cstdint>

#include "rasm/compute/Types.h"
#include "rasm/sim/kernels/CounterRng.h"

namespace rasm::sim {

/// Per-object plain shading and label data (index = object index = Embree geometry id).
struct SurfaceMaterial {
  Vec3f colour{0.7f, 0.7f, 0.7f};   ///< RGB 0..1
  Vec3f colour2{0.4f, 0.4f, 0.4f};  ///< RGB 0..1
  int pattern = 0;                  ///< 0 solid, 1 checker, 2 stripes, 3 noise (World.h Pattern)
  float inv_period = 10.f;          ///< 1 / period_m
  int stripe_axis = 0;
  RigidF T_object_world;  ///< world -> object frame (rigid; pattern period in metres)
  std::uint16_t instance_id = 0;
  std::uint16_t class_id = 0;
};

struct LightF {
  Vec3f direction{0.f, 0.f, -1.f};  ///< unit, direction light travels
  float ambient = 0.35f;
  float diffuse = 0.65f;
};

/// Lattice values of the value noise: 64 x 64 random numbers in [0, 1) (Wellons' lowbias32 hash
/// of the cell index), computed at compile time. With the default 0.3 m feature size the pattern
/// repeats every 19 m, further than any wall; a table lookup is ~3x cheaper than hashing four
/// lattice points per pixel.
struct NoiseLattice {
  float v[64 * 64];
};
constexpr NoiseLattice makeNoiseLattice() {
  NoiseLattice t{};
  for (std::uint32_t i = 0; i < 64 * 64; ++i) {
    std::uint32_t h = i * 0x8DA6B343u + 0x6A09E667u;
    h ^= h >> 16;
    h *= 0x7FEB352Du;
    h ^= h >> 15;
    h *= 0x846CA68Bu;
    h ^= h >> 16;
    t.v[i] = float(h >> 8) * (1.0f / 16777216.0f);
  }
  return t;
}
inline constexpr NoiseLattice kNoiseLattice = makeNoiseLattice();

/// Value noise on the integer lattice of a plane, bilinear with smoothstep weights, in [0, 1].
/// `plane` shifts the lattice so that different planes get different patterns.
RASM_HD_INLINE float valueNoise2(float u, float v, std::uint32_t plane) {
  const float fu = std::floor(u), fv = std::floor(v);
  const std::uint32_t iu = std::uint32_t(int(fu)) + plane * 17u,
                      iv = std::uint32_t(int(fv)) + plane * 41u;
  float tu = u - fu, tv = v - fv;
  tu = tu * tu * (3.f - 2.f * tu);
  tv = tv * tv * (3.f - 2.f * tv);
  const float* L = kNoiseLattice.v;
  const std::uint32_t r0 = (iv & 63u) * 64u, r1 = ((iv + 1u) & 63u) * 64u, c0 = iu & 63u,
                      c1 = (iu + 1u) & 63u;
  const float a = L[r0 + c0], b = L[r0 + c1], c = L[r1 + c0], d = L[r1 + c1];
  const float ab = a + (b - a) * tu, cd = c + (d - c) * tu;
  return ab + (cd - ab) * tv;
}

/// Blend weight of colour2 at world point p_world with world normal n_world, evaluated in the
/// object's frame (metres). Noise is 2-D on the object-frame coordinate plane most facing the
/// surface (walls and floors are planes; half the cost of 3-D noise), indexed by that plane and
/// the surface's offset along its normal axis so that parallel faces differ.
RASM_HD_INLINE float patternWeight(const SurfaceMaterial& m, const Vec3f& p_world,
                                   const Vec3f& n_world) {
  const Vec3f p_obj = m.T_object_world.apply(p_world);
  // A tiny offset keeps faces that lie exactly on a cell boundary (box faces at +-size/2) from
  // flickering between the two colours.
  const Vec3f q = p_obj * m.inv_period + Vec3f::Constant(1e-3f);
  switch (m.pattern) {
    case 1: {
      const int s = int(std::floor(q.x())) + int(std::floor(q.y())) + int(std::floor(q.z()));
      return (s & 1) ? 1.f : 0.f;
    }
    case 2:
      return (int(std::floor(q[m.stripe_axis])) & 1) ? 1.f : 0.f;
    case 3: {
      const Vec3f n_obj = m.T_object_world.rotate(n_world);
      const float ax = std::abs(n_obj.x()), ay = std::abs(n_obj.y()), az = std::abs(n_obj.z());
      if (ax >= ay && ax >= az)
        return valueNoise2(q.y(), q.z(), std::uint32_t(int(std::floor(q.x()))) * 3u + 0u);
      if (ay >= az)
        return valueNoise2(q.x(), q.z(), std::uint32_t(int(std::floor(q.y()))) * 3u + 1u);
      return valueNoise2(q.x(), q.y(), std::uint32_t(int(std::floor(q.z()))) * 3u + 2u);
    }
    default:
      return 0.f;
  }
}

/// Shaded RGB (0..1) of world point p with unit normal n facing the viewer.
RASM_HD_INLINE Vec3f shadeSurface(const SurfaceMaterial& m, const LightF& light,
                                  const Vec3f& p_world, const Vec3f& n_world) {
  const float w = m.pattern == 0 ? 0.f : patternWeight(m, p_world, n_world);
  const Vec3f albedo = m.colour * (1.f - w) + m.colour2 * w;
  const float lambert = -n_world.dot(light.direction);
  return albedo * (light.ambient + light.diffuse * (lambert > 0.f ? lambert : 0.f));
}

RASM_HD_INLINE Bgr8 toBgr8(const Vec3f& rgb) {
  auto q = [](float v) {  // clamp with minss / maxss, then truncate: no branches
    float s = v * 255.f + 0.5f;
    s = s > 0.f ? s : 0.f;
    s = s < 255.f ? s : 255.f;
    return std::uint8_t(int(s));
  };
  Bgr8 out;
  out.r = q(rgb.x());
  out.g = q(rgb.y());
  out.b = q(rgb.z());
  return out;
}

}  // namespace rasm::sim
