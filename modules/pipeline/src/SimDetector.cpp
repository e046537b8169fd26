#include "rasm/pipeline/SimDetector.h"

#include "rasm/core/Error.h"
#include "rasm/models/ClassVocabulary.h"

namespace rasm::pipeline {

using classification::Detection;
using classification::DetectorInput;

SimDetector::SimDetector(const sim::TDetectorParams& params, const sim::RayScene* scene,
                         std::uint64_t seed)
    : m_detector(params, scene), m_seed(seed) {
  const auto& names = models::classNames();  // entry 0 is "none"
  m_names.assign(names.begin() + 1, names.end());
}

std::vector<Detection> SimDetector::detect(const DetectorInput& input) {
  const RgbdFrame* f = input.frame;
  if (!f || f->gt_instance.empty() || f->gt_class.empty() || !f->gt_T_world_cam)
    throwInputError("[classification] detectors = sim_detector (frame " +
                        std::to_string(input.frame_index) + ")",
                    "the simulated detector needs the simulator's ground truth (instance and "
                    "class images, camera pose); use dnn_detector / zero_shot on real data");
  std::vector<Detection> out;
  for (const sim::Detection& d : m_detector.detect(*f, m_seed)) {
    if (d.class_id <= 0) continue;
    Detection o;
    o.box = d.box;
    o.scores.push_back({d.class_id - 1, d.score});
    out.push_back(std::move(o));
  }
  return out;
}

}  // namespace rasm::pipeline
