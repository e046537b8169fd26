#pragma once
// Builds the detectors [classification] detectors names, each from its own section, and owns
// those sections' params (so the pipeline stage lists them as its INI sections).

#include <memory>
#include <string>
#include <vector>

#include "rasm/classification/Detector.h"
#include "rasm/classification/DnnDetector.h"
#include "rasm/classification/TClassificationParams.h"
#include "rasm/classification/ZeroShotDetector.h"
#include "rasm/sim/SimulatedDetector.h"

namespace mrpt::config {
class CLoadableOptions;
}

namespace rasm::classification {

struct DetectorSections {
  sim::TDetectorParams sim_detector;
  TDnnDetectorParams dnn_detector;
  TZeroShotParams zero_shot;

  /// (section name, params) of every detector section.
  std::vector<std::pair<std::string, mrpt::config::CLoadableOptions*>> list();
};

struct DetectorBuild {
  std::vector<std::unique_ptr<Detector>> detectors;
  /// Detectors left out (optional ones whose files are missing), one line each.
  std::vector<std::string> warnings;
};

/// The detectors of `params.detectorList()` in that order. `sim_scene`: the simulator's scene for
/// the simulated detector's occlusion test (may be null). A listed detector whose own section says
/// enabled = false is left out with a warning; so is a DNN detector whose files are missing when
/// its `required` is false. Throws InputError for a detector that cannot be built otherwise.
DetectorBuild makeDetectors(const TClassificationParams& params, DetectorSections& sections,
                            const sim::RayScene* sim_scene);

}  // namespace rasm::classification
