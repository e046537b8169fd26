#pragma once
// Evaluation of a classified surfel map against ground truth (`rasm eval
// classification`, docs/classification.md "Evaluation"). Pure computation over per-surfel labels,
// like segmentation/SegmentationMetrics.h: the caller gives each surfel its segment and its
// ground-truth instance (the simulator: the instance of the nearest world surface), each segment
// its predicted class (objects.json), and the world's objects with their classes.
//
// Classes are compared by name (canonical: the caller maps aliases such as Darknet's
// "diningtable" to one spelling). For an object g and a segment s, |s ∩ g| counts the surfels of
// s whose instance is g.
//   evaluated object   not structure, size_m > min_object_size_m (10 cm), >= min_object_surfels
//                      surfels in the map (an object never seen is not counted against the map).
//   its segment        the dominant segment of g: the s > 0 maximising |s ∩ g| (none when all of
//                      g's surfels have segment 0).
//   segmented          g's dominant segment's majority instance is g (the segment is g's own, not
//                      g merged into its desk) and holds at least min_segment_share of g.
//   correct            g's segment carries g's class (the segment's best class).
//   object_accuracy    correct / evaluated objects.
//   segmented_accuracy correct / segmented objects, over objects whose class is in
//                      `detectable_classes` (empty: all): the issue's target ("segmented
//                      COCO-class objects larger than 10 cm carry the right class").
//   per class c        recall = objects of class c correct / evaluated objects of class c;
//                      precision = segments predicted c whose majority instance is an object of
//                      class c / segments predicted c (segments of >= min_object_surfels surfels
//                      with a non-void majority).
//   confusion          evaluated objects by (true class, predicted class of their segment, "none"
//                      when it has no class or no segment).
//   by views           object accuracy of the evaluated objects binned by the detections fused
//                      into their segment (`segment_detections`; the views in which a detector
//                      saw the object and the fusion found its segment): bins 0, 1-2, 3-5, 6-10,
//                      11+.

#include <cstdint>
#include <map>
#include <set>
#include <string>
#include <vector>

namespace rasm::classification {

struct GtClassObject {
  std::uint32_t instance_id = 0;
  std::string class_name;
  std::string name;  ///< report only
  double size_m = 0.0;
  bool is_structure = false;
};

struct ClassificationMetricsParams {
  double min_object_size_m = 0.10;
  std::size_t min_object_surfels = 50;
  double min_segment_share = 0.5;
  double min_object_iou = 0.5;  ///< object level: a reported object matches above this IoU
  std::set<std::string> detectable_classes;  ///< for segmented_accuracy; empty = every class
};

struct ObjectClassResult {
  GtClassObject object;
  std::size_t surfels = 0;
  bool evaluated = false;
  std::uint32_t segment = 0;   ///< dominant segment, 0 = none
  double segment_share = 0.0;  ///< |s ∩ g| / |g|
  bool segmented = false;
  std::string predicted = "none";
  bool correct = false;
  bool detectable = false;
  int views = 0;  ///< detections fused into its segment
};

struct ClassStats {
  std::size_t objects = 0, objects_correct = 0;           ///< recall = correct / objects
  std::size_t segments_predicted = 0, segments_true = 0;  ///< precision = true / predicted
  double recall() const;
  double precision() const;  ///< NaN when nothing was predicted
};

struct ViewBin {
  int min_views = 0, max_views = 0;  ///< inclusive; max_views < 0: no upper bound
  std::size_t objects = 0, correct = 0;
};

struct ClassificationMetrics {
  std::size_t evaluated = 0, correct = 0;
  std::size_t segmented_detectable = 0, segmented_detectable_correct = 0;
  double object_accuracy = 0.0;     ///< NaN when nothing is evaluated
  double segmented_accuracy = 0.0;  ///< NaN when no detectable object is segmented
  std::map<std::string, ClassStats> per_class;
  /// confusion[true][predicted] = objects.
  std::map<std::string, std::map<std::string, std::size_t>> confusion;
  std::vector<ObjectClassResult> per_object;
  std::vector<ViewBin> by_views;
};

// Object level (the object list a user reads, objects.json): a reported object is the union of
// its segments' surfels R; a ground-truth object g is the map's surfels whose instance is g, G.
//   IoU(R, g)          |R ∩ G| / (|R| + |G| - |R ∩ G|); above 0.5 R covers more than half of G and
//                      G more than half of R, so an object and a reported object match at most
//                      once each (reported objects hold disjoint segments).
//   found              an evaluated object of a detectable class (as above) whose matching
//                      reported object (IoU > min_object_iou) carries its class.
//   recall             found / evaluated objects of detectable classes.
//   precision          reported objects that match an object of their class with IoU >
//                      min_object_iou / reported objects (the floor listed as a table, a phantom of
//                      a few surfels, a desk and its keyboard as one object all count against it).

/// One entry of objects.json: its class and its segments.
struct ReportedObject {
  std::uint32_t id = 0;
  std::string class_name;
  std::vector<std::uint32_t> segments;
};

struct ReportedObjectResult {
  ReportedObject object;
  std::size_t surfels = 0;
  std::uint32_t best_instance = 0;  ///< the ground-truth instance of largest IoU, 0 = none
  std::string best_name, best_class = "none";
  double iou = 0.0;      ///< with best_instance
  bool correct = false;  ///< iou > min_object_iou and best_class == the object's class
};

struct ObjectLevelMetrics {
  std::size_t reported = 0, reported_correct = 0;
  std::size_t objects = 0, objects_found = 0;  ///< evaluated objects of detectable classes
  double precision = 0.0;                      ///< NaN when nothing is reported
  double recall = 0.0;                         ///< NaN when no object is evaluated
  std::vector<ReportedObjectResult> per_reported;
  std::vector<std::string> missed;  ///< names of the evaluated detectable objects not found
};

/// Object-level precision and recall (above). `segment` and `instance` per surfel as for
/// computeClassificationMetrics; classes compared by canonical name.
ObjectLevelMetrics computeObjectLevelMetrics(const std::vector<std::uint32_t>& segment,
                                             const std::vector<std::uint32_t>& instance,
                                             const std::vector<ReportedObject>& reported,
                                             const std::vector<GtClassObject>& objects,
                                             const ClassificationMetricsParams& params);

/// `segment_class`: predicted class name per segment id (absent or "none" = no class).
ClassificationMetrics computeClassificationMetrics(
    const std::vector<std::uint32_t>& segment, const std::vector<std::uint32_t>& instance,
    const std::map<std::uint32_t, std::string>& segment_class,
    const std::vector<GtClassObject>& objects, const ClassificationMetricsParams& params,
    const std::map<std::uint32_t, int>& segment_detections = {});

}  // namespace rasm::classification
