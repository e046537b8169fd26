#include "rasm/core/FrameProcessing.h"

#include "rasm/core/ComputeOptions.h"

#include <immintrin.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "rasm/core/kernels/FrameKernels.h"

namespace rasm {

void computeVertexMap(const Image<float>& depth_m, const CameraIntrinsics& K, Image<Vec3f>& vertex,
                      const VertexMapOptions& opt, compute::Backend backend) {
  if (backend == compute::Backend::Cuda) return cuda::computeVertexMap(depth_m, K, vertex, opt);
  const int w = depth_m.width(), h = depth_m.height();
  vertex.resize(w, h);
  const kernels::VertexMapKernel k{depth_m.view(), vertex.view(), K.plain(), opt.min_depth_m,
                                   opt.max_depth_m};
  compute::forEach2D(w, h, k);
}

void computeNormalMap(const Image<Vec3f>& vertex, Image<Vec3f>& normal, float max_jump_rel,
                      compute::Backend backend) {
  if (backend == compute::Backend::Cuda)
    return cuda::computeNormalMap(vertex, normal, max_jump_rel);
  const int w = vertex.width(), h = vertex.height();
  normal.resize(w, h);
  const kernels::NormalMapKernel k{vertex.view(), normal.view(), max_jump_rel};
  compute::forEach2D(w, h, k);
}

void downsampleDepth(const Image<float>& in, Image<float>& out, float max_diff_m) {
  out.resize((in.width() + 1) / 2, (in.height() + 1) / 2);
  kernels::DepthDownsampleKernel k{in.view(), out.view(), max_diff_m};
  compute::forEach2D(out.width(), out.height(), k);
}

namespace {

/// Lanes of v moved k (0..3) places up (towards lane 3) / down (towards lane 0), zeros shifted in.
template <int k>
inline __m128 lanesUp(__m128 v) {
  if constexpr (k == 0)
    return v;
  else
    return _mm_castsi128_ps(_mm_slli_si128(_mm_castps_si128(v), 4 * k));
}
template <int k>
inline __m128 lanesDown(__m128 v) {
  if constexpr (k == 0)
    return v;
  else
    return _mm_castsi128_ps(_mm_srli_si128(_mm_castps_si128(v), 4 * k));
}

/// The sums (w z and w) of one accumulator row for the group of four pixels being visited (cur)
/// and its two neighbouring groups: a pair at column offset dx lands in up to two groups.
struct GroupSums {
  __m128 prev_s, prev_w, cur_s, cur_w, next_s, next_w;
  void clear() { prev_s = prev_w = cur_s = cur_w = next_s = next_w = _mm_setzero_ps(); }
  /// Adds (s, w), lane l belonging to column x + l + dx of the group at x, |dx| <= 3.
  template <int dx>
  void add(__m128 s, __m128 w) {
    if constexpr (dx >= 0) {
      cur_s = _mm_add_ps(cur_s, lanesUp<dx>(s));
      cur_w = _mm_add_ps(cur_w, lanesUp<dx>(w));
      if constexpr (dx > 0) {
        next_s = _mm_add_ps(next_s, lanesDown<4 - dx>(s));
        next_w = _mm_add_ps(next_w, lanesDown<4 - dx>(w));
      }
    } else {
      cur_s = _mm_add_ps(cur_s, lanesDown<-dx>(s));
      cur_w = _mm_add_ps(cur_w, lanesDown<-dx>(w));
      prev_s = _mm_add_ps(prev_s, lanesUp<4 + dx>(s));
      prev_w = _mm_add_ps(prev_w, lanesUp<4 + dx>(w));
    }
  }
};

/// The forward half of the radius-R window (dy > 0, or dy = 0 and dx > 0), row by row.
struct Offset {
  int dx, dy;
};
template <int R>
constexpr int forwardCount() {
  int n = 0;
  for (int dy = 0; dy <= R; ++dy)
    for (int dx = -R; dx <= R; ++dx) n += (dy > 0 || dx > 0) && dx * dx + dy * dy <= R * R;
  return n;
}
template <int R>
constexpr std::array<Offset, forwardCount<R>()> forwardOffsets() {
  std::array<Offset, forwardCount<R>()> o{};
  int n = 0;
  for (int dy = 0; dy <= R; ++dy)
    for (int dx = -R; dx <= R; ++dx)
      if ((dy > 0 || dx > 0) && dx * dx + dy * dy <= R * R) o[n++] = {dx, dy};
  return o;
}

/// The forward pairs of one group of four pixels zp (valid lanes pv) at column x: each adds its
/// weight to the group's sums (sum, wsum) and, in GroupSums, to its neighbour's.
template <int R>
struct PairSums {
  const float* const* zq_rows;  ///< padded input rows y .. y + R
  int x;
  __m128 zp, pv;
  const __m128* space;
  __m128 v_id2;
  __m128& sum;
  __m128& wsum;
  GroupSums* g;

