#pragma once
// Surfel splatting and point projection kernels of II-A / II-D, written once for the CPU (OpenMP)
// and CUDA launchers. Plain header: compute/ and Eigen only.
//
// Depth test: every candidate writes (float depth bits << 32 | surfel index) with a 64-bit atomic
// min. Positive IEEE floats order like their bit patterns, so the minimum is the nearest surfel,
// ties broken by the lower index: the result is the same for any thread interleaving.

#include <cmath>
#include <cstdint>
#include <cstring>

#include "rasm/compute/ImageView.h"
#include "rasm/compute/Lanes.h"
#include "rasm/compute/Types.h"
#include "rasm/surfel_map/SurfelArrays.h"

namespace rasm::maps::kernels {

constexpr std::uint64_t kEmptyPacked = ~std::uint64_t(0);

RASM_HD_INLINE std::uint32_t floatBits(float f) {
#ifdef __CUDA_ARCH__
  return __float_as_uint(f);
#else
  std::uint32_t u;
  std::memcpy(&u, &f, sizeof(u));
  return u;
#endif
}
RASM_HD_INLINE float bitsFloat(std::uint32_t u) {
#ifdef __CUDA_ARCH__
  return __uint_as_float(u);
#else
  float f;
  std::memcpy(&f, &u, sizeof(f));
  return f;
#endif
}

/// depth > 0 required.
RASM_HD_INLINE std::uint64_t packDepthIndex(float depth, int index) {
  return (std::uint64_t(floatBits(depth)) << 32) | std::uint64_t(std::uint32_t(index));
}
RASM_HD_INLINE int unpackIndex(std::uint64_t v) {
  return v == kEmptyPacked ? -1 : int(std::uint32_t(v));
}
RASM_HD_INLINE float unpackDepth(std::uint64_t v) {
  return v == kEmptyPacked ? 0.0f : bitsFloat(std::uint32_t(v >> 32));
}

RASM_HD_INLINE void atomicMinU64(std::uint64_t* addr, std::uint64_t v) {
#ifdef __CUDA_ARCH__
  atomicMin(reinterpret_cast<unsigned long long*>(addr), static_cast<unsigned long long>(v));
#else
  std::uint64_t cur = __atomic_load_n(addr, __ATOMIC_RELAXED);
  while (v < cur &&
         !__atomic_compare_exchange_n(addr, &cur, v, true, __ATOMIC_RELAXED, __ATOMIC_RELAXED)) {
  }
#endif
}

/// min / max without libm's NaN handling (fminf/fmaxf are calls without -ffast-math).
RASM_HD_INLINE float minF(float a, float b) {
  return a < b ? a : b;
}
RASM_HD_INLINE float maxF(float a, float b) {
  return a > b ? a : b;
}

/// Pixel of a projection with pixel centres at integer coordinates: round to nearest.
RASM_HD_INLINE int pixelOf(float u) {
  return int(floorf(u + 0.5f));
}
/// Sub-pixel of the 4x map (IndexMap4x): floor(4 (u + 0.5)), so sub-pixel / 4 == pixelOf(u).
RASM_HD_INLINE int subPixelOf4x(float u) {
  return int(floorf(4.0f * (u + 0.5f)));
}

/// A surfel's centre in the camera frame and its index: what a projection pass hands on to the
/// passes after it (fusion's association and carving), so they need not transform it again.
struct CameraPoint {
  Vec3f pc;
  std::int32_t index;
};

/// No 4x candidate (candidateKey4x).
constexpr std::uint32_t kNoCandidate = 0xffffffffu;

/// Where the point projection of the 4x index map (IndexMap4x, PointKernel with scale 4) puts a
/// surfel whose camera-frame centre is pc: (sub-pixel row << 16) | sub-pixel column, or
/// kNoCandidate outside the depth range or the image (frames up to 16383 pixels wide). Same
/// arithmetic as PointKernel, so both give the same candidates.
/// candidateKey4x() of a centre at depth z that projects to (u, v).
RASM_HD_INLINE std::uint32_t candidateKey4x(float z, float u, float v, const PinholeF& K,
                                            float min_depth_m, float max_depth_m) {
  if (!(z >= min_depth_m && z <= max_depth_m)) return kNoCandidate;
  const int sx = subPixelOf4x(u), sy = subPixelOf4x(v);
  if (sx < 0 || sy < 0 || sx >= 4 * K.width || sy >= 4 * K.height) return kNoCandidate;
  return (std::uint32_t(sy) << 16) | std::uint32_t(sx);
}
RASM_HD_INLINE std::uint32_t candidateKey4x(const Vec3f& pc, const PinholeF& K, float min_depth_m,
                                            float max_depth_m) {
  const float z = pc.z();
  if (!(z >= min_depth_m && z <= max_depth_m)) return kNoCandidate;
  return candidateKey4x(z, K.fx * pc.x() / z + K.cx, K.fy * pc.y() / z + K.cy, K, min_depth_m,
                        max_depth_m);
}
/// Frame pixel row / column and sub-pixel (0-15, row-major in the 4x4 block) of a key.
RASM_HD_INLINE int candidateRow(std::uint32_t key) {
  return int(key >> 18);
}
RASM_HD_INLINE int candidateColumn(std::uint32_t key) {
  return int((key & 0xffffu) >> 2);
}
RASM_HD_INLINE int candidateSubPixel(std::uint32_t key) {
  return int(((key >> 16) & 3u) * 4u + (key & 3u));
}

/// u = pi(p) (II-A) of camera-frame centres pc over lanes: u = fx x / z + cx, v = fy y / z + cy
/// (the render's culling, the splat's centre pixel; z <= 0 gives coordinates the view tests
/// reject).
template <class F>
RASM_HD_INLINE void projectCentre(const PinholeF& K, const lanes::LaneVec3<F>& pc, F& u, F& v) {
  u = K.fx * pc.x / pc.z + K.cx;
  v = K.fy * pc.y / pc.z + K.cy;
}

/// The per-surfel filters of a render (RenderOptions) after block culling: alive, stable only,
/// confidence, time window (map time), depth range, back faces, and the centre's projection within
/// [lo, hi] (pixels; the image grown by the splat radius).
struct VisibilityTest {
  SurfelArrays s;
  RigidF T_cam_world;
  PinholeF K;
  Vec3f camera_centre_world = Vec3f::Zero();
  float min_depth_m = 0.1f, max_depth_m = 10.0f;
  float min_confidence = 0.0f;
  float min_t_last = -3.0e38f;
  /// Creation time window (map time): surfels made in [min_t_init, max_t_init) (loop closure's
  /// inactive and active parts of the map).
  float min_t_init = -3.0e38f, max_t_init = 3.0e38f;
  bool stable_only = false;
  bool cull_back_faces = false;
  float u_lo = 0, u_hi = 0, v_lo = 0, v_hi = 0;

