#include "rasm/sim/SurfaceInstance.h"

#include <cmath>
#include <stdexcept>

#include "RaySceneImpl.h"
#include "rasm/models/ClassVocabulary.h"

namespace rasm::sim {

namespace {

using V3 = Eigen::Vector3f;

/// Closest point to p on triangle abc (Ericson, Real-Time Collision Detection, 5.1.5).
V3 closestPointOnTriangle(const V3& p, const V3& a, const V3& b, const V3& c) {
  const V3 ab = b - a, ac = c - a, ap = p - a;
  const float d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0.f && d2 <= 0.f) return a;
  const V3 bp = p - b;
  const float d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0.f && d4 <= d3) return b;
  const float vc = d1 * d4 - d3 * d2;
  if (vc <= 0.f && d1 >= 0.f && d3 <= 0.f) return a + (d1 / (d1 - d3)) * ab;
  const V3 cp = p - c;
  const float d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0.f && d5 <= d6) return c;
  const float vb = d5 * d2 - d1 * d6;
  if (vb <= 0.f && d2 >= 0.f && d6 <= 0.f) return a + (d2 / (d2 - d6)) * ac;
  const float va = d3 * d6 - d5 * d4;
  if (va <= 0.f && (d4 - d3) >= 0.f && (d5 - d6) >= 0.f)
    return b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b);
  const float denom = 1.f / (va + vb + vc);
  if (!std::isfinite(denom)) return a;  // degenerate triangle: its vertices are its points
  return a + ab * (vb * denom) + ac * (vc * denom);
}

struct QueryState {
  const std::vector<const float*>* vertices;
  const std::vector<const unsigned*>* triangles;
  V3 p;
  int object = -1;
  float dist = 0.f;
  V3 point = V3::Zero();
};

bool closestPointCallback(RTCPointQueryFunctionArguments* args) {
  auto* st = static_cast<QueryState*>(args->userPtr);
  const unsigned g = args->geomID;
  if (g >= st->vertices->size()) return false;
  const float* v = (*st->vertices)[g];
  const unsigned* t = (*st->triangles)[g];
  if (!v || !t) return false;
  const unsigned* tri = t + 3 * std::size_t(args->primID);
  const auto vert = [&](unsigned k) { return V3(v[3 * k], v[3 * k + 1], v[3 * k + 2]); };
  const V3 q = closestPointOnTriangle(st->p, vert(tri[0]), vert(tri[1]), vert(tri[2]));
  const float d = (q - st->p).norm();
  if (d < args->query->radius) {
    args->query->radius = d;  // shrink the search to the best so far
    st->dist = d;
    st->object = int(g);
    st->point = q;
    return true;
  }
  return false;
}

}  // namespace

SurfaceInstanceQuery::SurfaceInstanceQuery(const RayScene& scene) : m_scene(&scene) {
  const RayScene::Impl& m = scene.impl();
  const std::size_t n = m.world.objects.size();
  m_vertices.assign(n, nullptr);
  m_triangles.assign(n, nullptr);
  for (std::size_t i = 0; i < n; ++i) {
    if (m.world.objects[i].mesh.triangles.empty()) continue;
    RTCGeometry g = rtcGetGeometry(m.scene, unsigned(i));
    if (!g) continue;
    m_vertices[i] =
        static_cast<const float*>(rtcGetGeometryBufferData(g, RTC_BUFFER_TYPE_VERTEX, 0));
    m_triangles[i] =
        static_cast<const unsigned*>(rtcGetGeometryBufferData(g, RTC_BUFFER_TYPE_INDEX, 0));
  }
}

NearestSurface SurfaceInstanceQuery::nearest(const Eigen::Vector3f& p, float max_dist_m) const {
  if (!(max_dist_m > 0.f) || !std::isfinite(max_dist_m))
    throw std::invalid_argument("SurfaceInstanceQuery::nearest: max_dist_m > 0 expected");
  NearestSurface r;
  if (!p.allFinite()) return r;
  QueryState st{&m_vertices, &m_triangles, p};
  RTCPointQuery q;
  q.x = p.x();
  q.y = p.y();
  q.z = p.z();
  q.time = 0.f;
  q.radius = max_dist_m;
  RTCPointQueryContext ctx;
  rtcInitPointQueryContext(&ctx);
  rtcPointQuery(m_scene->impl().scene, &q, &ctx, &closestPointCallback, &st);
  if (st.object < 0) return r;
  const WorldObject& o = m_scene->world().objects[std::size_t(st.object)];
  r.object = st.object;
  r.instance_id = o.instance_id;
  r.class_id = o.class_id;
  r.distance_m = st.dist;
  r.point = st.point;
  return r;
}

std::vector<NearestSurface> SurfaceInstanceQuery::nearest(
    const std::vector<Eigen::Vector3f>& points, float max_dist_m) const {
  if (!(max_dist_m > 0.f) || !std::isfinite(max_dist_m))
    throw std::invalid_argument("SurfaceInstanceQuery::nearest: max_dist_m > 0 expected");
  std::vector<NearestSurface> out(points.size());
  const long long n = (long long)points.size();
#pragma omp parallel for schedule(dynamic, 4096)
  for (long long i = 0; i < n; ++i)
    out[std::size_t(i)] = nearest(points[std::size_t(i)], max_dist_m);
  return out;
}

std::vector<WorldInstanceInfo> worldInstances(const World& world) {
  std::vector<WorldInstanceInfo> out;
  out.reserve(world.objects.size());
  for (std::size_t i = 0; i < world.objects.size(); ++i) {
    const WorldObject& o = world.objects[i];
    WorldInstanceInfo w;
    w.object = int(i);
    w.instance_id = o.instance_id;
    w.class_id = o.class_id;
    w.class_name = o.class_id < models::numClasses() ? models::className(o.class_id)
                                                     : std::to_string(o.class_id);
    w.name = o.name;
    w.is_static = o.is_static;
    w.is_structure = models::isStructureClass(o.class_id);
    if (!o.mesh.vertices.empty())
      w.extent_m = o.mesh.bounds().sizes().cwiseProduct(o.scale.cwiseAbs());
    w.size_m = double(w.extent_m.maxCoeff());
    out.push_back(std::move(w));
  }
  return out;
}

}  // namespace rasm::sim
