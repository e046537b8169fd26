#pragma once
// The views an exploration considered (the candidates of a plan) or drove to (its goals), as
// exploration.json "candidate_views" holds them and the run's 3-D scenes draw them
// (run/RunScene.h).

#include <Eigen/Core>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace rasm::autonomy {

/// A view the exploration considered (a candidate of a plan) or drove to (a goal).
struct SceneView {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();    ///< camera centre, world (m)
  Eigen::Vector3d direction = Eigen::Vector3d::UnitX();  ///< optical axis, unit, world
  double gain = 0.0;  ///< the planner's information gain IG(a) (V); ordering key of baselines
  bool reachable = true;
  bool goal = false;  ///< a goal the robot drove to (exploration.json "goals")
};
/// exploration.json "candidate_views": [{"position": [x,y,z], "direction": [dx,dy,dz], "gain": g,
/// "reachable": b, "goal": b}, ...].
nlohmann::json sceneViewsJson(const std::vector<SceneView>& views);
/// The inverse; InputError naming `what` and the entry when an entry lacks a field.
std::vector<SceneView> sceneViewsFromJson(const nlohmann::json& j, const std::string& what);

}  // namespace rasm::autonomy
