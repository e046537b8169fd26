#pragma once
// Reading a run folder's JSON files for the app's commands: readRunJson (any of them: InputError
// naming the file when it is missing or not JSON) and the "objects" array of objects.json
// (section IV; ClassificationStage writes it), read by `rasm objects` and `rasm eval
// classification` (InputError also when it has no "objects" array).

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "rasm/core/Error.h"

namespace rasm::app {

/// The JSON document at `path`; `expected` says what the file should be when it is missing.
inline nlohmann::json readRunJson(const std::string& path, const std::string& expected) {
  std::ifstream f(path);
  if (!f) rasm::throwInputError(path, "missing; " + expected);
  nlohmann::json j;
  try {
    f >> j;
  } catch (const std::exception& e) {
    rasm::throwInputError(path, std::string("is not valid JSON: ") + e.what());
  }
  return j;
}

inline nlohmann::json readRunObjects(const std::string& run_dir) {
  const std::string path = (std::filesystem::path(run_dir) / "objects.json").string();
  nlohmann::json j = readRunJson(
      path, "expected the objects.json that `rasm run` writes ([classification] enabled)");
  if (!j.contains("objects") || !j["objects"].is_array())
    rasm::throwInputError(path, "expected an \"objects\" array");
  return j["objects"];
}

/// The "other_segments" array of objects.json (classified segments that are not objects; empty
/// for a run folder written before it existed).
inline nlohmann::json readRunOtherSegments(const std::string& run_dir) {
  const std::string path = (std::filesystem::path(run_dir) / "objects.json").string();
  nlohmann::json j = readRunJson(
      path, "expected the objects.json that `rasm run` writes ([classification] enabled)");
  if (!j.contains("other_segments")) return nlohmann::json::array();
  if (!j["other_segments"].is_array())
    rasm::throwInputError(path, "expected \"other_segments\" to be an array");
  return j["other_segments"];
}

}  // namespace rasm::app
