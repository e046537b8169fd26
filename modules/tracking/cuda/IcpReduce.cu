// CUDA launcher of the ICP reduction of section II-C: the IcpReduceKernel::pixel() the CPU runs
// with [compute] simd = false (its SSE reduction by default), one thread per processed pixel, the
// IcpAccumulator sums reduced per block (warp shuffles, then across warps in shared memory),
// per-block partials summed on the host in block order.
#include <cuda_runtime.h>

#include <memory>
#include <vector>

#include "rasm/compute/ParallelCuda.cuh"
#include "rasm/tracking/IcpCuda.h"

namespace rasm::tracking::cuda {

namespace {

using compute::cuda::check;
using compute::cuda::DeviceBuffer;
using kernels::IcpAccumulator;
using kernels::IcpReduceKernel;

constexpr int kBlock = 256;
constexpr int kWarps = kBlock / 32;
constexpr int kN = IcpAccumulator::kSize;

__global__ void icpReduceKernel(IcpReduceKernel k, int n, double* partials) {
  __shared__ double smem[kWarps][kN];
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  float a[kN];
  for (int j = 0; j < kN; ++j) a[j] = 0.f;
  if (i < n) {
    const int cols = k.cols();
    const int x = (i % cols) * k.stride, y = (i / cols) * k.stride;
    float J[6], r = 0.f, w = 0.f, depth = 0.f;
    const int s = k.pixel(x, y, J, r, w, depth);
    if (s != kernels::kIcpInvalid) a[IcpAccumulator::kValid] = 1.f;
    if (s == kernels::kIcpInlier) kernels::accumulateTerm(a, J, r, w, depth);
  }
  const int lane = threadIdx.x & 31, warp = threadIdx.x >> 5;
  for (int j = 0; j < kN; ++j) {
    double v = a[j];
    for (int off = 16; off > 0; off >>= 1) v += __shfl_down_sync(0xffffffffu, v, off);
    if (lane == 0) smem[warp][j] = v;
  }
  __syncthreads();
  if (threadIdx.x < kN) {
    double s = 0;
    for (int wi = 0; wi < kWarps; ++wi) s += smem[wi][threadIdx.x];
    partials[size_t(blockIdx.x) * kN + threadIdx.x] = s;
  }
}

/// Compact device copy of a host image view.
struct DeviceImage {
  std::unique_ptr<DeviceBuffer<Vec3f>> buf;
  int w = 0, h = 0;
  void upload(const ImageView<const Vec3f>& v) {
    if (!buf || w != v.width || h != v.height) {
      buf = std::make_unique<DeviceBuffer<Vec3f>>(size_t(std::max(1, v.width)) *
                                                  std::max(1, v.height));
      w = v.width;
      h = v.height;
    }
    if (v.empty()) return;
    check(cudaMemcpy2D(buf->ptr, sizeof(Vec3f) * w, v.data, v.pitch_bytes, sizeof(Vec3f) * w, h,
                       cudaMemcpyHostToDevice),
          "IcpCudaReducer upload");
  }
  ImageView<const Vec3f> view() const {
    return ImageView<const Vec3f>(buf ? buf->ptr : nullptr, w, h);
  }
};

struct LevelImages {
  DeviceImage frame_vertex, frame_normal, model_vertex, model_normal;
};

}  // namespace

struct IcpCudaReducer::Impl {
  std::vector<LevelImages> levels;
  std::unique_ptr<DeviceBuffer<double>> partials;
  std::vector<double> host_partials;
};

bool built() {
  return true;
}

IcpCudaReducer::IcpCudaReducer() : m_impl(std::make_unique<Impl>()) {}
IcpCudaReducer::~IcpCudaReducer() = default;

void IcpCudaReducer::upload(int level, const IcpReduceKernel& k) {
  if (level >= int(m_impl->levels.size())) m_impl->levels.resize(level + 1);
  LevelImages& L = m_impl->levels[level];
  L.frame_vertex.upload(k.frame_vertex);
  L.frame_normal.upload(k.frame_normal);
  L.model_vertex.upload(k.model_vertex);
  L.model_normal.upload(k.model_normal);
}

IcpAccumulator IcpCudaReducer::reduce(int level, const IcpReduceKernel& k_host) {
  if (level >= int(m_impl->levels.size()))
    throw std::runtime_error("IcpCudaReducer::reduce: level not uploaded");
  const LevelImages& L = m_impl->levels[level];
  IcpReduceKernel k = k_host;
  k.frame_vertex = L.frame_vertex.view();
  k.frame_normal = L.frame_normal.view();
  k.model_vertex = L.model_vertex.view();
  k.model_normal = L.model_normal.view();
  IcpAccumulator total;
  const int n = k.rows() * k.cols();
  if (n <= 0 || k.model_vertex.empty()) return total;
  const int blocks = (n + kBlock - 1) / kBlock;
  if (!m_impl->partials || m_impl->partials->count < size_t(blocks) * kN)
    m_impl->partials = std::make_unique<DeviceBuffer<double>>(size_t(blocks) * kN);
  icpReduceKernel<<<blocks, kBlock>>>(k, n, m_impl->partials->ptr);
  check(cudaGetLastError(), "icpReduceKernel launch");
  m_impl->host_partials.resize(size_t(blocks) * kN);
  check(cudaMemcpy(m_impl->host_partials.data(), m_impl->partials->ptr,
                   sizeof(double) * blocks * kN, cudaMemcpyDeviceToHost),
        "icpReduceKernel download");
  double* t = total.s;
  for (int b = 0; b < blocks; ++b)
    for (int j = 0; j < kN; ++j) t[j] += m_impl->host_partials[size_t(b) * kN + j];
  return total;
}

IcpAccumulator reduceIcp(const IcpReduceKernel& k) {
  IcpCudaReducer r;
  r.upload(0, k);
  return r.reduce(0, k);
}

}  // namespace rasm::tracking::cuda
