#pragma once
// Per-pixel and per-surfel kernels of surfel fusion (II-B, II-D, III segment weights, V-B view
// bins), written once for the CPU (OpenMP) and CUDA launchers. Plain header: compute/, Eigen and
// the plain kernel headers of core and surfel_map.

#include <cmath>
#include <cstdint>

#include "rasm/compute/ImageView.h"
#include "rasm/compute/Types.h"
#include "rasm/core/SurfelMath.h"
#include "rasm/surfel_map/SurfelArrays.h"
#include "rasm/surfel_map/kernels/RenderKernels.h"
#include "rasm/surfel_map/kernels/ViewBins.h"

namespace rasm::fusion::kernels {

/// Per-pixel outcome bits of the association and update passes.
enum PixelFlag : std::uint16_t {
  kPixValid = 1,           ///< usable measurement (vertex, normal, depth range, incidence)
  kPixAssociated = 2,      ///< matched an existing surfel
  kPixFused = 4,           ///< geometry averaged (radius rule passed)
  kPixNew = 8,             ///< no match: becomes a new surfel
  kPixBecameStable = 16,   ///< the matched surfel crossed the stability threshold
  kPixRelabelled = 32,     ///< the matched surfel changed from one segment to another (III)
  kPixCovered = 64,        ///< no candidate of its own, but a neighbour's surfel covers it
  kPixCrossedBlock = 128,  ///< the update moved the surfel into another spatial-index block
  /// Bits 8-9: free-space carving verdict on the updated surfel (CarveTest::Action), evaluated on
  /// its state after the update and applied by the cleanup.
  kPixCarveShift = 8,
};

/// Plain copy of TFusionParams with derived values, for kernels.
struct FusionKernelParams {
  float sigma = 0.6f;
  float min_depth_m = 0.1f, max_depth_m = 5.0f;
  float min_cos_incidence = 0.17f;
  float assoc_dz_abs_m = 0.03f, assoc_dz_rel = 0.01f;
  float min_cos_normal = 0.94f;
  float radius_update_ratio = 1.5f;
  bool average_radius = true;  ///< TFusionParams::average_radius
  bool neighbour_coverage_check = true;
  float stable_confidence = 10.0f;
  float max_confidence = 0.0f;  ///< 0 = no cap
  bool update_segments = true;
  bool update_view_bins = true;
  float ic_lambda1 = 0.5f, ic_d_min_m = 1.0f;
  int n_azimuth = 0, n_elevation = 0;
  float inv_block_size = 2.0f;  ///< 1 / spatial-index block edge (1/m): block crossings
};

/// Whether a pixel's camera-frame vertex v and normal n make a measurement (II-B): both valid
/// (x not NaN), depth within [min_depth_m, max_depth_m], and the incidence cosine -n.v / |v|
/// not below min_cos_incidence. Over lanes (compute/Lanes.h): the scalar kernels and fusion's
/// four-pixel CPU association run this body.
template <class F>
RASM_HD_INLINE lanes::MaskOf<F> measurable(const FusionKernelParams& p, const lanes::LaneVec3<F>& v,
                                           const lanes::LaneVec3<F>& n) {
  const F cos_inc = -lanes::dot(n, v) / lanes::sqrtL(lanes::dot(v, v));
  return v.x == v.x && n.x == n.x && v.z >= p.min_depth_m && v.z <= p.max_depth_m &&
         !(cos_inc < p.min_cos_incidence);
}

/// The measurement of pixel (x, y) (II-B): camera-frame vertex and normal, confidence weight
/// w = exp(-gamma^2 / (2 sigma^2)) and radius r = z / (sqrt(2) f n_z). False when unusable.
struct FrameView {
  ImageView<const Bgr8> colour;  ///< may be empty
  ImageView<const Vec3f> vertex_cam;
  ImageView<const Vec3f> normal_cam;
  ImageView<const std::uint32_t> labels;  ///< may be empty
  /// w per pixel (it depends only on the pixel, the intrinsics and sigma: a cached table);
  /// computed on the fly when empty.
  ImageView<const float> weight;
  PinholeF K;
  float focal_px = 525.0f;