  /// Whether attributes() can reject a surfel whose confidence is >= 0: when false, a projection
  /// pass over the spatial index (which holds live surfels only) need not load the flags, times or
  /// normals at all.
  RASM_HD_INLINE bool filtersAttributes() const {
    return stable_only || min_confidence > 0.0f || min_t_last > -3.0e38f || min_t_init > -3.0e38f ||
           max_t_init < 3.0e38f || cull_back_faces;
  }

  /// The attribute and back-face filters only (for surfels known to be inside the frustum).
  RASM_HD_INLINE bool attributes(int i) const {
    const std::uint32_t cf = s.colour_flags[i];
    if (cf & kSurfelFree) return false;
    if (stable_only && !(cf & kSurfelStable)) return false;
    if (s.pos_conf[i].w() < min_confidence) return false;
    if (min_t_last > -3.0e38f && s.t_last[i] < min_t_last) return false;  // no window: no load
    if ((min_t_init > -3.0e38f || max_t_init < 3.0e38f) &&
        (s.t_init[i] < min_t_init || s.t_init[i] >= max_t_init))
      return false;
    return !cull_back_faces || s.normal(i).dot(camera_centre_world - s.position(i)) > 0.0f;
  }

  RASM_HD_INLINE bool operator()(int i) const {
    if (!attributes(i)) return false;
    return inView(T_cam_world.apply(s.position(i)));
  }

