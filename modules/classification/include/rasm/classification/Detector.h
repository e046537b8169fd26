#pragma once
// The detector interface of section IV. A detector takes a colour image and returns boxes with
// per-class scores (Detection.h). Real detectors (DnnDetector: YOLO family on OpenCV dnn;
// ZeroShotDetector: HOG templates of IV-A) look at the image only; the simulator's detector
// (pipeline/SimDetector.h) reads the frame's ground truth instead, so the input carries the whole
// frame.
// Detectors run on worker threads (DetectorWorker.h): detect() is called from one thread at a
// time per detector object, never concurrently on the same object.

#include <cstddef>
#include <memory>
#include <opencv2/core/mat.hpp>
#include <string>
#include <vector>

#include "rasm/classification/Detection.h"
#include "rasm/core/RgbdFrame.h"

namespace rasm::classification {

struct DetectorInput {
  cv::Mat bgr;                       ///< 8-bit 3-channel B,G,R (CV_8UC3)
  const RgbdFrame* frame = nullptr;  ///< the whole frame when there is one (ground truth: sim)
  std::size_t frame_index = 0;
};

class Detector {
 public:
  virtual ~Detector() = default;
  /// Short name of this detector instance (its INI section, e.g. "dnn_detector", "zero_shot").
  virtual std::string name() const = 0;
  /// Names of the classes its ClassScore::class_index refers to (COCO names as in coco.names for
  /// COCO-trained models; Darknet spellings are accepted by ClassList as aliases).
  virtual const std::vector<std::string>& classNames() const = 0;
  /// Detections in one image. Throws on failure (the worker then disables the detector).
  virtual std::vector<Detection> detect(const DetectorInput& input) = 0;
};

/// A cv::Mat header over an RgbdFrame's colour image (no copy; valid while the frame lives).
cv::Mat colourMat(const RgbdFrame& frame);

}  // namespace rasm::classification
