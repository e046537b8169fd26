// Stand-ins for the CUDA launcher (cuda/IcpReduce.cu) in builds without CUDA.
#include "rasm/tracking/IcpCuda.h"

#ifndef RASM_HAVE_CUDA
#include <stdexcept>

namespace rasm::tracking::cuda {

namespace {
[[noreturn]] void noCuda() {
  throw std::runtime_error("rasm was built without CUDA (RASM_WITH_CUDA=OFF or no nvcc)");
}
}  // namespace

bool built() {
  return false;
}
struct IcpCudaReducer::Impl {};
IcpCudaReducer::IcpCudaReducer() = default;
IcpCudaReducer::~IcpCudaReducer() = default;
void IcpCudaReducer::upload(int, const kernels::IcpReduceKernel&) {
  noCuda();
}
kernels::IcpAccumulator IcpCudaReducer::reduce(int, const kernels::IcpReduceKernel&) {
  noCuda();
}
kernels::IcpAccumulator reduceIcp(const kernels::IcpReduceKernel&) {
  noCuda();
}

}  // namespace rasm::tracking::cuda
#endif
