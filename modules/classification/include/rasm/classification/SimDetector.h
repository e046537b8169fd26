#pragma once
// The simulator's detector (rasm/sim/SimulatedDetector.h: misses, false positives, box jitter,
// confusions, drawn from the frame's ground truth) behind the Detector interface, so simulated
// runs exercise the same workers, association and fusion as real detectors. Its classes are the
// class vocabulary's (models/ClassVocabulary.h) in id order: class index k is sim class id k + 1.

#include <cstdint>

#include "rasm/classification/Detector.h"
#include "rasm/sim/SimulatedDetector.h"

namespace rasm::classification {

class SimDetector : public Detector {
 public:
  /// `scene` (may be null: no occlusion test) must outlive the detector.
  SimDetector(const sim::TDetectorParams& params, const sim::RayScene* scene, std::uint64_t seed);

  std::string name() const override { return "sim_detector"; }
  const std::vector<std::string>& classNames() const override { return m_names; }
  /// Throws InputError when the input has no frame with ground truth (gt_instance, gt_class and
  /// gt_T_world_cam): the simulated detector cannot run on real images.
  std::vector<Detection> detect(const DetectorInput& input) override;

 private:
  sim::SimulatedDetector m_detector;
  std::uint64_t m_seed;
  std::vector<std::string> m_names;
};

}  // namespace rasm::classification
