#pragma once
// The object layer over the segments (IV's map as a user reads it; objects as entities as
// Fusion++ keeps them): one object per physical thing, however many segments it fell into.
//
// Per segment the layer keeps what the detectors said about it: the log-odds class histogram
// of the detections associated with it (the same Bayes update as the surfels', IV:
// evidenceLogitUnits + maps::classEvidenceAdd, 4 slots of ClassEvidence.h), how many detections
// it received and its views: the frames a detector processed in which the segment covered at
// least [objects] min_view_pixels of L^p, each marked detected when one of the frame's detections
// went to it. These follow the segmentation's relabelling (merged segments add their histograms
// and unite their views).
//
// Grouping (update). Two segments are pieces of one object when (a) each one's own best class
// is the same class with probability >= link_min_probability, (b) neither is structure on its own
// (a floor named "dining table" must not swallow the table), (c) their axis-aligned boxes
// overlap or leave a gap of at most link_max_gap_m on every axis, and (d) detections held both
// (one associated, the other a piece of its box: the detections' merge evidence), in at least
// link_min_codetection_fraction of the detections of the less detected one (two desks side by
// side touch, but each has its own boxes), or they were never in one view and the smaller one's
// box lies mostly inside the other's (link_min_box_containment: one thing seen in pieces on
// different visits, which no detection could hold together);
// objects are the connected
// components (so a desk split at its folds into a top and a side panel, both named, is one
// object; two chairs 0.5 m apart are two). A segment no rule links is an object of its own, and
// so is one the segment table does not hold yet (it is refreshed every few frames, III).
//
// Identity. An object keeps its id while its segments merge, change or are joined by new ones:
// each new group takes the oldest (smallest) id its segments had; groups are served by size
// (surfels), so when an object splits the larger part keeps the id and the other gets a new one.
// Ids are never reused.
//
// An object's data: the histogram of all its segments' detections (log-odds added, so each
// detection counts once: the association gives it to one segment), its views (a frame and
// detector counted once however many of its segments were visible), the existence probability
// (detected + 1) / (views + 2) over the detectors whose class list holds its class (Laplace's
// rule: detected in 1 of 1 views is 0.67, in 1 of 20 is 0.09), the frames it was seen and
// detected in, its segments' axis-aligned box (their union) and an upright oriented box (the
// axes of its largest segment's upright box, extents covering every segment's upright box).
// verdict: objectVerdict (ObjectVerdict.h) of the whole object; Structure also when its segments
// are thin planes in the plane of a structure segment of the table (a piece of the floor under
// a desk that the desk's boxes named "dining table"); then RarelyDetected when its existence
// probability is below min_existence_probability.

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <map>
#include <set>
#include <utility>
#include <vector>

#include "rasm/classification/ClassFusion.h"
#include "rasm/classification/ObjectVerdict.h"
#include "rasm/classification/TClassificationParams.h"
#include "rasm/classification/TObjectParams.h"
#include "rasm/core/Image.h"
#include "rasm/segmentation/SegmentTable.h"
#include "rasm/surfel_map/ClassEvidence.h"

namespace rasm::classification {

/// One detector's result on one frame, as the object layer needs it.
struct DetectorView {
  std::size_t frame = 0;  ///< the frame's index in the run
  int detector = 0;       ///< which detector (ClassificationStage's worker index)
  /// (segment, pixels of it in the frame's L^p) for every segment of L^p (segmentPixelCounts).
  std::vector<std::pair<std::uint32_t, int>> segment_pixels;
  /// The segment of each detection that found one (one entry per detection).
  std::vector<std::uint32_t> detected_segments;
  /// (detected segment, piece) for every piece of those detections (Association::pieces).
  std::vector<std::pair<std::uint32_t, std::uint32_t>> co_detected;
  /// The class evidence the detections gave (as fused into the surfels).
  std::vector<SegmentEvidence> evidence;
};

/// (segment, pixels) of every nonzero label of `labels`, sorted by segment.
std::vector<std::pair<std::uint32_t, int>> segmentPixelCounts(const Image<std::uint32_t>& labels);

/// A class of an object's histogram and its posterior.
struct ClassProbability {
  int class_id = 0;
  float probability = 0.5f;
};

struct MapObject {
  int id = 0;                           ///< persistent over the run, from 1
  std::vector<std::uint32_t> segments;  ///< sorted
  maps::ClassEvidence histogram;        ///< log-odds of its detections (IV)
  /// The histogram's classes by decreasing posterior (at most maps::kClassSlots; those above
  /// 0.5 first); best = top[0] when its posterior exceeds 0.5.
  std::vector<ClassProbability> top;
  ClassProbability best, runner_up;
  int detections = 0;  ///< detections associated with its segments
  int views = 0;       ///< views by the detectors that report its class
  int views_detected = 0;
  double existence_probability = 0.5;  ///< (views_detected + 1) / (views + 2)
  std::size_t first_seen_frame = 0, last_seen_frame = 0;
  int frames_seen = 0;      ///< distinct frames with a view of it (any detector)
  int frames_detected = 0;  ///< distinct frames in which a detection went to it
  int surfels = 0;          ///< of its segments with geometry
  /// false: none of its segments is in the segment table (gone from the map, or no segmentation
  /// stage): no surfels, so never reported (a fragment at most).
  bool has_geometry = false;
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();  ///< surfel-weighted (world, m)
  Eigen::Vector3d bbox_min = Eigen::Vector3d::Zero(), bbox_max = Eigen::Vector3d::Zero();
  Eigen::Matrix3d box_axes = Eigen::Matrix3d::Identity();  ///< upright: 2 horizontal, +z
  Eigen::Vector3d box_centre = Eigen::Vector3d::Zero(), box_extents_m = Eigen::Vector3d::Zero();
  ObjectVerdict verdict = ObjectVerdict::Unconfirmed;
};

class ObjectMap {
 public:
  ObjectMap() = default;
  ObjectMap(const TObjectParams& objects, const TClassificationParams& classification)
      : m_params(objects), m_thresholds(classification) {}

