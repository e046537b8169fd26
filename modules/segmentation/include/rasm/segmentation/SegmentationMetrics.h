#pragma once
// Evaluation of a segmented surfel map against ground-truth instances
// (`rasm eval segmentation`, docs/segmentation.md "Evaluation"). Pure computation over per-surfel
// labels: the caller assigns each surfel its ground-truth instance (the simulator: the instance of
// the nearest world surface, rasm/sim/SurfaceInstance.h) and says which instances are objects.
//
// Notation. For a predicted segment s (id > 0) and a ground-truth instance g (id > 0):
//   |g|      surfels whose instance is g (whatever their segment, 0 included)
//   |s|      surfels of segment s whose instance is not 0 (instance 0 = void: no surface near the
//            surfel, or unknown; void surfels are removed from predictions, as in standard PQ)
//   |s ∩ g|  surfels of segment s and instance g
//   IoU(s, g) = |s ∩ g| / (|s| + |g| - |s ∩ g|)
// Evaluated objects: the instances listed in `objects` whose size (largest extent of the object's
// own bounding box) is > min_object_size_m and that hold >= min_object_surfels surfels in the map
// (an object the camera never saw is not counted against the segmentation; how many were left out
// is reported). Every other non-void instance (structure, small or barely seen objects) takes part
// in the unions and majorities but is never a match target.
//
// Metrics:
//   matched pair      evaluated object g and segment s with IoU(s, g) > iou_threshold (0.5). With a
//                     threshold >= 0.5 each object and each segment is in at most one pair.
//   recovered         g is in a matched pair ("recovered as one segment");
//                     objects_recovered_fraction = recovered / evaluated objects.
//   TP, FN            matched pairs; evaluated objects not recovered.
//   FP                segments s not in a matched pair whose majority instance (the g maximising
//                     |s ∩ g|, ties to the lower id) is an evaluated object. Unmatched segments
//                     whose majority is structure, a non-evaluated object, or that hold only void
//                     surfels are ignored (the "stuff"/void rule of PQ, here class-agnostic).
//   SQ = mean IoU over TP (0 when TP = 0); RQ = TP / (TP + FP/2 + FN/2); PQ = SQ * RQ.
//   owned segments    segments whose majority instance is g; segments_per_object = mean number of
//                     owned segments over the evaluated objects that own at least one
//                     (over-segmentation, 1 is ideal); objects_without_segment counts the others.
//   dominant segment  of g: the segment s > 0 maximising |s ∩ g| (ties to the lower id), none
//                     when all of g's surfels have segment 0.
//   under-segmented   g shares a segment with another instance: some segment s holding at least
//                     a quarter of g (|s ∩ g| >= 0.25 |g|) holds at least half as many surfels of
//                     some other non-void instance h (object, furniture or structure) as of g:
//                     max_{h != g} |s ∩ h| >= 0.5 |s ∩ g|. `merged_with` = that h, for the
//                     qualifying s with the largest |s ∩ g|. (A mug merged into its desk's
//                     segment counts; a few stray desk surfels in the mug's segment, or a few mug
//                     surfels in the desk's segment while the rest of the mug has segment 0, do
//                     not.)
// Undefined values (a ratio over an empty set) are NaN; JSON writers turn them into null.

#include <cstdint>
#include <string>
#include <vector>

namespace rasm::segmentation {

/// A ground-truth instance that may count as an object.
struct GtObject {
  std::uint32_t instance_id = 0;  ///< > 0
  int class_id = 0;               ///< for the report only (0 = unknown)
  std::string class_name;         ///< for the report only
  std::string name;               ///< for the report only ("desk_1"), may be empty
  double size_m = 0.0;            ///< largest extent of its bounding box (m)
  bool is_static = false;         ///< furniture (report only)
};

struct SegmentationMetricsParams {
  double iou_threshold = 0.5;            ///< a match needs IoU > this (>= 0.5 keeps matches unique)
  double min_object_size_m = 0.10;       ///< objects need size_m > this
  std::size_t min_object_surfels = 50;   ///< and at least this many surfels in the map
  double undersegment_ratio = 0.5;       ///< see "under-segmented" above (0.5)
  double undersegment_min_share = 0.25;  ///< see "under-segmented" above (0.25)
  bool stable_only = false;              ///< use only surfels with stable != 0 (needs `stable`)
};

/// Per-object row (every listed object larger than min_object_size_m, evaluated or not).
struct ObjectResult {
  GtObject object;
  std::size_t surfels = 0;         ///< |g|
  std::size_t unsegmented = 0;     ///< surfels of g with segment 0
  bool evaluated = false;          ///< surfels >= min_object_surfels
  std::uint32_t best_segment = 0;  ///< the segment maximising IoU(s, g) (0 = none)
  double iou = 0.0;                ///< IoU(best_segment, g)
  bool recovered = false;
  std::uint32_t dominant_segment = 0;
  std::size_t owned_segments = 0;
  bool undersegmented = false;
  std::uint32_t merged_with = 0;  ///< instance h when under-segmented
};

struct SegmentationMetrics {
  // What was covered.
  std::size_t surfels = 0;            ///< surfels used (after stable_only)
  std::size_t void_surfels = 0;       ///< instance 0
  std::size_t segmented_surfels = 0;  ///< segment > 0
  std::size_t segments = 0;           ///< distinct segment ids > 0
  std::size_t objects_listed = 0;     ///< objects passed in
  std::size_t objects_over_size = 0;  ///< of those, size_m > min_object_size_m
  std::size_t objects_unseen = 0;     ///< over size but < min_object_surfels surfels
  std::size_t objects_evaluated = 0;

  // The metrics (definitions in the header comment).
  std::size_t recovered = 0;
  double objects_recovered_fraction = 0.0;
  std::size_t tp = 0, fp = 0, fn = 0;
  double sq = 0.0, rq = 0.0, pq = 0.0;
  double segments_per_object = 0.0;
  std::size_t objects_without_segment = 0;
  std::size_t undersegmented_objects = 0;
  double undersegmented_fraction = 0.0;

  std::vector<ObjectResult> per_object;  ///< in the order of `objects`
};

/// Computes the metrics. `segment` and `instance` hold one entry per surfel; `stable` is empty or
/// as long (used with params.stable_only). Throws std::invalid_argument when there are no surfels
/// (none at all or none stable with stable_only), sizes differ, params are out of range or an
/// object's instance id is 0 or repeated. With no evaluated object every ratio is NaN.
SegmentationMetrics computeSegmentationMetrics(const std::vector<std::uint32_t>& segment,
                                               const std::vector<std::uint32_t>& instance,
                                               const std::vector<std::uint8_t>& stable,
                                               const std::vector<GtObject>& objects,
                                               const SegmentationMetricsParams& params = {});

/// Label stability: how often a stable surfel's segment id changed, per stable surfel
/// (label_changes_stable / stable_surfels, counted by the segmentation stage over a run).
/// NaN when stable_surfels is 0.
double labelChangesPerStableSurfel(std::uint64_t label_changes_stable,
                                   std::uint64_t stable_surfels);

}  // namespace rasm::segmentation
