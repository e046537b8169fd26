#pragma once
// CPU launcher of the ICP reduction (II-C): IcpReduceKernel's pixels four at a time (SSE). Each
// lane runs the kernel's float operations in the same order (Eigen's 3-term sums as
// a0 + (a1 + a2), its cross product), and the inliers enter the sums in pixel order, so the
// result is bit-identical to compute::reduce1D over the kernel itself (tested). Kernels with a
// model confidence map take the scalar path.

#include "rasm/tracking/kernels/IcpKernels.h"

namespace rasm::tracking {

/// The reduction of one ICP iteration at one level, on the CPU.
kernels::IcpAccumulator reduceIcpCpu(const kernels::IcpReduceKernel& k);

}  // namespace rasm::tracking
