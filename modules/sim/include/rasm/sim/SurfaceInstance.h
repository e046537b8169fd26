#pragma once
// Which ground-truth instance a 3-D point belongs to: the instance (and class) of the world
// surface nearest to it (`rasm eval segmentation`, docs/segmentation.md "Evaluation"), and the
// objects of a world with their sizes.
//
// The nearest surface is exact: an Embree closest-point query (rtcPointQuery) over the triangles
// of the RayScene's BVH within max_dist_m of the point, with the exact point-triangle distance
// (Ericson, Real-Time Collision Detection 5.1.5). Unlike SurfaceDistance.h (ray-cast upper
// bound) it never overestimates. Ties between objects at the same distance (a point on the line
// where a mug stands on a desk) go to the object found first by the traversal, which is the same
// for the same scene.

#include <Eigen/Core>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "rasm/sim/RayScene.h"

namespace rasm::sim {

struct NearestSurface {
  int object = -1;                ///< index into World::objects; -1 = no surface within max_dist_m
  std::uint16_t instance_id = 0;  ///< 0 when object < 0
  std::uint16_t class_id = 0;
  float distance_m = std::numeric_limits<float>::infinity();
  Eigen::Vector3f point = Eigen::Vector3f::Zero();  ///< nearest surface point (world)
};

/// Closest-point queries on a RayScene (kept by reference: it must outlive this). Thread-safe.
class SurfaceInstanceQuery {
 public:
  explicit SurfaceInstanceQuery(const RayScene& scene);

  /// Nearest surface to `p` within max_dist_m (> 0); object -1 when none or p is not finite.
  NearestSurface nearest(const Eigen::Vector3f& p, float max_dist_m) const;
  /// nearest() of every point (parallel over points; the same result for any thread count).
  std::vector<NearestSurface> nearest(const std::vector<Eigen::Vector3f>& points,
                                      float max_dist_m) const;

  const RayScene& scene() const { return *m_scene; }

 private:
  const RayScene* m_scene;
  /// Per object: world-space vertices and triangles (as attached to the BVH).
  std::vector<const float*> m_vertices;
  std::vector<const unsigned*> m_triangles;
};

/// An instance of a world as ground truth for segmentation.
struct WorldInstanceInfo {
  int object = -1;  ///< index into World::objects
  std::uint16_t instance_id = 0;
  std::uint16_t class_id = 0;
  std::string class_name;  ///< models::className(class_id) ("none" for 0)
  std::string name;        ///< WorldObject::name (may be empty)
  bool is_static = false;
  bool is_structure = false;  ///< floor, wall, ceiling, door (models::isStructureClass)
  /// Edge lengths of the object's bounding box in its own frame, scale applied (m).
  Eigen::Vector3f extent_m = Eigen::Vector3f::Zero();
  double size_m = 0.0;  ///< largest of extent_m
};

/// Every instance of `world`, in World::objects order.
std::vector<WorldInstanceInfo> worldInstances(const World& world);

}  // namespace rasm::sim
