#include "rasm/autonomy/SimObjectScore.h"

#include "rasm/models/ClassVocabulary.h"
#include "rasm/pipeline/stages/ClassificationStage.h"
#include "rasm/sim/SurfaceInstance.h"
#include "rasm/surfel_map/CSurfelMap.h"

namespace rasm::autonomy {

using pipeline::ClassificationStage;

SimObjectScore::SimObjectScore(const sim::RayScene& scene)
    : m_instances(std::make_unique<sim::SurfaceInstanceQuery>(scene)) {
  for (const sim::WorldInstanceInfo& w : sim::worldInstances(scene.world()))
    m_objects.push_back(
        {w.instance_id, w.class_name, w.name, w.size_m, w.is_structure || w.class_id == 0});
  for (int id = 1; id <= models::kNumCocoClasses; ++id)
    m_params.detectable_classes.insert(models::className(id));
}

SimObjectScore::~SimObjectScore() = default;

SimObjectScore::Score SimObjectScore::score(
    const std::vector<Eigen::Vector3f>& positions, const std::vector<std::uint32_t>& segment,
    const std::map<std::uint32_t, std::string>& segment_class) const {
  const auto nearest = m_instances->nearest(positions, 0.05f);
  std::vector<std::uint32_t> instance(positions.size());
  for (std::size_t i = 0; i < positions.size(); ++i) instance[i] = nearest[i].instance_id;
  const auto m = classification::computeClassificationMetrics(segment, instance, segment_class,
                                                              m_objects, m_params);
  Score s;
  for (const auto& o : m.per_object)
    if (o.detectable) {
      ++s.detectable;
      s.correct += o.correct;
    }
  return s;
}

SimObjectScore::Score SimObjectScore::score(const maps::CSurfelMap& map,
                                            const ClassificationStage& classification) const {
  const StableSurfels s = stableSurfels(map);
  return score(s.positions, s.segment, classification.segmentClassNames(map));
}

}  // namespace rasm::autonomy
