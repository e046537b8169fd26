#pragma once
// What a 2-D detector reports for one image (paper IV): boxes with independent (multilabel) class
// probabilities p_{c,d} in [0, 1], which the map fuses into its surfels' class evidence with the
// Bayes rule of IV. Class indices are the detector's own (Detector::classNames()); ClassList maps
// them to the map's class ids.

#include <cstddef>
#include <opencv2/core/types.hpp>
#include <vector>

namespace rasm::classification {

/// One class of a detection: index into the detector's classNames() and its probability.
struct ClassScore {
  int class_index = 0;
  float score = 0.f;  ///< p_{c,d}(i) in [0, 1]
};

/// The viewpoint of the zero-shot template that matched (IV-A: "the matching pose is also
/// detected"): azimuth / elevation of the camera around the model (degrees, model frame of
/// ProceduralModels.h: z up, +x the object's front) and the template's index in its bank. The
/// model looks the same every azimuth_period_deg (its bank's azimuth symmetry; 360: none), so the
/// azimuth is known modulo that.
struct PoseHint {
  bool valid = false;
  float azimuth_deg = 0.f;
  float elevation_deg = 0.f;
  int template_index = -1;
  float azimuth_period_deg = 360.f;
};

struct Detection {
  cv::Rect2f box;  ///< pixels (x, y, width, height), clipped to the image
  /// The classes the detector gives evidence for (at least one; the others carry none: they stay
  /// at the prior, they are not pushed to 0). Sorted by decreasing score.
  std::vector<ClassScore> scores;
  PoseHint pose;

  int bestIndex() const { return scores.empty() ? -1 : scores.front().class_index; }
  float bestScore() const { return scores.empty() ? 0.f : scores.front().score; }
};

/// Greedy per-class non-maximum suppression (OpenCV NMSBoxes per best class): keeps detections
/// whose best score is >= score_threshold and drops those overlapping a kept one of the same best
/// class by IoU > iou_threshold. Order of the result: decreasing best score.
std::vector<Detection> suppressPerClass(std::vector<Detection> detections, float score_threshold,
                                        float iou_threshold);

}  // namespace rasm::classification
