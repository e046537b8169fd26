#include "rasm/core/FrameProcessing.h"

#include <opencv2/imgproc.hpp>
#include <stdexcept>

#include "rasm/core/kernels/FrameKernels.h"

namespace rasm {

void computeVertexMap(const Image<float>& depth_m, const CameraIntrinsics& K, Image<Vec3f>& vertex,
                      const VertexMapOptions& opt, compute::Backend backend) {
  if (backend == compute::Backend::Cuda) return cuda::computeVertexMap(depth_m, K, vertex, opt);
  vertex.resize(depth_m.width(), depth_m.height());
  kernels::VertexMapKernel k{depth_m.view(), vertex.view(), K.plain(), opt.min_depth_m, opt.max_depth_m};
  compute::forEach2D(depth_m.width(), depth_m.height(), k);
}

void computeNormalMap(const Image<Vec3f>& vertex, Image<Vec3f>& normal, float max_jump_rel,
                      compute::Backend backend) {
  if (backend == compute::Backend::Cuda) return cuda::computeNormalMap(vertex, normal, max_jump_rel);
  normal.resize(vertex.width(), vertex.height());
  kernels::NormalMapKernel k{vertex.view(), normal.view(), max_jump_rel};
  compute::forEach2D(vertex.width(), vertex.height(), k);
}

void downsampleDepth(const Image<float>& in, Image<float>& out, float max_diff_m) {
  out.resize((in.width() + 1) / 2, (in.height() + 1) / 2);
  kernels::DepthDownsampleKernel k{in.view(), out.view(), max_diff_m};
  compute::forEach2D(out.width(), out.height(), k);
}

void bilateralFilterDepth(const Image<float>& in, Image<float>& out, int radius, float sigma_space_px,
                          float sigma_depth_m) {
  if (&in == &out) throw std::invalid_argument("bilateralFilterDepth: in and out must differ");
  out.resize(in.width(), in.height());
  // OpenCV's bilateral filter (SIMD, exp look-up tables) is ~20x faster than the plain kernel on
  // the CPU. Invalid pixels (0) differ from valid depth by metres, so their range weight
  // exp(-dz^2 / 2 sigma^2) underflows to 0 and they do not leak into valid ones; pixels invalid
  // in the input are reset to 0 (BilateralDepthKernel is the same filter for the CUDA path).
  const cv::Mat src(in.height(), in.width(), CV_32F, const_cast<float*>(in.data()), in.pitchBytes());
  cv::Mat dst(out.height(), out.width(), CV_32F, out.data(), out.pitchBytes());
  cv::bilateralFilter(src, dst, 2 * radius + 1, sigma_depth_m, sigma_space_px, cv::BORDER_REPLICATE);
  compute::forEach2D(in.width(), in.height(), [&](int x, int y) {
    if (!(in(x, y) > 0.0f)) out(x, y) = 0.0f;
  });
}

void buildFramePyramid(const Image<float>& depth_m, const CameraIntrinsics& K, int levels,
                       std::vector<FrameLevel>& pyramid, const VertexMapOptions& opt) {
  pyramid.resize(levels);
  for (int l = 0; l < levels; ++l) {
    FrameLevel& L = pyramid[l];
    L.K = K.level(l);
    if (l == 0)
      L.depth_m = depth_m;
    else
      downsampleDepth(pyramid[l - 1].depth_m, L.depth_m);
    computeVertexMap(L.depth_m, L.K, L.vertex, opt);
    computeNormalMap(L.vertex, L.normal);
  }
}

#ifndef RASM_HAVE_CUDA
namespace cuda {
void computeVertexMap(const Image<float>&, const CameraIntrinsics&, Image<Vec3f>&, const VertexMapOptions&) {
  throw std::runtime_error("rasm was built without CUDA (RASM_WITH_CUDA=OFF or no nvcc)");
}
void computeNormalMap(const Image<Vec3f>&, Image<Vec3f>&, float) {
  throw std::runtime_error("rasm was built without CUDA (RASM_WITH_CUDA=OFF or no nvcc)");
}
}  // namespace cuda
#endif

}  // namespace rasm
