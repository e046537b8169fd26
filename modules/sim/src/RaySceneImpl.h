#pragma once
// Private: the Embree side of RayScene, shared by the sensor, robot and detector sources.

#include <embree3/rtcore.h>

#include <vector>

#include "rasm/sim/RayScene.h"
#include "rasm/sim/kernels/SurfaceShading.h"

namespace rasm::sim {

struct RayScene::Impl {
  World world;
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;                 ///< all objects; geometry id == object index
  std::vector<RTCScene> object_scenes;      ///< one per object (geometry id 0)
  std::vector<Eigen::AlignedBox3f> bounds;  ///< world-space per object
  std::vector<SurfaceMaterial> materials;   ///< per object, plain data for shading kernels

  ~Impl();
};

/// Fills an RTCRayHit for a single ray.
inline void initRayHit(RTCRayHit& rh, const Eigen::Vector3f& o, const Eigen::Vector3f& d,
                       float t_min, float t_max) {
  rh.ray.org_x = o.x();
  rh.ray.org_y = o.y();
  rh.ray.org_z = o.z();
  rh.ray.dir_x = d.x();
  rh.ray.dir_y = d.y();
  rh.ray.dir_z = d.z();
  rh.ray.tnear = t_min;
  rh.ray.tfar = t_max;
  rh.ray.time = 0.f;
  rh.ray.mask = 0xFFFFFFFFu;
  rh.ray.id = 0;
  rh.ray.flags = 0;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
}

}  // namespace rasm::sim
