#include "rasm/surfel_map/SurfelRenderer.h"

#include "rasm/core/ComputeOptions.h"

#include <immintrin.h>

#include <cmath>
#include <stdexcept>

#include "rasm/surfel_map/kernels/RenderKernels.h"

namespace rasm::maps {

namespace {

RigidF toRigid(const Eigen::Isometry3d& T) {
  return RigidF::fromMatrix(T.matrix().cast<float>());
}

void fillEmpty(Image<std::uint64_t>& img) {
  const int w = img.width();
  compute::forEach1D(img.height(), [&](int y) {
    std::uint64_t* r = img.row(y);
    for (int x = 0; x < w; ++x) r[x] = kernels::kEmptyPacked;
  });
}

template <typename T>
ImageView<T> viewIf(bool wanted, Image<T>& img, int w, int h) {
  if (!wanted) {
    img = Image<T>();
    return ImageView<T>();
  }
  img.resize(w, h);
  return img.view();
}

/// Row bands for the CPU launchers: each band's rows are depth-tested by one thread with plain
/// (non-atomic) min writes, so no `lock cmpxchg` serialises the memory accesses. The minimum does
/// not depend on the visiting order, so the result equals the atomic path's.
int numBands(int rows, int per_thread) {
  const int t = compute::maxThreads();
  return t <= 1 ? 1 : std::min(rows, per_thread * t);
}

void pointsCpu(const kernels::PointKernel& k, int n, std::int64_t* ids,
               std::vector<std::uint64_t>& values) {
  values.resize(n);
  compute::forEach1D(n, [&](int j) { ids[j] = k.target(j, values[j]); });
  const int h = k.packed.height, w = k.packed.width, nb = numBands(h, 1);
#pragma omp parallel for schedule(static, 1)
  for (int b = 0; b < nb; ++b) {
    const std::int64_t lo = std::int64_t(h) * b / nb * w, hi = std::int64_t(h) * (b + 1) / nb * w;
    for (int j = 0; j < n; ++j) {
      const std::int64_t id = ids[j];
      if (id < lo || id >= hi) continue;
      kernels::depthTest(&k.packed(int(id % w), int(id / w)), values[j], false);
    }
  }
}

/// The resolve pass of a render: per pixel, the winner of the packed depth test -> the outputs
/// `opt` asks for (sized here; the others stay empty views).
kernels::ResolveKernel resolveKernel(const SurfelArrays& arr, const Image<std::uint64_t>& packed,
                                     const Eigen::Isometry3d& T_world_cam, const PinholeF& K,
                                     const RenderOptions& opt, RenderedMaps& out) {
  const int w = packed.width(), h = packed.height();
  out.index.resize(w, h);
  kernels::ResolveKernel r;
  r.s = arr;
  r.packed = packed.cview();
  r.T_world_cam = toRigid(T_world_cam);
  r.K = K;
  r.splat = opt.splat;
  r.index = out.index.view();
  r.depth_m = viewIf((opt.outputs & kRenderDepth) != 0, out.depth_m, w, h);
  r.vertex_world = viewIf((opt.outputs & kRenderVertex) != 0, out.vertex_world, w, h);
  r.normal_world = viewIf((opt.outputs & kRenderNormal) != 0, out.normal_world, w, h);
  r.colour = viewIf((opt.outputs & kRenderColour) != 0, out.colour, w, h);
  r.confidence = viewIf((opt.outputs & kRenderConfidence) != 0, out.confidence, w, h);
  r.segment = viewIf((opt.outputs & kRenderSegment) != 0, out.segment, w, h);
  return r;
}

}  // namespace

struct SurfelRenderer::Culling {
  std::vector<int> blocks;
  std::vector<std::uint8_t> inside;  ///< per block: entirely inside the frustum
  kernels::VisibilityTest test;
  bool attribute_filters = false;  ///< test.filtersAttributes()
};

void SurfelRenderer::cull(const SurfelStore& map, const Eigen::Isometry3d& T_world_cam,
                          const CameraIntrinsics& K, const RenderOptions& opt, float margin_px,
                          Culling& c) const {
  if (!K.valid()) throw std::invalid_argument("SurfelRenderer: invalid intrinsics " + K.toString());
  const RigidF T_wc = toRigid(T_world_cam);
  const PinholeF Kp = K.plain();
  const CameraFrustum frustum =
      CameraFrustum::fromCamera(T_wc, Kp, opt.min_depth_m, opt.max_depth_m);
  // Grow the culling by the largest radius and by the pixel margin at the far plane.
  const float f_min = float(std::min(std::fabs(K.fx), std::fabs(K.fy)));
  const float margin_m = map.radiusBound() + margin_px / f_min * opt.max_depth_m;
  c.blocks.clear();
  c.inside.clear();
  map.spatialIndex().blocksInFrustum(frustum, margin_m, c.blocks, &c.inside);

  kernels::VisibilityTest& test = c.test;
  test.s = map.arrays();
  test.T_cam_world = toRigid(T_world_cam.inverse());
  test.K = Kp;
  test.camera_centre_world = T_wc.translation();
  test.min_depth_m = opt.min_depth_m;
  test.max_depth_m = opt.max_depth_m;
  test.min_confidence = opt.min_confidence;
  if (std::isfinite(opt.time_window_s))
    test.min_t_last = map.toMapTime(opt.now_s - opt.time_window_s);
  if (std::isfinite(opt.created_after_s)) test.min_t_init = map.toMapTime(opt.created_after_s);
  if (std::isfinite(opt.created_before_s)) test.max_t_init = map.toMapTime(opt.created_before_s);
  test.stable_only = opt.stable_only;
  test.cull_back_faces = opt.cull_back_faces;
  test.u_lo = -0.5f - margin_px;
  test.u_hi = float(K.width) - 0.5f + margin_px;
  test.v_lo = -0.5f - margin_px;
  test.v_hi = float(K.height) - 0.5f + margin_px;
  c.attribute_filters = test.filtersAttributes();
}

namespace {

/// Four surfels of a render's visible members, after the filters: lanes set in `mask` passed,
/// `idx[0..3]` their indices (unused lanes repeat a passing one), centres and projections.
struct MemberGroup {
  const int* idx;
  int mask;
  __m128 x, y, z, u, v;
};

/// The splat launcher's culling (SimdPath::Splat): forVisibleMembers' filters four surfels per
/// SSE operation, handing on four at a time (MemberGroup). The arrays of the members kAhead
/// places on are prefetched (the flags twice as far ahead, so that with stable_only the geometry
/// of unstable surfels is not fetched); `members`, `n`: the block's member list, or its stable
/// prefix (membersToVisit).
template <typename G>
inline void forVisibleMemberGroups(const kernels::VisibilityTest& test, bool attribute_filters,
                                   bool inside, bool want_normals, const int* members, int n,
                                   G&& g) {
  constexpr int kAhead = 12, kChunk = 64;
  const SurfelArrays& a = test.s;
  const PinholeF& K = test.K;
  const float wmin = test.min_confidence;
  const int* m = members;
  int buf[kChunk + 4];
  for (int k0 = 0; k0 < n; k0 += kChunk) {
    // Attribute filters (scalar), prefetching the members ahead.
    const int k1 = std::min(n, k0 + kChunk);
    int nbuf = 0;
    for (int k = k0; k < k1; ++k) {
      if (attribute_filters && k + 2 * kAhead < n)
        __builtin_prefetch(&a.colour_flags[m[k + 2 * kAhead]]);
      if (k + kAhead < n) {
        const int j = m[k + kAhead];
        if (!test.stable_only || (a.colour_flags[j] & kSurfelStable)) {
          __builtin_prefetch(&a.pos_conf[j]);
          if (want_normals) __builtin_prefetch(&a.normal_radius[j]);
        }
      }
      const int i = m[k];
      if (!attribute_filters || test.attributes(i)) buf[nbuf++] = i;
    }
    // Projection, four surfels per SSE operation: the operations of RigidF::apply and of the
    // pixel coordinates in the same order, so the values equal the scalar ones.
    for (int q = 0; q < nbuf; q += 4) {
      const int nl = std::min(4, nbuf - q);
      for (int l = nl; l < 4; ++l) buf[q + l] = buf[q];  // pad with a valid surfel
      __m128 r0 = _mm_load_ps(a.pos_conf[buf[q]].data());
      __m128 r1 = _mm_load_ps(a.pos_conf[buf[q + 1]].data());
      __m128 r2 = _mm_load_ps(a.pos_conf[buf[q + 2]].data());
      __m128 r3 = _mm_load_ps(a.pos_conf[buf[q + 3]].data());
      _MM_TRANSPOSE4_PS(r0, r1, r2, r3);  // r0 = x, r1 = y, r2 = z, r3 = confidence
      using lanes::F4;
      const lanes::LaneVec3<F4> pc =
          lanes::apply(test.T_cam_world, lanes::LaneVec3<F4>{F4(r0), F4(r1), F4(r2)});
      F4 u4, v4;
      kernels::projectCentre(K, pc, u4, v4);
      auto ok = attribute_filters ? F4::mask_type(true) : !(F4(r3) < wmin);
      if (!inside) ok = ok && test.inView(pc.z, u4, v4);
      const int mask = lanes::bits(ok) & ((1 << nl) - 1);
      if (!mask) continue;
      g(MemberGroup{buf + q, mask, static_cast<__m128>(pc.x), static_cast<__m128>(pc.y),
                    static_cast<__m128>(pc.z), static_cast<__m128>(u4), static_cast<__m128>(v4)});
    }
  }
}

/// forVisibleMembers calls f(i, pc, u, v) for every member i of a culled block that passes the
/// render filters: the kernel's VisibilityTest one surfel at a time (attributes, then the
/// geometric test unless the block lies inside the frustum), with its camera-frame centre pc and
/// its projection (u, v). Member order is not memory order: the arrays of the members kAhead
/// places on are prefetched. (Its SSE copy earned 1.5% of redkitchen's frame time and was
/// deleted: docs/slam-eval.md "SSE paths".)
template <typename F>
inline void forVisibleMembers(const kernels::VisibilityTest& test, bool attribute_filters,
                              bool inside, bool want_normals, const int* m, int n, F&& f) {
  constexpr int kAhead = 12;
  const SurfelArrays& a = test.s;
  for (int k = 0; k < n; ++k) {
    if (k + kAhead < n) {
      __builtin_prefetch(&a.pos_conf[m[k + kAhead]]);
      if (want_normals) __builtin_prefetch(&a.normal_radius[m[k + kAhead]]);
    }
    const int i = m[k];
    if (attribute_filters ? !test.attributes(i) : a.pos_conf[i].w() < test.min_confidence) continue;
    const Vec3f pc = test.T_cam_world.apply(a.position(i));
    float u, v;
    kernels::projectCentre(test.K, lanes::lanesOf(pc), u, v);
    if (!inside && !test.inView(pc.z(), u, v)) continue;
    f(i, pc, u, v);
  }
}

/// SplatKernel::footprintAt of the four surfels of a group on four lanes: its bodies
/// (splatBounds, splatPixels) over lanes::F4, so the footprints are bit-identical. Returns the
/// mask of the lanes whose footprint is drawn (footprintAt true), written to out[lane].
inline int footprints4(const kernels::SplatKernel& k, const MemberGroup& g,
                       kernels::SplatFootprint out[4]) {
  const SurfelArrays& a = k.s;
  __m128 nx = _mm_load_ps(a.normal_radius[g.idx[0]].data());
  __m128 ny = _mm_load_ps(a.normal_radius[g.idx[1]].data());
  __m128 nz = _mm_load_ps(a.normal_radius[g.idx[2]].data());
  __m128 r = _mm_load_ps(a.normal_radius[g.idx[3]].data());
  _MM_TRANSPOSE4_PS(nx, ny, nz, r);  // world normal x, y, z and radius per lane
  using lanes::F4;
  const lanes::LaneVec3<F4> nc =
      lanes::rotate(k.T_cam_world, lanes::LaneVec3<F4>{F4(nx), F4(ny), F4(nz)});
  const F4 z(g.z);
  F4 u_lo, u_hi, v_lo, v_hi;
  kernels::splatBounds(k.K, k.max_radius_px, lanes::LaneVec3<F4>{F4(g.x), F4(g.y), z}, nc, F4(r),
                       F4(g.u), F4(g.v), u_lo, u_hi, v_lo, v_hi);
  F4 x0, x1, y0, y1, uc, vc;
  kernels::splatPixels(u_lo, u_hi, v_lo, v_hi, F4(g.u), F4(g.v), k.packed.width, k.packed.height,
                       x0, x1, y0, y1, uc, vc);
  const int mask =
      g.mask & lanes::bits(z >= k.min_depth_m && z <= k.max_depth_m && x0 <= x1 && y0 <= y1);
  if (!mask) return 0;
  alignas(16) float PX[4], PY[4], PZ[4], NX[4], NY[4], NZ[4], R[4];
  alignas(16) int X0[4], X1[4], Y0[4], Y1[4], UC[4], VC[4];
  _mm_store_ps(PX, g.x);
  _mm_store_ps(PY, g.y);
  _mm_store_ps(PZ, g.z);
  lanes::store(NX, nc.x);
  lanes::store(NY, nc.y);
  lanes::store(NZ, nc.z);
  _mm_store_ps(R, r);
  lanes::storeInt(X0, x0);
  lanes::storeInt(X1, x1);
  lanes::storeInt(Y0, y0);
  lanes::storeInt(Y1, y1);
  lanes::storeInt(UC, uc);
  lanes::storeInt(VC, vc);
  for (int m = mask; m; m &= m - 1) {
    const int l = __builtin_ctz(unsigned(m));
    kernels::SplatFootprint& f = out[l];
    f.pc = Vec3f(PX[l], PY[l], PZ[l]);
    f.nc = Vec3f(NX[l], NY[l], NZ[l]);
    f.r = R[l];
    f.i = g.idx[l];
    f.uc = UC[l];
    f.vc = VC[l];
    f.x0 = X0[l];
    f.x1 = X1[l];
    f.y0 = Y0[l];
    f.y1 = Y1[l];
  }
  return mask;
}

/// The members of block b a render visits: with stable_only only the block's stable prefix
/// (VoxelBlockIndex keeps stable surfels first), else all.
inline int membersToVisit(const VoxelBlockIndex& index, int b,
                          const kernels::VisibilityTest& test) {
  return test.stable_only ? index.stableCount(b) : int(index.members(b).size());
}

int threadId() {
#ifdef _OPENMP
  return omp_get_thread_num();
#else
  return 0;
#endif
}
int teamSize() {
#ifdef _OPENMP
  return omp_get_num_threads();
#else
  return 1;
#endif
}

/// Depth test of two adjacent pixels dst[0..1] at once: dst[j] = min(dst[j], packed lane j) for
/// the lanes set in `lanes` (2 bits), the (depth bits << 32 | index) minimum as an unsigned
/// 64-bit compare done as a signed one of the values with the top bit flipped.
alignas(16) constexpr std::uint64_t kPairLanes[4][2] = {
    {0, 0}, {~0ull, 0}, {0, ~0ull}, {~0ull, ~0ull}};
inline void depthTestPair(std::uint64_t* dst, __m128i packed, int lanes) {
  const __m128i top = _mm_set1_epi64x(std::int64_t(0x8000000000000000ull));
  const __m128i lane = _mm_load_si128(reinterpret_cast<const __m128i*>(kPairLanes[lanes]));
  const __m128i cur = _mm_loadu_si128(reinterpret_cast<const __m128i*>(dst));
  const __m128i less = _mm_cmpgt_epi64(_mm_xor_si128(cur, top), _mm_xor_si128(packed, top));
  _mm_storeu_si128(reinterpret_cast<__m128i*>(dst),
                   _mm_blendv_epi8(cur, packed, _mm_and_si128(less, lane)));
}

/// SplatKernel::rasterize (plain min writes) with four pixels of a row per SSE operation: the
/// same float operations in the same order per pixel, so the result is identical; the branches of
/// the tiny footprints (a few pixels each) become masks.
inline void rasterizeSse(const kernels::SplatKernel& k, const kernels::SplatFootprint& f, int y_lo,
                         int y_hi) {
  const Vec3f& pc = f.pc;
  const Vec3f& nc = f.nc;
  const float z = pc.z(), r = f.r;
  const float n_dot_p = nc.dot(pc), r2 = r * r;
  const float inv_fx = 1.0f / k.K.fx, inv_fy = 1.0f / k.K.fy;
  const __m128 v_cx = _mm_set1_ps(k.K.cx), v_inv_fx = _mm_set1_ps(inv_fx);
  const __m128 v_lane = _mm_set_ps(3.0f, 2.0f, 1.0f, 0.0f);
  const __m128i v_idx = _mm_set1_epi32(f.i);
  const int w = k.packed.width;
  alignas(16) float t_lane[4];
  for (int y = y_lo; y <= y_hi; ++y) {
    const float ry = (float(y) - k.K.cy) * inv_fy;
    const float denom_y = nc.y() * ry + nc.z();
    std::uint64_t* row = k.packed.row(y);
    for (int x0 = f.x0; x0 <= f.x1; x0 += 4) {
      const __m128 xs = _mm_add_ps(_mm_set1_ps(float(x0)), v_lane);
      const __m128 rx = _mm_mul_ps(_mm_sub_ps(xs, v_cx), v_inv_fx);
      lanes::F4::mask_type hit;
      __m128 t = static_cast<__m128>(kernels::rayDiscDepth(
          lanes::F4(rx), lanes::F4(ry), lanes::F4(denom_y), pc, nc, n_dot_p, r2, hit));
      int mask = lanes::bits(hit);
      const int n = std::min(4, f.x1 - x0 + 1);
      mask &= (1 << n) - 1;
      const int centre = (y == f.vc && f.uc >= x0 && f.uc < x0 + n) ? f.uc - x0 : -1;
      if (centre >= 0) {
        // The centre's own pixel is always covered: plane depth, else centre depth.
        _mm_store_ps(t_lane, t);
        float& tc = t_lane[centre];
        if (!(tc > 0.0f) || fabsf(tc - z) > r) tc = z;
        mask |= 1 << centre;
        t = _mm_load_ps(t_lane);
      }
      if (!mask) continue;
      if (x0 + 3 < w) {  // the four lanes, two pixels per depthTestPair
        const __m128i tb = _mm_castps_si128(t);
        depthTestPair(row + x0, _mm_unpacklo_epi32(v_idx, tb), mask & 3);
        depthTestPair(row + x0 + 2, _mm_unpackhi_epi32(v_idx, tb), mask >> 2);
      } else {  // the last columns: lanes past the row end are another row's pixels
        _mm_store_ps(t_lane, t);
        while (mask) {
          const int l = __builtin_ctz(unsigned(mask));
          mask &= mask - 1;
          kernels::depthTest(&row[x0 + l], kernels::packDepthIndex(t_lane[l], f.i), false);
        }
      }
    }
  }
}

/// rasterizeSse of a footprint at most 2 pixels wide over exactly the two rows y_lo, y_lo + 1:
/// both rows in one SSE operation (lanes (x0, y), (x0 + 1, y), (x0, y + 1), (x0 + 1, y + 1)),
/// the same float operations per pixel. 38% of the redkitchen footprints are 1x2 or 2x2.
inline void rasterizeTwoRowsSse(const kernels::SplatKernel& k, const kernels::SplatFootprint& f,
                                int y_lo) {
  const Vec3f& pc = f.pc;
  const Vec3f& nc = f.nc;
  const float z = pc.z(), r = f.r;
  const float n_dot_p = nc.dot(pc), r2 = r * r;
  const float inv_fx = 1.0f / k.K.fx, inv_fy = 1.0f / k.K.fy;
  const float ry0 = (float(y_lo) - k.K.cy) * inv_fy, ry1 = (float(y_lo + 1) - k.K.cy) * inv_fy;
  const float rx0 = (float(f.x0) - k.K.cx) * inv_fx, rx1 = (float(f.x0 + 1) - k.K.cx) * inv_fx;
  const __m128 ry = _mm_setr_ps(ry0, ry0, ry1, ry1), rx = _mm_setr_ps(rx0, rx1, rx0, rx1);
  const __m128 denom_y =
      _mm_add_ps(_mm_mul_ps(_mm_set1_ps(nc.y()), ry), _mm_set1_ps(nc.z()));  // per row
  const __m128 v_abs = _mm_castsi128_ps(_mm_set1_epi32(0x7fffffff));
  const __m128 v_z = _mm_set1_ps(z), v_zero = _mm_setzero_ps();
  lanes::F4::mask_type hit;
  __m128 t = static_cast<__m128>(kernels::rayDiscDepth(
      lanes::F4(rx), lanes::F4(ry), lanes::F4(denom_y), pc, nc, n_dot_p, r2, hit));
  const __m128 dz = _mm_sub_ps(t, v_z);
  const int cols = f.x1 > f.x0 ? 0x5 | 0xa : 0x5;  // lanes of column x0 + 1 only when drawn
  int mask = lanes::bits(hit) & cols;
  if ((f.vc == y_lo || f.vc == y_lo + 1) && f.uc >= f.x0 && f.uc <= f.x1) {
    // The centre's own pixel is always covered: plane depth, else centre depth.
    const int centre = (f.uc - f.x0) + 2 * (f.vc - y_lo);
    const __m128 at_centre =
        _mm_castsi128_ps(_mm_cmpeq_epi32(_mm_setr_epi32(0, 1, 2, 3), _mm_set1_epi32(centre)));
    const __m128 off = _mm_and_ps(
        at_centre,
        _mm_or_ps(_mm_cmpngt_ps(t, v_zero), _mm_cmpgt_ps(_mm_and_ps(dz, v_abs), _mm_set1_ps(r))));
    t = _mm_or_ps(_mm_andnot_ps(off, t), _mm_and_ps(off, v_z));
    mask |= 1 << centre;
  }
  if (!mask) return;
  if (f.x0 + 1 < k.packed.width) {  // the two pixels of each row at once
    const __m128i tb = _mm_castps_si128(t), v_idx = _mm_set1_epi32(f.i);
    depthTestPair(k.packed.row(y_lo) + f.x0, _mm_unpacklo_epi32(v_idx, tb), mask & 3);
    depthTestPair(k.packed.row(y_lo + 1) + f.x0, _mm_unpackhi_epi32(v_idx, tb), mask >> 2);
  } else {  // the last column: the lane past the row end is another row's pixel
    alignas(16) float t_lane[4];
    _mm_store_ps(t_lane, t);
    for (int m = mask; m; m &= m - 1) {
      const int l = __builtin_ctz(unsigned(m));
      kernels::depthTest(k.packed.row(y_lo + (l >> 1)) + f.x0 + (l & 1),
                         kernels::packDepthIndex(t_lane[l], f.i), false);
    }
  }
}

/// Resolves row y: ResolveKernel's outputs, with the pixel rays (x - cx) / fx tabulated per column
/// (the same values the kernel divides out per pixel) and the winning surfels' arrays prefetched a
/// few pixels ahead. Returns the number of pixels a surfel won.
inline int resolveRow(const kernels::ResolveKernel& r, int y, const float* ray_x) {
  constexpr int kAhead = 8;
  const int w = r.index.width;
  const std::uint64_t* row = r.packed.row(y);
  const bool want_depth = !r.depth_m.empty(), want_vertex = !r.vertex_world.empty(),
             want_normal = !r.normal_world.empty(), want_colour = !r.colour.empty(),
             want_conf = !r.confidence.empty(), want_segment = !r.segment.empty();
  const bool want_pos = want_conf || (want_vertex && !r.splat);
  const float ry = (float(y) - r.K.cy) / r.K.fy;
  const float nan = compute::invalidFloat();
  std::int32_t* index = r.index.row(y);
  int drawn = 0;
  for (int x = 0; x < w; ++x) {
    if (x + kAhead < w) {
      const int j = kernels::unpackIndex(row[x + kAhead]);
      if (j >= 0) {
        if (want_normal) __builtin_prefetch(&r.s.normal_radius[j]);
        if (want_pos) __builtin_prefetch(&r.s.pos_conf[j]);
        if (want_colour) __builtin_prefetch(&r.s.colour_flags[j]);
        if (want_segment) __builtin_prefetch(&r.s.segment[j]);
      }
    }
    const std::uint64_t v = row[x];
    const int i = kernels::unpackIndex(v);
    index[x] = i;
    if (i < 0) {
      if (want_depth) r.depth_m(x, y) = 0.0f;
      if (want_vertex) r.vertex_world(x, y) = Vec3f(nan, nan, nan);
      if (want_normal) r.normal_world(x, y) = Vec3f(nan, nan, nan);
      if (want_colour) r.colour(x, y) = Bgr8{};
      if (want_conf) r.confidence(x, y) = 0.0f;
      if (want_segment) r.segment(x, y) = 0u;
      continue;
    }
    ++drawn;
    const float t = kernels::unpackDepth(v);
    if (want_depth) r.depth_m(x, y) = t;
    if (want_vertex)
      r.vertex_world(x, y) =
          r.splat ? r.T_world_cam.apply(Vec3f(ray_x[x] * t, ry * t, t)) : r.s.position(i);
    if (want_normal) r.normal_world(x, y) = r.s.normal(i);
    if (want_colour) r.colour(x, y) = unpackColour(r.s.colour_flags[i]);
    if (want_conf) r.confidence(x, y) = r.s.confidence(i);
    if (want_segment) r.segment(x, y) = r.s.segment[i];
  }
  return drawn;
}

/// (x - cx) / fx per column, as ResolveKernel computes it.
void pixelRays(const PinholeF& K, std::vector<float>& ray_x) {
  ray_x.resize(K.width);
  for (int x = 0; x < K.width; ++x) ray_x[x] = (float(x) - K.cx) / K.fx;
}

}  // namespace

void SurfelRenderer::collectVisible(const SurfelStore& map, const Eigen::Isometry3d& T_world_cam,
                                    const CameraIntrinsics& K, const RenderOptions& opt,
                                    float margin_px, std::vector<int>& visible,
                                    RenderStats* stats) const {
  visible.clear();
  Culling c;
  cull(map, T_world_cam, K, opt, margin_px, c);
  const VoxelBlockIndex& index = map.spatialIndex();

  // Per-block results keep the output in block order whatever the thread schedule.
  const int nb = int(c.blocks.size());
  per_block_.resize(std::max<std::size_t>(per_block_.size(), std::size_t(nb)));
  long long tested = 0;
#pragma omp parallel for schedule(dynamic, 4) reduction(+ : tested)
  for (int j = 0; j < nb; ++j) {
    const int n = membersToVisit(index, c.blocks[j], c.test);
    std::vector<int>& out = per_block_[j];
    out.clear();
    tested += n;
    forVisibleMembers(c.test, c.attribute_filters, c.inside[j] != 0, false,
                      index.members(c.blocks[j]).data(), n,
                      [&](int i, const Vec3f&, float, float) { out.push_back(i); });
  }
  std::size_t total = 0;
  for (int j = 0; j < nb; ++j) total += per_block_[j].size();
  visible.reserve(total);
  for (int j = 0; j < nb; ++j)
    visible.insert(visible.end(), per_block_[j].begin(), per_block_[j].end());

  if (stats) {
    stats->blocks_total = index.numBlocks();
    stats->blocks_visited = nb;
    stats->surfels_tested = tested;
    stats->surfels_drawn = (long long)visible.size();
  }
}

void SurfelRenderer::splatCpu(const SurfelStore& map, const Eigen::Isometry3d& T_world_cam,
                              const CameraIntrinsics& K, const RenderOptions& opt,
                              RenderedMaps& out, RenderStats* stats) {
  const int w = K.width, h = K.height;
  Culling c;
  cull(map, T_world_cam, K, opt, opt.max_splat_radius_px, c);
  const VoxelBlockIndex& index = map.spatialIndex();
  const SurfelArrays arr = map.arrays();
  packed_.resize(w, h);
  const kernels::SplatKernel k{arr,
                               nullptr,
                               c.test.T_cam_world,
                               c.test.K,
                               opt.min_depth_m,
                               opt.max_depth_m,
                               opt.max_splat_radius_px,
                               packed_.view()};

  const kernels::ResolveKernel r = resolveKernel(arr, packed_, T_world_cam, c.test.K, opt, out);

  std::vector<float> ray_x;
  pixelRays(c.test.K, ray_x);
  // Footprints are binned by row band as they are computed (one pass over the visible blocks);
  // then each band is depth-tested by one thread with plain min writes and resolved while its
  // rows are in cache. A footprint crossing a band border is drawn in both bands, clipped.
  const int nt = compute::maxThreads();
  const int nbands = nt <= 1 ? 1 : std::min(h, 4 * nt);
  std::vector<int> band_lo(nbands + 1), band_of_row(h);
  for (int b = 0; b <= nbands; ++b) band_lo[b] = int(std::int64_t(h) * b / nbands);
  for (int b = 0; b < nbands; ++b)
    for (int y = band_lo[b]; y < band_lo[b + 1]; ++y) band_of_row[y] = b;
  if (int(band_fp_.size()) < nt * nbands) band_fp_.resize(nt * nbands);
  const int nb = int(c.blocks.size());
  long long tested = 0, drawn = 0, pixels = 0;
#pragma omp parallel num_threads(nt) reduction(+ : tested, drawn, pixels)
  {
    const int t = threadId();
    std::vector<kernels::SplatFootprint>* mine = &band_fp_[std::size_t(t) * nbands];
    for (int b = 0; b < nbands; ++b) mine[b].clear();
#pragma omp for schedule(dynamic, 2)
    for (int j = 0; j < nb; ++j) {
      const int n = membersToVisit(index, c.blocks[j], c.test);
      tested += n;
      forVisibleMemberGroups(c.test, c.attribute_filters, c.inside[j] != 0, true,
                             index.members(c.blocks[j]).data(), n, [&](const MemberGroup& g) {
                               drawn += __builtin_popcount(unsigned(g.mask));
                               kernels::SplatFootprint fp[4];
                               for (int m = footprints4(k, g, fp); m; m &= m - 1) {
                                 const kernels::SplatFootprint& f = fp[__builtin_ctz(unsigned(m))];
                                 for (int b = band_of_row[f.y0]; b <= band_of_row[f.y1]; ++b)
                                   mine[b].push_back(f);
                               }
                             });
    }
    const int tn = teamSize();
#pragma omp for schedule(dynamic, 1)
    for (int b = 0; b < nbands; ++b) {
      const int lo = band_lo[b], hi = band_lo[b + 1] - 1;
      for (int y = lo; y <= hi; ++y) {
        std::uint64_t* row = packed_.row(y);
        for (int x = 0; x < w; ++x) row[x] = kernels::kEmptyPacked;
      }
      for (int tt = 0; tt < tn; ++tt)
        for (const kernels::SplatFootprint& f : band_fp_[std::size_t(tt) * nbands + b]) {
          const int y0 = std::max(lo, f.y0), y1 = std::min(hi, f.y1);
          if (y1 == y0 + 1 && f.x1 <= f.x0 + 1)
            rasterizeTwoRowsSse(k, f, y0);
          else
            rasterizeSse(k, f, y0, y1);
        }
      for (int y = lo; y <= hi; ++y) pixels += resolveRow(r, y, ray_x.data());
    }
  }
  if (stats) {
    stats->blocks_total = index.numBlocks();
    stats->blocks_visited = nb;
    stats->surfels_tested = tested;
    stats->surfels_drawn = drawn;
    stats->pixels_drawn = pixels;
  }
}

void SurfelRenderer::render(const SurfelStore& map, const Eigen::Isometry3d& T_world_cam,
                            const CameraIntrinsics& K, const RenderOptions& opt, RenderedMaps& out,
                            RenderStats* stats) {
  const bool sse = compute::simdEnabled(compute::SimdPath::Splat);
  if (backend_ == compute::Backend::Cpu && opt.splat && sse) {
    splatCpu(map, T_world_cam, K, opt, out, stats);
    return;
  }
  const int w = K.width, h = K.height;
  collectVisible(map, T_world_cam, K, opt, opt.splat ? opt.max_splat_radius_px : 0.5f, visible_,
                 stats);
  const SurfelArrays arr = map.arrays();
  const RigidF T_cw = toRigid(T_world_cam.inverse());
  const PinholeF Kp = K.plain();

  packed_.resize(w, h);
  if (backend_ == compute::Backend::Cuda) {
    cuda::splatPacked(arr, visible_, T_cw, Kp, opt, packed_);
  } else if (opt.splat) {
    // [compute] simd = false: the splat kernel the CUDA path runs, one surfel per call (atomic
    // depth test), instead of splatCpu's SSE footprints and banded rasterization.
    fillEmpty(packed_);
    const kernels::SplatKernel k{arr,
                                 visible_.data(),
                                 T_cw,
                                 Kp,
                                 opt.min_depth_m,
                                 opt.max_depth_m,
                                 opt.max_splat_radius_px,
                                 packed_.view()};
    compute::forEach1D(int(visible_.size()), k);
  } else {
    fillEmpty(packed_);
    kernels::PointKernel k{arr, visible_.data(), T_cw,   Kp, opt.min_depth_m, opt.max_depth_m,
                           1,   packed_.view(),  nullptr};
    ids_.resize(visible_.size());
    pointsCpu(k, int(visible_.size()), ids_.data(), values_);
  }

  const kernels::ResolveKernel r = resolveKernel(arr, packed_, T_world_cam, Kp, opt, out);
  long long pixels = 0;
  if (!sse) {
    // The resolve kernel itself (resolveRow is its tabulated-ray copy).
    compute::forEach2D(w, h, r);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) pixels += out.index(x, y) >= 0;
  } else {
    std::vector<float> ray_x;
    pixelRays(Kp, ray_x);
#pragma omp parallel for schedule(dynamic, 8) reduction(+ : pixels)
    for (int y = 0; y < h; ++y) pixels += resolveRow(r, y, ray_x.data());
  }
  if (stats) stats->pixels_drawn = pixels;
}

