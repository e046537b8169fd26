#pragma once
// CUDA launcher of kernels::IcpReduceKernel (cuda/IcpReduce.cu): one thread per processed pixel,
// a block reduction of the IcpAccumulator sums in double, per-block partials summed on the host in
// a fixed order. Plain header (compute/ + the kernel header). Without a CUDA build every method
// throws std::runtime_error; callers check compute::cudaAvailability() first.

#include <memory>

#include "rasm/tracking/kernels/IcpKernels.h"

namespace rasm::tracking::cuda {

/// Whether this build contains the CUDA launcher.
bool built();

/// Keeps device copies of the four images of each pyramid level between iterations.
class IcpCudaReducer {
 public:
  IcpCudaReducer();
  ~IcpCudaReducer();
  IcpCudaReducer(const IcpCudaReducer&) = delete;
  IcpCudaReducer& operator=(const IcpCudaReducer&) = delete;

  /// Uploads the frame and model images of `k` (views of HOST memory) into slot `level`.
  void upload(int level, const kernels::IcpReduceKernel& k);
  /// Runs `k` on the GPU with the images of slot `level` (k's own views are ignored; its poses,
  /// intrinsics and thresholds are used).
  kernels::IcpAccumulator reduce(int level, const kernels::IcpReduceKernel& k);

 private:
  struct Impl;
  std::unique_ptr<Impl> m_impl;
};

/// One-shot: upload + reduce (tests).
kernels::IcpAccumulator reduceIcp(const kernels::IcpReduceKernel& k);

}  // namespace rasm::tracking::cuda