  template <std::size_t K>
  void pair() {
    constexpr Offset o = forwardOffsets<R>()[K];
    const __m128 zq = _mm_loadu_ps(zq_rows[o.dy] + x + o.dx);
    __m128 wt = static_cast<__m128>(kernels::bilateralWeight(
        lanes::F4(space[K]), lanes::F4(_mm_sub_ps(zq, zp)), lanes::F4(v_id2)));
    wt = _mm_and_ps(wt, _mm_and_ps(pv, _mm_cmpgt_ps(zq, _mm_setzero_ps())));
    sum = _mm_add_ps(sum, _mm_mul_ps(wt, zq));
    wsum = _mm_add_ps(wsum, wt);
    g[o.dy].template add<o.dx>(_mm_mul_ps(wt, zp), wt);  // q's share
  }
  template <std::size_t... K>
  void all(std::index_sequence<K...>) {
    (pair<K>(), ...);
  }
};

/// One band of rows [lo, hi) of the pair-symmetric bilateral filter (bilateralFilterDepth):
/// pixel rows of the padded input `prow(y)`, sums in rows of `acc` (R + 1 slots of 2 x aw floats).
template <int R, typename RowOf>
void bilateralBand(const RowOf& prow, Image<float>& out, int lo, int hi, int w4,
                   float sigma_space_px, float sigma_depth_m, std::vector<float>& acc) {
  constexpr auto taps = forwardOffsets<R>();
  constexpr int kTaps = int(taps.size());
  // Weight = kernels::bilateralWeight(space[k], dz, id2), its terms in log2 units.
  __m128 space[kTaps + 1];
  for (int k = 0; k < kTaps; ++k)
    space[k] = _mm_set1_ps(kernels::bilateralSpaceLog2(
        taps[k].dx * taps[k].dx + taps[k].dy * taps[k].dy, sigma_space_px));
  const __m128 v_id2 = _mm_set1_ps(kernels::bilateralDepthLog2(sigma_depth_m));
  const __m128 v_zero = _mm_setzero_ps(), v_one = _mm_set1_ps(1.0f);
  const int w = out.width(), aw = w4 + 8, slots = R + 1;
  acc.assign(std::size_t(2) * slots * aw, 0.0f);
  // Accumulator columns x (-4 <= x < w4 + 4) of image row y; 16-byte aligned at x % 4 == 0.
  const auto sums = [&](int y) { return acc.data() + std::size_t(2) * (y % slots) * aw + 4; };
  const auto addTo = [](float* p, __m128 v) { _mm_store_ps(p, _mm_add_ps(_mm_load_ps(p), v)); };
  GroupSums g[R + 1];  // per row offset dy = 0..R
  // Rows lo - R .. lo - 1 only add their pairs' weights to the band's first rows.
  for (int y = std::max(0, lo - R); y < hi; ++y) {
    const float* zp_row = prow(y);
    const float* zq_rows[R + 1];
    for (int dy = 0; dy <= R; ++dy) {
      g[dy].clear();
      zq_rows[dy] = prow(y + dy);
    }
    for (int x = 0; x < w4; x += 4) {
      for (int dy = 0; dy <= R; ++dy) {  // the group at x - 8 is complete: add it, shift
        GroupSums& q = g[dy];
        if (x >= 4) {
          float* s_row = sums(y + dy);
          addTo(s_row + x - 8, q.prev_s);
          addTo(s_row + aw + x - 8, q.prev_w);
        }
        q.prev_s = q.cur_s;
        q.prev_w = q.cur_w;
        q.cur_s = q.next_s;
        q.cur_w = q.next_w;
        q.next_s = q.next_w = v_zero;
      }
      const __m128 zp = _mm_loadu_ps(zp_row + x);
      const __m128 pv = _mm_cmpgt_ps(zp, v_zero);
      // The centre tap: weight exp(0) = 1.
      __m128 sum = _mm_and_ps(zp, pv), wsum = _mm_and_ps(v_one, pv);
      PairSums<R> ps{zq_rows, x, zp, pv, space, v_id2, sum, wsum, g};
      ps.all(std::make_index_sequence<kTaps>{});
      g[0].cur_s = _mm_add_ps(g[0].cur_s, sum);
      g[0].cur_w = _mm_add_ps(g[0].cur_w, wsum);
    }
    for (int dy = 0; dy <= R; ++dy) {  // the last groups
      const GroupSums& q = g[dy];
      float* s_row = sums(y + dy);
      if (w4 >= 8) {
        addTo(s_row + w4 - 8, q.prev_s);
        addTo(s_row + aw + w4 - 8, q.prev_w);
      }
      addTo(s_row + w4 - 4, q.cur_s);
      addTo(s_row + aw + w4 - 4, q.cur_w);
      addTo(s_row + w4, q.next_s);
      addTo(s_row + aw + w4, q.next_w);
    }
    // Row y has all its pairs now (rows y - R .. y): write it, then reuse its slot for y + R + 1.
    float* sp = sums(y);
    const float* wp = sp + aw;
    if (y >= lo) {
      float* o = out.row(y);
      int x = 0;
      for (; x + 3 < w; x += 4) {
        const __m128 zp = _mm_loadu_ps(zp_row + x);
        // Invalid centres: 0 (their wsum is 0; the division's NaN is masked away).
        _mm_storeu_ps(o + x, _mm_and_ps(_mm_div_ps(_mm_load_ps(sp + x), _mm_load_ps(wp + x)),
                                        _mm_cmpgt_ps(zp, v_zero)));
      }
      for (; x < w; ++x) o[x] = zp_row[x] > 0.0f ? sp[x] / wp[x] : 0.0f;
    }
    std::fill(sp - 4, sp - 4 + 2 * aw, 0.0f);
  }
}

}  // namespace

void bilateralFilterDepth(const Image<float>& in, Image<float>& out, int radius,
                          float sigma_space_px, float sigma_depth_m) {
  if (&in == &out) throw std::invalid_argument("bilateralFilterDepth: in and out must differ");
  if (radius < 0 || radius > 3 || !(sigma_space_px > 0.0f) || !(sigma_depth_m > 0.0f))
    throw std::invalid_argument("bilateralFilterDepth: radius must be 0..3 (got " +
                                std::to_string(radius) + ") and both sigmas > 0");
  const int w = in.width(), h = in.height();
  out.resize(w, h);
  if (w == 0 || h == 0) return;
  if (!compute::simdEnabled(compute::SimdPath::BilateralFilter)) {  // the CUDA path's kernel
    const kernels::BilateralDepthKernel k{in.view(), out.view(), radius, sigma_space_px,
                                          sigma_depth_m};
    return compute::forEach2D(w, h, k);
  }
  // BilateralDepthKernel's filter (the CUDA path's): a circular window (dx^2 + dy^2 <= radius^2,
  // as OpenCV's bilateralFilter: 13 taps at radius 2), weights exp(-(dx^2 + dy^2) / 2 sigma_s^2 -
  // dz^2 / 2 sigma_d^2) over the VALID neighbours inside the image; invalid pixels (depth <= 0 or
  // NaN) stay 0. The weight of a pair of pixels is symmetric, so each pair is weighted once:
  // pixel p visits the forward half of the window (dy > 0, or dy = 0 and dx > 0) and adds the
  // weight to its own sums and to its neighbour q's, which halves the exponentials (6 instead of
  // 13 per pixel at radius 2). Four pixels per SSE operation; the sums of the rows a group reaches
  // are gathered in registers (GroupSums) and added to the band's accumulator rows once per group
  // and row, aligned (overlapping unaligned read-modify-writes stalled on store forwarding). The
  // sums' order differs from the kernel's, within float rounding; it does not depend on the
  // thread count. Why not OpenCV's bilateralFilter: docs/history/slam-eval.md (its TBB threads
  // competed with the OpenMP team).
  //
  // Padded copy, invalid depths as 0: `radius` rows above and below, `radius` columns left and
  // at least radius + 3 right, so that every group of four pixels reads inside it.
  const int r = radius, w4 = (w + 3) & ~3, pw = (w4 + 2 * r + 3) & ~3, ph = h + 2 * r;
  thread_local std::vector<float> padded;  // (the calling thread's; the team uses `pad`)
  padded.resize(std::size_t(pw) * ph);
  float* const pad = padded.data();
  const auto prow = [pad, pw, r](int y) {
    return pad + std::size_t(y + r) * pw + r;
  };                                                                           // image row y
  std::fill(pad, pad + std::size_t(r) * pw, 0.0f);                             // rows above
  std::fill(pad + std::size_t(h + r) * pw, pad + std::size_t(ph) * pw, 0.0f);  // rows below
  compute::forEach1D(h, [&](int y) {
    const float* src = in.row(y);
    float* dst = prow(y);
    std::fill(dst - r, dst, 0.0f);  // columns left and right
    std::fill(dst + w, dst - r + pw, 0.0f);
    for (int x = 0; x < w; ++x) dst[x] = src[x] > 0.0f ? src[x] : 0.0f;
  });
  const int nt = compute::maxThreads();
  const int nbands = nt <= 1 ? 1 : std::min(h, 4 * nt);
  compute::forEach1D(nbands, [&](int b) {
    const int lo = int(std::int64_t(h) * b / nbands), hi = int(std::int64_t(h) * (b + 1) / nbands);
    thread_local std::vector<float> acc;  // this thread's accumulator rows
    switch (r) {
      case 0:
        return bilateralBand<0>(prow, out, lo, hi, w4, sigma_space_px, sigma_depth_m, acc);
      case 1:
        return bilateralBand<1>(prow, out, lo, hi, w4, sigma_space_px, sigma_depth_m, acc);
      case 2:
        return bilateralBand<2>(prow, out, lo, hi, w4, sigma_space_px, sigma_depth_m, acc);
      default:
        return bilateralBand<3>(prow, out, lo, hi, w4, sigma_space_px, sigma_depth_m, acc);
    }
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
void computeVertexMap(const Image<float>&, const CameraIntrinsics&, Image<Vec3f>&,
                      const VertexMapOptions&) {
  throw std::runtime_error("rasm was built without CUDA (RASM_WITH_CUDA=OFF or no nvcc)");
}
void computeNormalMap(const Image<Vec3f>&, Image<Vec3f>&, float) {
  throw std::runtime_error("rasm was built without CUDA (RASM_WITH_CUDA=OFF or no nvcc)");
}
}  // namespace cuda
#endif

}  // namespace rasm
