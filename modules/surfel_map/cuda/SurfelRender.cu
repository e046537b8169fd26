// CUDA launchers of the splat / point kernels (kernels/RenderKernels.h): the functor bodies the
// CPU runs with [compute] simd = false (by default its SSE splat path, bit-identical to them).
// Reference launchers: the arrays the kernels read are copied to the device per call (the map is
// host-resident), so transfers dominate for large maps.
#include <cuda_runtime.h>

#include <vector>

#include "rasm/compute/ParallelCuda.cuh"
#include "rasm/surfel_map/SurfelRenderer.h"
#include "rasm/surfel_map/kernels/RenderKernels.h"

namespace rasm::maps::cuda {

namespace {
namespace cu = compute::cuda;

/// Device copies of the arrays the render kernels read (positions, normals/radii).
struct DeviceSurfels {
  cu::DeviceBuffer<Vec4f> pos_conf, normal_radius;
  cu::DeviceBuffer<int> visible;
  SurfelArrays arrays;
  DeviceSurfels(const SurfelArrays& a, const std::vector<int>& vis)
      : pos_conf(std::size_t(a.size)), normal_radius(std::size_t(a.size)), visible(vis.size()) {
    if (a.size > 0) {
      pos_conf.upload(a.pos_conf);
      normal_radius.upload(a.normal_radius);
    }
    if (!vis.empty()) visible.upload(vis.data());
    arrays = a;
    arrays.pos_conf = pos_conf.ptr;
    arrays.normal_radius = normal_radius.ptr;
    arrays.colour_flags = nullptr;  // not read by the splat / point kernels
    arrays.t_init = arrays.t_last = nullptr;
    arrays.basis = nullptr;
    arrays.segment = nullptr;
    arrays.segment_w = nullptr;
    arrays.class_ev = nullptr;
    arrays.view_ic = nullptr;
  }
};

struct FillKernel {
  std::uint64_t* p;
  RASM_HD_INLINE void operator()(int i) const { p[i] = kernels::kEmptyPacked; }
};

void download(const cu::DeviceBuffer<std::uint64_t>& d, int w, int h, Image<std::uint64_t>& img) {
  cu::check(cudaMemcpy2D(img.data(), img.pitchBytes(), d.ptr, sizeof(std::uint64_t) * w,
                         sizeof(std::uint64_t) * w, h, cudaMemcpyDeviceToHost),
            "download packed");
}
}  // namespace

void splatPacked(const SurfelArrays& a, const std::vector<int>& visible, const RigidF& T_cam_world,
                 const PinholeF& K, const RenderOptions& opt, Image<std::uint64_t>& packed) {
  const int w = packed.width(), h = packed.height();
  DeviceSurfels d(a, visible);
  cu::DeviceBuffer<std::uint64_t> buf(std::size_t(w) * h);
  cu::forEach1D(w * h, FillKernel{buf.ptr});
  const ImageView<std::uint64_t> view(buf.ptr, w, h);
  if (opt.splat) {
    kernels::SplatKernel k{
        d.arrays,        d.visible.ptr,           T_cam_world, K, opt.min_depth_m,
        opt.max_depth_m, opt.max_splat_radius_px, view};
    cu::forEach1D(int(visible.size()), k);
  } else {
    kernels::PointKernel k{d.arrays,        d.visible.ptr,   T_cam_world, K,
                           opt.min_depth_m, opt.max_depth_m, 1,           view,
                           nullptr};
    cu::forEach1D(int(visible.size()), k);
  }
  download(buf, w, h, packed);
}

void pointsPacked4x(const SurfelArrays& a, const std::vector<int>& visible,
                    const RigidF& T_cam_world, const PinholeF& K, const RenderOptions& opt,
                    Image<std::uint64_t>& packed4x, std::vector<std::int64_t>& touched) {
  const int w = packed4x.width(), h = packed4x.height();
  DeviceSurfels d(a, visible);
  cu::DeviceBuffer<std::uint64_t> buf(std::size_t(w) * h);
  cu::DeviceBuffer<std::int64_t> dtouched(visible.size());
  cu::forEach1D(w * h, FillKernel{buf.ptr});
  kernels::PointKernel k{
      d.arrays,        d.visible.ptr,   T_cam_world, K,
      opt.min_depth_m, opt.max_depth_m, 4,           ImageView<std::uint64_t>(buf.ptr, w, h),
      dtouched.ptr};
  cu::forEach1D(int(visible.size()), k);
  download(buf, w, h, packed4x);
  touched.resize(visible.size());
  if (!visible.empty()) dtouched.download(touched.data());
}

}  // namespace rasm::maps::cuda