  RASM_HD_INLINE bool measure(int x, int y, const FusionKernelParams& p, Vec3f& v, Vec3f& n,
                              float& w, float& r) const {
    v = vertex_cam(x, y);
    n = normal_cam(x, y);
    if (!measurable(p, lanes::lanesOf(v), lanes::lanesOf(n))) return false;
    const float z = v.z();
    w = weight.empty() ? confidenceWeight(normalizedRadialDistance(float(x), float(y), K), p.sigma)
                       : weight(x, y);
    r = surfelRadius(z, n.z(), focal_px);
    return true;
  }
  RASM_HD_INLINE Bgr8 colourAt(int x, int y) const {
    return colour.empty() ? Bgr8{128, 128, 128} : colour(x, y);
  }
};

RASM_HD_INLINE std::uint8_t blendU8(std::uint8_t a, std::uint8_t b, float wa, float wb) {
  const float v = float(a) * wa + float(b) * wb + 0.5f;
  return std::uint8_t(v > 255.0f ? 255.0f : v);
}

/// The bin update of updateViewBin once the bin and the camera distance are known.
RASM_HD_INLINE void updateViewBinAt(const maps::SurfelArrays& s, int i, int bin, float dist,
                                    const FusionKernelParams& prm) {
  std::uint8_t* row = s.viewRow(i);
  if (row[bin] == 255) return;  // already saturated: IC <= 1
  const std::uint8_t q =
      maps::quantizeUnit(maps::kernels::informationContent(dist, prm.ic_lambda1, prm.ic_d_min_m));
  if (q > row[bin]) row[bin] = q;
}

/// Bin update of V-B: b_v(i) <- max(b_v(i), IC(s)) for the bin of the camera direction.
RASM_HD_INLINE void updateViewBin(const maps::SurfelArrays& s, int i, const Vec3f& p,
                                  const Vec3f& n, const Vec3f& b, const Vec3f& camera_centre,
                                  const FusionKernelParams& prm) {
  if (!prm.update_view_bins || s.n_view_bins <= 0) return;
  float dist;
  const float bin =
      maps::kernels::viewBinOfCamera(lanes::lanesOf(p), lanes::lanesOf(n), lanes::lanesOf(b),
                                     camera_centre, prm.n_azimuth, prm.n_elevation, dist);
  if (bin >= 0.0f) updateViewBinAt(s, i, int(bin), dist, prm);
}

/// Whether a surfel moved from p_old to p_new changed spatial-index block (VoxelBlockIndex's
/// block coordinates: floor(p / block size)); the caller then re-bins it.
RASM_HD_INLINE bool crossedBlock(const Vec3f& p_old, const Vec3f& p_new, float inv_block_size) {
  return floorf(p_new.x() * inv_block_size) != floorf(p_old.x() * inv_block_size) ||
         floorf(p_new.y() * inv_block_size) != floorf(p_old.y() * inv_block_size) ||
         floorf(p_new.z() * inv_block_size) != floorf(p_old.z() * inv_block_size);
}

/// Redundant-surfel merging (Keller et al. 2013, sec. 4.3: "merge points with similar position
/// and normal and overlapping radii"; ElasticFusion's clean-up step). Two surfels are redundant
/// when their normals agree within the merge gate, their centres are within the association
/// depth gate of each other along the normal (max(abs, rel * z), z = camera depth) and one disc
/// contains the other's centre (in-plane distance <= the larger radius).
struct MergeTest {
  float min_cos_normal = 0.97f;  ///< cos(merge_max_normal_angle_deg)
  float dz_abs_m = 0.03f, dz_rel = 0.01f;

