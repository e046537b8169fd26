#include "rasm/surfel_map/SurfelRenderer.h"

#include <cmath>
#include <stdexcept>

#include "rasm/surfel_map/kernels/RenderKernels.h"

namespace rasm::maps {

namespace {

RigidF toRigid(const Eigen::Isometry3d& T) { return RigidF::fromMatrix(T.matrix().cast<float>()); }

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

void splatCpu(const kernels::SplatKernel& k, int n, std::vector<kernels::SplatFootprint>& fp,
              std::vector<std::uint32_t>& rows) {
  constexpr std::uint32_t kNone = 0xffffffffu;
  fp.resize(n);
  rows.resize(n);
  compute::forEach1D(n, [&](int j) {
    rows[j] =
        k.footprint(j, fp[j]) ? (std::uint32_t(fp[j].y0) | (std::uint32_t(fp[j].y1) << 16)) : kNone;
  });
  const int h = k.packed.height, nb = numBands(h, 2);
#pragma omp parallel for schedule(dynamic, 1)
  for (int b = 0; b < nb; ++b) {
    const int lo = int(std::int64_t(h) * b / nb), hi = int(std::int64_t(h) * (b + 1) / nb) - 1;
    for (int j = 0; j < n; ++j) {
      const std::uint32_t r = rows[j];
      if (r == kNone) continue;
      const int y0 = int(r & 0xffffu), y1 = int(r >> 16);
      if (y1 < lo || y0 > hi) continue;
      k.rasterize(fp[j], std::max(lo, y0), std::min(hi, y1), false);
    }
  }
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

}  // namespace

void SurfelRenderer::collectVisible(const SurfelStore& map, const Eigen::Isometry3d& T_world_cam,
                                    const CameraIntrinsics& K, const RenderOptions& opt,
                                    float margin_px, std::vector<int>& visible,
                                    RenderStats* stats) const {
  visible.clear();
  if (!K.valid()) throw std::invalid_argument("SurfelRenderer: invalid intrinsics " + K.toString());
  const RigidF T_wc = toRigid(T_world_cam);
  const PinholeF Kp = K.plain();
  const VoxelBlockIndex& index = map.spatialIndex();

  std::vector<int> blocks;
  std::vector<std::uint8_t> inside;
  const CameraFrustum frustum =
      CameraFrustum::fromCamera(T_wc, Kp, opt.min_depth_m, opt.max_depth_m);
  // Grow the culling by the largest radius and by the pixel margin at the far plane.
  const float f_min = float(std::min(std::fabs(K.fx), std::fabs(K.fy)));
  const float margin_m = map.radiusBound() + margin_px / f_min * opt.max_depth_m;
  index.blocksInFrustum(frustum, margin_m, blocks, &inside);

  kernels::VisibilityTest test;
  test.s = map.arrays();
  test.T_cam_world = toRigid(T_world_cam.inverse());
  test.K = Kp;
  test.camera_centre_world = T_wc.translation();
  test.min_depth_m = opt.min_depth_m;
  test.max_depth_m = opt.max_depth_m;
  test.min_confidence = opt.min_confidence;
  if (std::isfinite(opt.time_window_s))
    test.min_t_last = map.toMapTime(opt.now_s - opt.time_window_s);
  test.stable_only = opt.stable_only;
  test.cull_back_faces = opt.cull_back_faces;
  test.u_lo = -0.5f - margin_px;
  test.u_hi = float(K.width) - 0.5f + margin_px;
  test.v_lo = -0.5f - margin_px;
  test.v_hi = float(K.height) - 0.5f + margin_px;

  // Per-block results keep the output in block order whatever the thread schedule.
  const int nb = int(blocks.size());
  per_block_.resize(std::max<std::size_t>(per_block_.size(), std::size_t(nb)));
  long long tested = 0;
#pragma omp parallel for schedule(dynamic, 4) reduction(+ : tested)
  for (int j = 0; j < nb; ++j) {
    const std::vector<int>& members = index.members(blocks[j]);
    std::vector<int>& out = per_block_[j];
    out.clear();
    tested += (long long)members.size();
    if (inside[j]) {  // every centre is in the frustum: only the attribute filters remain
      for (int i : members)
        if (test.attributes(i)) out.push_back(i);
    } else {
      for (int i : members)
        if (test(i)) out.push_back(i);
    }
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

void SurfelRenderer::render(const SurfelStore& map, const Eigen::Isometry3d& T_world_cam,
                            const CameraIntrinsics& K, const RenderOptions& opt, RenderedMaps& out,
                            RenderStats* stats) {
  const int w = K.width, h = K.height;
  collectVisible(map, T_world_cam, K, opt, opt.splat ? opt.max_splat_radius_px : 0.5f, visible_,
                 stats);
  const SurfelArrays arr = map.arrays();
  const RigidF T_cw = toRigid(T_world_cam.inverse());
  const PinholeF Kp = K.plain();

  packed_.resize(w, h);
  if (backend_ == compute::Backend::Cuda) {
    cuda::splatPacked(arr, visible_, T_cw, Kp, opt, packed_);
  } else {
    fillEmpty(packed_);
    if (opt.splat) {
      kernels::SplatKernel k{arr,
                             visible_.data(),
                             T_cw,
                             Kp,
                             opt.min_depth_m,
                             opt.max_depth_m,
                             opt.max_splat_radius_px,
                             packed_.view()};
      splatCpu(k, int(visible_.size()), footprints_, rows_);
    } else {
      kernels::PointKernel k{arr, visible_.data(), T_cw,   Kp, opt.min_depth_m, opt.max_depth_m,
                             1,   packed_.view(),  nullptr};
      ids_.resize(visible_.size());
      pointsCpu(k, int(visible_.size()), ids_.data(), values_);
    }
  }

  out.index.resize(w, h);
  kernels::ResolveKernel r;
  r.s = arr;
  r.packed = packed_.cview();
  r.T_world_cam = toRigid(T_world_cam);
  r.K = Kp;
  r.splat = opt.splat;
  r.index = out.index.view();
  r.depth_m = viewIf((opt.outputs & kRenderDepth) != 0, out.depth_m, w, h);
  r.vertex_world = viewIf((opt.outputs & kRenderVertex) != 0, out.vertex_world, w, h);
  r.normal_world = viewIf((opt.outputs & kRenderNormal) != 0, out.normal_world, w, h);
  r.colour = viewIf((opt.outputs & kRenderColour) != 0, out.colour, w, h);
  r.confidence = viewIf((opt.outputs & kRenderConfidence) != 0, out.confidence, w, h);
  r.segment = viewIf((opt.outputs & kRenderSegment) != 0, out.segment, w, h);
  compute::forEach2D(w, h, r);
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