void SurfelRenderer::renderIndexMap4x(const SurfelStore& map, const Eigen::Isometry3d& T_world_cam,
                                      const CameraIntrinsics& K, const RenderOptions& opt,
                                      IndexMap4x& out, RenderStats* stats) {
  constexpr int S = IndexMap4x::kScale;
  const int W = K.width * S, H = K.height * S;
  if (!out.packed.sameSize(W, H)) {
    out.packed.resize(W, H);
    fillEmpty(out.packed);
  } else {
    // Sparse clear: only the sub-pixels the previous render wrote (O(visible), not O(16 W H)).
    for (std::int64_t id : out.touched)
      if (id >= 0) out.packed(int(id % W), int(id / W)) = kernels::kEmptyPacked;
  }
  out.width = K.width;
  out.height = K.height;
  collectVisible(map, T_world_cam, K, opt, 0.5f, out.visible, stats);
  out.touched.assign(out.visible.size(), -1);
  const SurfelArrays arr = map.arrays();
  const RigidF T_cw = toRigid(T_world_cam.inverse());
  if (backend_ == compute::Backend::Cuda) {
    cuda::pointsPacked4x(arr, out.visible, T_cw, K.plain(), opt, out.packed, out.touched);
  } else {
    kernels::PointKernel k{arr,       out.visible.data(), T_cw,
                           K.plain(), opt.min_depth_m,    opt.max_depth_m,
                           S,         out.packed.view(),  nullptr};
    pointsCpu(k, int(out.visible.size()), out.touched.data(), values_);
  }
}