  RASM_HD_INLINE bool redundant(const maps::SurfelArrays& s, int i, int j, float z) const {
    const Vec4f a = s.normal_radius[i], b = s.normal_radius[j];
    const Vec3f na = a.head<3>(), nb = b.head<3>();
    if (na.dot(nb) < min_cos_normal) return false;
    const Vec3f d = s.pos_conf[j].head<3>() - s.pos_conf[i].head<3>();
    const float along = d.dot(na);
    const float dz = maps::kernels::maxF(dz_abs_m, dz_rel * z);  // as PixelMeasurement::dz_max
    if (along > dz || along < -dz) return false;
    const float r = a.w() > b.w() ? a.w() : b.w();
    return d.squaredNorm() - along * along <= r * r;
  }
};

/// Merges surfel `loser` into `keep` (the one with the higher confidence): confidence-weighted
/// averages of position, normal, colour and radius as a fusion update would make them, summed
/// confidence (capped), the earlier t_init and later t_last, the element-wise max of the view
/// bins (each bin holds the best IC seen from its direction), and the segment weight of the
/// kept segment (+ the loser's when both carry the same label). Class evidence stays the kept
/// surfel's unless it has none, then it takes the loser's: both surfels saw the same detections
/// of their segment, so adding the two would count them twice. Returns true when the kept
/// surfel's position crossed a spatial-index block border.
RASM_HD_INLINE bool mergeSurfels(const maps::SurfelArrays& s, int keep, int loser,
                                 const FusionKernelParams& prm) {
  const Vec4f pk = s.pos_conf[keep], pl = s.pos_conf[loser];
  const Vec4f nk = s.normal_radius[keep], nl = s.normal_radius[loser];
  const float ck = pk.w(), cl = pl.w();
  const float inv = ck + cl > 0.0f ? 1.0f / (ck + cl) : 0.5f;
  const float a0 = ck + cl > 0.0f ? ck * inv : 0.5f, a1 = 1.0f - a0;
  const Vec3f p = a0 * pk.head<3>() + a1 * pl.head<3>();
  Vec3f n = a0 * nk.head<3>() + a1 * nl.head<3>();
  const float len = n.norm();
  n = len > 1e-6f ? Vec3f(n * (1.0f / len)) : Vec3f(nk.head<3>());
  const float r = a0 * nk.w() + a1 * nl.w();
  float c = ck + cl;
  if (prm.max_confidence > 0.0f && c > prm.max_confidence) c = prm.max_confidence;
  std::uint32_t cf = s.colour_flags[keep];
  const Bgr8 co = maps::unpackColour(cf), cn = maps::unpackColour(s.colour_flags[loser]);
  cf = maps::packColour(
      Bgr8{blendU8(co.b, cn.b, a0, a1), blendU8(co.g, cn.g, a0, a1), blendU8(co.r, cn.r, a0, a1)},
      cf & 0xff000000u);
  if (c >= prm.stable_confidence) cf |= maps::kSurfelStable;
  s.pos_conf[keep] = Vec4f(p.x(), p.y(), p.z(), c);
  s.normal_radius[keep] = Vec4f(n.x(), n.y(), n.z(), r);
  s.colour_flags[keep] = cf;
  s.basis[keep] = maps::kernels::updateBasis(n, s.basis[keep]);
  if (s.t_init[loser] < s.t_init[keep]) s.t_init[keep] = s.t_init[loser];
  if (s.t_last[loser] > s.t_last[keep]) s.t_last[keep] = s.t_last[loser];
  if (s.segment[keep] == 0u) {
    s.segment[keep] = s.segment[loser];
    s.segment_w[keep] = s.segment_w[loser];
  } else if (s.segment[keep] == s.segment[loser]) {
    s.segment_w[keep] += s.segment_w[loser];
  }
  if (s.n_classes > 0 && maps::classEvidenceEmpty(s.class_ev[keep]))
    s.class_ev[keep] = s.class_ev[loser];
  if (s.n_view_bins > 0) {
    std::uint8_t* rk = s.viewRow(keep);
    const std::uint8_t* rl = s.viewRow(loser);
    for (int b = 0; b < s.n_view_bins; ++b)
      if (rl[b] > rk[b]) rk[b] = rl[b];
  }
  return crossedBlock(pk.head<3>(), p, prm.inv_block_size);
}

/// A pixel's measurement with the association gates derived from it (II-D).
struct PixelMeasurement {
  // (initialised: GCC 12 cannot see that the kernels read them only after a successful measure)
  Vec3f v = Vec3f::Zero(), n = Vec3f::Zero();  ///< camera-frame vertex and normal
  Vec3f n_world = Vec3f::Zero();  ///< normal in the world frame (compared with the surfel normals)
  float w = 0, r = 0;             ///< confidence weight and radius (II-B)
  float z = 0, dz_max = 0, inv_v = 0, inv_r = 0;
};

/// The fields of m that follow from its vertex v and radius r: z, the depth gate, 1/|v|, 1/r.
/// (Over lanes: the depth gate max(abs, rel z), 1 / |v| and 1 / r of a vertex v and radius r.)
template <class F>
RASM_HD_INLINE void associationGates(const FusionKernelParams& prm, const lanes::LaneVec3<F>& v,
                                     const F& r, F& dz_max, F& inv_v, F& inv_r) {
  const F rel = prm.assoc_dz_rel * v.z;
  dz_max = lanes::select(prm.assoc_dz_abs_m > rel, F(prm.assoc_dz_abs_m), rel);
  inv_v = 1.0f / lanes::sqrtL(lanes::dot(v, v));
  inv_r = 1.0f / r;
}
RASM_HD_INLINE void deriveGates(const FusionKernelParams& prm, PixelMeasurement& m) {
  m.z = m.v.z();
  associationGates(prm, lanes::lanesOf(m.v), m.r, m.dz_max, m.inv_v, m.inv_r);
}

RASM_HD_INLINE bool measureForAssociation(const FrameView& frame, int x, int y,
                                          const FusionKernelParams& prm, const RigidF& T_world_cam,
                                          PixelMeasurement& m) {
  if (!frame.measure(x, y, prm, m.v, m.n, m.w, m.r)) return false;
  m.n_world = T_world_cam.rotate(m.n);
  deriveGates(prm, m);
  return true;
}

/// II-D association of one pixel: the most similar of its candidates (camera-frame centres and
/// indices), -1 when none passes the gates. Normals are compared in the world frame (one rotation
/// per pixel instead of one per candidate).
/// Gates: |z_s - z| <= max(abs, rel z) along the ray, angle(n_s, n) <= max angle.
/// Similarity cost (lowest wins, lower index on ties): d_perp / r + (1 - cos) / (1 - cos_max)
/// + (max(r_s, r) / min(r_s, r) - 1), i.e. distance of the surfel to the pixel ray in units of the
/// measurement radius, normal disagreement relative to the gate, and radius mismatch.
RASM_HD_INLINE int bestCandidate(const PixelMeasurement& m, const maps::kernels::CameraPoint* c,
                                 int n, const maps::SurfelArrays& s,
                                 const FusionKernelParams& prm) {
  const float cos_range = 1.0f - prm.min_cos_normal;
  const float inv_cos_range = 1.0f / (cos_range > 1e-6f ? cos_range : 1e-6f);
  int best = -1;
  float best_cost = 3.0e38f;
  for (int k = 0; k < n; ++k) {
    const Vec3f& pc = c[k].pc;
    if (fabsf(pc.z() - m.z) > m.dz_max) continue;
    const int i = c[k].index;
    const Vec4f nr = s.normal_radius[i];
    const float cos_n = nr.head<3>().dot(m.n_world);
    if (cos_n < prm.min_cos_normal) continue;
    const float d_perp = pc.cross(m.v).norm() * m.inv_v;
    const float rs = nr.w(), r = m.r;
    const float r_hi = rs > r ? rs : r, r_lo = rs > r ? r : rs;
    const float cost = d_perp * m.inv_r + (1.0f - cos_n) * inv_cos_range +
                       (r_hi / (r_lo > 1e-9f ? r_lo : 1e-9f) - 1.0f);
    if (cost < best_cost || (cost == best_cost && i < best)) {
      best_cost = cost;
      best = i;
    }
  }
  return best;
}

/// Whether one of the candidates, in its current state (the map after this frame's updates),
/// passes the depth and normal gates and its disc reaches the pixel ray (neighbour coverage, see
/// CoverageKernel). The candidates' camera-frame centres are current except for surfel `updated`
/// (the one their pixel updated, -1 none), which is transformed again.
RASM_HD_INLINE bool coversRay(const PixelMeasurement& m, const maps::kernels::CameraPoint* c, int n,
                              int updated, const maps::SurfelArrays& s, const RigidF& T_cam_world,
                              const FusionKernelParams& prm) {
  for (int k = 0; k < n; ++k) {
    const int i = c[k].index;
    const Vec3f pc = i == updated ? T_cam_world.apply(s.position(i)) : c[k].pc;
    if (fabsf(pc.z() - m.z) > m.dz_max) continue;
    const Vec4f nr = s.normal_radius[i];
    if (nr.head<3>().dot(m.n_world) < prm.min_cos_normal) continue;
    if (pc.cross(m.v).norm() * m.inv_v <= nr.w()) return true;
  }
  return false;
}

/// Candidates of a frame pixel from the compact lists of SurfelRenderer::renderCandidates4x (CPU).
struct ListCandidates {
  const maps::kernels::CameraPoint* entries = nullptr;
  const std::uint32_t* first = nullptr;
  const std::uint8_t* count = nullptr;
  int width = 0, height = 0;

