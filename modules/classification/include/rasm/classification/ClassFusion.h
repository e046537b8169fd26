#pragma once
// Segment-level fusion of detections into the map (paper IV).
//
// Association. For each detection d and segment l of the propagated label map L^p of the frame
// the detection was computed on, I(l, d) counts the pixels of l inside d's box and U(l, d) =
// |l| + |box| - I(l, d) the union; the detection belongs to s_d = argmax_l I(l, d) / U(l, d)
// (the paper prints argmin: a typo, the best overlap is wanted) when that IoU reaches min_iou.
// Segments, not boxes, take the class: a box that covers an object and part of the wall behind
// it overlaps the object's segment with a high IoU and the wall's (a large segment) with a low
// one, so the wall is not labelled (the paper's argument for segment-level fusion).
//
// Bayes fusion. Every surfel of s_d updates p_c(i) <- p_d p / (p_d p + (1 - p_d)(1 - p)) for each
// class i the detection reports, which in log-odds is L += logit(p_d) (ClassEvidence.h); classes
// it does not report carry no evidence. A segment's class is the one with the highest mean
// posterior over its surfels (a surfel without evidence for a class counts at the 0.5 prior).

#include <cstdint>
#include <vector>

#include "rasm/classification/Detection.h"
#include "rasm/core/Image.h"
#include "rasm/surfel_map/SurfelArrays.h"

namespace rasm::classification {

struct Association {
  std::uint32_t segment = 0;  ///< s_d; 0 = no segment reached min_iou
  float iou = 0.f;            ///< I / U of s_d
  int intersection = 0;       ///< I(s_d, d), pixels
  int union_ = 0;             ///< U(s_d, d), pixels
  /// The other segments with at least piece_min_inside_fraction of their pixels in the box
  /// (sorted; empty when s_d is 0): pieces of the same thing, or things in front of it.
  std::vector<std::uint32_t> pieces;
};

/// s_d for each detection (same order). `labels`: L^p (0 = no segment). Boxes are clipped to
/// the image; a box outside it has no segment. Pieces are listed only when
/// piece_min_inside_fraction is in (0, 1].
std::vector<Association> associateDetections(const Image<std::uint32_t>& labels,
                                             const std::vector<Detection>& detections,
                                             float min_iou, float piece_min_inside_fraction = 0.f);

/// How a detector's score becomes the p_d of the Bayes update.
enum class ScoreModel {
  /// p_d = score (the paper: scores are approximate probabilities; a score below 0.5 lowers p).
  Probability,
  /// p_d = 0.5 + 0.5 (score - s0) / (1 - s0) for score > s0, else 0.5 (no evidence): a
  /// detection is evidence for its class in proportion to how far its score rises above the
  /// neutral score s0, and never evidence against it (detectors whose scores are not calibrated
  /// probabilities: a true but weak YOLO detection at 0.3 must not lower the class).
  Vote,
};
/// p_d of a score under `model` (s0: the Vote model's neutral score), clamped to
/// [1 - max_p, max_p].
float detectionProbability(float score, ScoreModel model, float max_p, float s0 = 0.f);

/// Evidence for one class of one segment: L += weight logit(p_detection) for its surfels.
struct SegmentEvidence {
  std::uint32_t segment = 0;
  int class_id = 0;
  float p_detection = 0.5f;
  float weight = 1.f;  ///< 1: the paper's update; < 1 a weaker one (e.g. the association's IoU)
};

/// The Bayes update of IV that one evidence item makes, in log-odds: weight logit(p_detection),
/// in the fixed-point units of ClassEvidence.h. Every fusion of detections (the surfels',
/// fuseSegmentEvidence; the objects', ObjectMap) adds exactly this with maps::classEvidenceAdd.
int evidenceLogitUnits(const SegmentEvidence& e);

struct FusionCounts {
  std::size_t surfels = 0;  ///< surfel updates (a surfel counts once per evidence item)
  std::size_t dropped = 0;  ///< updates with no slot left (ClassEvidence.h slot rule)
};

/// Applies the evidence to every live surfel of each segment (one parallel pass over the map;
/// pass SurfelStore::arraysForClassEvidence(), which does not invalidate fusion's caches).
FusionCounts fuseSegmentEvidence(const maps::SurfelArrays& surfels,
                                 const std::vector<SegmentEvidence>& evidence);

/// The same update applied to the listed surfels (indices into `surfels`; dead ones skipped; a
/// slot freed and reused since is not told apart) instead of a segment's: evidence that waited
/// (PoseConsensus.h) lands on the surfels its detection saw, whichever segments they belong to
/// now.
FusionCounts fuseSurfelListEvidence(const maps::SurfelArrays& surfels,
                                    const std::vector<std::int32_t>& indices,
                                    const std::vector<SegmentEvidence>& evidence);

/// The class of one segment: best and runner-up by mean posterior over its surfels.
struct SegmentClass {
  std::uint32_t segment = 0;
  int surfels = 0;
  int best_id = 0;  ///< 0 when no class's mean posterior exceeds 0.5
  float best_p = 0.5f;
  int runner_up_id = 0;
  float runner_up_p = 0.5f;
};

/// Every segment with live surfels, sorted by segment id.
std::vector<SegmentClass> segmentClasses(const maps::SurfelArrays& surfels);

}  // namespace rasm::classification