void SurfelRenderer::sortCandidateRow(int y, int team, std::uint32_t b, std::uint32_t e,
                                      std::vector<std::uint32_t>& col,
                                      std::vector<RowPoint>& sorted, PointCandidates4x& out) const {
  const int w = out.width, h = out.height;
  kernels::CameraPoint* entries = out.entries.data();
  std::fill(col.begin(), col.end(), 0u);
  for (int tt = 0; tt < team; ++tt)
    for (const RowPoint& rp : row_points_[std::size_t(tt) * h + y]) ++col[rp.column + 1];
  for (int x = 0; x < w; ++x) col[x + 1] += col[x];  // col[x] = start of column x in the row
  sorted.resize(e - b);
  for (int tt = 0; tt < team; ++tt)
    for (const RowPoint& rp : row_points_[std::size_t(tt) * h + y]) sorted[col[rp.column]++] = rp;
  // col[x] is now the end of column x.
  std::uint32_t* first = out.first.data() + std::size_t(y) * w;
  std::uint8_t* count = out.count.data() + std::size_t(y) * w;
  std::uint32_t pb = 0;
  for (int x = 0; x < w; ++x) {
    const std::uint32_t pe = col[x];
    first[x] = b + pb;
    std::uint32_t m = b + pb, n = pe - pb;
    if (n <= 1) {
      if (n) entries[m] = sorted[pb].p;
      count[x] = std::uint8_t(n);
      pb = pe;
      continue;
    }
    // Candidates first, hidden ones after them.
    std::uint32_t hidden = b + pe;
    for (std::uint32_t q = pb; q < pe; ++q) {
      const std::uint64_t v = kernels::packDepthIndex(sorted[q].p.pc.z(), sorted[q].p.index);
      bool wins = true;
      for (std::uint32_t o = pb; o < pe; ++o)
        if (o != q && sorted[o].sub == sorted[q].sub &&
            kernels::packDepthIndex(sorted[o].p.pc.z(), sorted[o].p.index) < v) {
          wins = false;
          break;
        }
      if (wins)
        entries[m++] = sorted[q].p;
      else
        entries[--hidden] = sorted[q].p;
    }
    count[x] = std::uint8_t(m - first[x]);
    pb = pe;
  }
}