  /// The geometric part: depth range and the centre's projection within [lo, hi].
  RASM_HD_INLINE bool inView(const Vec3f& pc) const {
    float u, v;
    projectCentre(K, lanes::lanesOf(pc), u, v);
    return inView(pc.z(), u, v);
  }
  /// inView() with the projection (u, v) of the centre already computed; over lanes (the CPU
  /// render's culling tests four surfels at once).
  template <class F>
  RASM_HD_INLINE lanes::MaskOf<F> inView(const F& z, const F& u, const F& v) const {
    return z >= min_depth_m && z <= max_depth_m && u >= u_lo && u <= u_hi && v >= v_lo && v <= v_hi;
  }
};

/// The depth test write: 64-bit atomic min (shared buffer) or a plain min (the CPU launcher gives
/// each thread its own rows, see SurfelRenderer.cpp). Both keep the minimum, so results agree.
RASM_HD_INLINE void depthTest(std::uint64_t* p, std::uint64_t v, bool atomic) {
  if (atomic)
    atomicMinU64(p, v);
  else if (v < *p)
    *p = v;
}

/// Where one surfel's splat lands: camera-frame centre and normal, radius, the centre's pixel and
/// the clipped pixel bounding box (rows y0..y1, empty when y0 > y1).
struct SplatFootprint {
  Vec3f pc, nc;
  float r;
  int i;
  int uc, vc;
  int x0, x1, y0, y1;
};

/// The pixel box [u_lo, u_hi] x [v_lo, v_hi] of a surfel disc's projection (II-A's splat, before
/// rounding), over lanes (compute/Lanes.h: SplatKernel and the CPU splat's four-surfel groups run
/// this body): the disc (camera-frame centre pc, normal nc, radius r) lies in the box pc +- e with
/// e_a = r sqrt(1 - n_a^2), and x/z, y/z over a box are extreme at its corners; the box is
/// clamped to max_radius_px around the centre's projection (u, v), which bounds the cost of discs
/// very close to the camera (and is the whole box where the near corner is within 1 mm of z = 0).
template <class F>
RASM_HD_INLINE void splatBounds(const PinholeF& K, float max_radius_px,
                                const lanes::LaneVec3<F>& pc, const lanes::LaneVec3<F>& nc,
                                const F& r, const F& u, const F& v, F& u_lo, F& u_hi, F& v_lo,
                                F& v_hi) {
  using lanes::maxL;
  using lanes::minL;
  const F zero(0.0f);
  const F ex = r * lanes::sqrtL(maxL(zero, 1.0f - nc.x * nc.x));
  const F ey = r * lanes::sqrtL(maxL(zero, 1.0f - nc.y * nc.y));
  const F ez = r * lanes::sqrtL(maxL(zero, 1.0f - nc.z * nc.z));
  u_lo = u - max_radius_px;
  u_hi = u + max_radius_px;
  v_lo = v - max_radius_px;
  v_hi = v + max_radius_px;
  const F z0 = pc.z - ez, z1 = pc.z + ez;
  const lanes::MaskOf<F> near_ok = z0 > 1e-3f;
  const F iz0 = 1.0f / z0, iz1 = 1.0f / z1;
  const F x0 = pc.x - ex, x1 = pc.x + ex, y0 = pc.y - ey, y1 = pc.y + ey;
  const F ax = minL(minL(x0 * iz0, x0 * iz1), minL(x1 * iz0, x1 * iz1));
  const F bx = maxL(maxL(x0 * iz0, x0 * iz1), maxL(x1 * iz0, x1 * iz1));
  const F ay = minL(minL(y0 * iz0, y0 * iz1), minL(y1 * iz0, y1 * iz1));
  const F by = maxL(maxL(y0 * iz0, y0 * iz1), maxL(y1 * iz0, y1 * iz1));
  const F ua = K.fx * ax + K.cx, ub = K.fx * bx + K.cx;  // fx may be negative
  const F va = K.fy * ay + K.cy, vb = K.fy * by + K.cy;
  u_lo = lanes::select(near_ok, maxL(u_lo, minL(ua, ub)), u_lo);
  u_hi = lanes::select(near_ok, minL(u_hi, maxL(ua, ub)), u_hi);
  v_lo = lanes::select(near_ok, maxL(v_lo, minL(va, vb)), v_lo);
  v_hi = lanes::select(near_ok, minL(v_hi, maxL(va, vb)), v_hi);
}

/// The pixels [x0, x1] x [y0, y1] a splat depth-tests, as integer-valued floats over lanes: the
/// box of splatBounds rounded inwards, widened to the centre's own pixel (uc, vc) = pixelOf(u, v)
/// (always a candidate: SplatKernel::rasterize) and clipped to the width x height image. Empty
/// where x0 > x1 or y0 > y1 (the box lies outside the image).
template <class F>
RASM_HD_INLINE void splatPixels(const F& u_lo, const F& u_hi, const F& v_lo, const F& v_hi,
                                const F& u, const F& v, int width, int height, F& x0, F& x1, F& y0,
                                F& y1, F& uc, F& vc) {
  using lanes::maxL;
  using lanes::minL;
  uc = lanes::floorL(u + 0.5f);
  vc = lanes::floorL(v + 0.5f);
  x0 = maxL(F(0.0f), minL(lanes::ceilL(u_lo), uc));
  y0 = maxL(F(0.0f), minL(lanes::ceilL(v_lo), vc));
  x1 = minL(F(float(width - 1)), maxL(lanes::floorL(u_hi), uc));
  y1 = minL(F(float(height - 1)), maxL(lanes::floorL(v_hi), vc));
}

/// II-A's splat test of one pixel, over lanes (SplatKernel::rasterize and the CPU splat's four
/// pixels at once): the pixel's ray d = (rx, ry, 1) meets the plane n.(q - p) = 0 of the disc
/// (camera-frame centre pc, normal nc, n_dot_p = nc.pc, squared radius r2) at q = t d with
/// t = n.p / n.d (-1 where the ray is parallel to the plane); `hit` where t > 0 and q lies within
/// the disc. denom_y = nc_y ry + nc_z, the row's part of n.d.
template <class F>
RASM_HD_INLINE F rayDiscDepth(const F& rx, const F& ry, const F& denom_y, const Vec3f& pc,
                              const Vec3f& nc, float n_dot_p, float r2, lanes::MaskOf<F>& hit) {
  const F denom = nc.x() * rx + denom_y;
  const F t = lanes::select(lanes::absL(denom) >= 1e-6f, n_dot_p / denom, F(-1.0f));
  const F dx = t * rx - pc.x(), dy = t * ry - pc.y(), dz = t - pc.z();
  hit = t > 0.0f && !(dx * dx + dy * dy + dz * dz > r2);
  return t;
}

/// Draws surfel visible[k] as a disc of its radius in its plane (II-A splatting). For each pixel of
/// the disc's projected bounding box whose ray hits the disc, the ray/disc intersection depth
/// competes in `packed`. Cost per surfel: O(footprint), clamped at max_radius_px.
struct SplatKernel {
  SurfelArrays s;
  const int* visible = nullptr;
  RigidF T_cam_world;
  PinholeF K;
  float min_depth_m = 0.1f;
  float max_depth_m = 10.0f;
  float max_radius_px = 12.0f;
  ImageView<std::uint64_t> packed;

