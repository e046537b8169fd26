// CUDA launcher of the fusion association / update kernel (kernels/FusionKernels.h): the same
// functor body the CPU path runs. Reference launcher: the map is host-resident, so the arrays the
// kernel touches are copied to the device and back per frame.
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

void associateUpdate(const kernels::AssociateUpdateKernel& k) {
  const maps::SurfelArrays& s = k.s;
  const std::size_t n = std::size_t(s.size);
  DeviceArray<Vec4f> pos(s.pos_conf, n), nrm(s.normal_radius, n);
  DeviceArray<std::uint32_t> cf(s.colour_flags, n), seg(s.segment, n);
  DeviceArray<float> tl(s.t_last, n), segw(s.segment_w, n);
  DeviceArray<Vec3f> basis(s.basis, n);
  DeviceArray<std::uint8_t> view(s.view_ic, n * std::size_t(s.n_view_bins));

  DeviceView<const Bgr8> colour(k.frame.colour);
  DeviceView<const Vec3f> vertex(k.frame.vertex_cam), normal(k.frame.normal_cam);
  DeviceView<const std::uint32_t> labels(k.frame.labels);
  DeviceView<const std::uint64_t> index4x(k.index4x);
  DeviceView<std::int32_t> pixel_surfel(k.pixel_surfel);
  DeviceView<std::uint8_t> flags(k.flags);

  kernels::AssociateUpdateKernel d = k;
  d.frame.colour = colour.device();
  d.frame.vertex_cam = vertex.device();
  d.frame.normal_cam = normal.device();
  d.frame.labels = labels.device();
  d.index4x = index4x.device();
  d.pixel_surfel = pixel_surfel.device();
  d.flags = flags.device();
  d.s.pos_conf = pos.buf.ptr;
  d.s.normal_radius = nrm.buf.ptr;
  d.s.colour_flags = cf.buf.ptr;
  d.s.t_last = tl.buf.ptr;
  d.s.basis = basis.buf.ptr;
  d.s.segment = seg.buf.ptr;
  d.s.segment_w = segw.buf.ptr;
  d.s.view_ic = view.buf.ptr;
  d.s.t_init = nullptr;  // not read by the kernel
  d.s.class_p = nullptr;
  cu::forEach2D(k.pixel_surfel.width, k.pixel_surfel.height, d);

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