  /// Sets `out` to the candidates of pixel (x, y) and returns how many (buf is not used).
  RASM_HD_INLINE int get(int x, int y, maps::kernels::CameraPoint* /*buf*/,
                         const maps::kernels::CameraPoint*& out) const {
    const int p = y * width + x;
    out = entries + first[p];
    return count[p];
  }
};

/// Candidates of a frame pixel from the 4x packed index map (IndexMap4x; the CUDA path): the
/// surfels of its 4x4 sub-pixel block, transformed into the camera frame (their current state).
struct Map4xCandidates {
  ImageView<const std::uint64_t> index4x;
  maps::SurfelArrays s;
  RigidF T_cam_world;
  int width = 0, height = 0;  ///< of the frame

  /// Fills buf (16 entries) with the candidates of pixel (x, y); out = buf.
  RASM_HD_INLINE int get(int x, int y, maps::kernels::CameraPoint* buf,
                         const maps::kernels::CameraPoint*& out) const {
    int n = 0;
    for (int sy = 4 * y; sy < 4 * y + 4; ++sy)
      for (int sx = 4 * x; sx < 4 * x + 4; ++sx) {
        const int i = maps::kernels::unpackIndex(index4x(sx, sy));
        if (i < 0) continue;
        buf[n].pc = T_cam_world.apply(s.position(i));
        buf[n].index = i;
        ++n;
      }
    out = buf;
    return n;
  }
};

/// Association, one frame pixel per call (II-D), read-only on the map: picks the most similar
/// candidate (bestCandidate), or marks the pixel as a new surfel (kPixNew; CoverageKernel may
/// still drop it). Each surfel is a candidate of one pixel only, so the updates of the next pass
/// are exclusive.
template <typename Candidates>
struct AssociateKernel {
  FrameView frame;
  FusionKernelParams prm;
  Candidates candidates;
  maps::SurfelArrays s;
  RigidF T_world_cam;
  ImageView<std::int32_t> pixel_surfel;  ///< out: matched surfel, -2 new, -1 none
  ImageView<std::uint16_t> flags;        ///< out: PixelFlag bits

  RASM_HD_INLINE void operator()(int x, int y) const {
    PixelMeasurement m;
    associate(x, y, m);
  }