  /// False when the surfel is outside the depth range or its footprint misses the image.
  RASM_HD_INLINE bool footprint(int k, SplatFootprint& f) const {
    return footprintOf(visible[k], f);
  }

  /// footprint() of surfel i.
  RASM_HD_INLINE bool footprintOf(int i, SplatFootprint& f) const {
    return footprintAt(i, T_cam_world.apply(s.position(i)), f);
  }

  /// footprint() of surfel i whose camera-frame centre pc is already known.
  RASM_HD_INLINE bool footprintAt(int i, const Vec3f& pc, SplatFootprint& f) const {
    const float z = pc.z();
    if (!(z >= min_depth_m && z <= max_depth_m)) return false;
    return footprintAt(i, pc, K.fx * pc.x() / z + K.cx, K.fy * pc.y() / z + K.cy, f);
  }

  /// footprint() of surfel i whose camera-frame centre pc projects to (u, v).
  RASM_HD_INLINE bool footprintAt(int i, const Vec3f& pc, float u, float v,
                                  SplatFootprint& f) const {
    f.i = i;
    const float z = pc.z();
    if (!(z >= min_depth_m && z <= max_depth_m)) return false;
    const Vec3f nc = T_cam_world.rotate(s.normal(i));
    const float r = s.radius(i);
    float u_lo, u_hi, v_lo, v_hi;
    splatBounds(K, max_radius_px, lanes::lanesOf(pc), lanes::lanesOf(nc), r, u, v, u_lo, u_hi, v_lo,
                v_hi);
    float x0, x1, y0, y1, uc, vc;
    splatPixels(u_lo, u_hi, v_lo, v_hi, u, v, packed.width, packed.height, x0, x1, y0, y1, uc, vc);
    f.x0 = int(x0);
    f.x1 = int(x1);
    f.y0 = int(y0);
    f.y1 = int(y1);
    f.pc = pc;
    f.nc = nc;
    f.r = r;
    f.uc = int(uc);
    f.vc = int(vc);
    return x0 <= x1 && y0 <= y1;
  }

