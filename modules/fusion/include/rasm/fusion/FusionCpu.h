#pragma once
// SSE CPU launchers of fusion's per-pixel kernels (II-D), four pixels per SSE operation:
//  - associateRowCpu: AssociateKernel's pixel measurement (FrameView::measure and the
//    association gates) on four lanes, then each pixel's candidate scan (bestCandidate);
//  - updateRowCpu: UpdateKernel::update. The per-surfel update is one long dependency chain
//    (averaging, two normalisations, the basis' double cross product, the view bin): scalar, one
//    pixel's chain left the core waiting on square-root and division latencies.
// Each lane runs the kernel's float operations in the same order (Eigen's 3-term sums as
// a0 + (a1 + a2), RigidF's as ((a0 + a1) + a2) + a3), so the outputs are bit-identical to the
// kernels' (tested). Colour, segment weights, the carving verdict and the view bins of the layouts
// that need trigonometry stay scalar per lane (the kernel's own code).

#include "rasm/fusion/ViewInfoThresholds.h"
#include "rasm/fusion/kernels/FusionKernels.h"

namespace rasm::fusion {

/// What an associated pixel keeps from its association for the update (AssociateKernel::associate):
/// camera-frame vertex, world-frame normal, confidence weight and radius (II-B). 32 bytes, so four
/// of them transpose into eight SSE planes.
struct alignas(16) KeptMeasurement {
  Vec3f v, n_world;
  float w, r;
};

/// AssociateKernel::associate of every pixel of row y (k.pixel_surfel, k.flags), keeping the
/// measurement of each pixel with a valid one (associated or new) in kept[x]. Candidates' normals
/// are prefetched a few pixels ahead. Needs the weight table (k.frame.weight); without it the
/// kernel runs per pixel.
void associateRowCpu(const kernels::AssociateKernel<kernels::ListCandidates>& k, int y,
                     KeptMeasurement* kept);

/// measureForAssociation of the pixels xs[0..3] of row y (needs fv.weight) on four lanes, lanes
/// >= nl ignored: returns the mask of the lanes with a usable measurement (bit l) and sets m[l]
/// for those. (associateRowCpu's first step; xs may repeat columns.)
int measureFour(const kernels::FrameView& fv, const kernels::FusionKernelParams& prm,
                const RigidF& T_world_cam, int y, const int xs[4], int nl,
                kernels::PixelMeasurement m[4]);

/// CoverageKernel of every pixel of row y flagged kPixNew, with the measurements `kept` of that
/// row by associateRowCpu instead of measuring the pixel again (the same values).
void coverRowCpu(const kernels::CoverageKernel<kernels::ListCandidates>& k, int y,
                 const KeptMeasurement* kept);

/// The update of every associated pixel of row y (k.pixel_surfel >= 0) with the measurements
/// `kept` of that row (indexed by column), in column order; the surfels' arrays are prefetched a
/// few pixels ahead (segment arrays when `labels`, view-bin rows when `bins`).
/// With `ic` (built for k.prm's IC parameters) the view bins skip their exponential where it
/// cannot raise the bin (ViewInfoThresholds); the result is the same.
void updateRowCpu(const kernels::UpdateKernel& k, int y, const KeptMeasurement* kept, bool labels,
                  bool bins, const ViewInfoThresholds* ic = nullptr);

}  // namespace rasm::fusion
