#include "rasm/core/FrameProcessing.h"

#include <immintrin.h>

#include <cmath>
#include <stdexcept>
#include <vector>

#include "rasm/core/kernels/FrameKernels.h"

namespace rasm {

void computeVertexMap(const Image<float>& depth_m, const CameraIntrinsics& K, Image<Vec3f>& vertex,
                      const VertexMapOptions& opt, compute::Backend backend) {
  if (backend == compute::Backend::Cuda) return cuda::computeVertexMap(depth_m, K, vertex, opt);
  vertex.resize(depth_m.width(), depth_m.height());
  kernels::VertexMapKernel k{depth_m.view(), vertex.view(), K.plain(), opt.min_depth_m, opt.max_depth_m};
  compute::forEach2D(depth_m.width(), depth_m.height(), k);
}

namespace {

/// x, y and z of the four consecutive Vec3f at p (12 floats, any alignment).
struct Vec3x4 {
  __m128 x, y, z;
};
inline Vec3x4 load4(const Vec3f* p) {
  const float* f = p->data();
  const __m128 a = _mm_loadu_ps(f), b = _mm_loadu_ps(f + 4), c = _mm_loadu_ps(f + 8);
  // a = x0 y0 z0 x1, b = y1 z1 x2 y2, c = z2 x3 y3 z3
  const __m128 bc = _mm_shuffle_ps(b, c, _MM_SHUFFLE(1, 0, 3, 2));  // x2 y2 z2 x3
  Vec3x4 v;
  v.x = _mm_shuffle_ps(a, bc, _MM_SHUFFLE(3, 0, 3, 0));
  v.y = _mm_shuffle_ps(_mm_shuffle_ps(a, b, _MM_SHUFFLE(0, 0, 1, 1)),
                       _mm_shuffle_ps(b, c, _MM_SHUFFLE(2, 2, 3, 3)), _MM_SHUFFLE(2, 0, 2, 0));
  v.z = _mm_shuffle_ps(_mm_shuffle_ps(a, b, _MM_SHUFFLE(1, 1, 2, 2)),
                       _mm_shuffle_ps(c, c, _MM_SHUFFLE(3, 3, 0, 0)), _MM_SHUFFLE(2, 0, 2, 0));
  return v;
}

/// NormalMapKernel on pixels x .. x + 3 of an inner row (1 <= x, x + 3 <= width - 2): the same
/// float operations in the same order per lane as the kernel (Eigen's cross, and its 3-term
/// sums as a0 + (a1 + a2)), so the normals are bit-identical.
inline void normals4(const Vec3f* up, const Vec3f* row, const Vec3f* down, int x, float max_jump_rel,
                     Vec3f* out) {
  const Vec3x4 c = load4(row + x), l = load4(row + x - 1), r = load4(row + x + 1),
               u = load4(up + x), d = load4(down + x);
  __m128 ok = _mm_and_ps(_mm_and_ps(_mm_cmpeq_ps(c.x, c.x), _mm_cmpeq_ps(l.x, l.x)),
                         _mm_and_ps(_mm_cmpeq_ps(r.x, r.x), _mm_and_ps(_mm_cmpeq_ps(u.x, u.x),
                                                                       _mm_cmpeq_ps(d.x, d.x))));
  const __m128 abs_mask = _mm_castsi128_ps(_mm_set1_epi32(0x7fffffff));
  const __m128 lim = _mm_mul_ps(_mm_set1_ps(max_jump_rel), c.z);
  const auto within = [&](__m128 z) {
    return _mm_cmple_ps(_mm_and_ps(_mm_sub_ps(z, c.z), abs_mask), lim);
  };
  ok = _mm_and_ps(ok, _mm_and_ps(_mm_and_ps(within(l.z), within(r.z)),
                                 _mm_and_ps(within(u.z), within(d.z))));
  const __m128 ax = _mm_sub_ps(r.x, l.x), ay = _mm_sub_ps(r.y, l.y), az = _mm_sub_ps(r.z, l.z);
  const __m128 bx = _mm_sub_ps(d.x, u.x), by = _mm_sub_ps(d.y, u.y), bz = _mm_sub_ps(d.z, u.z);
  __m128 nx = _mm_sub_ps(_mm_mul_ps(ay, bz), _mm_mul_ps(az, by));
  __m128 ny = _mm_sub_ps(_mm_mul_ps(az, bx), _mm_mul_ps(ax, bz));
  __m128 nz = _mm_sub_ps(_mm_mul_ps(ax, by), _mm_mul_ps(ay, bx));
  const __m128 len = _mm_sqrt_ps(
      _mm_add_ps(_mm_mul_ps(nx, nx), _mm_add_ps(_mm_mul_ps(ny, ny), _mm_mul_ps(nz, nz))));
  ok = _mm_and_ps(ok, _mm_cmpgt_ps(len, _mm_setzero_ps()));
  nx = _mm_div_ps(nx, len);
  ny = _mm_div_ps(ny, len);
  nz = _mm_div_ps(nz, len);
  const __m128 dot =
      _mm_add_ps(_mm_mul_ps(nx, c.x), _mm_add_ps(_mm_mul_ps(ny, c.y), _mm_mul_ps(nz, c.z)));
  const __m128 flip = _mm_and_ps(_mm_cmpgt_ps(dot, _mm_setzero_ps()), _mm_set1_ps(-0.0f));
  const __m128 nan = _mm_set1_ps(compute::invalidFloat());
  const auto pick = [&](__m128 v) {
    return _mm_or_ps(_mm_and_ps(ok, _mm_xor_ps(v, flip)), _mm_andnot_ps(ok, nan));
  };
  alignas(16) float X[4], Y[4], Z[4];
  _mm_store_ps(X, pick(nx));
  _mm_store_ps(Y, pick(ny));
  _mm_store_ps(Z, pick(nz));
  for (int k = 0; k < 4; ++k) out[x + k] = Vec3f(X[k], Y[k], Z[k]);
}

}  // namespace

void computeNormalMap(const Image<Vec3f>& vertex, Image<Vec3f>& normal, float max_jump_rel,
                      compute::Backend backend) {
  if (backend == compute::Backend::Cuda) return cuda::computeNormalMap(vertex, normal, max_jump_rel);
  const int w = vertex.width(), h = vertex.height();
  normal.resize(w, h);
  const kernels::NormalMapKernel k{vertex.view(), normal.view(), max_jump_rel};
  // The kernel at the borders and row ends, four pixels per SSE operation in between (the
  // level-0 normal map took ~20 ns per pixel through the kernel, branching on every test).
  compute::forEach1D(h, [&](int y) {
    if (y < 1 || y >= h - 1) {
      for (int x = 0; x < w; ++x) k(x, y);
      return;
    }
    const Vec3f *up = vertex.row(y - 1), *row = vertex.row(y), *down = vertex.row(y + 1);
    Vec3f* out = normal.row(y);
    k(0, y);
    int x = 1;
    for (; x + 3 <= w - 2; x += 4) normals4(up, row, down, x, max_jump_rel, out);
    for (; x < w; ++x) k(x, y);
  });
}

void downsampleDepth(const Image<float>& in, Image<float>& out, float max_diff_m) {
  out.resize((in.width() + 1) / 2, (in.height() + 1) / 2);
  kernels::DepthDownsampleKernel k{in.view(), out.view(), max_diff_m};
  compute::forEach2D(out.width(), out.height(), k);
}

namespace {

/// 2^t for t <= 0, four lanes: t = n + f with n = round(t), f in [-0.5, 0.5], 2^f by its
/// degree-5 Taylor polynomial (relative error < 3e-6, plenty for filter weights); t below -126
/// gives 2^-126, not 0.
inline __m128 exp2NonPositive(__m128 t) {
  t = _mm_max_ps(t, _mm_set1_ps(-126.0f));
  const __m128 n = _mm_round_ps(t, _MM_FROUND_TO_NEAREST_INT | _MM_FROUND_NO_EXC);
  const __m128 f = _mm_sub_ps(t, n);
  __m128 p = _mm_set1_ps(1.5403530e-4f);
  p = _mm_add_ps(_mm_mul_ps(p, f), _mm_set1_ps(1.3333558e-3f));
  p = _mm_add_ps(_mm_mul_ps(p, f), _mm_set1_ps(9.6181291e-3f));
  p = _mm_add_ps(_mm_mul_ps(p, f), _mm_set1_ps(5.5504109e-2f));
  p = _mm_add_ps(_mm_mul_ps(p, f), _mm_set1_ps(2.4022651e-1f));
  p = _mm_add_ps(_mm_mul_ps(p, f), _mm_set1_ps(6.9314718e-1f));
  p = _mm_add_ps(_mm_mul_ps(p, f), _mm_set1_ps(1.0f));
  const __m128i e = _mm_slli_epi32(_mm_add_epi32(_mm_cvtps_epi32(n), _mm_set1_epi32(127)), 23);
  return _mm_mul_ps(p, _mm_castsi128_ps(e));
}

constexpr double kLog2e = 1.4426950408889634;

struct BilateralTap {
  int dx, dy;
  float space_log2;  ///< (dx^2 + dy^2) / (2 sigma_s^2) * log2(e): weight = 2^-(space + range)
};

}  // namespace

void bilateralFilterDepth(const Image<float>& in, Image<float>& out, int radius, float sigma_space_px,
                          float sigma_depth_m) {
  if (&in == &out) throw std::invalid_argument("bilateralFilterDepth: in and out must differ");
  if (radius < 0 || !(sigma_space_px > 0.0f) || !(sigma_depth_m > 0.0f))
    throw std::invalid_argument("bilateralFilterDepth: radius must be >= 0 and both sigmas > 0");
  const int w = in.width(), h = in.height();
  out.resize(w, h);
  // BilateralDepthKernel's filter (the CUDA path's), four pixels per SSE operation: a circular
  // window (dx^2 + dy^2 <= radius^2, as OpenCV's bilateralFilter: 13 taps at radius 2), weights
  // exp(-(dx^2 + dy^2) / 2 sigma_s^2 - dz^2 / 2 sigma_d^2) over the VALID neighbours inside the
  // image; invalid pixels (depth <= 0 or NaN) stay 0. OpenCV's filter (used before) ran 9-13 ms
  // per 640x480 frame on TBB threads that competed with the OpenMP team; this one ~5 ms on 2
  // threads (docs/slam-eval.md, round 4).
  std::vector<BilateralTap> taps;
  for (int dy = -radius; dy <= radius; ++dy)
    for (int dx = -radius; dx <= radius; ++dx)
      if (dx * dx + dy * dy <= radius * radius)
        taps.push_back({dx, dy, float(double(dx * dx + dy * dy) /
                                      (2.0 * double(sigma_space_px) * sigma_space_px) * kLog2e)});
  const float id2_log2 = float(kLog2e / (2.0 * double(sigma_depth_m) * sigma_depth_m));
  const __m128 v_id2 = _mm_set1_ps(id2_log2), v_zero = _mm_setzero_ps();
  // One tap: w = exp(-s - dz^2 / 2 sigma_d^2) = 2^-(s log2 e + dz^2 log2 e / 2 sigma_d^2) for
  // valid neighbour depths z, added to sum (w z) and wsum (w).
  const auto addTap = [&](const BilateralTap& t, __m128 z, __m128 vc, __m128& sum, __m128& wsum) {
    const __m128 dz = _mm_sub_ps(z, vc);
    __m128 wt = exp2NonPositive(
        _mm_sub_ps(_mm_set1_ps(-t.space_log2), _mm_mul_ps(_mm_mul_ps(dz, dz), v_id2)));
    wt = _mm_and_ps(wt, _mm_cmpgt_ps(z, v_zero));
    sum = _mm_add_ps(sum, _mm_mul_ps(wt, z));
    wsum = _mm_add_ps(wsum, wt);
  };
  // One pixel (any position): the same arithmetic on lane 0, taps outside the image skipped.
  const auto pixel = [&](int x, int y) {
    const float c = in(x, y);
    if (!(c > 0.0f)) return 0.0f;
    const __m128 vc = _mm_set1_ps(c);
    __m128 sum = v_zero, wsum = v_zero;
    for (const BilateralTap& t : taps) {
      const int sx = x + t.dx, sy = y + t.dy;
      if (sx < 0 || sy < 0 || sx >= w || sy >= h) continue;
      addTap(t, _mm_set1_ps(in(sx, sy)), vc, sum, wsum);
    }
    return _mm_cvtss_f32(_mm_div_ps(sum, wsum));
  };
  const int x_lo = std::min(radius, w), x_hi = std::max(x_lo, w - radius);  // interior columns
  compute::forEach1D(h, [&](int y) {
    float* o = out.row(y);
    if (y < radius || y >= h - radius) {
      for (int x = 0; x < w; ++x) o[x] = pixel(x, y);
      return;
    }
    int x = 0;
    for (; x < x_lo; ++x) o[x] = pixel(x, y);
    for (; x + 3 < x_hi; x += 4) {
      const __m128 vc = _mm_loadu_ps(in.row(y) + x);
      __m128 sum = v_zero, wsum = v_zero;
      for (const BilateralTap& t : taps)
        addTap(t, _mm_loadu_ps(in.row(y + t.dy) + x + t.dx), vc, sum, wsum);
      // Invalid centres: 0 (their wsum may be 0; the division's NaN is masked away).
      _mm_storeu_ps(o + x, _mm_and_ps(_mm_div_ps(sum, wsum), _mm_cmpgt_ps(vc, v_zero)));
    }
    for (; x < w; ++x) o[x] = pixel(x, y);
  });
}

void buildFramePyramid(const Image<float>& depth_m, const CameraIntrinsics& K, int levels,
                       std::vector<FrameLevel>& pyramid, const VertexMapOptions& opt) {
  pyramid.resize(levels);
  for (int l = 0; l < levels; ++l) {
    FrameLevel& L = pyramid[l];
    L.K = K.level(l);
    if (l == 0)
      L.depth_m = depth_m;
    else
      downsampleDepth(pyramid[l - 1].depth_m, L.depth_m);
    computeVertexMap(L.depth_m, L.K, L.vertex, opt);
    computeNormalMap(L.vertex, L.normal);
  }
}

#ifndef RASM_HAVE_CUDA
namespace cuda {
void computeVertexMap(const Image<float>&, const CameraIntrinsics&, Image<Vec3f>&, const VertexMapOptions&) {
  throw std::runtime_error("rasm was built without CUDA (RASM_WITH_CUDA=OFF or no nvcc)");
}
void computeNormalMap(const Image<Vec3f>&, Image<Vec3f>&, float) {
  throw std::runtime_error("rasm was built without CUDA (RASM_WITH_CUDA=OFF or no nvcc)");
}
}  // namespace cuda
#endif

}  // namespace rasm