  /// Depth-tests the footprint's pixels in rows [y_lo, y_hi].
  RASM_HD_INLINE void rasterize(const SplatFootprint& f, int y_lo, int y_hi, bool atomic) const {
    const Vec3f& pc = f.pc;
    const Vec3f& nc = f.nc;
    const float z = pc.z(), r = f.r;
    const float n_dot_p = nc.dot(pc), r2 = r * r;
    const float inv_fx = 1.0f / K.fx, inv_fy = 1.0f / K.fy;
    for (int y = y_lo; y <= y_hi; ++y) {
      const float ry = (float(y) - K.cy) * inv_fy;
      const float denom_y = nc.y() * ry + nc.z();
      std::uint64_t* row = packed.row(y);
      for (int x = f.x0; x <= f.x1; ++x) {
        const float rx = (float(x) - K.cx) * inv_fx;
        bool hit;
        float t = rayDiscDepth(rx, ry, denom_y, pc, nc, n_dot_p, r2, hit);
        if (x == f.uc && y == f.vc) {
          // The centre's own pixel is covered even when the disc is smaller than the pixel (a
          // surfel seen from farther away than it was measured): plane depth, else centre depth.
          if (!(t > 0.0f) || fabsf(t - z) > r) t = z;
        } else if (!hit) {
          continue;
        }
        depthTest(&row[x], packDepthIndex(t, f.i), atomic);
      }
    }
  }

