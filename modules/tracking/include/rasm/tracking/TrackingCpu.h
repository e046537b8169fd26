#pragma once
// SSE CPU launchers of the tracking kernels (II-C), four pixels per SSE operation:
//  - reduceIcpCpu: IcpReduceKernel's pixels; each lane runs the kernel's float operations in the
//    same order (Eigen's 3-term sums as a0 + (a1 + a2), its cross product), and the inliers enter
//    the sums in pixel order, so the result is bit-identical to compute::reduce1D over the kernel
//    itself (tested). Kernels with a model confidence map take the scalar path.
//  - downsampleModelCpu: ModelDownsampleKernel over four output pixels, bit-identical likewise
//    (tested); with the optional intensity or confidence maps the kernel runs per pixel.

#include "rasm/tracking/kernels/IcpKernels.h"

namespace rasm::tracking {

/// The reduction of one ICP iteration at one level, on the CPU.
kernels::IcpAccumulator reduceIcpCpu(const kernels::IcpReduceKernel& k);

/// One level of the model pyramid (k.out_* from k.in_*), on the CPU.
void downsampleModelCpu(const kernels::ModelDownsampleKernel& k);

}  // namespace rasm::tracking
