#pragma once
// CUDA launchers for the same kernel functors the CPU launchers run (Parallel.h). Included only
// from .cu files; depends on nothing but compute/ and Eigen.

#include <cuda_runtime.h>

#include <stdexcept>
#include <string>

namespace rasm::compute::cuda {

inline void check(cudaError_t e, const char* what) {
  if (e != cudaSuccess) throw std::runtime_error(std::string(what) + ": " + cudaGetErrorString(e));
}

template <typename F>
__global__ void forEach1DKernel(int n, F f) {
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i < n) f(i);
}

template <typename F>
__global__ void forEach2DKernel(int w, int h, F f) {
  const int x = blockIdx.x * blockDim.x + threadIdx.x;
  const int y = blockIdx.y * blockDim.y + threadIdx.y;
  if (x < w && y < h) f(x, y);
}

template <typename F>
void forEach1D(int n, const F& f) {
  if (n <= 0) return;
  forEach1DKernel<<<(n + 255) / 256, 256>>>(n, f);
  check(cudaGetLastError(), "forEach1D launch");
  check(cudaDeviceSynchronize(), "forEach1D");
}

template <typename F>
void forEach2D(int w, int h, const F& f) {
  if (w <= 0 || h <= 0) return;
  const dim3 block(32, 8);
  const dim3 grid((w + block.x - 1) / block.x, (h + block.y - 1) / block.y);
  forEach2DKernel<<<grid, block>>>(w, h, f);
  check(cudaGetLastError(), "forEach2D launch");
  check(cudaDeviceSynchronize(), "forEach2D");
}

/// Device buffer (RAII) for plain data.
template <typename T>
struct DeviceBuffer {
  T* ptr = nullptr;
  size_t count = 0;
  explicit DeviceBuffer(size_t n) : count(n) {
    check(cudaMalloc(&ptr, n * sizeof(T) + 1), "cudaMalloc");
  }
  ~DeviceBuffer() { cudaFree(ptr); }
  DeviceBuffer(const DeviceBuffer&) = delete;
  DeviceBuffer& operator=(const DeviceBuffer&) = delete;
  void upload(const T* host) {
    check(cudaMemcpy(ptr, host, count * sizeof(T), cudaMemcpyHostToDevice), "upload");
  }
  void download(T* host) const {
    check(cudaMemcpy(host, ptr, count * sizeof(T), cudaMemcpyDeviceToHost), "download");
  }
};

}  // namespace rasm::compute::cuda
