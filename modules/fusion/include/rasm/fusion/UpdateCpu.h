#pragma once
// CPU launcher of the surfel update of II-D (kernels::UpdateKernel::update), four associated
// pixels per SSE operation. The per-surfel update is one long dependency chain (averaging, two
// normalisations, the basis' double cross product): scalar, one pixel's chain left the core
// waiting on square-root and division latencies. Each lane runs the kernel's float operations in
// the same order (Eigen's 3-term sums as a0 + (a1 + a2), RigidF's as ((a0 + a1) + a2) + a3), so
// the map is bit-identical to the kernel's (tested). Colour, segment weights, view bins and the
// carving verdict stay scalar per lane (the kernel's own code).

#include "rasm/fusion/kernels/FusionKernels.h"

namespace rasm::fusion {

/// What an associated pixel keeps from its association for the update (AssociateKernel::associate):
/// camera-frame vertex, world-frame normal, confidence weight and radius (II-B). 32 bytes, so four
/// of them transpose into eight SSE planes.
struct alignas(16) KeptMeasurement {
  Vec3f v, n_world;
  float w, r;
};

/// The update of every associated pixel of row y (k.pixel_surfel >= 0) with the measurements
/// `kept` of that row (indexed by column), in column order; the surfels' arrays are prefetched a
/// few pixels ahead (segment arrays when `labels`, view-bin rows when `bins`).
void updateRowCpu(const kernels::UpdateKernel& k, int y, const KeptMeasurement* kept, bool labels,
                  bool bins);

}  // namespace rasm::fusion
