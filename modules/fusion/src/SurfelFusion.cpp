#include "rasm/fusion/SurfelFusion.h"
#include "rasm/core/Angles.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "rasm/core/ComputeOptions.h"
#include "rasm/core/Error.h"
#include "rasm/core/SurfelMath.h"
#include "rasm/core/Timing.h"
#include "rasm/fusion/FusionCpu.h"
#include "rasm/fusion/kernels/FusionKernels.h"

namespace rasm::fusion {

namespace {

RigidF toRigid(const Eigen::Isometry3d& T) {
  return RigidF::fromMatrix(T.matrix().cast<float>());
}

kernels::FusionKernelParams plainParams(const TFusionParams& p,
                                        const maps::SurfelStoreOptions& layout) {
  kernels::FusionKernelParams k;
  k.sigma = p.confidence_sigma;
  k.min_depth_m = p.min_depth_m;
  k.max_depth_m = p.max_depth_m;
  k.min_cos_incidence = std::cos(p.max_incidence_deg * kRadPerDegF);
  k.assoc_dz_abs_m = p.assoc_max_depth_diff_m;
  k.assoc_dz_rel = p.assoc_max_depth_diff_rel;
  k.min_cos_normal = std::cos(p.assoc_max_normal_angle_deg * kRadPerDegF);
  k.radius_update_ratio = p.radius_update_ratio;
  k.average_radius = p.average_radius;
  k.neighbour_coverage_check = p.neighbour_coverage_check;
  k.stable_confidence = p.stable_confidence;
  k.max_confidence = p.max_confidence;
  k.update_segments = p.update_segments;
  k.update_view_bins = p.update_view_bins && layout.nViewBins() > 0;
  k.ic_lambda1 = p.ic_lambda1;
  k.ic_d_min_m = p.ic_d_min_m;
  k.n_azimuth = layout.view_bins_azimuth;
  k.n_elevation = layout.view_bins_elevation;
  k.inv_block_size = 1.0f / layout.block_size_m;  // as VoxelBlockIndex computes block coordinates
  return k;
}

kernels::CarveTest carveTest(const TFusionParams& p, const FusionInput& in) {
  kernels::CarveTest t;
  t.depth_m = in.depth_m;
  t.K = in.K.plain();
  t.min_depth_m = p.min_depth_m;
  t.max_depth_m = p.max_depth_m;
  t.margin_abs_m = p.carve_margin_m;
  t.margin_rel = p.carve_margin_rel;
  t.stable_confidence = p.stable_confidence;
  t.stable_decay = p.carve_stable_decay;
  return t;
}

template <typename T>
void checkSize(const ImageView<const T>& v, const CameraIntrinsics& K, const char* what,
               bool optional) {
  if (optional && v.empty()) return;
  if (v.empty() || v.width != K.width || v.height != K.height) {
    std::ostringstream s;
    s << what << " is " << v.width << "x" << v.height << ", expected " << K.width << "x" << K.height
      << " (the intrinsics)";
    throwInputError("SurfelFusion input", s.str());
  }
}

kernels::FrameView frameView(const FusionInput& in) {
  kernels::FrameView f;
  f.colour = in.colour;
  f.vertex_cam = in.vertex_cam;
  f.normal_cam = in.normal_cam;
  f.labels = in.labels;
  f.K = in.K.plain();
  f.focal_px = float(0.5 * (std::fabs(in.K.fx) + std::fabs(in.K.fy)));
  return f;
}

}  // namespace

FusionInput makeFusionInput(const RgbdFrame& frame, const Image<Vec3f>& vertex_cam,
                            const Image<Vec3f>& normal_cam, const Eigen::Isometry3d& T_world_cam,
                            const Image<std::uint32_t>* labels) {
  FusionInput in;
  in.depth_m = frame.depth_m.view();
  if (!frame.colour.empty()) in.colour = frame.colour.view();
  in.vertex_cam = vertex_cam.view();
  in.normal_cam = normal_cam.view();
  in.K = frame.intrinsics;
  in.T_world_cam = T_world_cam;
  in.timestamp_s = frame.timestamp_s;
  if (labels && !labels->empty()) in.labels = labels->view();
  return in;
}

SurfelFusion::SurfelFusion(const TFusionParams& params, compute::Backend backend)
    : m_params(params), m_backend(backend), m_renderer(compute::Backend::Cpu) {
  setBackend(backend);
}

void SurfelFusion::setBackend(compute::Backend b) {
  m_backend = b;
  m_renderer.setBackend(b);
}

FusionStats SurfelFusion::fuse(maps::SurfelStore& map, const FusionInput& in) {
  FusionStats st = integrate(map, in);
  cleanup(map, in, st);
  return st;
}

namespace {

int threadId() {
#ifdef _OPENMP
  return omp_get_thread_num();
#else
  return 0;
#endif
}

/// Open-addressing int -> int table for the compaction remap of pixelSurfels(): O(removed) to
/// build, O(1) per pixel to look up, small enough to stay in cache.
struct RemapTable {
  std::vector<std::int32_t>& slots;  ///< key, value pairs; key -1 = empty
  std::uint32_t mask = 0;

