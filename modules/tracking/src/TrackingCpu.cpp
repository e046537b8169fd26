#include "rasm/tracking/TrackingCpu.h"

#include <cstdint>

#include "rasm/compute/Sse.h"

#include "rasm/compute/Parallel.h"
#include "rasm/core/ComputeOptions.h"

namespace rasm::tracking {

namespace {

using kernels::IcpAccumulator;
using kernels::IcpReduceKernel;

using sse::gather3;
using sse::rigidRow;
using sse::select;
using sse::sum3;

/// pshufb controls that move the 4-byte lanes set in a 4-bit mask to the front, in lane order.
struct LeftPack {
  __m128i ctl[16];
  LeftPack() {
    for (int m = 0; m < 16; ++m) {
      alignas(16) std::uint8_t b[16];
      int k = 0;
      for (int l = 0; l < 4; ++l)
        if ((m >> l) & 1) {
          for (int j = 0; j < 4; ++j) b[4 * k + j] = std::uint8_t(4 * l + j);
          ++k;
        }
      for (; k < 4; ++k)
        for (int j = 0; j < 4; ++j) b[4 * k + j] = 0x80;  // zero
      ctl[m] = _mm_load_si128(reinterpret_cast<const __m128i*>(b));
    }
  }
};
const LeftPack kLeftPack;

/// One work item (a row segment), as kernels::reduceRowSegment with IcpReduceKernel::pixel.
template <int kSegment>
void reduceSegmentSse(const IcpReduceKernel& k, int item, IcpAccumulator& acc) {
  const auto [y, xs0, xs1] = kernels::rowSegment<kSegment>(k, item);
  alignas(64) float Jb[6][kSegment];
  alignas(64) float wJb[6][kSegment];
  alignas(64) float rb[kSegment];
  alignas(64) float wb[kSegment];
  float depth_sum = 0.f;
  int valid = 0, n = 0;

  const Vec3f* fv = k.frame_vertex.row(y);
  const Vec3f* fn = k.frame_normal.row(y);
  const float* Tm = k.T_model_cam.m;
  const float* Tw = k.T_world_cam.m;
  const __m128 zero = _mm_setzero_ps(), one = _mm_set1_ps(1.0f), half = _mm_set1_ps(0.5f);
  const __m128 fx = _mm_set1_ps(k.K_model.fx), fy = _mm_set1_ps(k.K_model.fy);
  const __m128 cx = _mm_set1_ps(k.K_model.cx), cy = _mm_set1_ps(k.K_model.cy);
  const __m128 lo = _mm_set1_ps(-0.5f);
  const __m128 u_hi = _mm_set1_ps(float(k.model_vertex.width) - 0.5f);
  const __m128 v_hi = _mm_set1_ps(float(k.model_vertex.height) - 0.5f);
  const __m128 max_d2 = _mm_set1_ps(k.max_dist_m * k.max_dist_m);
  const __m128 min_cos = _mm_set1_ps(k.min_normal_cos);
  const __m128 pvx = _mm_set1_ps(k.pivot_world.x()), pvy = _mm_set1_ps(k.pivot_world.y()),
               pvz = _mm_set1_ps(k.pivot_world.z());
  const __m128 abs_mask = _mm_castsi128_ps(_mm_set1_epi32(0x7fffffff));
  const __m128 sigma1 = _mm_set1_ps(kernels::depthNoiseSigma(1.0f));
  const __m128 huber = _mm_set1_ps(k.huber_delta_m);
  const bool use_huber = k.huber_delta_m > 0.0f;

  const bool last_row = y == k.frame_vertex.height - 1;
  const int last_x = k.frame_vertex.width - 1;
  const int model_last_u = k.model_vertex.width - 1, model_last_v = k.model_vertex.height - 1;
  for (int xs = xs0; xs < xs1; xs += 4) {
    const int nl = xs1 - xs < 4 ? xs1 - xs : 4;
    int X[4];
    bool L[4];
    for (int l = 0; l < 4; ++l) {
      X[l] = (xs + (l < nl ? l : 0)) * k.stride;  // padding lanes repeat the first pixel
      L[l] = last_row && X[l] == last_x;
    }
    __m128 vx, vy, vz, nx, ny, nz;
    gather3(fv[X[0]], fv[X[1]], fv[X[2]], fv[X[3]], L[0], L[1], L[2], L[3], vx, vy, vz);
    gather3(fn[X[0]], fn[X[1]], fn[X[2]], fn[X[3]], L[0], L[1], L[2], L[3], nx, ny, nz);
    const int lanes = (1 << nl) - 1;
    const int valid_mask =
        lanes & _mm_movemask_ps(_mm_and_ps(_mm_cmpeq_ps(vx, vx), _mm_cmpeq_ps(nx, nx)));
    valid += __builtin_popcount(unsigned(valid_mask));
    if (!valid_mask) continue;
    // Projective association in the model camera.
    const __m128 pmx = rigidRow(Tm, vx, vy, vz), pmy = rigidRow(Tm + 4, vx, vy, vz),
                 pmz = rigidRow(Tm + 8, vx, vy, vz);
    __m128 ok = _mm_cmpgt_ps(pmz, zero);
    const __m128 iz = _mm_div_ps(one, pmz);
    const __m128 u = _mm_add_ps(_mm_mul_ps(_mm_mul_ps(fx, pmx), iz), cx);
    const __m128 vv = _mm_add_ps(_mm_mul_ps(_mm_mul_ps(fy, pmy), iz), cy);
    ok = _mm_and_ps(ok, _mm_and_ps(_mm_and_ps(_mm_cmpgt_ps(u, lo), _mm_cmpgt_ps(vv, lo)),
                                   _mm_and_ps(_mm_cmplt_ps(u, u_hi), _mm_cmplt_ps(vv, v_hi))));
    int mask = valid_mask & _mm_movemask_ps(ok);
    if (!mask) continue;
    alignas(16) int UI[4], VI[4];
    _mm_store_si128(reinterpret_cast<__m128i*>(UI), _mm_cvttps_epi32(_mm_add_ps(u, half)));
    _mm_store_si128(reinterpret_cast<__m128i*>(VI), _mm_cvttps_epi32(_mm_add_ps(vv, half)));
    // Lanes outside the mask read the first masked lane's model pixel (never used).
    const int l0 = __builtin_ctz(unsigned(mask));
    const Vec3f* q[4];
    const Vec3f* mn[4];
    bool M[4];
    for (int l = 0; l < 4; ++l) {
      const int ll = (mask >> l) & 1 ? l : l0;
      q[l] = &k.model_vertex(UI[ll], VI[ll]);
      mn[l] = &k.model_normal(UI[ll], VI[ll]);
      M[l] = UI[ll] == model_last_u && VI[ll] == model_last_v;
    }
    __m128 qx, qy, qz, mx, my, mz;
    gather3(*q[0], *q[1], *q[2], *q[3], M[0], M[1], M[2], M[3], qx, qy, qz);
    gather3(*mn[0], *mn[1], *mn[2], *mn[3], M[0], M[1], M[2], M[3], mx, my, mz);
    ok = _mm_and_ps(_mm_cmpeq_ps(qx, qx), _mm_cmpeq_ps(mx, mx));
    // Compatibility: distance and normal angle.
    const __m128 px = rigidRow(Tw, vx, vy, vz), py = rigidRow(Tw + 4, vx, vy, vz),
                 pz = rigidRow(Tw + 8, vx, vy, vz);
    const __m128 dx = _mm_sub_ps(px, qx), dy = _mm_sub_ps(py, qy), dz = _mm_sub_ps(pz, qz);
    ok = _mm_and_ps(
        ok,
        _mm_cmpngt_ps(sum3(_mm_mul_ps(dx, dx), _mm_mul_ps(dy, dy), _mm_mul_ps(dz, dz)), max_d2));
    const __m128 nwx = rigidRow(Tw, nx, ny, nz, false), nwy = rigidRow(Tw + 4, nx, ny, nz, false),
                 nwz = rigidRow(Tw + 8, nx, ny, nz, false);
    ok = _mm_and_ps(
        ok, _mm_cmpnlt_ps(sum3(_mm_mul_ps(nwx, mx), _mm_mul_ps(nwy, my), _mm_mul_ps(nwz, mz)),
                          min_cos));
    mask &= _mm_movemask_ps(ok);
    if (!mask) continue;
    const __m128 r = sum3(_mm_mul_ps(mx, dx), _mm_mul_ps(my, dy), _mm_mul_ps(mz, dz));
    const __m128 pcx = _mm_sub_ps(px, pvx), pcy = _mm_sub_ps(py, pvy), pcz = _mm_sub_ps(pz, pvz);
    const __m128 c0 = _mm_sub_ps(_mm_mul_ps(pcy, mz), _mm_mul_ps(pcz, my));
    const __m128 c1 = _mm_sub_ps(_mm_mul_ps(pcz, mx), _mm_mul_ps(pcx, mz));
    const __m128 c2 = _mm_sub_ps(_mm_mul_ps(pcx, my), _mm_mul_ps(pcy, mx));
    // IRLS weight: noise scale s = sigma(1 m) / sigma(z), then Huber on |r| s.
    __m128 s = one;
    if (k.depth_noise_weighting) {
      const __m128 d = _mm_sub_ps(vz, _mm_set1_ps(0.4f));
      s = _mm_div_ps(sigma1, _mm_add_ps(_mm_set1_ps(0.0012f),
                                        _mm_mul_ps(_mm_mul_ps(_mm_set1_ps(0.0019f), d), d)));
    }
    __m128 h = one;
    if (use_huber) {
      const __m128 ar = _mm_mul_ps(_mm_and_ps(r, abs_mask), s);
      const __m128 big = _mm_cmpgt_ps(ar, huber);
      h = _mm_or_ps(_mm_and_ps(big, _mm_div_ps(huber, ar)), _mm_andnot_ps(big, one));
    }
    const __m128 w = _mm_mul_ps(_mm_mul_ps(s, s), h);
    alignas(16) float VZ[4];
    _mm_store_ps(VZ, vz);
    for (int m = mask; m; m &= m - 1) depth_sum += VZ[__builtin_ctz(unsigned(m))];  // pixel order
    const __m128 J[6] = {mx, my, mz, c0, c1, c2};
    if (n <= kSegment - 4) {
      // The inliers of the four lanes, left-packed in pixel order (the kernel's loop), straight
      // into the buffers; the store's lanes past them are overwritten or never summed.
      const __m128i ctl = kLeftPack.ctl[mask];
      const auto pack = [&](__m128 v) {
        return _mm_castsi128_ps(_mm_shuffle_epi8(_mm_castps_si128(v), ctl));
      };
      for (int c = 0; c < 6; ++c) {
        _mm_storeu_ps(&Jb[c][n], pack(J[c]));
        _mm_storeu_ps(&wJb[c][n], pack(_mm_mul_ps(w, J[c])));
      }
      _mm_storeu_ps(&rb[n], pack(r));
      _mm_storeu_ps(&wb[n], pack(w));
      n += __builtin_popcount(unsigned(mask));
    } else {  // the segment's last slots: lane by lane
      alignas(16) float Jl[6][4], R[4], W[4];
      for (int c = 0; c < 6; ++c) _mm_store_ps(Jl[c], J[c]);
      _mm_store_ps(R, r);
      _mm_store_ps(W, w);
      for (int m = mask; m; m &= m - 1) {
        const int l = __builtin_ctz(unsigned(m));
        for (int c = 0; c < 6; ++c) {
          Jb[c][n] = Jl[c][l];
          wJb[c][n] = W[l] * Jl[c][l];
        }
        rb[n] = R[l];
        wb[n] = W[l];
        ++n;
      }
    }
  }
  kernels::accumulateSegment<kSegment>(Jb, wJb, rb, wb, n, valid, depth_sum, acc);
}

}  // namespace

kernels::IcpAccumulator reduceIcpCpu(const kernels::IcpReduceKernel& k) {
  if (k.model_confidence.data || !compute::simdEnabled(compute::SimdPath::IcpReduce))
    return compute::reduce1D<IcpAccumulator>(k.items(), k);
  return compute::reduce1D<IcpAccumulator>(k.items(), [&](int i, IcpAccumulator& acc) {
    reduceSegmentSse<IcpReduceKernel::kSegment>(k, i, acc);
  });
}

namespace {

/// ModelDownsampleKernel of the four output pixels x0..x0+3 of row y, all of whose 2x2 input
/// blocks lie inside the input: samples in the kernel's order (dy, dx), masked sums (adding +0
/// to a sum that started at +0 is exact), the same divisions.
void downsampleFour(const kernels::ModelDownsampleKernel& k, int x0, int y) {
  const int w = k.in_vertex.width, h = k.in_vertex.height;
  const float* m = k.T_model_world.m;
  const __m128 nan = _mm_set1_ps(compute::invalidFloat());
  __m128 vx[4], vy[4], vz[4], nx[4], ny[4], nz[4], z[4], ok[4];
  __m128 nearest = _mm_set1_ps(1e30f);
  for (int s = 0; s < 4; ++s) {
    const int dy = s >> 1, dx = s & 1, sy = 2 * y + dy;
    const Vec3f* vr = k.in_vertex.row(sy);
    const Vec3f* nr = k.in_normal.row(sy);
    int xs[4];
    bool last[4];
    for (int l = 0; l < 4; ++l) {
      xs[l] = 2 * (x0 + l) + dx;
      last[l] = sy == h - 1 && xs[l] == w - 1;
    }
    gather3(vr[xs[0]], vr[xs[1]], vr[xs[2]], vr[xs[3]], last[0], last[1], last[2], last[3], vx[s],
            vy[s], vz[s]);
    const bool nlast = sy == k.in_normal.height - 1;
    const int nw = k.in_normal.width - 1;
    gather3(nr[xs[0]], nr[xs[1]], nr[xs[2]], nr[xs[3]], nlast && xs[0] == nw, nlast && xs[1] == nw,
            nlast && xs[2] == nw, nlast && xs[3] == nw, nx[s], ny[s], nz[s]);
    ok[s] = _mm_and_ps(_mm_cmpeq_ps(vx[s], vx[s]), _mm_cmpeq_ps(nx[s], nx[s]));
    z[s] = rigidRow(m + 8, vx[s], vy[s], vz[s]);
    nearest = select(_mm_and_ps(ok[s], _mm_cmplt_ps(z[s], nearest)), z[s], nearest);
  }
  const __m128 any = _mm_or_ps(_mm_or_ps(ok[0], ok[1]), _mm_or_ps(ok[2], ok[3]));
  const __m128 max_diff = _mm_set1_ps(k.max_diff_m);
  __m128 sx = _mm_setzero_ps(), sy = sx, sz = sx, tx = sx, ty = sx, tz = sx, cnt = sx;
  for (int s = 0; s < 4; ++s) {
    const __m128 sel = _mm_and_ps(ok[s], _mm_cmple_ps(_mm_sub_ps(z[s], nearest), max_diff));
    sx = _mm_add_ps(sx, _mm_and_ps(sel, vx[s]));
    sy = _mm_add_ps(sy, _mm_and_ps(sel, vy[s]));
    sz = _mm_add_ps(sz, _mm_and_ps(sel, vz[s]));
    tx = _mm_add_ps(tx, _mm_and_ps(sel, nx[s]));
    ty = _mm_add_ps(ty, _mm_and_ps(sel, ny[s]));
    tz = _mm_add_ps(tz, _mm_and_ps(sel, nz[s]));
    cnt = _mm_add_ps(cnt, _mm_and_ps(sel, _mm_set1_ps(1.0f)));
  }
  const __m128 len = _mm_sqrt_ps(sum3(_mm_mul_ps(tx, tx), _mm_mul_ps(ty, ty), _mm_mul_ps(tz, tz)));
  const __m128 good = _mm_and_ps(any, _mm_cmpgt_ps(len, _mm_set1_ps(1e-6f)));
  const auto out = [&](__m128 a, __m128 d) { return select(good, _mm_div_ps(a, d), nan); };
  __m128 o0 = out(sx, cnt), o1 = out(sy, cnt), o2 = out(sz, cnt), o3 = nan;
  __m128 p0 = out(tx, len), p1 = out(ty, len), p2 = out(tz, len), p3 = nan;
  _MM_TRANSPOSE4_PS(o0, o1, o2, o3);
  _MM_TRANSPOSE4_PS(p0, p1, p2, p3);
  alignas(16) float V[4][4], N[4][4];
  _mm_store_ps(V[0], o0);
  _mm_store_ps(V[1], o1);
  _mm_store_ps(V[2], o2);
  _mm_store_ps(V[3], o3);
  _mm_store_ps(N[0], p0);
  _mm_store_ps(N[1], p1);
  _mm_store_ps(N[2], p2);
  _mm_store_ps(N[3], p3);
  Vec3f* ov = k.out_vertex.row(y) + x0;
  Vec3f* on = k.out_normal.row(y) + x0;
  for (int l = 0; l < 4; ++l) {
    ov[l] = Vec3f(V[l][0], V[l][1], V[l][2]);
    on[l] = Vec3f(N[l][0], N[l][1], N[l][2]);
  }
}

}  // namespace

void downsampleModelCpu(const kernels::ModelDownsampleKernel& k) {
  const int ow = k.out_vertex.width, oh = k.out_vertex.height;
  if (k.out_intensity.data || k.out_confidence.data ||
      !compute::simdEnabled(compute::SimdPath::ModelDownsample)) {
    compute::forEach2D(ow, oh, k);
    return;
  }
  // Output columns whose 2x2 blocks are whole: 2 x + 1 < input width (and rows likewise).
  const int full_cols = k.in_vertex.width / 2, full_rows = k.in_vertex.height / 2;
  const int groups = full_cols / 4;
  compute::forEach1D(oh, [&](int y) {
    int x = 0;
    if (y < full_rows)
      for (int g = 0; g < groups; ++g, x += 4) downsampleFour(k, x, y);
    for (; x < ow; ++x) k(x, y);
  });
}

}  // namespace rasm::tracking
