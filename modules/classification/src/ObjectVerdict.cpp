#include "rasm/classification/ObjectVerdict.h"

#include <algorithm>
#include <functional>

namespace rasm::classification {

const char* toString(ObjectVerdict v) {
  switch (v) {
    case ObjectVerdict::Object:
      return "object";
    case ObjectVerdict::Unconfirmed:
      return "unconfirmed";
    case ObjectVerdict::Fragment:
      return "fragment";
    case ObjectVerdict::Structure:
      return "structure";
    case ObjectVerdict::RarelyDetected:
      return "rarely_detected";
  }
  return "?";
}

bool isStructure(const Eigen::Vector3d& extents_m, const TClassificationParams& params) {
  Eigen::Vector3d e = extents_m.cwiseAbs();
  std::sort(e.data(), e.data() + 3, std::greater<double>());
  const double max_thickness_m =
      std::max(params.structure_max_thickness_m, params.structure_max_thickness_fraction * e[1]);
  return e[1] > params.structure_min_extent_m && e[2] < max_thickness_m;
}

ObjectVerdict objectVerdict(const SegmentClass& c, const Eigen::Vector3d& extents_m,
                            const TClassificationParams& params) {
  if (c.best_id == 0 || c.best_p < params.min_object_probability) return ObjectVerdict::Unconfirmed;
  Eigen::Vector3d e = extents_m.cwiseAbs();
  std::sort(e.data(), e.data() + 3, std::greater<double>());
  if (c.surfels < params.min_object_surfels || !(e[0] > params.min_object_size_m))
    return ObjectVerdict::Fragment;
  if (isStructure(e, params)) return ObjectVerdict::Structure;
  return ObjectVerdict::Object;
}

}  // namespace rasm::classification