  RemapTable(std::vector<std::int32_t>& storage, std::size_t entries) : slots(storage) {
    std::size_t cap = 16;
    while (cap < 2 * entries) cap *= 2;
    slots.assign(2 * cap, -1);
    mask = std::uint32_t(cap - 1);
  }
  static std::uint32_t hash(std::int32_t k) { return std::uint32_t(k) * 2654435761u; }
  void put(std::int32_t k, std::int32_t v) {
    std::uint32_t h = hash(k) & mask;
    while (slots[2 * h] != -1 && slots[2 * h] != k) h = (h + 1) & mask;
    slots[2 * h] = k;
    slots[2 * h + 1] = v;
  }
  /// True and v set when k is in the table.
  bool get(std::int32_t k, std::int32_t& v) const {
    for (std::uint32_t h = hash(k) & mask;; h = (h + 1) & mask) {
      if (slots[2 * h] == k) {
        v = slots[2 * h + 1];
        return true;
      }
      if (slots[2 * h] == -1) return false;
    }
  }
};

}  // namespace

bool SurfelFusion::scheduleValid(const maps::SurfelStore& map) const {
  return m_schedule_map == &map && m_schedule_generation == map.generation() &&
         m_schedule.size() == map.size() &&
         m_schedule.maxAge() == float(m_params.unstable_max_age_s) &&
         m_schedule.maxIdle() == float(m_params.unstable_max_idle_s);
}

void SurfelFusion::scheduleSeen(const maps::SurfelStore& map) {
  m_schedule_map = &map;
  m_schedule_generation = map.generation();
}

FusionStats SurfelFusion::integrate(maps::SurfelStore& map, const FusionInput& in) {
  FusionStats st;
  renderIndexMap(map, in, st);
  updateSurfels(map, in, st);
  addSurfels(map, in, st);
  return st;
}

SurfelFusion::FrameSetup SurfelFusion::setUpFrame(const maps::SurfelStore& map,
                                                  const FusionInput& in) {
  FrameSetup f;
  f.prm = plainParams(m_params, map.options());
  f.fv = frameView(in);
  const int w = in.K.width, h = in.K.height;
  if (!(m_weight_K == in.K) || m_weight_sigma != m_params.confidence_sigma) {
    // w = exp(-gamma^2 / (2 sigma^2)) (II-B) depends only on the pixel: tabulate it once.
    m_weight.resize(w, h);
    const PinholeF Kp = in.K.plain();
    const float sigma = m_params.confidence_sigma;
    compute::forEach2D(w, h, [&](int x, int y) {
      m_weight(x, y) = confidenceWeight(normalizedRadialDistance(float(x), float(y), Kp), sigma);
    });
    m_weight_K = in.K;
    m_weight_sigma = sigma;
  }
  f.fv.weight = m_weight.cview();
  f.T_wc = toRigid(in.T_world_cam);
  f.T_cw = toRigid(in.T_world_cam.inverse());
  f.now = map.toMapTime(in.timestamp_s);
  return f;
}

void SurfelFusion::requirePass(Pass expected, const char* pass) const {
  if (m_pass != expected)
    throw std::logic_error(std::string("SurfelFusion::") + pass +
                           ": the passes of one frame run in order (renderIndexMap, updateSurfels, "
                           "addSurfels, cleanup)");
}

IndexMapView SurfelFusion::indexMap() const {
  IndexMapView v;
  if (!m_index_fresh) return v;
  if (cpu())
    v.lists = &m_candidates;
  else
    v.packed = &m_index4x;
  return v;
}

IndexMapView SurfelFusion::renderIndexMap(maps::SurfelStore& map, const FusionInput& in,
                                          FusionStats& st) {
  if (!in.K.valid()) throwInputError("SurfelFusion input", "invalid intrinsics " + in.K.toString());
  checkSize(in.depth_m, in.K, "depth image", false);
  checkSize(in.vertex_cam, in.K, "vertex map", false);
  checkSize(in.normal_cam, in.K, "normal map", false);
  checkSize(in.colour, in.K, "colour image", true);
  checkSize(in.labels, in.K, "label image L^p", true);

  if (!map.hasTimeOrigin()) map.setTimeOrigin(in.timestamp_s);
  const float now = map.toMapTime(in.timestamp_s);
  const maps::SurfelStore& cmap = map;  // read access that does not count as a modification
  if (!scheduleValid(map))
    m_schedule.rebuild(cmap.arrays(), now, float(m_params.unstable_max_age_s),
                       float(m_params.unstable_max_idle_s));
  if (m_params.resort_unsorted_fraction < 1.0f && map.allIndexed() &&
      map.unsortedFraction() > m_params.resort_unsorted_fraction) {
    // Nothing of this frame holds surfel indices yet; the pruning schedule follows the sort.
    const auto t_sort = Clock::now();
    std::vector<int> new_of_old;  // (freed at once: 4 bytes per surfel at the sort's peak)
    map.sortByBlock(&new_of_old);
    m_schedule.permute(new_of_old);
    scheduleSeen(map);
    st.resorted = true;
    st.ms_resort = msSince(t_sort);
  }
  m_due_now.clear();
  const auto t0 = Clock::now();

  // 1. 4x point index map of every surfel in view (II-D).
  maps::RenderOptions& ro = m_index_options;
  ro = maps::RenderOptions();
  ro.min_depth_m = m_params.min_depth_m;
  // Surfels up to the association gate behind the far limit can still match a far pixel.
  ro.max_depth_m = m_params.max_depth_m * (1.0f + m_params.assoc_max_depth_diff_rel) +
                   m_params.assoc_max_depth_diff_m;
  ro.splat = false;
  // The CUDA backend associates on the packed 4x map; its merging runs the CPU's merge pass
  // (mergeCpu, on the host-resident map) over the same candidate lists the CPU path renders here,
  // so both backends merge the same pairs (the lists are rendered on the host: the cost of the
  // CUDA backend's merging, docs/architecture.md).
  if (cpu() || m_params.merge_redundant)
    m_renderer.renderCandidates4x(map, in.T_world_cam, in.K, ro, m_candidates, &st.render);
  if (!cpu()) m_renderer.renderIndexMap4x(map, in.T_world_cam, in.K, ro, m_index4x, &st.render);
  m_index_fresh = true;
  m_pass = Pass::Rendered;
  st.ms_index_map = msSince(t0);
  return indexMap();
}

void SurfelFusion::tallyRow(const maps::SurfelArrays& arr, int y) {
  const int t = threadId();
  std::array<int, 7>& c = m_counts[t];
  const std::uint16_t* f = m_flags.row(y);
  const std::int32_t* ps = m_pixel_surfel.row(y);
  int fresh = 0;
  for (int x = 0; x < m_flags.width(); ++x) {
    const std::uint16_t b = f[x];
    if (!b) continue;
    ++c[0];
    c[1] += (b & kernels::kPixAssociated) != 0;
    c[2] += (b & kernels::kPixFused) != 0;
    c[3] += (b & kernels::kPixBecameStable) != 0;
    if (b & kernels::kPixRelabelled) {
      ++c[4];
      c[6] += (arr.colour_flags[ps[x]] & maps::kSurfelStable) != 0;
    }
    c[5] += (b & kernels::kPixCovered) != 0;
    fresh += (b & kernels::kPixNew) != 0;
    if (b & kernels::kPixCrossedBlock) m_thread_lists[t].push_back(ps[x]);
    if (b & kernels::kPixBecameStable) m_stable_lists[t].push_back(ps[x]);
  }
  m_row_offset[y + 1] = fresh;
}

void SurfelFusion::associateUpdateCpu(const kernels::AssociateKernel<kernels::ListCandidates>& ak,
                                      const kernels::UpdateKernel& uk,
                                      const kernels::CoverageKernel<kernels::ListCandidates>& ck,
                                      const maps::SurfelArrays& arr) {
  const int w = m_flags.width(), h = m_flags.height(), nt = compute::maxThreads();
  const kernels::FusionKernelParams& prm = uk.prm;
  const bool labels = prm.update_segments && !uk.frame.labels.empty();
  const bool bins = prm.update_view_bins && arr.n_view_bins > 0;
  // The association keeps each measured pixel's measurement for the update and the neighbour
  // coverage, which would otherwise measure the pixel again (the same values:
  // FrameView::measure); two rows per thread, as the coverage of row y - 1 follows the update of
  // row y (below). Both launchers prefetch the surfels a few pixels ahead: they are spread over
  // the map's memory. (SSE, bit-identical to the kernels.)
  std::vector<std::vector<KeptMeasurement>> kept(nt, std::vector<KeptMeasurement>(2 * w));
  const auto keptRow = [&](int y) { return kept[threadId()].data() + (y & 1) * w; };
  if (bins) m_ic.build(prm.ic_lambda1, prm.ic_d_min_m);
  const bool cover = prm.neighbour_coverage_check;
  const auto coverRowMeasuring = [&](int y) {
    for (int x = 0; x < w; ++x) ck(x, y);
    tallyRow(arr, y);
  };
  // Row bands: in a band, row y is associated and updated, then the coverage of row y - 1 runs
  // while its neighbourhood is in cache (rows y - 2 .. y are final). The first and last row of
  // a band border another band: their coverage waits for every band.
  const int nbands = nt <= 1 ? 1 : std::min(h, 4 * nt);
  const auto band = [&](int b) {
    return std::pair<int, int>(int(std::int64_t(h) * b / nbands),
                               int(std::int64_t(h) * (b + 1) / nbands));
  };
#pragma omp parallel num_threads(nt)
  {
#pragma omp for schedule(dynamic, 1)
    for (int b = 0; b < nbands; ++b) {
      const auto [lo, hi] = band(b);
      for (int y = lo; y < hi; ++y) {
        associateRowCpu(ak, y, keptRow(y));
        updateRowCpu(uk, y, keptRow(y), labels, bins, bins ? &m_ic : nullptr);
        if (!cover) {
          tallyRow(arr, y);
        } else if (y - 1 > lo) {
          coverRowCpu(ck, y - 1, keptRow(y - 1));
          if (y - 1 < hi - 1) tallyRow(arr, y - 1);
        }
      }
    }
    if (cover) {
#pragma omp for schedule(dynamic, 1)
      for (int b = 0; b < nbands; ++b) {
        const auto [lo, hi] = band(b);
        if (hi > lo) coverRowMeasuring(lo);
        if (hi - 1 > lo) coverRowMeasuring(hi - 1);
      }
    }
  }
}

void SurfelFusion::updateSurfels(maps::SurfelStore& map, const FusionInput& in, FusionStats& st) {
  requirePass(Pass::Rendered, "updateSurfels");
  const auto t0 = Clock::now();
  const FrameSetup fs = setUpFrame(map, in);
  const int w = in.K.width, h = in.K.height;

  // 2. association (read-only, every pixel), then the update of the chosen surfels.
  m_pixel_surfel.resize(w, h);
  m_flags.resize(w, h);
  const maps::SurfelArrays arr = map.arrays();
  kernels::UpdateKernel uk;
  uk.frame = fs.fv;
  uk.prm = fs.prm;
  uk.s = arr;
  uk.T_world_cam = fs.T_wc;
  uk.T_cam_world = fs.T_cw;
  uk.now = fs.now;
  uk.pixel_surfel = m_pixel_surfel.cview();
  uk.flags = m_flags.view();
  // On the CPU the carving verdict on each updated surfel is taken right after its update (its
  // state does not change before the cleanup applies it); the other visible surfels are judged by
  // the cleanup on the centres the projection computed.
  uk.carve = cpu() && m_params.carve_free_space;
  uk.carve_test = carveTest(m_params, in);
  // Per row, once its flags are final (tallyRow): statistics, the row's count of new surfels (the
  // prefix sum below turns the counts into first indices) and the updated surfels that crossed a
  // block border (re-binned in the spatial index).
  const int nt = compute::maxThreads();
  m_thread_lists.resize(nt);
  for (auto& l : m_thread_lists) l.clear();
  m_stable_lists.resize(nt);
  for (auto& l : m_stable_lists) l.clear();
  m_counts.assign(nt, std::array<int, 7>{});
  m_row_offset.assign(h + 1, 0);
  // Association and neighbour-coverage kernels over either candidate source (CPU lists, CUDA
  // 4x index map): the same frame, map, poses and per-pixel outputs.
  const auto setUpKernels = [&](auto& ak, auto& ck, const auto& candidates) {
    ak.frame = ck.frame = fs.fv;
    ak.prm = ck.prm = fs.prm;
    ak.candidates = ck.candidates = candidates;
    ak.s = ck.s = arr;
    ak.T_world_cam = ck.T_world_cam = fs.T_wc;
    ck.T_cam_world = fs.T_cw;
    ak.pixel_surfel = ck.pixel_surfel = m_pixel_surfel.view();
    ak.flags = ck.flags = m_flags.view();
  };
  if (cpu()) {
    kernels::ListCandidates lists;
    lists.entries = m_candidates.entries.data();
    lists.first = m_candidates.first.data();
    lists.count = m_candidates.count.data();
    lists.width = w;
    lists.height = h;
    kernels::AssociateKernel<kernels::ListCandidates> ak;
    kernels::CoverageKernel<kernels::ListCandidates> ck;
    setUpKernels(ak, ck, lists);
    if (compute::simdEnabled(compute::SimdPath::Fusion)) {
      associateUpdateCpu(ak, uk, ck, arr);
    } else {
      // [compute] simd = false: the kernel bodies alone, in the CUDA path's order (association
      // of every pixel, update, then the neighbour coverage over the updated surfels).
      compute::forEach2D(w, h, ak);
      compute::forEach2D(w, h, uk);
      if (fs.prm.neighbour_coverage_check) compute::forEach2D(w, h, ck);
#pragma omp parallel for schedule(static) num_threads(nt)
      for (int y = 0; y < h; ++y) tallyRow(arr, y);
    }
  } else {
    kernels::Map4xCandidates map4x;
    map4x.index4x = m_index4x.packed.cview();
    map4x.s = arr;
    map4x.T_cam_world = fs.T_cw;
    map4x.width = w;
    map4x.height = h;
    kernels::AssociateKernel<kernels::Map4xCandidates> ak;
    kernels::CoverageKernel<kernels::Map4xCandidates> ck;
    setUpKernels(ak, ck, map4x);
    cuda::associateUpdate(ak, uk, ck);
#pragma omp parallel for schedule(static) num_threads(nt)
    for (int y = 0; y < h; ++y) tallyRow(arr, y);
  }
  st.ms_update = msSince(t0);
  m_pass = Pass::Updated;
}

void SurfelFusion::addSurfels(maps::SurfelStore& map, const FusionInput& in, FusionStats& st) {
  requirePass(Pass::Updated, "addSurfels");
  const auto t0 = Clock::now();
  const FrameSetup fs = setUpFrame(map, in);
  const int h = in.K.height;
  const int nt = int(m_counts.size());

  // 3. new surfels: per-row counts (tallyRow), exclusive prefix sum, row-parallel writes in
  // pixel order.
  for (int y = 0; y < h; ++y) m_row_offset[y + 1] += m_row_offset[y];
  const int added = m_row_offset[h];
  const int first = map.allocate(added);
  for (int y = 0; y <= h; ++y) m_row_offset[y] += first;
  kernels::NewSurfelKernel nk;
  nk.frame = fs.fv;
  nk.prm = fs.prm;
  nk.s = map.arrays();  // after allocate(): the arrays may have moved
  nk.T_world_cam = fs.T_wc;
  nk.now = fs.now;
  nk.flags = m_flags.cview();
  nk.row_first = m_row_offset.data();
  nk.pixel_surfel = m_pixel_surfel.view();
  compute::forEach1D(h, nk);
  map.indexAppended();

  std::vector<int>& movers = m_removed;
  movers.clear();
  for (int t = 0; t < nt; ++t) {
    st.valid_pixels += m_counts[t][0];
    st.associated += m_counts[t][1];
    st.fused += m_counts[t][2];
    st.became_stable += m_counts[t][3];
    st.relabelled += m_counts[t][4];
    st.relabelled_stable += m_counts[t][6];
    st.covered += m_counts[t][5];
    movers.insert(movers.end(), m_thread_lists[t].begin(), m_thread_lists[t].end());
  }
  // In surfel order, not the thread schedule's: the order of the index's member lists (and with
  // it the order sortByBlock() gives the store) must not depend on the thread count.
  std::sort(movers.begin(), movers.end());
  map.reindex(movers);
  std::vector<int>& became_stable = m_stable_changed;
  became_stable.clear();
  for (const auto& l : m_stable_lists)
    became_stable.insert(became_stable.end(), l.begin(), l.end());
  std::sort(became_stable.begin(), became_stable.end());
  map.refreshStable(became_stable);  // the index keeps stable surfels first

  // New surfels enter the pruning schedule.
  m_schedule.grow(map.size());
  const maps::SurfelArrays a = static_cast<const maps::SurfelStore&>(map).arrays();
  for (int i = first; i < first + added; ++i)
    if (!(a.colour_flags[i] & maps::kSurfelStable) && m_schedule.file(a, i, fs.now))
      m_due_now.push_back(i);
  scheduleSeen(map);

  st.ms_add = msSince(t0);
  st.added = added;
  st.map_size = map.size();
  m_pass = Pass::Added;
}

void SurfelFusion::mergeCpu(maps::SurfelStore& map, std::vector<int>& removed) {
  const maps::SurfelArrays a = map.arrays();
  const kernels::FusionKernelParams prm = plainParams(m_params, map.options());
  kernels::MergeTest test;
  test.min_cos_normal = std::cos(m_params.merge_max_normal_angle_deg * kRadPerDegF);
  test.dz_abs_m = m_params.assoc_max_depth_diff_m;
  test.dz_rel = m_params.assoc_max_depth_diff_rel;
  const std::uint64_t* excluded = m_remap_bits.data();
  const auto isExcluded = [excluded](int i) { return (excluded[i >> 6] >> (i & 63)) & 1u; };
  const int w = m_candidates.width, h = m_candidates.height;
  const maps::kernels::CameraPoint* entries = m_candidates.entries.data();
  const std::uint32_t* first = m_candidates.first.data();
  const int nt = compute::maxThreads();
  // Per thread: (loser, kept) pairs and survivors that crossed a block border.
  std::vector<std::vector<std::pair<int, int>>> pairs(nt);
  std::vector<std::vector<int>> crossed(nt);
  const int stride = std::max(1, m_params.merge_row_stride);
  const int row0 = int(m_merge_round++ % std::uint64_t(stride));
  const int n_rows = row0 < h ? (h - row0 + stride - 1) / stride : 0;
  // Every surfel is in the list of exactly one pixel (its centre's), and merging only touches
  // surfels of one list: rows run in parallel without races.
#pragma omp parallel num_threads(nt)
  {
    const int t = threadId();
    constexpr int kMaxList = 32;  // longer lists (rare) are left alone
    constexpr int kAhead = 6;
    bool gone[kMaxList];
    int idx[kMaxList];
    float z[kMaxList];
#pragma omp for schedule(dynamic, 8)
    for (int r = 0; r < n_rows; ++r) {
      const int y = row0 + r * stride;
      for (int x = 0; x < w; ++x) {
        const std::size_t p = std::size_t(y) * w + x;
        if (x + kAhead < w) {  // the lists' surfels are spread over the map's memory
          const std::uint32_t e = first[p + kAhead + 1];
          if (e - first[p + kAhead] >= 2)
            for (std::uint32_t q = first[p + kAhead]; q < e; ++q) {
              __builtin_prefetch(&a.pos_conf[entries[q].index]);
              __builtin_prefetch(&a.normal_radius[entries[q].index]);
            }
        }
        const std::uint32_t q0 = first[p];
        const int n = int(first[p + 1] - q0);
        if (n < 2 || n > kMaxList) continue;
        // The renderer's order within a list depends on the thread schedule: merge in surfel
        // index order so that the result does not.
        for (int k = 0; k < n; ++k) {
          const maps::kernels::CameraPoint& cp = entries[q0 + k];
          int m = k;
          for (; m > 0 && idx[m - 1] > cp.index; --m) {
            idx[m] = idx[m - 1];
            z[m] = z[m - 1];
          }
          idx[m] = cp.index;
          z[m] = cp.pc.z();
        }
        for (int k = 0; k < n; ++k) gone[k] = isExcluded(idx[k]);
        for (int k = 0; k < n; ++k) {
          if (gone[k]) continue;
          int cur = k;
          for (int m = k + 1; m < n; ++m) {
            if (gone[m]) continue;
            const int i = idx[cur], j = idx[m];
            if (!test.redundant(a, i, j, z[cur])) continue;
            // The surfel with more confidence (the older on ties) absorbs the other.
            const bool keep_i = a.pos_conf[i].w() > a.pos_conf[j].w() ||
                                (a.pos_conf[i].w() == a.pos_conf[j].w() && i < j);
            const int keep = keep_i ? i : j, lose = keep_i ? j : i;
            if (kernels::mergeSurfels(a, keep, lose, prm)) crossed[t].push_back(keep);
            pairs[t].emplace_back(lose, keep);
            gone[keep_i ? m : cur] = true;
            if (!keep_i) cur = m;
          }
        }
      }
    }
  }
  std::vector<int>& kept = m_stable_changed;
  kept.clear();
  for (int t = 0; t < nt; ++t) {
    for (const auto& pr : pairs[t]) {
      removed.push_back(pr.first);
      m_merged.push_back(pr);
      kept.push_back(pr.second);
    }
  }
  std::sort(kept.begin(), kept.end());  // (schedule-independent order, as in integrate())
  map.refreshStable(kept);              // summed confidence may have made a survivor stable
  // A survivor may be listed twice; one that was merged on later is removed (reindex of a
  // removed surfel is harmless: the removal drops it from the index).
  std::vector<int> movers;
  for (auto& c : crossed) movers.insert(movers.end(), c.begin(), c.end());
  if (!movers.empty()) {
    std::sort(movers.begin(), movers.end());
    movers.erase(std::unique(movers.begin(), movers.end()), movers.end());
    map.reindex(movers);
  }
}

void SurfelFusion::carveCpu(const maps::SurfelStore& map, const FusionInput& in,
                            std::vector<int>& removed, std::vector<int>& demoted) {
  // Updated surfels: the verdict the update pass recorded in their pixel's flags.
  const maps::SurfelArrays a = map.arrays();
  const kernels::CarveTest test = carveTest(m_params, in);
  const int w = m_flags.width(), h = m_flags.height();
  const int nt = compute::maxThreads();
  m_thread_lists.resize(2 * std::size_t(nt));
  for (auto& l : m_thread_lists) l.clear();
#pragma omp parallel num_threads(nt)
  {
    const int t = threadId();
    std::vector<int>& rem = m_thread_lists[2 * t];
    std::vector<int>& dem = m_thread_lists[2 * t + 1];
    const auto act = [&](int i, kernels::CarveTest::Action action) {
      if (action == kernels::CarveTest::kRemove) {
        rem.push_back(i);
      } else if (action != kernels::CarveTest::kKeep) {
        test.decay(a, i, action);
        if (action == kernels::CarveTest::kDemote) dem.push_back(i);
      }
    };
#pragma omp for schedule(static) nowait
    for (int y = 0; y < h; ++y) {
      const std::uint16_t* f = m_flags.row(y);
      const std::int32_t* ps = m_pixel_surfel.row(y);
      for (int x = 0; x < w; ++x) {
        const int v = (f[x] >> kernels::kPixCarveShift) & 3;
        if (v) act(ps[x], kernels::CarveTest::Action(v));
      }
    }
    // The other surfels of the view are unchanged since the projection: judge them on the
    // centres it computed, pixel by pixel (a surfel of pixel p's list projects onto p: pixelOf
    // of its centre is its 4x sub-pixel / 4). A surfel was updated iff its pixel chose it.
    const maps::kernels::CameraPoint* entries = m_candidates.entries.data();
    const std::uint32_t* first = m_candidates.first.data();
#pragma omp for schedule(static) nowait
    for (int y = 1; y < h - 1; ++y) {  // (violatesAt: border pixels have no 3x3 evidence)
      const std::int32_t* ps = m_pixel_surfel.row(y);
      const float* depth = in.depth_m.row(y);
      for (int x = 1; x < w - 1; ++x) {
        const std::size_t p = std::size_t(y) * w + x;
        const std::uint32_t q0 = first[p], q1 = first[p + 1];
        if (q0 == q1) continue;
        const float dc = depth[x];
        const float margin = maps::kernels::maxF(test.margin_abs_m, test.margin_rel * dc);
        for (std::uint32_t q = q0; q < q1; ++q) {
          const maps::kernels::CameraPoint& cp = entries[q];
          if (!test.inFrontOf(cp.pc.z(), dc, margin) || cp.index == ps[x] ||
              !test.inFrontOfNeighbourhood(cp.pc.z(), x, y))
            continue;
          act(cp.index, test.action(a.colour_flags[cp.index], a.pos_conf[cp.index].w()));
        }
      }
    }
    const maps::kernels::CameraPoint* others = m_candidates.others.data();
    const int n_others = int(m_candidates.others.size());
#pragma omp for schedule(static) nowait
    for (int k = 0; k < n_others; ++k) {
      const maps::kernels::CameraPoint& cp = others[k];
      if (test.violates(cp.pc))
        act(cp.index, test.action(a.colour_flags[cp.index], a.pos_conf[cp.index].w()));
    }
  }
  for (int t = 0; t < nt; ++t) {
    removed.insert(removed.end(), m_thread_lists[2 * t].begin(), m_thread_lists[2 * t].end());
    demoted.insert(demoted.end(), m_thread_lists[2 * t + 1].begin(),
                   m_thread_lists[2 * t + 1].end());
  }
}

void SurfelFusion::carveVisible(maps::SurfelStore& map, const FusionInput& in,
                                std::vector<int>& removed, std::vector<int>& demoted) {
  if (cpu()) {  // entries + others: every visible surfel (PointCandidates4x)
    m_visible.clear();
    for (const maps::kernels::CameraPoint& cp : m_candidates.entries) m_visible.push_back(cp.index);
    for (const maps::kernels::CameraPoint& cp : m_candidates.others) m_visible.push_back(cp.index);
  }
  const std::vector<int>& vis = cpu() ? m_visible : m_index4x.visible;
  std::vector<std::uint8_t> action(vis.size());
  kernels::CarveKernel ck;
  ck.s = map.arrays();
  ck.visible = vis.data();
  ck.T_cam_world = toRigid(in.T_world_cam.inverse());
  ck.test = carveTest(m_params, in);
  ck.action = action.data();
  compute::forEach1D(int(vis.size()), ck);
  for (std::size_t k = 0; k < vis.size(); ++k) {
    if (action[k] == kernels::CarveTest::kRemove)
      removed.push_back(vis[k]);
    else if (action[k] == kernels::CarveTest::kDemote)
      demoted.push_back(vis[k]);
  }
}

void SurfelFusion::remapPixelSurfels(const std::vector<int>& removed,
                                     const std::vector<std::pair<int, int>>& moved, int old_size) {
  // Keep pixelSurfels() valid: removed -> -1, moved -> new index. A bit per surfel index (kept
  // between frames, set and cleared only for the affected ones) filters the pixels cheaply.
  if (m_pixel_surfel.empty()) return;
  RemapTable table(m_remap_table, removed.size() + moved.size());
  if (m_remap_bits.size() < std::size_t(old_size / 64 + 1))
    m_remap_bits.resize(old_size / 64 + 1, 0);
  std::uint64_t* bits = m_remap_bits.data();
  for (int i : removed) {
    table.put(i, -1);
    bits[i >> 6] |= std::uint64_t(1) << (i & 63);
  }
  for (const auto& [from, to] : moved) {  // `from` is never a removed one
    table.put(from, to);
    bits[from >> 6] |= std::uint64_t(1) << (from & 63);
  }
  // Merged surfels: their pixels now refer to the surfel they were merged into (where that
  // one went). m_merged is in merge order and a kept surfel may itself be merged later in its
  // pixel's chain: resolve from the last pair back.
  for (auto it = m_merged.rbegin(); it != m_merged.rend(); ++it) {
    std::int32_t v = it->second;
    table.get(it->second, v);  // moved -> new index, removed (or merged on) -> its target
    table.put(it->first, v);
  }
  const int w = m_pixel_surfel.width(), h = m_pixel_surfel.height();
  compute::forEach1D(h, [&](int y) {
    std::int32_t* r = m_pixel_surfel.row(y);
    for (int x = 0; x < w; ++x) {
      const std::int32_t i = r[x];
      std::int32_t v;
      if (i >= 0 && (bits[i >> 6] >> (i & 63) & 1u) && table.get(i, v)) r[x] = v;
    }
  });
  for (int i : removed) bits[i >> 6] = 0;
  for (const auto& fm : moved) bits[fm.first >> 6] = 0;
}

void SurfelFusion::cleanup(maps::SurfelStore& map, const FusionInput& in, FusionStats& st) {
  const auto t_start = std::chrono::steady_clock::now();
  const auto finish = [&] {
    st.map_size = map.size();
    scheduleSeen(map);
    st.ms_cleanup +=
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t_start)
            .count();
  };
  const bool index_fresh = m_index_fresh && m_pass == Pass::Added;
  m_index_fresh = false;  // the view refers to indices that the removal below invalidates
  m_pass = Pass::None;
  const float now = map.toMapTime(in.timestamp_s);
  const maps::SurfelStore& cmap = map;
  if (!scheduleValid(map)) {
    m_schedule.rebuild(cmap.arrays(), now, float(m_params.unstable_max_age_s),
                       float(m_params.unstable_max_idle_s));
    m_due_now.clear();
  }
  std::vector<int>& removed = m_removed;
  std::vector<int>& demoted = m_demoted;
  removed.clear();
  demoted.clear();

