#pragma once
// Ray-casting acceleration structure of a World (Embree 3 BVH, CPU). Built once, then queried
// concurrently from any number of threads (all query methods are const and thread-safe).
// Embree stays out of this header: sensor, robot and detector reach it through src/.

#include <Eigen/Core>
#include <limits>
#include <memory>

#include "rasm/sim/World.h"

namespace rasm::sim {

struct RayHit {
  bool hit = false;
  float t = 0.f;  ///< ray parameter: hit point = origin + t * dir (dir not normalized)
  Eigen::Vector3f point = Eigen::Vector3f::Zero();
  Eigen::Vector3f normal = Eigen::Vector3f::Zero();  ///< unit geometric normal, facing the ray
  int object = -1;                                   ///< index into World::objects
};

class RayScene {
 public:
  /// Builds the BVH of all objects (in world coordinates, scale applied) plus one small BVH per
  /// object for occlusion-free queries. The world is copied.
  explicit RayScene(World world);
  ~RayScene();
  RayScene(const RayScene&) = delete;
  RayScene& operator=(const RayScene&) = delete;

  const World& world() const;

  /// Closest hit along origin + t * dir, t in [t_min, t_max].
  RayHit castRay(const Eigen::Vector3f& origin, const Eigen::Vector3f& dir, float t_min = 0.f,
                 float t_max = std::numeric_limits<float>::infinity()) const;
  /// Any hit in [t_min, t_max].
  bool occluded(const Eigen::Vector3f& origin, const Eigen::Vector3f& dir, float t_min = 0.f,
                float t_max = std::numeric_limits<float>::infinity()) const;
  /// Closest hit on object `object_index` alone, as if nothing else existed.
  RayHit castRayAlone(int object_index, const Eigen::Vector3f& origin, const Eigen::Vector3f& dir,
                      float t_min = 0.f,
                      float t_max = std::numeric_limits<float>::infinity()) const;
  /// World-space bounds of one object.
  const Eigen::AlignedBox3f& objectBounds(int object_index) const;

  struct Impl;
  const Impl& impl() const { return *impl_; }

 private:
  std::unique_ptr<Impl> impl_;
};

}  // namespace rasm::sim