  /// operator() that also returns the pixel's measurement m (valid when the result is >= 0):
  /// the matched surfel, -2 new, -1 no usable measurement.
  RASM_HD_INLINE int associate(int x, int y, PixelMeasurement& m) const {
    if (!measureForAssociation(frame, x, y, prm, T_world_cam, m)) {
      pixel_surfel(x, y) = -1;
      flags(x, y) = 0;
      return -1;
    }
    maps::kernels::CameraPoint buf[16];
    const maps::kernels::CameraPoint* c = nullptr;
    const int n = candidates.get(x, y, buf, c);
    const int best = bestCandidate(m, c, n, s, prm);
    pixel_surfel(x, y) = best >= 0 ? best : -2;
    flags(x, y) =
        best >= 0 ? std::uint16_t(kPixValid | kPixAssociated) : std::uint16_t(kPixValid | kPixNew);
    return best >= 0 ? best : -2;
  }
};

/// Neighbour coverage of a pixel the association left without a match, after the updates:
/// each surfel is a candidate of exactly one pixel, so after sub-pixel camera motion a pixel's
/// own 4x4 block is empty in ~1/3 of the cases (points are spread like a Poisson process) even
/// though a surfel of the same surface projects into the neighbouring block. Adding a surfel there
/// would duplicate the surface (real Kinect data grew the map by 25% of the pixels per frame).
/// The 8 neighbouring blocks are searched for a surfel that, as this frame's updates left it,
/// passes the depth and normal gates and whose disc reaches the pixel ray; the measurement is then
/// dropped (neither fused nor added). Reading the map only after every update makes the outcome
/// independent of pixel order and thread count.
template <typename Candidates>
struct CoverageKernel {
  FrameView frame;
  FusionKernelParams prm;
  Candidates candidates;
  maps::SurfelArrays s;
  RigidF T_world_cam, T_cam_world;
  ImageView<std::int32_t> pixel_surfel;  ///< in/out
  ImageView<std::uint16_t> flags;        ///< in/out

  RASM_HD_INLINE void operator()(int x, int y) const {
    if (!(flags(x, y) & kPixNew)) return;
    PixelMeasurement m;
    measureForAssociation(frame, x, y, prm, T_world_cam, m);  // kPixNew: a valid measurement
    cover(x, y, m);
  }

  /// operator() of a kPixNew pixel whose association measurement m the caller kept (of m it
  /// reads v, n_world, z, dz_max and inv_v).
  RASM_HD_INLINE void cover(int x, int y, const PixelMeasurement& m) const {
    maps::kernels::CameraPoint buf[16];
    const maps::kernels::CameraPoint* c = nullptr;
    const int w = pixel_surfel.width, h = pixel_surfel.height;
    // The 4-neighbours first (the likelier cover: the outcome is the same in any order).
    const int dx[8] = {-1, 1, 0, 0, -1, 1, -1, 1}, dy[8] = {0, 0, -1, 1, -1, -1, 1, 1};
    for (int k = 0; k < 8; ++k) {
      const int px = x + dx[k], py = y + dy[k];
      if (px < 0 || py < 0 || px >= w || py >= h) continue;
      const int n = candidates.get(px, py, buf, c);
      if (coversRay(m, c, n, pixel_surfel(px, py), s, T_cam_world, prm)) {
        pixel_surfel(x, y) = -1;  // measured but neither fused nor added
        flags(x, y) = kPixValid | kPixCovered;
        return;
      }
    }
  }
};

/// Free-space carving test (II-D "akin to space carving") of one surfel whose centre is pc in the
/// camera frame: the centre projects onto pixel u whose whole 3x3 neighbourhood has valid measured
/// depth, and it lies in front of the nearest of those depths by more than max(abs, rel * depth).
/// Unstable violators are removed; stable ones lose confidence (w *= decay) and the stable flag
/// once w < the threshold (the next violation removes them).
struct CarveTest {
  ImageView<const float> depth_m;
  PinholeF K;
  float min_depth_m = 0.1f, max_depth_m = 5.0f;
  float margin_abs_m = 0.05f, margin_rel = 0.02f;
  float stable_confidence = 10.0f;
  float stable_decay = 0.5f;

  enum Action : std::uint8_t { kKeep = 0, kRemove = 1, kDecay = 2, kDemote = 3 };

  RASM_HD_INLINE bool violates(const Vec3f& pc) const {
    const float z = pc.z();
    if (!(z > 0.0f)) return false;
    return violatesAt(z, maps::kernels::pixelOf(K.fx * pc.x() / z + K.cx),
                      maps::kernels::pixelOf(K.fy * pc.y() / z + K.cy));
  }

  /// violates() of a centre at depth z > 0 that projects onto pixel (u, v).
  RASM_HD_INLINE bool violatesAt(float z, int u, int v) const {
    if (u < 1 || v < 1 || u >= depth_m.width - 1 || v >= depth_m.height - 1) return false;
    // Most surfels sit at (or behind) the measured depth: the centre pixel decides cheaply.
    const float dc = depth_m(u, v);
    return inFrontOf(z, dc, maps::kernels::maxF(margin_abs_m, margin_rel * dc)) &&
           inFrontOfNeighbourhood(z, u, v);
  }
  /// The centre-pixel part of violatesAt(): dc = depth_m(u, v), margin of dc.
  RASM_HD_INLINE static bool inFrontOf(float z, float dc, float margin_dc) {
    return dc - z > margin_dc;
  }
  /// The rest of violatesAt() for a surfel that passed inFrontOf() at an inner pixel (u, v).
  RASM_HD_INLINE bool inFrontOfNeighbourhood(float z, int u, int v) const {
    float d_min = 3.0e38f;
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        const float d = depth_m(u + dx, v + dy);
        if (!(d >= min_depth_m && d <= max_depth_m)) return false;  // not observed: no evidence
        d_min = d < d_min ? d : d_min;
      }
    return d_min - z > maps::kernels::maxF(margin_abs_m, margin_rel * d_min);
  }