  // Free-space carving over the surfels of the rendered view (II-D). Surfels added this frame are
  // not in the view; surfels updated this frame sit at the measured depth. One rule (CarveTest),
  // two traversals that select the same surfels (SurfelFusion.CarvingTraversalsAgree).
  if (m_params.carve_free_space && index_fresh) {
    if (cpu() && compute::simdEnabled(compute::SimdPath::Fusion))
      carveCpu(map, in, removed, demoted);
    else
      carveVisible(map, in, removed, demoted);
    // (sorted: the order of the per-thread lists depends on the schedule)
    std::sort(removed.begin(), removed.end());
    std::sort(demoted.begin(), demoted.end());
  }
  st.removed_carved = int(removed.size());
  st.demoted_carved = int(demoted.size());
  map.refreshStable(demoted);

  // Redundant-surfel merging over the view (Keller et al. 2013). Carved and demoted surfels take
  // no part (marked in m_remap_bits, all zero between frames).
  m_merged.clear();
  if (m_params.merge_redundant && index_fresh) {  // (both backends: see renderIndexMap)
    if (m_remap_bits.size() < std::size_t(map.size() / 64 + 1))
      m_remap_bits.resize(map.size() / 64 + 1, 0);
    for (int i : removed) m_remap_bits[i >> 6] |= std::uint64_t(1) << (i & 63);
    for (int i : demoted) m_remap_bits[i >> 6] |= std::uint64_t(1) << (i & 63);
    mergeCpu(map, removed);
    for (int i : removed) m_remap_bits[i >> 6] = 0;
    for (int i : demoted) m_remap_bits[i >> 6] = 0;
  }
  st.merged = int(m_merged.size());
  const std::size_t n_carved_merged = removed.size();

