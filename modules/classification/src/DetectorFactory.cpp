#include "rasm/classification/DetectorFactory.h"

#include "rasm/classification/SimDetector.h"
#include "rasm/core/Error.h"

namespace rasm::classification {

std::vector<std::pair<std::string, mrpt::config::CLoadableOptions*>> DetectorSections::list() {
  return {
      {"sim_detector", &sim_detector}, {"dnn_detector", &dnn_detector}, {"zero_shot", &zero_shot}};
}

DetectorBuild makeDetectors(const TClassificationParams& params, DetectorSections& sections,
                            const sim::RayScene* sim_scene) {
  DetectorBuild out;
  for (const std::string& name : params.detectorList()) {
    if (name == "sim_detector") {
      out.detectors.push_back(std::make_unique<SimDetector>(sections.sim_detector, sim_scene,
                                                            std::uint64_t(params.seed)));
    } else if (name == "dnn_detector") {
      std::string warning;
      auto d = makeDnnDetector(sections.dnn_detector, &warning, name);
      if (d)
        out.detectors.push_back(std::move(d));
      else
        out.warnings.push_back((warning.empty() ? "[dnn_detector] enabled = false" : warning) +
                               " (running without " + name + ")");
    } else if (name == "zero_shot") {
      if (sections.zero_shot.enabled)
        out.detectors.push_back(ZeroShotDetector::fromParams(sections.zero_shot, name));
      else
        out.warnings.push_back(
            "[classification] detectors lists zero_shot but [zero_shot] "
            "enabled = false (running without zero_shot)");
    } else {
      out.warnings.push_back("[classification] detectors: '" + name +
                             "' is not built into this version; left out");
    }
  }
  return out;
}

}  // namespace rasm::classification
