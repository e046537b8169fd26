#pragma once
// GPU-side helpers of the device check (device_kernels.cu, CUDA builds only): what the device is,
// and how long each launcher's kernel takes on data that is already on the device (the
// launchers themselves copy their inputs per call, which device_check.cpp times separately).
// Plain header: compute/ and the kernel headers, so device_check.cpp also builds without CUDA.

#include <string>

#include "rasm/core/kernels/FrameKernels.h"
#include "rasm/fusion/kernels/FusionKernels.h"
#include "rasm/surfel_map/kernels/RenderKernels.h"

namespace rasm::device::gpu {

struct Info {
  bool available = false;
  std::string reason;  ///< why not (the driver's message)
  std::string name;
  int cc_major = 0, cc_minor = 0, sm_count = 0;
  double memory_gib = 0;
  int driver_version = 0, runtime_version = 0;
};
Info info();

// Each helper takes a kernel whose views and arrays point to HOST memory, uploads them once
// (not timed), launches the kernel `reps` times through compute/ParallelCuda.cuh and returns the
// median milliseconds of one launch (cudaEvent). Kernels that write their inputs (fusion) get
// them restored between launches (not timed).
double vertexMapMs(const kernels::VertexMapKernel& k, int reps);
double normalMapMs(const kernels::NormalMapKernel& k, int reps);
/// Clear of the packed buffer + SplatKernel over n_visible surfels.
double splatMs(const maps::kernels::SplatKernel& k, int n_visible, int reps);
/// Clear + PointKernel (scale 1 or 4) over n_visible surfels.
double pointsMs(const maps::kernels::PointKernel& k, int n_visible, int reps);

struct FusionMs {
  double associate = 0, update = 0, coverage = 0;
};
FusionMs fusionMs(const fusion::kernels::AssociateKernel<fusion::kernels::Map4xCandidates>& a,
                  const fusion::kernels::UpdateKernel& u,
                  const fusion::kernels::CoverageKernel<fusion::kernels::Map4xCandidates>& c,
                  int reps);

}  // namespace rasm::device::gpu
