#pragma once
// The simulator's detector (rasm/sim/SimulatedDetector.h: misses, false positives, box jitter,
// confusions, drawn from the frame's ground truth) behind classification's Detector interface, so
// simulated runs exercise the same workers, association and fusion as real detectors. Its classes
// are the class vocabulary's (models/ClassVocabulary.h) in id order: class index k is class id
// k + 1. It lives here rather than in classification, which does not depend on the simulator:
// ClassificationStage adds it as the detector kind sim_detector ([sim_detector]).

#include <cstdint>

#include "rasm/classification/Detector.h"
#include "rasm/sim/SimulatedDetector.h"

namespace rasm::pipeline {

class SimDetector : public classification::Detector {
 public:
  /// `scene` (may be null: no occlusion test) must outlive the detector.
  SimDetector(const sim::TDetectorParams& params, const sim::RayScene* scene, std::uint64_t seed);

  std::string name() const override { return "sim_detector"; }
  const std::vector<std::string>& classNames() const override { return m_names; }
  /// Throws InputError when the input has no frame with ground truth (gt_instance, gt_class and
  /// gt_T_world_cam): the simulated detector cannot run on real images.
  std::vector<classification::Detection> detect(
      const classification::DetectorInput& input) override;

 private:
  sim::SimulatedDetector m_detector;
  std::uint64_t m_seed;
  std::vector<std::string> m_names;
};

}  // namespace rasm::pipeline
