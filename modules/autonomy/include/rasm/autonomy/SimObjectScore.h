#pragma once
// Objects carrying their class, against a simulated world's ground truth: the measure that
// exploration.json, exploration.png, frames.csv objects_correct and plot_objects.png report.
//
// Every detectable object of the world counts (a COCO class that is not structure), seen or not.
// Each stable surfel of the map takes the world instance of the surface nearest to it (within
// 5 cm); classification::computeClassificationMetrics then says which objects the map's segment
// classes name right.

#include <Eigen/Core>
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "rasm/autonomy/StableSurfels.h"
#include "rasm/classification/ClassificationMetrics.h"

namespace rasm::maps {
class CSurfelMap;
}
namespace rasm::sim {
class RayScene;
class SurfaceInstanceQuery;
}  // namespace rasm::sim

namespace rasm::pipeline {
class ClassificationStage;
}  // namespace rasm::pipeline

namespace rasm::autonomy {

class SimObjectScore {
 public:
  /// `scene`: the world the frames come from (it must outlive this).
  explicit SimObjectScore(const sim::RayScene& scene);
  ~SimObjectScore();

  struct Score {
    std::size_t correct = 0;     ///< detectable objects whose class the map names right
    std::size_t detectable = 0;  ///< detectable objects of the world
    double fraction() const { return detectable > 0 ? double(correct) / double(detectable) : 0.0; }
  };
  /// The score of the map's stable surfels (`positions`, world frame, m) with their segment ids
  /// and the segments' class names (ClassificationStage::segmentClassNames).
  Score score(const std::vector<Eigen::Vector3f>& positions,
              const std::vector<std::uint32_t>& segment,
              const std::map<std::uint32_t, std::string>& segment_class) const;
  /// The same of a map as the classification stage names it now.
  Score score(const maps::CSurfelMap& map,
              const pipeline::ClassificationStage& classification) const;

 private:
  std::unique_ptr<sim::SurfaceInstanceQuery> m_instances;
  std::vector<classification::GtClassObject> m_objects;
  classification::ClassificationMetricsParams m_params;
};

}  // namespace rasm::autonomy
