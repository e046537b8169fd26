#pragma once
// The project's own approximate object models, generated from a few dimensions each. They are
// the meshes of the shipped worlds (modules/sim/models/<name>.obj, written by
// `rasm sim make-models`) and the "approximate geometric models" the zero-shot classifier of
// paper section IV-A renders its templates from.
// Model frame: metres, z up, origin at the centre of the footprint on the supporting surface
// (z = 0 is the bottom), +x is the object's front (screen, keys, seat front, clock face).

#include <string>
#include <vector>

#include "rasm/models/Mesh.h"

namespace rasm::models {

struct ProceduralModel {
  std::string name;        ///< file stem: "mug" -> mug.obj
  std::string class_name;  ///< ClassVocabulary.h name of the object it depicts
  std::string description;
};

/// All generated models: mug, bottle, chair, monitor, keyboard, clock, conference_phone,
/// headphones, laptop, desk, shelf.
const std::vector<ProceduralModel>& proceduralModels();

/// Generates a model by name; throws InputError for unknown names.
TriangleMesh makeProceduralModel(const std::string& name);

/// Writes every model as <dir>/<name>.obj; returns the paths written.
std::vector<std::string> writeProceduralModels(const std::string& dir);

}  // namespace rasm::models