  /// False when violatesAt() cannot hold for a surfel just updated by the measurement of pixel
  /// (x, y) at depth z, with which it was associated within the depth gate dz_max (so no need to
  /// project it). Proof: the old centre was within dz_max of z along the gate, the measured point
  /// lies on the pixel's ray, and the updated centre is their weighted mean (or the old centre):
  /// it projects inside pixel (x, y)'s square, so (x, y) is in the 3x3 neighbourhood of its pixel,
  /// and its depth is at least z - dz_max. A violation needs that neighbourhood valid with
  /// d_min - z_c > max(abs, rel d_min) >= abs and d_min <= depth(x, y): ruled out when
  /// depth(x, y) - (z - dz_max) <= abs - 0.1 mm (the tolerance covers float rounding, ~1 um). The
  /// default gates (3 cm / 1%, carving 5 cm / 2%) skip nearly every updated surfel; a depth(x, y)
  /// unlike the filtered z (edges), or a NaN, keeps the full test.
  RASM_HD_INLINE bool updatedMayViolate(int x, int y, float z, float dz_max) const {
    return !(depth_m(x, y) - (z - dz_max) <= margin_abs_m - 1e-4f);
  }

  /// What a violation does to a surfel with these flags and confidence.
  RASM_HD_INLINE Action action(std::uint32_t colour_flags, float confidence) const {
    if (!(colour_flags & maps::kSurfelStable)) return kRemove;
    return confidence * stable_decay < stable_confidence ? kDemote : kDecay;
  }

  /// Applies kDecay / kDemote to surfel i.
  RASM_HD_INLINE void decay(const maps::SurfelArrays& s, int i, Action a) const {
    s.pos_conf[i].w() = s.pos_conf[i].w() * stable_decay;
    if (a == kDemote) s.colour_flags[i] &= ~std::uint32_t(maps::kSurfelStable);
  }
};

/// Update of the surfel a pixel was associated with, one frame pixel per call (II-D; Keller et al.
/// 2013, ElasticFusion): when r <= ratio * r_s, position, normal and colour become the
/// confidence-weighted means (w_s p_s + w p) / (w_s + w), the radius too (or, with
/// average_radius off, only when the new one is smaller: see update()); then w_s += w
/// (optionally capped), t_last = now, stable once w_s >= threshold. The basis follows the normal,
/// b <- -n x (n x b) (V-B); the segment weight follows L^p (III); the view bin of the camera
/// direction takes max(b_v, IC) (V-B). Optionally records the carving verdict on the updated
/// state (CarveTest) in the pixel's flags.
/// II-B's update of one surfel's geometry by an associated measurement, over lanes
/// (compute/Lanes.h: the scalar kernel and fusion's four-lane CPU update run this body).
/// In: the measurement's camera-frame vertex v, world normal nw, weight w and radius r, and the
/// surfel's position p, confidence c, normal ns, radius rs and basis b. Where the measurement is
/// fine enough (`fuse`: r <= radius_update_ratio rs), p and ns become the confidence-weighted
/// averages (a0 = c / (c + w), a1 = w / (c + w); ns renormalised), rs too when average_radius or
/// r < rs, and b is projected onto the new plane (updateBasis: -ns x (ns x b), normalised);
/// `basis_ok` is false where that projection is too short and updateBasis falls back to
/// anyPerpendicular (the caller's part); `crossed` where the new position left its
/// spatial-index block. Elsewhere the surfel keeps its geometry.
template <class F>
struct SurfelGeometryUpdate {
  lanes::LaneVec3<F> p, ns, b;
  F rs, a0, a1;
  lanes::MaskOf<F> fuse, basis_ok, crossed;
};
template <class F>
RASM_HD_INLINE SurfelGeometryUpdate<F> averageSurfelGeometry(
    const FusionKernelParams& prm, const RigidF& T_world_cam, const lanes::LaneVec3<F>& v,
    const lanes::LaneVec3<F>& nw, const F& w, const F& r, const lanes::LaneVec3<F>& p, const F& c,
    const lanes::LaneVec3<F>& ns, const F& rs, const lanes::LaneVec3<F>& b) {
  using lanes::select;
  SurfelGeometryUpdate<F> u;
  const lanes::LaneVec3<F> vw = lanes::apply(T_world_cam, v);
  u.fuse = r <= prm.radius_update_ratio * rs;
  const F inv_cw = 1.0f / (c + w);
  u.a0 = c * inv_cw;
  u.a1 = w * inv_cw;
  const lanes::LaneVec3<F> q = lanes::blend(u.a0, p, u.a1, vw);
  const lanes::LaneVec3<F> nn = lanes::blend(u.a0, ns, u.a1, nw);
  const F len = lanes::sqrtL(lanes::dot(nn, nn));
  u.ns = select(u.fuse && len > 1e-6f, lanes::scaled(nn, 1.0f / len), ns);
  // The radius: averaged like the rest (ElasticFusion), or only with smaller measurements
  // (TFusionParams::average_radius).
  const lanes::MaskOf<F> shrink = prm.average_radius ? u.fuse : (u.fuse && r < rs);
  u.rs = select(shrink, u.a0 * rs + u.a1 * r, rs);
  const lanes::LaneVec3<F> t = lanes::cross(u.ns, lanes::cross(u.ns, b));
  const lanes::LaneVec3<F> nb{-t.x, -t.y, -t.z};
  const F blen = lanes::sqrtL(lanes::dot(nb, nb));
  u.basis_ok = blen > 1e-4f;
  u.b = select(u.fuse, lanes::scaled(nb, 1.0f / blen), b);
  const float ib = prm.inv_block_size;
  u.crossed = u.fuse && (lanes::floorL(q.x * ib) != lanes::floorL(p.x * ib) ||
                         lanes::floorL(q.y * ib) != lanes::floorL(p.y * ib) ||
                         lanes::floorL(q.z * ib) != lanes::floorL(p.z * ib));
  u.p = select(u.fuse, q, p);
  return u;
}

