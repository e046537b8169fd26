#pragma once
// Reading a run folder's JSON files for the app's commands: readRunJson (any of them: InputError
// naming the file when it is missing or not JSON) and the "objects" array of objects.json
// (section IV; ClassificationStage writes it), read by `rasm objects` and `rasm eval
// classification` (InputError also when it has no "objects" array). An object is one entry with
// an `id` and its `segments` (the object layer, classification/ObjectMap.h); run folders written
// before the object layer have one segment per entry (`segment`): objectSegments reads both.

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

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

/// The segments of one entry of objects.json's "objects": its `segments`, or the one `segment`
/// of a run folder written before objects had several. `path` names the file in errors.
inline std::vector<std::uint32_t> objectSegments(const nlohmann::json& object,
                                                 const std::string& path) {
  if (object.contains("segments") && object["segments"].is_array()) {
    std::vector<std::uint32_t> out;
    for (const auto& s : object["segments"]) {
      if (!s.is_number_unsigned())
        rasm::throwInputError(path, "an object's \"segments\" holds a non-id: " + s.dump());
      out.push_back(s.get<std::uint32_t>());
    }
    return out;
  }
  if (object.contains("segment") && object["segment"].is_number_unsigned())
    return {object["segment"].get<std::uint32_t>()};
  rasm::throwInputError(path, "an object without \"segments\": " + object.dump());
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
