#include "rasm/fusion/SurfelFusion.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "rasm/core/Error.h"
#include "rasm/core/SurfelMath.h"
#include "rasm/fusion/kernels/FusionKernels.h"

namespace rasm::fusion {

namespace {

constexpr float kDegToRad = 3.14159265358979f / 180.0f;

RigidF toRigid(const Eigen::Isometry3d& T) { return RigidF::fromMatrix(T.matrix().cast<float>()); }

kernels::FusionKernelParams plainParams(const TFusionParams& p,
                                        const maps::SurfelStoreOptions& layout) {
  kernels::FusionKernelParams k;
  k.sigma = p.confidence_sigma;
  k.min_depth_m = p.min_depth_m;
  k.max_depth_m = p.max_depth_m;
  k.min_cos_incidence = std::cos(p.max_incidence_deg * kDegToRad);
  k.assoc_dz_abs_m = p.assoc_max_depth_diff_m;
  k.assoc_dz_rel = p.assoc_max_depth_diff_rel;
  k.min_cos_normal = std::cos(p.assoc_max_normal_angle_deg * kDegToRad);
  k.radius_update_ratio = p.radius_update_ratio;
  k.neighbour_coverage_check = p.neighbour_coverage_check;
  k.stable_confidence = p.stable_confidence;
  k.max_confidence = p.max_confidence;
  k.update_segments = p.update_segments;
  k.update_view_bins = p.update_view_bins && layout.nViewBins() > 0;
  k.ic_lambda1 = p.ic_lambda1;
  k.ic_d_min_m = p.ic_d_min_m;
  k.n_azimuth = layout.view_bins_azimuth;
  k.n_elevation = layout.view_bins_elevation;
  return k;
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

FusionStats SurfelFusion::integrate(maps::SurfelStore& map, const FusionInput& in) {
  if (!in.K.valid()) throwInputError("SurfelFusion input", "invalid intrinsics " + in.K.toString());
  checkSize(in.depth_m, in.K, "depth image", false);
  checkSize(in.vertex_cam, in.K, "vertex map", false);
  checkSize(in.normal_cam, in.K, "normal map", false);
  checkSize(in.colour, in.K, "colour image", true);
  checkSize(in.labels, in.K, "label image L^p", true);

  FusionStats st;
  const int w = in.K.width, h = in.K.height;
  if (!map.hasTimeOrigin()) map.setTimeOrigin(in.timestamp_s);
  const float now = map.toMapTime(in.timestamp_s);
  const kernels::FusionKernelParams prm = plainParams(m_params, map.options());
  kernels::FrameView fv = frameView(in);
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
  fv.weight = m_weight.cview();
  const RigidF T_wc = toRigid(in.T_world_cam), T_cw = toRigid(in.T_world_cam.inverse());

  using Clock = std::chrono::steady_clock;
  const auto ms = [](Clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
  };
  auto t0 = Clock::now();

  // 1. 4x point index map of every surfel in view (II-D).
  maps::RenderOptions ro;
  ro.min_depth_m = m_params.min_depth_m;
  // Surfels up to the association gate behind the far limit can still match a far pixel.
  ro.max_depth_m = m_params.max_depth_m * (1.0f + m_params.assoc_max_depth_diff_rel) +
                   m_params.assoc_max_depth_diff_m;
  ro.splat = false;
  m_renderer.renderIndexMap4x(map, in.T_world_cam, in.K, ro, m_index4x, &st.render);
  m_index_fresh = true;
  st.ms_index_map = ms(t0);
  t0 = Clock::now();

  // 2. association + update, per pixel.
  m_pixel_surfel.resize(w, h);
  m_flags.resize(w, h);
  kernels::AssociateUpdateKernel au;
  au.frame = fv;
  au.prm = prm;
  au.index4x = m_index4x.packed.cview();
  au.s = map.arrays();
  au.T_world_cam = T_wc;
  au.T_cam_world = T_cw;
  au.now = now;
  au.pixel_surfel = m_pixel_surfel.view();
  au.flags = m_flags.view();
  if (m_backend == compute::Backend::Cuda)
    cuda::associateUpdate(au);
  else
    compute::forEach2D(w, h, au);

  st.ms_update = ms(t0);
  t0 = Clock::now();

  // 3. new surfels: per-row counts, exclusive prefix sum, row-parallel writes in pixel order.
  m_row_offset.assign(h + 1, 0);
  compute::forEach1D(h, kernels::RowCountKernel{m_flags.cview(), m_row_offset.data() + 1});
  for (int y = 0; y < h; ++y) m_row_offset[y + 1] += m_row_offset[y];
  const int added = m_row_offset[h];
  const int first = map.allocate(added);
  for (int y = 0; y <= h; ++y) m_row_offset[y] += first;
  kernels::NewSurfelKernel nk;
  nk.frame = fv;
  nk.prm = prm;
  nk.s = map.arrays();  // after allocate(): the arrays may have moved
  nk.T_world_cam = T_wc;
  nk.now = now;
  nk.flags = m_flags.cview();
  nk.row_first = m_row_offset.data();
  nk.pixel_surfel = m_pixel_surfel.view();
  compute::forEach1D(h, nk);
  map.indexAppended();

  // Statistics and the surfels whose position moved (re-binned in the spatial index).
  m_scratch.clear();
  for (int y = 0; y < h; ++y) {
    const std::uint8_t* f = m_flags.row(y);
    const std::int32_t* ps = m_pixel_surfel.row(y);
    for (int x = 0; x < w; ++x) {
      const std::uint8_t b = f[x];
      if (!b) continue;
      ++st.valid_pixels;
      if (b & kernels::kPixAssociated) ++st.associated;
      if (b & kernels::kPixFused) {
        ++st.fused;
        m_scratch.push_back(ps[x]);
      }
      if (b & kernels::kPixBecameStable) ++st.became_stable;
      if (b & kernels::kPixRelabelled) ++st.relabelled;
      if (b & kernels::kPixCovered) ++st.covered;
    }
  }
  map.reindex(m_scratch);
  st.ms_add = ms(t0);
  st.added = added;
  st.map_size = map.size();
  return st;
}

void SurfelFusion::cleanup(maps::SurfelStore& map, const FusionInput& in, FusionStats& st) {
  const auto t_start = std::chrono::steady_clock::now();
  const auto finish = [&] {
    st.map_size = map.size();
    st.ms_cleanup +=
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t_start)
            .count();
  };
  const bool index_fresh = m_index_fresh;
  m_index_fresh = false;  // the view list refers to indices that the removal below invalidates
  const maps::SurfelArrays a = map.arrays();
  std::vector<int>& removed = m_scratch;
  removed.clear();

  // Free-space carving over the surfels of the rendered view (II-D). Surfels added this frame are
  // not in the view list; surfels updated this frame sit at the measured depth.
  if (m_params.carve_free_space && index_fresh && !m_index4x.visible.empty()) {
    const std::vector<int>& vis = m_index4x.visible;
    std::vector<std::uint8_t> action(vis.size());
    kernels::CarveKernel ck;
    ck.s = a;
    ck.visible = vis.data();
    ck.T_cam_world = toRigid(in.T_world_cam.inverse());
    ck.K = in.K.plain();
    ck.depth_m = in.depth_m;
    ck.min_depth_m = m_params.min_depth_m;
    ck.max_depth_m = m_params.max_depth_m;
    ck.margin_abs_m = m_params.carve_margin_m;
    ck.margin_rel = m_params.carve_margin_rel;
    ck.stable_confidence = m_params.stable_confidence;
    ck.stable_decay = m_params.carve_stable_decay;
    ck.action = action.data();
    compute::forEach1D(int(vis.size()), ck);
    for (std::size_t k = 0; k < vis.size(); ++k) {
      if (action[k] == 1) {
        removed.push_back(vis[k]);
        ++st.removed_carved;
      } else if (action[k] == 3) {
        ++st.demoted_carved;
      }
    }
  }

  // Unstable surfels older than the time window, or not fused for unstable_max_idle_s (II-D).
  // O(N) scan of three arrays (~1-2 ms per million surfels); per-thread lists concatenated in
  // thread order keep it deterministic.
  const float now = map.toMapTime(in.timestamp_s);
  const float max_age = float(m_params.unstable_max_age_s);
  const float max_idle = float(m_params.unstable_max_idle_s);
  const int nt = compute::maxThreads();
  std::vector<std::vector<int>> old_lists(nt);
#pragma omp parallel num_threads(nt)
  {
#ifdef _OPENMP
    const int t = omp_get_thread_num();
    const int tn = omp_get_num_threads();
#else
    const int t = 0, tn = 1;
#endif
    const int begin = int(std::int64_t(a.size) * t / tn),
              end = int(std::int64_t(a.size) * (t + 1) / tn);
    for (int i = begin; i < end; ++i)
      if (!(a.colour_flags[i] & maps::kSurfelStable) &&
          (now - a.t_init[i] > max_age || now - a.t_last[i] > max_idle))
        old_lists[t].push_back(i);
  }
  const std::size_t n_carved = removed.size();
  for (const auto& l : old_lists) removed.insert(removed.end(), l.begin(), l.end());
  std::sort(removed.begin(), removed.end());
  removed.erase(std::unique(removed.begin(), removed.end()), removed.end());
  st.removed_unstable = int(removed.size() - std::min(removed.size(), n_carved));
  // (a surfel both carved and old is counted as carved)
  if (removed.empty()) {
    finish();
    return;
  }

  std::vector<std::pair<int, int>> moved;
  map.remove(removed, &moved);

  // Keep pixelSurfels() valid: removed -> -1, moved -> new index.
  std::sort(moved.begin(), moved.end());
  const int lowest = removed.front();
  if (!m_pixel_surfel.empty()) {
    const int w = m_pixel_surfel.width(), h = m_pixel_surfel.height();
    compute::forEach1D(h, [&](int y) {
      std::int32_t* r = m_pixel_surfel.row(y);
      for (int x = 0; x < w; ++x) {
        const int i = r[x];
        if (i < lowest) continue;
        if (std::binary_search(removed.begin(), removed.end(), i)) {
          r[x] = -1;
          continue;
        }
        auto it = std::lower_bound(moved.begin(), moved.end(), std::make_pair(i, -1));
        if (it != moved.end() && it->first == i) r[x] = it->second;
      }
    });
  }
  finish();
}

#ifndef RASM_HAVE_CUDA
namespace cuda {
void associateUpdate(const kernels::AssociateUpdateKernel&) {
  throw std::runtime_error("rasm was built without CUDA (RASM_WITH_CUDA=OFF or no nvcc)");
}
}  // namespace cuda
#endif

}  // namespace rasm::fusion