struct UpdateKernel {
  FrameView frame;
  FusionKernelParams prm;
  maps::SurfelArrays s;
  RigidF T_world_cam, T_cam_world;
  float now = 0.0f;                            ///< map time
  ImageView<const std::int32_t> pixel_surfel;  ///< of AssociateKernel
  ImageView<std::uint16_t> flags;              ///< in/out: PixelFlag bits
  bool carve = false;                          ///< evaluate `carve_test` on the updated surfel
  CarveTest carve_test;

  RASM_HD_INLINE void operator()(int x, int y) const {
    const int i = pixel_surfel(x, y);
    if (i < 0) return;
    Vec3f v, n;
    float w = 0.0f, r = 0.0f;
    frame.measure(x, y, prm, v, n, w, r);  // associated pixels have a valid measurement
    update(x, y, i, v, T_world_cam.rotate(n), w, r);
  }

  /// The update of surfel i = pixel_surfel(x, y) by the pixel's measurement (FrameView::measure:
  /// camera-frame vertex v, confidence weight w, radius r) with its normal nw in the WORLD frame,
  /// for callers that kept the association's measurement (PixelMeasurement).
  RASM_HD_INLINE void update(int x, int y, int i, const Vec3f& v, const Vec3f& nw, float w,
                             float r) const {
    std::uint16_t f = flags(x, y);
    const Vec4f pcf = s.pos_conf[i];
    const Vec4f nr = s.normal_radius[i];
    std::uint32_t cf = s.colour_flags[i];
    const SurfelGeometryUpdate<float> u = averageSurfelGeometry<float>(
        prm, T_world_cam, lanes::lanesOf(v), lanes::lanesOf(nw), w, r,
        lanes::LaneVec3<float>{pcf.x(), pcf.y(), pcf.z()}, pcf.w(),
        lanes::LaneVec3<float>{nr.x(), nr.y(), nr.z()}, nr.w(), lanes::lanesOf(s.basis[i]));
    const Vec3f p(u.p.x, u.p.y, u.p.z), ns(u.ns.x, u.ns.y, u.ns.z);
    Vec3f b(u.b.x, u.b.y, u.b.z);
    if (u.fuse) {
      cf = blendColour(x, y, cf, u.a0, u.a1);
      if (!u.basis_ok) b = maps::kernels::anyPerpendicular(ns);  // (updateBasis's fallback)
      f |= kPixFused;
      if (u.crossed) f |= kPixCrossedBlock;
    }
    store(x, y, i, w, pcf.w(), p, ns, u.rs, b, cf, f, v.z());
    updateViewBin(s, i, p, ns, b, T_world_cam.translation(), prm);
  }

  /// The surfel colour (packed, flags kept) blended with pixel (x, y)'s by the weights a0, a1.
  RASM_HD_INLINE std::uint32_t blendColour(int x, int y, std::uint32_t cf, float a0,
                                           float a1) const {
    if (frame.colour.empty()) return cf;
    const Bgr8 co = maps::unpackColour(cf), cn = frame.colour(x, y);
    return maps::packColour(
        Bgr8{blendU8(co.b, cn.b, a0, a1), blendU8(co.g, cn.g, a0, a1), blendU8(co.r, cn.r, a0, a1)},
        cf & 0xff000000u);
  }

