#pragma once
// The "objects" array of a run folder's objects.json (section IV; ClassificationStage writes it),
// read by `rasm objects` and `rasm eval classification`. Throws InputError naming the file when it
// is missing, not JSON, or has no "objects" array.

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "rasm/core/Error.h"

namespace rasm::app {

inline nlohmann::json readRunObjects(const std::string& run_dir) {
  const std::string path = (std::filesystem::path(run_dir) / "objects.json").string();
  std::ifstream f(path);
  if (!f)
    rasm::throwInputError(path,
                          "missing; expected the objects.json that `rasm run` writes "
                          "([classification] enabled)");
  nlohmann::json j;
  try {
    f >> j;
  } catch (const std::exception& e) {
    rasm::throwInputError(path, std::string("is not valid JSON: ") + e.what());
  }
  if (!j.contains("objects") || !j["objects"].is_array())
    rasm::throwInputError(path, "expected an \"objects\" array");
  return j["objects"];
}

}  // namespace rasm::app
