// CUDA launchers of the II-A frame kernels: the functor bodies the CPU runs with [compute]
// simd = false (by default the CPU runs SSE launchers that are bit-identical to them).
#include <cuda_runtime.h>

#include "rasm/compute/Device.h"
#include "rasm/compute/ParallelCuda.cuh"
#include "rasm/core/FrameProcessing.h"
#include "rasm/core/kernels/FrameKernels.h"

namespace rasm {

namespace compute {
CudaAvailability cudaAvailability() {
  int n = 0;
  const cudaError_t e = cudaGetDeviceCount(&n);
  if (e != cudaSuccess) return {false, std::string("no CUDA device: ") + cudaGetErrorString(e)};
  if (n == 0) return {false, "no CUDA device present"};
  return {true, ""};
}
}  // namespace compute

namespace cuda {

template <typename T>
struct DeviceImage {
  compute::cuda::DeviceBuffer<T> buf;
  int w, h;
  DeviceImage(int w_, int h_) : buf(size_t(w_) * h_), w(w_), h(h_) {}
  ImageView<T> view() { return ImageView<T>(buf.ptr, w, h); }
  void upload(const Image<T>& im) {
    compute::cuda::check(cudaMemcpy2D(buf.ptr, sizeof(T) * w, im.data(), im.pitchBytes(),
                                      sizeof(T) * w, h, cudaMemcpyHostToDevice),
                         "upload image");
  }
  void download(Image<T>& im) {
    im.resize(w, h);
    compute::cuda::check(cudaMemcpy2D(im.data(), im.pitchBytes(), buf.ptr, sizeof(T) * w,
                                      sizeof(T) * w, h, cudaMemcpyDeviceToHost),
                         "download image");
  }
};

void computeVertexMap(const Image<float>& depth_m, const CameraIntrinsics& K, Image<Vec3f>& vertex,
                      const VertexMapOptions& opt) {
  const int w = depth_m.width(), h = depth_m.height();
  DeviceImage<float> d(w, h);
  DeviceImage<Vec3f> v(w, h);
  d.upload(depth_m);
  kernels::VertexMapKernel k{d.view(), v.view(), K.plain(), opt.min_depth_m, opt.max_depth_m};
  compute::cuda::forEach2D(w, h, k);
  v.download(vertex);
}

void computeNormalMap(const Image<Vec3f>& vertex, Image<Vec3f>& normal, float max_jump_rel) {
  const int w = vertex.width(), h = vertex.height();
  DeviceImage<Vec3f> v(w, h), n(w, h);
  v.upload(vertex);
  kernels::NormalMapKernel k{v.view(), n.view(), max_jump_rel};
  compute::cuda::forEach2D(w, h, k);
  n.download(normal);
}

}  // namespace cuda
}  // namespace rasm
