#include "rasm/fusion/FusionCpu.h"

#include "rasm/compute/Sse.h"

#include <cstring>
#include <limits>

namespace rasm::fusion {

namespace {

using sse::gather3;

/// x, y, z planes of the Vec3f of four columns xs[] of an image row.
/// (Only the last element of the last row, column last_x, has no 4 bytes after it; -1 none.)
inline void gatherRow(const Vec3f* row, const int* xs, int last_x, __m128& x, __m128& y,
                      __m128& z) {
  gather3(row[xs[0]], row[xs[1]], row[xs[2]], row[xs[3]], xs[0] == last_x, xs[1] == last_x,
          xs[2] == last_x, xs[3] == last_x, x, y, z);
}

/// The view bins (V-B) of four lanes: updateViewBin's maps::kernels::viewBinOfCamera over four
/// surfels. bin[l], or -1 where the camera sits on the surfel; dist[l] the camera distance.
void viewBins4(const kernels::FusionKernelParams& prm, const RigidF& T_world_cam,
               const lanes::LaneVec3<lanes::F4>& p, const lanes::LaneVec3<lanes::F4>& n,
               const lanes::LaneVec3<lanes::F4>& b, int bin[4], float dist[4]) {
  using lanes::F4;
  F4 d;
  const F4 bins = maps::kernels::viewBinOfCamera(p, n, b, T_world_cam.translation(), prm.n_azimuth,
                                                 prm.n_elevation, d);
  lanes::storeInt(bin, bins);
  lanes::store(dist, d);
}

/// kernels::updateViewBinAt, with the exponential skipped where it cannot raise the bin.
inline void updateViewBinAtCpu(const maps::SurfelArrays& s, int i, int bin, float dist,
                               const kernels::FusionKernelParams& prm,
                               const ViewInfoThresholds* ic) {
  if (ic) {
    const std::uint8_t v = s.viewRow(i)[bin];
    if (v == 255 || dist >= ic->below[v]) return;  // (a NaN distance takes the kernel's path)
  }
  kernels::updateViewBinAt(s, i, bin, dist, prm);
}

/// UpdateKernel::update of the surfels of n (1..4) pixels xs[] of row y: the geometry on four
/// lanes (lanes >= n repeat lane 0 and are not stored), the rest per lane (UpdateKernel::store).
void updateFour(const kernels::UpdateKernel& k, int y, const int* xs, int n,
                const KeptMeasurement* kept, const ViewInfoThresholds* ic) {
  const maps::SurfelArrays& s = k.s;
  const std::int32_t* ps = k.pixel_surfel.row(y);
  int idx[4];
  for (int l = 0; l < 4; ++l) idx[l] = ps[xs[l < n ? l : 0]];
  // Measurements: [v.x v.y v.z nw.x] and [nw.y nw.z w r] per lane.
  const KeptMeasurement* m[4];
  for (int l = 0; l < 4; ++l) m[l] = &kept[xs[l < n ? l : 0]];
  __m128 vx = _mm_load_ps(&m[0]->v.x()), vy = _mm_load_ps(&m[1]->v.x()),
         vz = _mm_load_ps(&m[2]->v.x()), nwx = _mm_load_ps(&m[3]->v.x());
  _MM_TRANSPOSE4_PS(vx, vy, vz, nwx);
  __m128 nwy = _mm_load_ps(&m[0]->n_world.y()), nwz = _mm_load_ps(&m[1]->n_world.y()),
         w = _mm_load_ps(&m[2]->n_world.y()), r = _mm_load_ps(&m[3]->n_world.y());
  _MM_TRANSPOSE4_PS(nwy, nwz, w, r);
  // Surfels: position + confidence, normal + radius, basis.
  __m128 px = _mm_load_ps(s.pos_conf[idx[0]].data()), py = _mm_load_ps(s.pos_conf[idx[1]].data()),
         pz = _mm_load_ps(s.pos_conf[idx[2]].data()), c = _mm_load_ps(s.pos_conf[idx[3]].data());
  _MM_TRANSPOSE4_PS(px, py, pz, c);
  __m128 nx = _mm_load_ps(s.normal_radius[idx[0]].data()),
         ny = _mm_load_ps(s.normal_radius[idx[1]].data()),
         nz = _mm_load_ps(s.normal_radius[idx[2]].data()),
         rs = _mm_load_ps(s.normal_radius[idx[3]].data());
  _MM_TRANSPOSE4_PS(nx, ny, nz, rs);
  __m128 b[4];
  for (int l = 0; l < 4; ++l) {
    const Vec3f& bl = s.basis[idx[l]];
    // One unaligned load reads 4 bytes past the element: inside the array unless it is the last.
    b[l] = idx[l] + 1 < s.size ? _mm_loadu_ps(bl.data()) : _mm_setr_ps(bl.x(), bl.y(), bl.z(), 0.f);
  }
  __m128 bx = b[0], by = b[1], bz = b[2], bw = b[3];
  _MM_TRANSPOSE4_PS(bx, by, bz, bw);

  using lanes::F4;
  const kernels::SurfelGeometryUpdate<F4> u = kernels::averageSurfelGeometry<F4>(
      k.prm, k.T_world_cam, {F4(vx), F4(vy), F4(vz)}, {F4(nwx), F4(nwy), F4(nwz)}, F4(w), F4(r),
      {F4(px), F4(py), F4(pz)}, F4(c), {F4(nx), F4(ny), F4(nz)}, F4(rs), {F4(bx), F4(by), F4(bz)});
  const int fused = lanes::bits(u.fuse), crossed = lanes::bits(u.crossed),
            basis_ok = lanes::bits(u.basis_ok);
  alignas(16) float P[3][4], N[4][4], B[3][4], A[2][4], C[4], W[4];
  lanes::store(P[0], u.p.x);
  lanes::store(P[1], u.p.y);
  lanes::store(P[2], u.p.z);
  lanes::store(N[0], u.ns.x);
  lanes::store(N[1], u.ns.y);
  lanes::store(N[2], u.ns.z);
  lanes::store(N[3], u.rs);
  lanes::store(B[0], u.b.x);
  lanes::store(B[1], u.b.y);
  lanes::store(B[2], u.b.z);
  lanes::store(A[0], u.a0);
  lanes::store(A[1], u.a1);
  _mm_store_ps(C, c);
  _mm_store_ps(W, w);
  // View bins on four lanes.
  const bool bins = k.prm.update_view_bins && s.n_view_bins > 0;
  int bin[4];
  float dist[4];
  if (bins) viewBins4(k.prm, k.T_world_cam, u.p, u.ns, u.b, bin, dist);
  for (int l = 0; l < n; ++l) {
    const int x = xs[l], i = idx[l];
    std::uint16_t f = k.flags(x, y);
    std::uint32_t cf = s.colour_flags[i];
    const Vec3f ns(N[0][l], N[1][l], N[2][l]);
    Vec3f bl(B[0][l], B[1][l], B[2][l]);
    if ((fused >> l) & 1) {
      cf = k.blendColour(x, y, cf, A[0][l], A[1][l]);
      if (!((basis_ok >> l) & 1)) bl = maps::kernels::updateBasis(ns, s.basis[i]);  // fallback
      f |= kernels::kPixFused;
      if ((crossed >> l) & 1) f |= kernels::kPixCrossedBlock;
    }
    const Vec3f p(P[0][l], P[1][l], P[2][l]);
    k.store(x, y, i, W[l], C[l], p, ns, N[3][l], bl, cf, f, m[l]->v.z());
    // (a basis from the fallback is not the lanes' one: that surfel's bin is computed again)
    if (bins && !(((fused & ~basis_ok) >> l) & 1)) {
      if (bin[l] >= 0) updateViewBinAtCpu(s, i, bin[l], dist[l], k.prm, ic);
    } else {
      kernels::updateViewBin(s, i, p, ns, bl, k.T_world_cam.translation(), k.prm);
    }
  }
}

}  // namespace

int measureFour(const kernels::FrameView& fv, const kernels::FusionKernelParams& prm,
                const RigidF& T_world_cam, int y, const int xs[4], int nl,
                kernels::PixelMeasurement m[4]) {
  const int w = fv.vertex_cam.width;
  // Only the last element of the last row has no 4 bytes after it inside the image.
  const int last_v = y == fv.vertex_cam.height - 1 ? w - 1 : -1;
  const int last_n = y == fv.normal_cam.height - 1 ? fv.normal_cam.width - 1 : -1;
  __m128 vx, vy, vz, nx, ny, nz;
  gatherRow(fv.vertex_cam.row(y), xs, last_v, vx, vy, vz);
  gatherRow(fv.normal_cam.row(y), xs, last_n, nx, ny, nz);
  using lanes::F4;
  const lanes::LaneVec3<F4> v{F4(vx), F4(vy), F4(vz)}, n{F4(nx), F4(ny), F4(nz)};
  const int valid = lanes::bits(kernels::measurable(prm, v, n)) & ((1 << nl) - 1);
  if (!valid) return 0;
  const float* wrow = fv.weight.row(y);
  const __m128 wt = nl == 4 && xs[3] == xs[0] + 3
                        ? _mm_loadu_ps(wrow + xs[0])
                        : _mm_setr_ps(wrow[xs[0]], wrow[xs[1]], wrow[xs[2]], wrow[xs[3]]);
  const F4 r = surfelRadiusOf(v.z, n.z, fv.focal_px);
  const lanes::LaneVec3<F4> nw = lanes::rotate(T_world_cam, n);
  F4 dz_max, inv_v, inv_r;
  kernels::associationGates(prm, v, r, dz_max, inv_v, inv_r);
  alignas(16) float V[3][4], N[3][4], NW[3][4], Wt[4], Rr[4], DZ[4], IV[4], IR[4];
  _mm_store_ps(V[0], vx);
  _mm_store_ps(V[1], vy);
  _mm_store_ps(V[2], vz);
  _mm_store_ps(N[0], nx);
  _mm_store_ps(N[1], ny);
  _mm_store_ps(N[2], nz);
  lanes::store(NW[0], nw.x);
  lanes::store(NW[1], nw.y);
  lanes::store(NW[2], nw.z);
  _mm_store_ps(Wt, wt);
  lanes::store(Rr, r);
  lanes::store(DZ, dz_max);
  lanes::store(IV, inv_v);
  lanes::store(IR, inv_r);
  for (int v = valid; v; v &= v - 1) {
    const int l = __builtin_ctz(unsigned(v));
    kernels::PixelMeasurement& pm = m[l];
    pm.v = Vec3f(V[0][l], V[1][l], V[2][l]);
    pm.n = Vec3f(N[0][l], N[1][l], N[2][l]);
    pm.n_world = Vec3f(NW[0][l], NW[1][l], NW[2][l]);
    pm.w = Wt[l];
    pm.r = Rr[l];
    pm.z = V[2][l];
    pm.dz_max = DZ[l];
    pm.inv_v = IV[l];
    pm.inv_r = IR[l];
  }
  return valid;
}

void associateRowCpu(const kernels::AssociateKernel<kernels::ListCandidates>& k, int y,
                     KeptMeasurement* kept) {
  constexpr int kAhead = 8;
  const kernels::ListCandidates& lists = k.candidates;
  const int w = k.frame.vertex_cam.width;
  if (k.frame.weight.empty()) {
    for (int x = 0; x < w; ++x) {
      kernels::PixelMeasurement m;
      if (k.associate(x, y, m) != -1) kept[x] = KeptMeasurement{m.v, m.n_world, m.w, m.r};
    }
    return;
  }
  std::int32_t* ps = k.pixel_surfel.row(y);
  std::uint16_t* fl = k.flags.row(y);
  const int p0 = y * lists.width;
  const std::uint32_t total = lists.first[std::size_t(lists.width) * lists.height];
  for (int x0 = 0; x0 < w; x0 += 4) {
    const int nl = w - x0 < 4 ? w - x0 : 4;
    int xs[4];
    for (int l = 0; l < 4; ++l) xs[l] = x0 + (l < nl ? l : 0);
    for (int l = 0; l < nl; ++l) {
      const int xa = x0 + l + kAhead;
      if (xa < w) {
        // The first two entries of the pixel, whatever its count: a loop over the count
        // mispredicted its exit at nearly every pixel. (A rare third candidate is not prefetched;
        // past the count are the pixel's hidden surfels or the next pixel's.)
        const std::uint32_t q = lists.first[p0 + xa];
        if (q + 1 < total) {
          __builtin_prefetch(&k.s.normal_radius[lists.entries[q].index]);
          __builtin_prefetch(&k.s.normal_radius[lists.entries[q + 1].index]);
        }
      }
    }
    kernels::PixelMeasurement m[4];
    const int valid = measureFour(k.frame, k.prm, k.T_world_cam, y, xs, nl, m);
    for (int l = 0; l < nl; ++l) {
      const int x = x0 + l, p = p0 + x;
      if (!((valid >> l) & 1)) {
        ps[x] = -1;
        fl[x] = 0;
        continue;
      }
      const int best =
          kernels::bestCandidate(m[l], lists.entries + lists.first[p], lists.count[p], k.s, k.prm);
      ps[x] = best >= 0 ? best : -2;
      fl[x] = best >= 0 ? std::uint16_t(kernels::kPixValid | kernels::kPixAssociated)
                        : std::uint16_t(kernels::kPixValid | kernels::kPixNew);
      kept[x] = KeptMeasurement{m[l].v, m[l].n_world, m[l].w, m[l].r};
    }
  }
}

void coverRowCpu(const kernels::CoverageKernel<kernels::ListCandidates>& k, int y,
                 const KeptMeasurement* kept) {
  const std::uint16_t* fl = k.flags.row(y);
  const int w = k.flags.width;
  for (int x = 0; x < w; ++x) {
    if (!(fl[x] & kernels::kPixNew)) continue;
    // The association's measurement again (CoverageKernel::cover reads v, n_world and the gates).
    kernels::PixelMeasurement m;
    m.v = kept[x].v;
    m.n_world = kept[x].n_world;
    m.w = kept[x].w;
    m.r = kept[x].r;
    kernels::deriveGates(k.prm, m);
    k.cover(x, y, m);
  }
}

void ViewInfoThresholds::build(float l1, float dm) {
  if (builtFor(l1, dm)) return;
  lambda1 = l1;
  d_min_m = dm;
  const auto q = [&](float d) {
    return maps::quantizeUnit(maps::kernels::informationContent(d, l1, dm));
  };
  // Positive floats are ordered as their bit patterns: bisect over those, between 0 (IC 1) and
  // the largest finite float (IC 0 for any lambda1 > 0).
  for (int v = 0; v < 255; ++v) {
    std::uint32_t lo = 0, hi = 0x7f7fffffu;  // q(lo) > v (or lo = 0), q(hi) <= v
    const auto at = [](std::uint32_t b) {
      float f;
      std::memcpy(&f, &b, sizeof f);
      return f;
    };
    if (q(at(hi)) > v) {  // never falls to v (lambda1 <= 0): never skip
      below[v] = std::numeric_limits<float>::infinity();
      continue;
    }
    while (hi - lo > 1) {
      const std::uint32_t mid = lo + (hi - lo) / 2;
      if (q(at(mid)) <= v)
        hi = mid;
      else
        lo = mid;
    }
    below[v] = q(at(lo)) <= v ? at(lo) : at(hi);
  }
}

void updateRowCpu(const kernels::UpdateKernel& k, int y, const KeptMeasurement* kept, bool labels,
                  bool bins, const ViewInfoThresholds* ic) {
  constexpr int kAhead = 8;
  const maps::SurfelArrays& s = k.s;
  const std::int32_t* ps = k.pixel_surfel.row(y);
  const int w = k.pixel_surfel.width;
  int xs[4], n = 0;
  for (int x = 0; x < w; ++x) {
    if (x + kAhead < w) {
      const int j = ps[x + kAhead];
      if (j >= 0) {
        __builtin_prefetch(&s.pos_conf[j], 1);
        __builtin_prefetch(&s.normal_radius[j], 1);
        __builtin_prefetch(&s.colour_flags[j], 1);
        __builtin_prefetch(&s.basis[j], 1);
        __builtin_prefetch(&s.t_last[j], 1);
        if (labels) {
          __builtin_prefetch(&s.segment[j], 1);
          __builtin_prefetch(&s.segment_w[j], 1);
        }
        if (bins) __builtin_prefetch(s.viewRow(j), 1);
      }
    }
    if (ps[x] < 0) continue;
    xs[n++] = x;
    if (n == 4) {
      updateFour(k, y, xs, 4, kept, ic);
      n = 0;
    }
  }
  if (n) updateFour(k, y, xs, n, kept, ic);
}

}  // namespace rasm::fusion
