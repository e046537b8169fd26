#pragma once
// SIMULATION of a YOLO-like 2-D object detector (paper section IV consumes such detections):
// it does not look at the image at all, but at the simulator's ground truth. For every visible
// labelled object of a detectable class it draws, with a seeded generator:
//  - detection with probability  p = p_max * s(size) * v(visible fraction), where
//    s = 1 / (1 + exp(-(sqrt(mask area) - size50_px) / size_scale_px)) rises with apparent size
//    and v = clamp((f - min_visible) / (1 - min_visible), 0, 1)^occlusion_exponent falls with
//    occlusion; f = visible pixels / pixels the object would cover with nothing in front of it
//    (ray cast against the object alone over its projected bounding box);
//  - a box from the visible instance mask, each edge jittered by N(0, (box_jitter * size)^2);
//  - with probability confusion_rate, a wrong class (a similar one when the object has one in
//    the confusion table, else any detectable class);
//  - a score in [0, 1] that grows with p (lower for confused classes);
// plus Poisson(false_positives_per_frame) false positives, half of them on unlabelled clutter.
// The classification module adapts Detection to its own detector interface.

#include <mrpt/config/CLoadableOptions.h>

#include <cstdint>
#include <opencv2/core/types.hpp>
#include <string>
#include <vector>

#include "rasm/core/RgbdFrame.h"
#include "rasm/sim/RayScene.h"

namespace rasm::sim {

struct Detection {
  cv::Rect2f box;    ///< pixels (x, y, width, height), inside the image
  int class_id = 0;  ///< SimClasses id (COCO k -> k + 1)
  std::string class_name;
  float score = 0.f;  ///< [0, 1]
  // Simulation bookkeeping (what a real detector cannot know), for evaluation:
  int gt_instance = 0;    ///< the object it came from; 0 for a false positive
  bool confused = false;  ///< class differs from the object's
  float visible_fraction = 1.f;
};

/// INI section [sim_detector] (keys as the member names).
struct TDetectorParams : public mrpt::config::CLoadableOptions {
  /// "coco" (the 80 COCO classes, like a COCO-trained YOLO), "all", or a comma-separated list
  /// of class names.
  std::string detectable_classes = "coco";
  double p_max = 0.95;
  double size50_px = 28.0;
  double size_scale_px = 8.0;
  double min_visible_fraction = 0.2;
  double occlusion_exponent = 1.0;
  double box_jitter = 0.04;
  double confusion_rate = 0.05;
  double false_positives_per_frame = 0.15;
  double score_noise = 0.08;
  int min_mask_pixels = 16;
  /// Compute the visible fraction by ray casting (needs the RayScene); false: assume 1.
  bool occlusion_aware = true;

  /// Parsed detectable_classes (class ids); throws InputError for unknown names.
  std::vector<int> detectableClassIds() const;

  void loadFromConfigFile(const mrpt::config::CConfigFileBase& cfg,
                          const std::string& section) override;
  void saveToConfigFile(mrpt::config::CConfigFileBase& cfg,
                        const std::string& section) const override;
  void validate(const std::string& section = "sim_detector") const;
};

class SimulatedDetector {
 public:
  /// `scene` (may be null) enables the occlusion-aware visible fraction; it must be the scene
  /// the frames were rendered from and outlive the detector.
  explicit SimulatedDetector(const TDetectorParams& params = {}, const RayScene* scene = nullptr);

  /// Detections for a simulated frame (needs gt_instance, gt_class and gt_T_world_cam). The
  /// result depends only on (frame contents, frame.index, seed).
  std::vector<Detection> detect(const RgbdFrame& frame, std::uint64_t seed = 0) const;

  /// Visible fraction of an instance in a frame: mask pixels / unoccluded projected pixels
  /// (1 without a scene). Exposed for tests.
  float visibleFraction(const RgbdFrame& frame, int instance_id, int mask_pixels) const;

  const TDetectorParams& params() const { return m_params; }

 private:
  TDetectorParams m_params;
  const RayScene* m_scene;
  std::vector<char> m_detectable;  ///< by class id
};

}  // namespace rasm::sim