void SurfelRenderer::renderCandidates4x(const SurfelStore& map,
                                        const Eigen::Isometry3d& T_world_cam,
                                        const CameraIntrinsics& K, const RenderOptions& opt,
                                        PointCandidates4x& out, RenderStats* stats) {
  Culling c;
  cull(map, T_world_cam, K, opt, 0.5f, c);
  const VoxelBlockIndex& index = map.spatialIndex();
  const int w = K.width, h = K.height, npix = w * h;
  if (w > 16383 || h > 16383)
    throw std::invalid_argument("SurfelRenderer::renderCandidates4x: image larger than 16383");
  const int nt = compute::maxThreads();
  out.width = w;
  out.height = h;
  row_points_.resize(std::size_t(nt) * h);
  others_.resize(nt);
  column_counts_.resize(nt);
  row_scratch_.resize(nt);
  out.first.resize(std::size_t(npix) + 1);
  out.count.resize(npix);
  std::vector<std::uint32_t> row_first(std::size_t(h) + 1, 0);
  const PinholeF Kp = c.test.K;
  const int nb = int(c.blocks.size());
  long long tested = 0;
  // Counting sort of the projected surfels by frame pixel, O(surfels in view + pixels):
  //   1. project the visible members into per-thread, per-image-row lists (no shared counters);
  //   2. prefix sum of the row sizes;
  //   3. per row: counting sort by column into the pixels' ranges, then per pixel move the nearest
  //      surfel of each sub-pixel ((depth, index) minimum, as the atomic min of the 4x map keeps)
  //      to the front: those are the pixel's candidates.
  // The result does not depend on the thread schedule (a pixel's range is in arbitrary order).
#pragma omp parallel num_threads(nt) reduction(+ : tested)
  {
    const int t = threadId(), tn = teamSize();
    std::vector<RowPoint>* rows = &row_points_[std::size_t(t) * h];
    for (int y = 0; y < h; ++y) rows[y].clear();
    std::vector<kernels::CameraPoint>& others = others_[t];
    others.clear();
#pragma omp for schedule(dynamic, 2)
    for (int j = 0; j < nb; ++j) {
      const int n = membersToVisit(index, c.blocks[j], c.test);
      tested += n;
      forVisibleMembers(
          c.test, c.attribute_filters, c.inside[j] != 0, false, index.members(c.blocks[j]).data(),
          n, [&](int i, const Vec3f& pc, float u, float v) {
            const std::uint32_t key =
                kernels::candidateKey4x(pc.z(), u, v, Kp, opt.min_depth_m, opt.max_depth_m);
            if (key == kernels::kNoCandidate) {
              others.push_back(kernels::CameraPoint{pc, i});
              return;
            }
            rows[kernels::candidateRow(key)].push_back(
                RowPoint{kernels::CameraPoint{pc, i}, std::uint16_t(kernels::candidateColumn(key)),
                         std::uint8_t(kernels::candidateSubPixel(key))});
          });
    }
#pragma omp single
    {
      std::uint32_t cur = 0;
      for (int y = 0; y < h; ++y) {
        row_first[y] = cur;
        for (int tt = 0; tt < tn; ++tt)
          cur += std::uint32_t(row_points_[std::size_t(tt) * h + y].size());
      }
      row_first[h] = cur;
      out.entries.resize(cur);
      std::size_t n_others = 0;
      for (int tt = 0; tt < tn; ++tt) n_others += others_[tt].size();
      out.others.clear();
      out.others.reserve(n_others);
      for (int tt = 0; tt < tn; ++tt)
        out.others.insert(out.others.end(), others_[tt].begin(), others_[tt].end());
    }
    column_counts_[t].resize(std::size_t(w) + 1);
#pragma omp for schedule(dynamic, 8)
    for (int y = 0; y < h; ++y)
      sortCandidateRow(y, tn, row_first[y], row_first[y + 1], column_counts_[t], row_scratch_[t],
                       out);
  }
  out.first[npix] = row_first[h];
  if (stats) {
    stats->blocks_total = index.numBlocks();
    stats->blocks_visited = nb;
    stats->surfels_tested = tested;
    stats->surfels_drawn = (long long)out.numVisible();
  }
}

#ifndef RASM_HAVE_CUDA
namespace cuda {
void splatPacked(const SurfelArrays&, const std::vector<int>&, const RigidF&, const PinholeF&,
                 const RenderOptions&, Image<std::uint64_t>&) {
  throw std::runtime_error("rasm was built without CUDA (RASM_WITH_CUDA=OFF or no nvcc)");
}
void pointsPacked4x(const SurfelArrays&, const std::vector<int>&, const RigidF&, const PinholeF&,
                    const RenderOptions&, Image<std::uint64_t>&, std::vector<std::int64_t>&) {
  throw std::runtime_error("rasm was built without CUDA (RASM_WITH_CUDA=OFF or no nvcc)");
}
}  // namespace cuda
#endif

}  // namespace rasm::maps
