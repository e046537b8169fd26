// Dry-run build of the device check (host compiler, no CUDA): the launchers device_check.cpp
// names are defined here and throw, as the product's CPU-only builds define them
// (FrameProcessing.cpp, SurfelRenderer.cpp, ...). The check never calls them without a device.

#include <stdexcept>

#include "rasm/core/FrameProcessing.h"
#include "rasm/fusion/kernels/FusionKernels.h"
#include "rasm/surfel_map/SurfelRenderer.h"
#include "rasm/tracking/IcpCuda.h"

namespace {
[[noreturn]] void noCuda() {
  throw std::runtime_error("device check built without CUDA");
}
}  // namespace

namespace rasm {
namespace cuda {
void computeVertexMap(const Image<float>&, const CameraIntrinsics&, Image<Vec3f>&,
                      const VertexMapOptions&) {
  noCuda();
}
void computeNormalMap(const Image<Vec3f>&, Image<Vec3f>&, float) {
  noCuda();
}
}  // namespace cuda

namespace maps::cuda {
void splatPacked(const SurfelArrays&, const std::vector<int>&, const RigidF&, const PinholeF&,
                 const RenderOptions&, Image<std::uint64_t>&) {
  noCuda();
}
void pointsPacked4x(const SurfelArrays&, const std::vector<int>&, const RigidF&, const PinholeF&,
                    const RenderOptions&, Image<std::uint64_t>&, std::vector<std::int64_t>&) {
  noCuda();
}
}  // namespace maps::cuda

namespace tracking::cuda {
struct IcpCudaReducer::Impl {};
bool built() {
  return false;
}
IcpCudaReducer::IcpCudaReducer() : m_impl(std::make_unique<Impl>()) {}
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
}  // namespace tracking::cuda

namespace fusion::cuda {
void associateUpdate(const kernels::AssociateKernel<kernels::Map4xCandidates>&,
                     const kernels::UpdateKernel&,
                     const kernels::CoverageKernel<kernels::Map4xCandidates>&) {
  noCuda();
}
}  // namespace fusion::cuda
}  // namespace rasm