  /// The rest of update() once the geometry (p, ns, rs, b) and colour cf are averaged, but the
  /// view bin (updateViewBin, independent of it): confidence c + w, the stable flag, the stores,
  /// the segment weight and the carving verdict; f: the pixel's flags so far, z: the depth of
  /// the pixel's measurement.
  RASM_HD_INLINE void store(int x, int y, int i, float w, float c, const Vec3f& p, const Vec3f& ns,
                            float rs, const Vec3f& b, std::uint32_t cf, std::uint16_t f,
                            float z) const {
    float c_new = c + w;
    if (prm.max_confidence > 0.0f && c_new > prm.max_confidence) c_new = prm.max_confidence;
    if (!(cf & maps::kSurfelStable) && c_new >= prm.stable_confidence) {
      cf |= maps::kSurfelStable;
      f |= kPixBecameStable;
    }
    s.pos_conf[i] = Vec4f(p.x(), p.y(), p.z(), c_new);
    s.normal_radius[i] = Vec4f(ns.x(), ns.y(), ns.z(), rs);
    s.colour_flags[i] = cf;
    s.basis[i] = b;
    s.t_last[i] = now;
    // Segment weight (III): same label accumulates w, another label erodes it; at 0 relabel.
    if (prm.update_segments && !frame.labels.empty()) {
      const std::uint32_t l = frame.labels(x, y);
      if (l != 0u) {
        if (s.segment[i] == l) {
          s.segment_w[i] += w;
        } else if (s.segment[i] == 0u || s.segment_w[i] - w <= 0.0f) {
          if (s.segment[i] != 0u) f |= kPixRelabelled;  // a change, not a first label
          s.segment[i] = l;
          s.segment_w[i] = w;
        } else {
          s.segment_w[i] -= w;
        }
      }
    }
    if (carve &&
        carve_test.updatedMayViolate(
            x, y, z, maps::kernels::maxF(prm.assoc_dz_abs_m, prm.assoc_dz_rel * z)) &&
        carve_test.violates(T_cam_world.apply(p)))
      f |= std::uint16_t(carve_test.action(cf, c_new) << kPixCarveShift);
    flags(x, y) = f;
  }
};

/// Writes the new surfels of row y (II-B) at indices row_first[y], row_first[y] + 1, ... in pixel
/// order: position V, normal N (world), colour, r = z / (sqrt2 f n_z), w = exp(-gamma^2/2sigma^2),
/// t_init = t_last = now, segment and segment weight from L^p (else 0 / 0), class evidence left
/// empty by the allocator (every p_c at the 0.5 prior), basis any unit vector perpendicular to
/// n, and the view bin of this view initialised with IC (V-B).
struct NewSurfelKernel {
  FrameView frame;
  FusionKernelParams prm;
  maps::SurfelArrays s;
  RigidF T_world_cam;
  float now = 0.0f;
  ImageView<const std::uint16_t> flags;
  const int* row_first = nullptr;
  ImageView<std::int32_t> pixel_surfel;

  RASM_HD_INLINE void operator()(int y) const {
    int i = row_first[y];
    const std::uint16_t* fr = flags.row(y);
    for (int x = 0; x < flags.width; ++x) {
      if (!(fr[x] & kPixNew)) continue;
      Vec3f v, n;
      float w = 0.0f, r = 0.0f;
      if (!frame.measure(x, y, prm, v, n, w, r)) continue;  // cannot happen: kPixNew implies valid
      const Vec3f p = T_world_cam.apply(v), nw = T_world_cam.rotate(n);
      const Vec3f b = maps::kernels::anyPerpendicular(nw);
      s.pos_conf[i] = Vec4f(p.x(), p.y(), p.z(), w);
      s.normal_radius[i] = Vec4f(nw.x(), nw.y(), nw.z(), r);
      s.colour_flags[i] = maps::packColour(frame.colourAt(x, y),
                                           w >= prm.stable_confidence ? maps::kSurfelStable : 0u);
      s.t_init[i] = now;
      s.t_last[i] = now;
      s.basis[i] = b;
      const std::uint32_t l = frame.labels.empty() ? 0u : frame.labels(x, y);
      s.segment[i] = l;
      s.segment_w[i] = l != 0u ? w : 0.0f;
      updateViewBin(s, i, p, nw, b, T_world_cam.translation(), prm);
      pixel_surfel(x, y) = i;
      ++i;
    }
  }
};

/// Free-space carving (CarveTest) of the surfels of a rendered view, one per call, on their current
/// state (index-map path: after the updates). action[k]: CarveTest::Action of surfel visible[k];
/// kDecay / kDemote are applied here, kRemove is left to the caller.
struct CarveKernel {
  maps::SurfelArrays s;
  const int* visible = nullptr;
  RigidF T_cam_world;
  CarveTest test;
  std::uint8_t* action = nullptr;

  RASM_HD_INLINE void operator()(int k) const {
    action[k] = CarveTest::kKeep;
    const int i = visible[k];
    if (!test.violates(T_cam_world.apply(s.position(i)))) return;
    const CarveTest::Action a = test.action(s.colour_flags[i], s.pos_conf[i].w());
    if (a != CarveTest::kRemove) test.decay(s, i, a);
    action[k] = a;
  }
};

}  // namespace rasm::fusion::kernels

namespace rasm::fusion::cuda {
/// CUDA launcher of the association (on the 4x index map), update and neighbour coverage kernels
/// (cuda/FusionKernels.cu): the kernels hold HOST views and arrays; they are copied to the device,
/// the three passes run over the frame one after the other (c is skipped when
/// c.prm.neighbour_coverage_check is off), and the surfel arrays, pixel_surfel and flags are
/// copied back. Throws std::runtime_error without CUDA or a device.
void associateUpdate(const kernels::AssociateKernel<kernels::Map4xCandidates>& a,
                     const kernels::UpdateKernel& u,
                     const kernels::CoverageKernel<kernels::Map4xCandidates>& c);
}  // namespace rasm::fusion::cuda
