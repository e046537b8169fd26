#pragma once
// Points on the office's surfaces for the map-checking tests (SurfaceDistance, SurfaceInstance):
// 3000 rays in random directions (fixed seed) from each of three eyes in the room, the hits kept.

#include <random>
#include <vector>

#include "rasm/sim/RayScene.h"

namespace rasm::sim::test {

inline std::vector<RayHit> officeRayHits(const RayScene& scene) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(-1.f, 1.f);
  std::vector<RayHit> hits;
  using V3f = Eigen::Vector3f;
  for (const V3f& eye : {V3f(4.f, 3.f, 1.5f), V3f(1.5f, 1.5f, 1.2f), V3f(6.5f, 4.5f, 0.5f)}) {
    const std::size_t end = hits.size() + 3000;
    while (hits.size() < end) {
      const V3f d(u(rng), u(rng), u(rng));
      if (d.norm() < 0.1f) continue;
      const RayHit h = scene.castRay(eye, d.normalized());
      if (h.hit) hits.push_back(h);
    }
  }
  return hits;
}

}  // namespace rasm::sim::test
