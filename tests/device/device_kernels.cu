// GPU-side helpers of the device check (DeviceKernels.h): device information and the time of each
// launcher's kernel on device-resident inputs, launched as the launchers launch them
// (compute/ParallelCuda.cuh). Includes only compute/, the kernel headers and Eigen.
#include <cuda_runtime.h>

#include <algorithm>
#include <memory>
#include <vector>

#include "DeviceKernels.h"
#include "rasm/compute/ParallelCuda.cuh"

namespace rasm::device::gpu {

namespace {
namespace cu = compute::cuda;

/// Dense device copy of a pitched host view.
template <typename T>
struct DeviceImage {
  using V = std::remove_const_t<T>;
  std::unique_ptr<cu::DeviceBuffer<V>> buf;
  int w = 0, h = 0;
  explicit DeviceImage(const ImageView<T>& host) : w(host.width), h(host.height) {
    if (host.empty()) return;
    buf = std::make_unique<cu::DeviceBuffer<V>>(std::size_t(w) * h);
    cu::check(cudaMemcpy2D(buf->ptr, sizeof(V) * w, host.data, host.pitch_bytes, sizeof(V) * w, h,
                           cudaMemcpyHostToDevice),
              "upload image");
  }
  ImageView<T> view() const { return buf ? ImageView<T>(buf->ptr, w, h) : ImageView<T>(); }
};

/// Device copy of one array of n elements (host pointer may be null: none), restorable.
template <typename T>
struct DeviceArray {
  std::unique_ptr<cu::DeviceBuffer<T>> buf, pristine;
  std::size_t n = 0;
  DeviceArray(const T* host, std::size_t count) : n(host ? count : 0) {
    if (!n) return;
    buf = std::make_unique<cu::DeviceBuffer<T>>(n);
    buf->upload(host);
  }
  T* ptr() const { return buf ? buf->ptr : nullptr; }
  void keep() {
    if (!n) return;
    pristine = std::make_unique<cu::DeviceBuffer<T>>(n);
    cu::check(cudaMemcpy(pristine->ptr, buf->ptr, n * sizeof(T), cudaMemcpyDeviceToDevice), "keep");
  }
  void restore() {
    if (pristine)
      cu::check(cudaMemcpy(buf->ptr, pristine->ptr, n * sizeof(T), cudaMemcpyDeviceToDevice),
                "restore");
  }
};

/// Device copies of the surfel arrays the launchers upload (SurfelRender.cu, FusionKernels.cu).
struct DeviceSurfels {
  DeviceArray<Vec4f> pos, nrm;
  DeviceArray<std::uint32_t> cf, seg;
  DeviceArray<float> tl, segw;
  DeviceArray<Vec3f> basis;
  DeviceArray<std::uint8_t> view;
  maps::SurfelArrays d;
  explicit DeviceSurfels(const maps::SurfelArrays& s)
      : pos(s.pos_conf, s.size),
        nrm(s.normal_radius, s.size),
        cf(s.colour_flags, s.size),
        seg(s.segment, s.size),
        tl(s.t_last, s.size),
        segw(s.segment_w, s.size),
        basis(s.basis, s.size),
        view(s.view_ic, std::size_t(s.size) * s.n_view_bins) {
    d = maps::SurfelArrays();
    d.size = s.size;
    d.n_view_bins = s.n_view_bins;
    d.pos_conf = pos.ptr();
    d.normal_radius = nrm.ptr();
    d.colour_flags = cf.ptr();
    d.segment = seg.ptr();
    d.t_last = tl.ptr();
    d.segment_w = segw.ptr();
    d.basis = basis.ptr();
    d.view_ic = view.ptr();
  }
  /// keep(): snapshot of every array; restore(): back to it (fusion writes the map).
  void keep() {
    each([](auto& a) { a.keep(); });
  }
  void restore() {
    each([](auto& a) { a.restore(); });
  }
  template <typename F>
  void each(F f) {
    f(pos);
    f(nrm);
    f(cf);
    f(seg);
    f(tl);
    f(segw);
    f(basis);
    f(view);
  }
};

struct FillKernel {
  std::uint64_t* p;
  RASM_HD_INLINE void operator()(int i) const { p[i] = maps::kernels::kEmptyPacked; }
};

/// Median ms of reps calls of launch() (cudaEvent around each); before() runs untimed first.
template <typename Launch, typename Before>
double medianMs(int reps, Launch launch, Before before) {
  cudaEvent_t a, b;
  cu::check(cudaEventCreate(&a), "cudaEventCreate");
  cu::check(cudaEventCreate(&b), "cudaEventCreate");
  std::vector<float> ms;
  for (int r = 0; r < std::max(1, reps); ++r) {
    before();
    cu::check(cudaDeviceSynchronize(), "sync");
    cu::check(cudaEventRecord(a), "cudaEventRecord");
    launch();
    cu::check(cudaEventRecord(b), "cudaEventRecord");
    cu::check(cudaEventSynchronize(b), "cudaEventSynchronize");
    float t = 0;
    cu::check(cudaEventElapsedTime(&t, a, b), "cudaEventElapsedTime");
    ms.push_back(t);
  }
  cudaEventDestroy(a);
  cudaEventDestroy(b);
  std::nth_element(ms.begin(), ms.begin() + ms.size() / 2, ms.end());
  return ms[ms.size() / 2];
}
template <typename Launch>
double medianMs(int reps, Launch launch) {
  return medianMs(reps, launch, [] {});
}

}  // namespace

Info info() {
  Info i;
  int n = 0;
  const cudaError_t e = cudaGetDeviceCount(&n);
  if (e != cudaSuccess) {
    i.reason = std::string("no CUDA device: ") + cudaGetErrorString(e);
    return i;
  }
  if (n == 0) {
    i.reason = "no CUDA device present";
    return i;
  }
  cudaDeviceProp p{};
  cu::check(cudaGetDeviceProperties(&p, 0), "cudaGetDeviceProperties");
  i.available = true;
  i.name = p.name;
  i.cc_major = p.major;
  i.cc_minor = p.minor;
  i.sm_count = p.multiProcessorCount;
  i.memory_gib = double(p.totalGlobalMem) / (1024.0 * 1024.0 * 1024.0);
  cudaDriverGetVersion(&i.driver_version);
  cudaRuntimeGetVersion(&i.runtime_version);
  return i;
}

double vertexMapMs(const kernels::VertexMapKernel& k, int reps) {
  DeviceImage<const float> d(k.depth_m);
  DeviceImage<Vec3f> v(k.vertex);
  kernels::VertexMapKernel dk = k;
  dk.depth_m = d.view();
  dk.vertex = v.view();
  return medianMs(reps, [&] { cu::forEach2D(v.w, v.h, dk); });
}

double normalMapMs(const kernels::NormalMapKernel& k, int reps) {
  DeviceImage<const Vec3f> v(k.vertex);
  DeviceImage<Vec3f> n(k.normal);
  kernels::NormalMapKernel dk = k;
  dk.vertex = v.view();
  dk.normal = n.view();
  return medianMs(reps, [&] { cu::forEach2D(n.w, n.h, dk); });
}

double splatMs(const maps::kernels::SplatKernel& k, int n_visible, int reps) {
  DeviceSurfels s(k.s);
  DeviceArray<int> vis(k.visible, std::size_t(n_visible));
  const int w = k.packed.width, h = k.packed.height;
  cu::DeviceBuffer<std::uint64_t> buf(std::size_t(w) * h);
  maps::kernels::SplatKernel dk = k;
  dk.s = s.d;
  dk.visible = vis.ptr();
  dk.packed = ImageView<std::uint64_t>(buf.ptr, w, h);
  return medianMs(reps, [&] {
    cu::forEach1D(w * h, FillKernel{buf.ptr});
    cu::forEach1D(n_visible, dk);
  });
}

double pointsMs(const maps::kernels::PointKernel& k, int n_visible, int reps) {
  DeviceSurfels s(k.s);
  DeviceArray<int> vis(k.visible, std::size_t(n_visible));
  const int w = k.packed.width, h = k.packed.height;
  cu::DeviceBuffer<std::uint64_t> buf(std::size_t(w) * h);
  cu::DeviceBuffer<std::int64_t> touched(std::size_t(std::max(1, n_visible)));
  maps::kernels::PointKernel dk = k;
  dk.s = s.d;
  dk.visible = vis.ptr();
  dk.packed = ImageView<std::uint64_t>(buf.ptr, w, h);
  dk.touched = k.touched ? touched.ptr : nullptr;
  return medianMs(reps, [&] {
    cu::forEach1D(w * h, FillKernel{buf.ptr});
    cu::forEach1D(n_visible, dk);
  });
}

FusionMs fusionMs(const fusion::kernels::AssociateKernel<fusion::kernels::Map4xCandidates>& a,
                  const fusion::kernels::UpdateKernel& u,
                  const fusion::kernels::CoverageKernel<fusion::kernels::Map4xCandidates>& c,
                  int reps) {
  DeviceSurfels s(a.s);
  s.keep();
  DeviceImage<const Bgr8> colour(a.frame.colour);
  DeviceImage<const Vec3f> vertex(a.frame.vertex_cam), normal(a.frame.normal_cam);
  DeviceImage<const std::uint32_t> labels(a.frame.labels);
  DeviceImage<const float> weight(a.frame.weight), depth(u.carve_test.depth_m);
  DeviceImage<const std::uint64_t> index4x(a.candidates.index4x);
  DeviceImage<std::int32_t> pixel_surfel(a.pixel_surfel);
  DeviceImage<std::uint16_t> flags(a.flags);

  fusion::kernels::FrameView f = a.frame;
  f.colour = colour.view();
  f.vertex_cam = vertex.view();
  f.normal_cam = normal.view();
  f.labels = labels.view();
  f.weight = weight.view();
  auto da = a;
  da.frame = f;
  da.s = s.d;
  da.candidates.index4x = index4x.view();
  da.candidates.s = s.d;
  da.pixel_surfel = pixel_surfel.view();
  da.flags = flags.view();
  auto du = u;
  du.frame = f;
  du.s = s.d;
  du.pixel_surfel = pixel_surfel.view();
  du.flags = flags.view();
  du.carve_test.depth_m = depth.view();
  auto dc = c;
  dc.frame = f;
  dc.s = s.d;
  dc.candidates.index4x = index4x.view();
  dc.candidates.s = s.d;
  dc.pixel_surfel = pixel_surfel.view();
  dc.flags = flags.view();
  const int w = a.pixel_surfel.width, h = a.pixel_surfel.height;

  FusionMs r;
  r.associate = medianMs(reps, [&] { cu::forEach2D(w, h, da); });
  // The update writes the surfels: each launch starts from the same map (and associations).
  r.update = medianMs(
      reps, [&] { cu::forEach2D(w, h, du); },
      [&] {
        s.restore();
        cu::forEach2D(w, h, da);
      });
  if (c.prm.neighbour_coverage_check)
    r.coverage = medianMs(
        reps, [&] { cu::forEach2D(w, h, dc); },
        [&] {
          s.restore();
          cu::forEach2D(w, h, da);
          cu::forEach2D(w, h, du);
        });
  return r;
}

}  // namespace rasm::device::gpu