  /// The class ids detector `detector` can report (its views count for objects of those classes
  /// only); a detector never declared counts for every class.
  void setDetectorClasses(int detector, const std::vector<int>& class_ids);
  /// Records one detector result: views of the segments it saw, detections and class evidence.
  void addDetectorView(const DetectorView& view);
  /// The segmentation renamed its segments: new = table[old] (0 or past the end of the table:
  /// old kept; 0: dropped). Merged segments unite their records.
  void relabel(const std::vector<std::uint32_t>& table);
  /// Regroups the segments into objects with `segments` (the segment table: sorted by id) and
  /// recomputes every object's data; ids carry over (header).
  void update(const std::vector<segmentation::SegmentStats>& segments);

  /// Every object of the last update (reported or not), by id.
  const std::vector<MapObject>& objects() const { return m_objects; }
  /// The object holding `segment` at the last update, null when none.
  const MapObject* objectOfSegment(std::uint32_t segment) const;
  /// The object of each segment at the last update, its segments renamed by every relabel since.
  const std::map<std::uint32_t, int>& objectIdOfSegment() const { return m_object_of_segment; }
  /// The object `id` of the last update, null when none.
  const MapObject* object(int id) const;
  /// A segment's own record (histogram, detections), null when the layer has none.
  struct SegmentRecord {
    maps::ClassEvidence histogram;
    int detections = 0;
    /// (frame, detector) -> detected; a view counts once per frame and detector.
    std::map<std::pair<std::size_t, int>, bool> views;
  };
  const SegmentRecord* segmentRecord(std::uint32_t segment) const;

 private:
  std::vector<std::vector<std::uint32_t>> groupSegments(
      const std::vector<segmentation::SegmentStats>& segments) const;
  void assignIds(std::vector<MapObject>& objects);
  MapObject describe(const std::vector<std::uint32_t>& group,
                     const std::vector<segmentation::SegmentStats>& segments,
                     const std::vector<const segmentation::SegmentStats*>& structure) const;
  /// Whether every segment of `group` the table holds is a piece of one of the `structure`
  /// segments (a thin plane in a floor's, wall's or ceiling's plane: TClassificationParams
  /// structure_piece_*), and one at least.
  bool partOfStructure(const std::vector<std::uint32_t>& group,
                       const std::vector<segmentation::SegmentStats>& segments,
                       const std::vector<const segmentation::SegmentStats*>& structure) const;
  void describeGeometry(MapObject& o,
                        const std::vector<segmentation::SegmentStats>& segments) const;
  bool reportsClass(int detector, int class_id) const;

  TObjectParams m_params;
  TClassificationParams m_thresholds;
  std::map<std::uint32_t, SegmentRecord> m_segments;
  /// Detections that held both segments of a pair (smaller label first); follows relabel.
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> m_codetections;
  /// Rule (d) of the grouping (header) for segments a and b.
  bool seenTogether(std::uint32_t a, std::uint32_t b) const;
  /// Rule (d)'s alternative: segments a and b never in one view, the smaller box at least
  /// link_min_box_containment inside the other.
  bool oneInsideTheOther(std::uint32_t a, std::uint32_t b, const segmentation::SegmentStats& sa,
                         const segmentation::SegmentStats& sb) const;
  std::map<int, std::set<int>> m_detector_classes;
  std::map<std::uint32_t, int> m_object_of_segment;  ///< last update's ids, follows relabel
  std::vector<MapObject> m_objects;
  int m_next_id = 1;
};

}  // namespace rasm::classification
