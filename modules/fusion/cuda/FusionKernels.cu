// CUDA launcher of the fusion association / update kernel (kernels/FusionKernels.h): the functor
// bodies the CPU runs with [compute] simd = false (by default the CPU runs SSE row launchers).
// Cleanup (carving, merging, pruning) runs on the host for this backend too: merging is the CPU's
// merge pass over the host-rendered candidate lists (SurfelFusion::renderIndexMap). Reference
// launcher: the map is host-resident, so the arrays the kernel touches are copied to the device
// and back per frame.
#include <cuda_runtime.h>

#include <memory>

#include "rasm/compute/ParallelCuda.cuh"
#include "rasm/fusion/kernels/FusionKernels.h"

namespace rasm::fusion::cuda {

namespace {
namespace cu = compute::cuda;

/// Dense device copy of a pitched host view (optionally copied back).
template <typename T>
struct DeviceView {
  std::unique_ptr<cu::DeviceBuffer<std::remove_const_t<T>>> buf;
  ImageView<T> host;
  explicit DeviceView(const ImageView<T>& h) : host(h) {
    if (h.empty()) return;
    buf =
        std::make_unique<cu::DeviceBuffer<std::remove_const_t<T>>>(std::size_t(h.width) * h.height);
    cu::check(cudaMemcpy2D(buf->ptr, sizeof(T) * h.width, h.data, h.pitch_bytes,
                           sizeof(T) * h.width, h.height, cudaMemcpyHostToDevice),
              "upload image");
  }
  ImageView<T> device() const {
    return buf ? ImageView<T>(buf->ptr, host.width, host.height) : ImageView<T>();
  }
  void download() const {
    if (!buf) return;
    cu::check(cudaMemcpy2D(const_cast<std::remove_const_t<T>*>(host.data), host.pitch_bytes,
                           buf->ptr, sizeof(T) * host.width, sizeof(T) * host.width, host.height,
                           cudaMemcpyDeviceToHost),
              "download image");
  }
};

/// Device copy of one surfel array (n elements), copied back by download().
template <typename T>
struct DeviceArray {
  cu::DeviceBuffer<T> buf;
  T* host;
  std::size_t n;
  DeviceArray(T* h, std::size_t count) : buf(count), host(h), n(count) {
    if (n) buf.upload(h);
  }
  void download() {
    if (n) buf.download(host);
  }
};
}  // namespace

void associateUpdate(const kernels::AssociateKernel<kernels::Map4xCandidates>& a,
                     const kernels::UpdateKernel& u,
                     const kernels::CoverageKernel<kernels::Map4xCandidates>& c) {
  const maps::SurfelArrays& s = a.s;
  const std::size_t n = std::size_t(s.size);
  DeviceArray<Vec4f> pos(s.pos_conf, n), nrm(s.normal_radius, n);
  DeviceArray<std::uint32_t> cf(s.colour_flags, n), seg(s.segment, n);
  DeviceArray<float> tl(s.t_last, n), segw(s.segment_w, n);
  DeviceArray<Vec3f> basis(s.basis, n);
  DeviceArray<std::uint8_t> view(s.view_ic, n * std::size_t(s.n_view_bins));

  DeviceView<const Bgr8> colour(a.frame.colour);
  DeviceView<const Vec3f> vertex(a.frame.vertex_cam), normal(a.frame.normal_cam);
  DeviceView<const std::uint32_t> labels(a.frame.labels);
  DeviceView<const float> weight(a.frame.weight), depth(u.carve_test.depth_m);
  DeviceView<const std::uint64_t> index4x(a.candidates.index4x);
  DeviceView<std::int32_t> pixel_surfel(a.pixel_surfel);
  DeviceView<std::uint16_t> flags(a.flags);

  maps::SurfelArrays d_s = s;
  d_s.pos_conf = pos.buf.ptr;
  d_s.normal_radius = nrm.buf.ptr;
  d_s.colour_flags = cf.buf.ptr;
  d_s.t_last = tl.buf.ptr;
  d_s.basis = basis.buf.ptr;
  d_s.segment = seg.buf.ptr;
  d_s.segment_w = segw.buf.ptr;
  d_s.view_ic = view.buf.ptr;
  d_s.t_init = nullptr;  // not read by the kernels
  d_s.class_ev = nullptr;
  kernels::FrameView d_frame = a.frame;
  d_frame.colour = colour.device();
  d_frame.vertex_cam = vertex.device();
  d_frame.normal_cam = normal.device();
  d_frame.labels = labels.device();
  d_frame.weight = weight.device();

  kernels::AssociateKernel<kernels::Map4xCandidates> da = a;
  da.frame = d_frame;
  da.candidates.index4x = index4x.device();
  da.candidates.s = d_s;
  da.s = d_s;
  da.pixel_surfel = pixel_surfel.device();
  da.flags = flags.device();
  cu::forEach2D(a.pixel_surfel.width, a.pixel_surfel.height, da);

  kernels::UpdateKernel du = u;
  du.frame = d_frame;
  du.s = d_s;
  du.pixel_surfel = pixel_surfel.device();
  du.flags = flags.device();
  du.carve_test.depth_m = depth.device();
  cu::forEach2D(a.pixel_surfel.width, a.pixel_surfel.height, du);

  if (c.prm.neighbour_coverage_check) {
    kernels::CoverageKernel<kernels::Map4xCandidates> dc = c;
    dc.frame = d_frame;
    dc.candidates.index4x = index4x.device();
    dc.candidates.s = d_s;
    dc.s = d_s;
    dc.pixel_surfel = pixel_surfel.device();
    dc.flags = flags.device();
    cu::forEach2D(a.pixel_surfel.width, a.pixel_surfel.height, dc);
  }

  pos.download();
  nrm.download();
  cf.download();
  seg.download();
  tl.download();
  segw.download();
  basis.download();
  view.download();
  pixel_surfel.download();
  flags.download();
}

}  // namespace rasm::fusion::cuda
