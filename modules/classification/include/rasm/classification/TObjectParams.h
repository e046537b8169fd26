#pragma once
// [objects]: the object layer over the segments (ObjectMap.h, docs/classification.md "Objects").
// Which segments form one object, and what an object needs to be reported beyond the
// [classification] thresholds (min_object_probability, min_object_surfels, min_object_size_m,
// structure_*), which apply to the object as a whole.

#include <mrpt/config/CLoadableOptions.h>

namespace rasm::classification {

struct TObjectParams : mrpt::config::CLoadableOptions {
  /// Two segments are pieces of one object when each one's own best class (of the detections
  /// fused into it) is the same class with at least this probability ...
  double link_min_probability = 0.6;
  /// ... and their axis-aligned boxes overlap or leave at most this gap on every axis (a desk
  /// split at its folds: the top and a side panel touch; two chairs 0.5 m apart do not).
  double link_max_gap_m = 0.05;
  /// ... and detections saw them together: a detection's box held the segment it was associated
  /// with and at least piece_min_inside_fraction of the other's pixels, in at least this
  /// fraction of the detections of the less detected of the two (and at least once). The top
  /// and side panel of one desk lie in most of the desk's boxes; two desks side by side, each
  /// with its own boxes, touch, and a box of one holds the other only in the views along the row
  /// (the office's desk_3 and desk_4). 0: the boxes' contact alone links them.
  double link_min_codetection_fraction = 0.5;
  /// ... or, when they were never in one view (no frame a detector processed showed both), the
  /// smaller one's box lies at least this fraction inside the other's (by volume, both boxes
  /// grown by 1 cm on every side so that flat pieces have one): one thing whose pieces were seen
  /// on different visits, so that no detection could hold both (the office's north monitor:
  /// half of its screen from the first pass, the whole monitor on the second, listed twice). Two
  /// things of one class side by side touch or overlap by a sliver, not by half; a desk top
  /// named "keyboard" contains the keyboard on it but was seen with it. 0: off.
  double link_min_box_containment = 0.5;
  /// A segment is a piece of a detection when this fraction of its pixels in the frame's L^p
  /// lies inside the detection's box.
  double piece_min_inside_fraction = 0.6;
  /// A frame a detector processed is a view of a segment (one in which it should have been
  /// detected) when the segment covers at least this many pixels of the frame's L^p (a segment
  /// seen at the image border or behind an occluder by a sliver is not).
  int min_view_pixels = 300;
  /// An object is reported only when its existence probability, (views with a detection + 1) /
  /// (views + 2) over the detectors that report its class, reaches this: an object detected
  /// once in 20 views it filled is a false positive (a phantom), not a thing.
  double min_existence_probability = 0.1;

  void loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s) override;
  void saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const override;
};

}  // namespace rasm::classification