  // Unstable surfels older than unstable_max_age_s or not fused for unstable_max_idle_s (II-D):
  // those whose time has come in the schedule, the surfels carving just demoted, and new surfels
  // that were due at once.
  const maps::SurfelArrays a = cmap.arrays();
  for (int i : demoted)
    if (m_schedule.file(a, i, now)) removed.push_back(i);
  m_schedule.collectDue(a, now, removed);
  for (int i : m_due_now) removed.push_back(i);
  m_due_now.clear();
  std::sort(removed.begin(), removed.end());
  removed.erase(std::unique(removed.begin(), removed.end()), removed.end());
  st.removed_unstable = int(removed.size() - std::min(removed.size(), n_carved_merged));
  // (a surfel both carved and old is counted as carved; merged ones are never carved)
  if (removed.empty()) {
    finish();
    return;
  }

  std::vector<std::pair<int, int>>& moved = m_moved;
  const int old_size = map.size();
  map.remove(removed, &moved);
  m_schedule.moved(moved, map.size());

  remapPixelSurfels(removed, moved, old_size);
  finish();
}

#ifndef RASM_HAVE_CUDA
namespace cuda {
void associateUpdate(const kernels::AssociateKernel<kernels::Map4xCandidates>&,
                     const kernels::UpdateKernel&,
                     const kernels::CoverageKernel<kernels::Map4xCandidates>&) {
  throw std::runtime_error("rasm was built without CUDA (RASM_WITH_CUDA=OFF or no nvcc)");
}
}  // namespace cuda
#endif

}  // namespace rasm::fusion
