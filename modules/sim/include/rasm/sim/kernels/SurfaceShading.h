#pragma once
// Colour of a simulated surface point: albedo from a solid procedural pattern (checker, stripes,
// value noise) evaluated in the object's frame, lit by one directional light with Lambertian
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
  RigidF T_object_world;            ///< world -> object frame (rigid; pattern period in metres)
  std::uint16_t instance_id = 0;
  std::uint16_t class_id = 0;
};

struct LightF {
  Vec3f direction{0.f, 0.f, -1.f};  ///< unit, direction light travels
  float ambient = 0.35f;
  float diffuse = 0.65f;
};

/// Value noise on the integer lattice, trilinear with smoothstep weights, in [0, 1].
RASM_HD_INLINE float valueNoise3(const Vec3f& p) {
  const float fx = std::floor(p.x()), fy = std::floor(p.y()), fz = std::floor(p.z());
  const int ix = int(fx), iy = int(fy), iz = int(fz);
  float tx = p.x() - fx, ty = p.y() - fy, tz = p.z() - fz;
  tx = tx * tx * (3.f - 2.f * tx);
  ty = ty * ty * (3.f - 2.f * ty);
  tz = tz * tz * (3.f - 2.f * tz);
  auto lattice = [](int x, int y, int z) {
    // Lattice values from a 32-bit integer hash (Wellons' lowbias32 finalizer).
    std::uint32_t h = std::uint32_t(x) * 0x8DA6B343u ^ std::uint32_t(y) * 0xD8163841u ^ std::uint32_t(z) * 0xCB1AB31Fu;
    h ^= h >> 16;
    h *= 0x7FEB352Du;
    h ^= h >> 15;
    h *= 0x846CA68Bu;
    h ^= h >> 16;
    return float(h >> 8) * (1.0f / 16777216.0f);
  };
  float c[2][2];
  for (int dz = 0; dz < 2; ++dz)
    for (int dy = 0; dy < 2; ++dy) {
      const float a = lattice(ix, iy + dy, iz + dz), b = lattice(ix + 1, iy + dy, iz + dz);
      c[dz][dy] = a + (b - a) * tx;
    }
  const float c0 = c[0][0] + (c[0][1] - c[0][0]) * ty;
  const float c1 = c[1][0] + (c[1][1] - c[1][0]) * ty;
  return c0 + (c1 - c0) * tz;
}

/// Blend weight of colour2 at an object-frame point (metres).
RASM_HD_INLINE float patternWeight(const SurfaceMaterial& m, const Vec3f& p_obj) {
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
    case 3:
      return valueNoise3(q);
    default:
      return 0.f;
  }
}

/// Shaded RGB (0..1) of world point p with unit normal n facing the viewer.
RASM_HD_INLINE Vec3f shadeSurface(const SurfaceMaterial& m, const LightF& light, const Vec3f& p_world,
                                  const Vec3f& n_world) {
  const float w = m.pattern == 0 ? 0.f : patternWeight(m, m.T_object_world.apply(p_world));
  const Vec3f albedo = m.colour * (1.f - w) + m.colour2 * w;
  const float lambert = -n_world.dot(light.direction);
  return albedo * (light.ambient + light.diffuse * (lambert > 0.f ? lambert : 0.f));
}

RASM_HD_INLINE Bgr8 toBgr8(const Vec3f& rgb) {
  auto q = [](float v) {
    const float s = v * 255.f + 0.5f;
    return std::uint8_t(s <= 0.f ? 0 : (s >= 255.f ? 255 : int(s)));
  };
  Bgr8 out;
  out.r = q(rgb.x());
  out.g = q(rgb.y());
  out.b = q(rgb.z());
  return out;
}

}  // namespace rasm::sim