  RASM_HD_INLINE void operator()(int k) const {
    SplatFootprint f;
    if (footprint(k, f)) rasterize(f, f.y0, f.y1, true);
  }
};

/// Projects surfel visible[k] as a point into the 1x (scale = 1) or 4x (scale = 4) index map.
/// With `touched`, records the linear sub-pixel id written (or -1) for a sparse clear.
struct PointKernel {
  SurfelArrays s;
  const int* visible = nullptr;
  RigidF T_cam_world;
  PinholeF K;
  float min_depth_m = 0.1f;
  float max_depth_m = 10.0f;
  int scale = 1;
  ImageView<std::uint64_t> packed;
  std::int64_t* touched = nullptr;

  /// Linear (sub-)pixel id of surfel visible[k] and its packed depth/index, or -1.
  RASM_HD_INLINE std::int64_t target(int k, std::uint64_t& value) const {
    const int i = visible[k];
    return targetOf(i, T_cam_world.apply(s.position(i)), value);
  }

  /// target() of surfel i whose camera-frame centre is pc.
  RASM_HD_INLINE std::int64_t targetOf(int i, const Vec3f& pc, std::uint64_t& value) const {
    const float z = pc.z();
    if (!(z >= min_depth_m && z <= max_depth_m)) return -1;
    const float u = K.fx * pc.x() / z + K.cx, v = K.fy * pc.y() / z + K.cy;
    const int sx = scale == 1 ? pixelOf(u) : int(floorf(float(scale) * (u + 0.5f)));
    const int sy = scale == 1 ? pixelOf(v) : int(floorf(float(scale) * (v + 0.5f)));
    if (!packed.inside(sx, sy)) return -1;
    value = packDepthIndex(z, i);
    return std::int64_t(sy) * packed.width + sx;
  }

  RASM_HD_INLINE void operator()(int k) const {
    std::uint64_t value = 0;
    const std::int64_t id = target(k, value);
    if (id >= 0) atomicMinU64(&packed(int(id % packed.width), int(id / packed.width)), value);
    if (touched) touched[k] = id;
  }
};

/// Per pixel: decodes the depth test winner and writes the requested model maps (empty views are
/// skipped). Splat mode: vertex = the ray point at the winning depth; point mode: surfel centre.
struct ResolveKernel {
  SurfelArrays s;
  ImageView<const std::uint64_t> packed;
  RigidF T_world_cam;
  PinholeF K;
  bool splat = true;
  ImageView<std::int32_t> index;
  ImageView<float> depth_m;
  ImageView<Vec3f> vertex_world;
  ImageView<Vec3f> normal_world;
  ImageView<Bgr8> colour;
  ImageView<float> confidence;
  ImageView<std::uint32_t> segment;

  RASM_HD_INLINE void operator()(int x, int y) const {
    const std::uint64_t v = packed(x, y);
    const int i = unpackIndex(v);
    index(x, y) = i;
    const float nan = compute::invalidFloat();
    if (i < 0) {
      if (!depth_m.empty()) depth_m(x, y) = 0.0f;
      if (!vertex_world.empty()) vertex_world(x, y) = Vec3f(nan, nan, nan);
      if (!normal_world.empty()) normal_world(x, y) = Vec3f(nan, nan, nan);
      if (!colour.empty()) colour(x, y) = Bgr8{};
      if (!confidence.empty()) confidence(x, y) = 0.0f;
      if (!segment.empty()) segment(x, y) = 0u;
      return;
    }
    const float t = unpackDepth(v);
    if (!depth_m.empty()) depth_m(x, y) = t;
    if (!vertex_world.empty())
      vertex_world(x, y) = splat ? T_world_cam.apply(Vec3f((float(x) - K.cx) / K.fx * t,
                                                           (float(y) - K.cy) / K.fy * t, t))
                                 : s.position(i);
    if (!normal_world.empty()) normal_world(x, y) = s.normal(i);
    if (!colour.empty()) colour(x, y) = unpackColour(s.colour_flags[i]);
    if (!confidence.empty()) confidence(x, y) = s.confidence(i);
    if (!segment.empty()) segment(x, y) = s.segment[i];
  }
};

}  // namespace rasm::maps::kernels
