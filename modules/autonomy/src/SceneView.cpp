#include "rasm/autonomy/SceneView.h"

#include "rasm/core/Error.h"

namespace rasm::autonomy {

namespace {
nlohmann::json vec3(const Eigen::Vector3d& v) {
  return {v.x(), v.y(), v.z()};
}

Eigen::Vector3d vec3From(const nlohmann::json& j, const std::string& what) {
  if (!j.is_array() || j.size() != 3 || !j[0].is_number() || !j[1].is_number() || !j[2].is_number())
    throwInputError(what, "expected an array of 3 numbers");
  return {j[0].get<double>(), j[1].get<double>(), j[2].get<double>()};
}
}  // namespace

nlohmann::json sceneViewsJson(const std::vector<SceneView>& views) {
  nlohmann::json out = nlohmann::json::array();
  for (const SceneView& v : views)
    out.push_back({{"position", vec3(v.position)},
                   {"direction", vec3(v.direction)},
                   {"gain", v.gain},
                   {"reachable", v.reachable},
                   {"goal", v.goal}});
  return out;
}

std::vector<SceneView> sceneViewsFromJson(const nlohmann::json& j, const std::string& what) {
  if (!j.is_array()) throwInputError(what, "expected an array of views");
  std::vector<SceneView> views;
  for (std::size_t i = 0; i < j.size(); ++i) {
    const std::string at = what + "[" + std::to_string(i) + "]";
    const nlohmann::json& e = j[i];
    if (!e.is_object() || !e.contains("position") || !e.contains("direction"))
      throwInputError(at, "expected an object with \"position\" and \"direction\"");
    SceneView v;
    v.position = vec3From(e["position"], at + ".position");
    v.direction = vec3From(e["direction"], at + ".direction");
    v.gain = e.value("gain", 0.0);
    v.reachable = e.value("reachable", true);
    v.goal = e.value("goal", false);
    views.push_back(v);
  }
  return views;
}

}  // namespace rasm::autonomy
