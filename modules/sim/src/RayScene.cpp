#include <stdexcept>
#include <string>

#include "RaySceneImpl.h"
#include "rasm/core/Error.h"

namespace rasm::sim {

namespace {

void check(RTCDevice dev, const char* what) {
  const RTCError e = rtcGetDeviceError(dev);
  if (e != RTC_ERROR_NONE)
    throw std::runtime_error(std::string("Embree error ") + std::to_string(int(e)) + " in " + what);
}

/// Triangle geometry of `mesh` (world coordinates) committed into `scene` as geometry `id`.
void attachMesh(RTCDevice dev, RTCScene scene, const models::TriangleMesh& mesh, unsigned id) {
  RTCGeometry g = rtcNewGeometry(dev, RTC_GEOMETRY_TYPE_TRIANGLE);
  auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(
      g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), mesh.vertices.size()));
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i)
    for (int k = 0; k < 3; ++k) v[3 * i + k] = mesh.vertices[i][k];
  auto* t = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
      g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), mesh.triangles.size()));
  for (std::size_t i = 0; i < mesh.triangles.size(); ++i)
    for (int k = 0; k < 3; ++k) t[3 * i + k] = unsigned(mesh.triangles[i][k]);
  rtcCommitGeometry(g);
  rtcAttachGeometryByID(scene, g, id);
  rtcReleaseGeometry(g);
}

RayHit toHit(const RTCRayHit& rh, const Eigen::Vector3f& o, const Eigen::Vector3f& d, int object) {
  RayHit h;
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return h;
  h.hit = true;
  h.t = rh.ray.tfar;
  h.point = o + h.t * d;
  h.normal = Eigen::Vector3f(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z).normalized();
  if (h.normal.dot(d) > 0.f) h.normal = -h.normal;
  h.object = object;
  return h;
}

}  // namespace

RayScene::Impl::~Impl() {
  for (RTCScene s : object_scenes) rtcReleaseScene(s);
  if (scene) rtcReleaseScene(scene);
  if (device) rtcReleaseDevice(device);
}

RayScene::RayScene(World world) : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  m.world = std::move(world);
  m.device = rtcNewDevice("verbose=0");
  if (!m.device)
    throw std::runtime_error("rtcNewDevice failed: " +
                             std::to_string(int(rtcGetDeviceError(nullptr))));
  // Robust traversal: rays through shared triangle edges (box corners, wall joints) never slip
  // through; worth a few percent of speed in a simulator whose ground truth must be watertight.
  m.scene = rtcNewScene(m.device);
  rtcSetSceneFlags(m.scene, RTC_SCENE_FLAG_ROBUST);
  rtcSetSceneBuildQuality(m.scene, RTC_BUILD_QUALITY_HIGH);
  const auto& objs = m.world.objects;
  m.object_scenes.resize(objs.size(), nullptr);
  m.bounds.resize(objs.size());
  m.materials.resize(objs.size());
  for (std::size_t i = 0; i < objs.size(); ++i) {
    const WorldObject& o = objs[i];
    const models::TriangleMesh wm = o.worldMesh();
    attachMesh(m.device, m.scene, wm, unsigned(i));
    m.object_scenes[i] = rtcNewScene(m.device);
    rtcSetSceneFlags(m.object_scenes[i], RTC_SCENE_FLAG_ROBUST);
    attachMesh(m.device, m.object_scenes[i], wm, 0);
    rtcCommitScene(m.object_scenes[i]);
    m.bounds[i] = wm.bounds();

    SurfaceMaterial& sm = m.materials[i];
    sm.colour = o.material.colour_rgb;
    sm.colour2 = o.material.colour2_rgb;
    sm.pattern = int(o.material.pattern);
    sm.inv_period = 1.f / o.material.period_m;
    sm.stripe_axis = o.material.stripe_axis;
    sm.T_object_world = RigidF::fromMatrix(o.T_world_object.inverse().matrix().cast<float>());
    sm.instance_id = o.instance_id;
    sm.class_id = o.class_id;
  }
  rtcCommitScene(m.scene);
  check(m.device, "building the world BVH");
}

RayScene::~RayScene() = default;

const World& RayScene::world() const {
  return impl_->world;
}

const Eigen::AlignedBox3f& RayScene::objectBounds(int i) const {
  return impl_->bounds.at(std::size_t(i));
}

RayHit RayScene::castRay(const Eigen::Vector3f& o, const Eigen::Vector3f& d, float t_min,
                         float t_max) const {
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  RTCRayHit rh;
  initRayHit(rh, o, d, t_min, t_max);
  rtcIntersect1(impl_->scene, &ctx, &rh);
  return toHit(rh, o, d, rh.hit.geomID == RTC_INVALID_GEOMETRY_ID ? -1 : int(rh.hit.geomID));
}

bool RayScene::occluded(const Eigen::Vector3f& o, const Eigen::Vector3f& d, float t_min,
                        float t_max) const {
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  RTCRayHit rh;
  initRayHit(rh, o, d, t_min, t_max);
  rtcOccluded1(impl_->scene, &ctx, &rh.ray);
  return rh.ray.tfar < 0.f;  // Embree sets tfar = -inf on a hit
}

RayHit RayScene::castRayAlone(int object, const Eigen::Vector3f& o, const Eigen::Vector3f& d,
                              float t_min, float t_max) const {
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  RTCRayHit rh;
  initRayHit(rh, o, d, t_min, t_max);
  rtcIntersect1(impl_->object_scenes.at(std::size_t(object)), &ctx, &rh);
  return toHit(rh, o, d, object);
}

}  // namespace rasm::sim
