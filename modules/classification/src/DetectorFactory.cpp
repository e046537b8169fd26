#include "rasm/classification/DetectorFactory.h"

#include <algorithm>

#include "rasm/core/Error.h"

namespace rasm::classification {

std::vector<std::pair<std::string, mrpt::config::CLoadableOptions*>> DetectorSections::list() {
  std::vector<std::pair<std::string, mrpt::config::CLoadableOptions*>> out;
  for (const DetectorKind& k : added) out.emplace_back(k.name, k.params);
  out.emplace_back("dnn_detector", &dnn_detector);
  out.emplace_back("zero_shot", &zero_shot);
  return out;
}

DetectorBuild makeDetectors(const TClassificationParams& params, DetectorSections& sections) {
  DetectorBuild out;
  for (const std::string& name : params.detectorList()) {
    const auto kind = std::find_if(sections.added.begin(), sections.added.end(),
                                   [&](const DetectorKind& k) { return k.name == name; });
    if (kind != sections.added.end()) {
      out.detectors.push_back(kind->make(params));
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
