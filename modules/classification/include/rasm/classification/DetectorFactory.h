#pragma once
// Builds the detectors [classification] detectors names, each from its own section, and owns
// those sections' params (so the pipeline stage lists them as its INI sections). The built-in
// detectors are dnn_detector and zero_shot; others are added as DetectorKinds by the code that
// knows them (the simulator's detector, sim_detector: pipeline/SimDetector.h), so classification
// does not depend on the simulator.

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "rasm/classification/Detector.h"
#include "rasm/classification/DnnDetector.h"
#include "rasm/classification/TClassificationParams.h"
#include "rasm/classification/ZeroShotDetector.h"

namespace mrpt::config {
class CLoadableOptions;
}

namespace rasm::classification {

/// A detector that classification does not build itself: its name in [classification] detectors
/// (also the name of its INI section), its section's params and how to build it.
struct DetectorKind {
  std::string name;
  /// The section's params, owned by whoever adds the kind; loaded and saved with the other
  /// detector sections.
  mrpt::config::CLoadableOptions* params = nullptr;
  /// Builds the detector from `params` (already loaded); throws InputError as makeDetectors does.
  std::function<std::unique_ptr<Detector>(const TClassificationParams&)> make;
};

struct DetectorSections {
  TDnnDetectorParams dnn_detector;
  TZeroShotParams zero_shot;
  /// Detector kinds added from outside, in the order they were added.
  std::vector<DetectorKind> added;

  /// (section name, params) of every detector section: the added kinds', then the built-in ones.
  std::vector<std::pair<std::string, mrpt::config::CLoadableOptions*>> list();
};

struct DetectorBuild {
  std::vector<std::unique_ptr<Detector>> detectors;
  /// Detectors left out (optional ones whose files are missing), one line each.
  std::vector<std::string> warnings;
};

/// The detectors of `params.detectorList()` in that order: the added kinds of `sections` by name,
/// else the built-in ones. A listed detector whose own section says enabled = false is left out
/// with a warning; so is a DNN detector whose files are missing when its `required` is false, and
/// a name that is neither added nor built in. Throws InputError for a detector that cannot be
/// built otherwise.
DetectorBuild makeDetectors(const TClassificationParams& params, DetectorSections& sections);

}  // namespace rasm::classification
