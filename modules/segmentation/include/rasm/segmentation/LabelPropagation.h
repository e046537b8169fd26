#pragma once
// Label propagation of section III: the frame's segments L_t take the labels of the map.
//   L^r(u)  the segment label of the map surfel the pixel would be fused with: among the 4x index
//           map candidates of u at T_t (fusion's IndexMapView), the one nearest in depth to the
//           measurement within a gate (0 when none, or when that surfel has no label);
//   Pi(r,l) pixels with L^r = r and L_t = l (sparse: a few map labels per current segment);
//   L^p(u)  for L_t(u) = l: the map label r maximising Pi(r, l), normalised by l's cardinality
//           over the pixels that have a map label, when that overlap reaches
//           propagation_min_overlap (and propagation_min_overlap_px pixels); else a new label.
// It also reports, for the merge confidence Psi, which map labels share a current segment and
// which map labels were in view.

#include <cstdint>
#include <utility>
#include <vector>

#include "rasm/core/Image.h"
#include "rasm/fusion/SurfelFusion.h"
#include "rasm/segmentation/GeometricSegmenter.h"
#include "rasm/segmentation/TSegmentationParams.h"
#include "rasm/surfel_map/SurfelArrays.h"

namespace rasm::segmentation {

struct Propagation {
  Image<std::uint32_t> rendered;    ///< L^r on every propagation_step_px-th pixel
  Image<std::uint32_t> propagated;  ///< L^p (0 where L_t is 0)
  /// Per current label l (index, [0] unused): its map label, new ones included.
  std::vector<std::uint32_t> label_of;
  int matched = 0;  ///< current segments that took a map label
  int created = 0;  ///< current segments that got a new label
  /// Map-label pairs (a < b) that share a current segment, each with at least merge_min_fraction
  /// of that segment's labelled pixels (sorted, unique).
  std::vector<std::pair<std::uint32_t, std::uint32_t>> cosegmented;
  /// Map labels in view with at least propagation_min_overlap_px pixels of L^r (sorted).
  std::vector<std::uint32_t> visible;
};

/// `next_label` is the first unused map label; it advances by the labels created.
void propagateLabels(const FrameSegments& segments, const Image<Vec3f>& vertex_cam,
                     const fusion::IndexMapView& index_map, const maps::SurfelArrays& surfels,
                     const TSegmentationParams& params, std::uint32_t& next_label,
                     Propagation& out);

}  // namespace rasm::segmentation
