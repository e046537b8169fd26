#pragma once
// What the pipeline's run tests share: a fresh temporary output folder per process, reading the
// files a run writes, and the quarter-VGA camera the simulated runs use to stay fast.

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "rasm/pipeline/RunConfig.h"

namespace rasm::pipeline::testing {

/// <temp>/rasm_test_<name>_<pid>, removed if it exists (tests run as parallel processes).
inline std::string tempDir(const std::string& name) {
  const std::filesystem::path p = std::filesystem::temp_directory_path() /
                                  ("rasm_test_" + name + "_" + std::to_string(::getpid()));
  std::filesystem::remove_all(p);
  return p.string();
}

inline nlohmann::json readJson(const std::string& path) {
  std::ifstream f(path);
  return nlohmann::json::parse(f);
}

inline std::string readText(const std::string& path) {
  std::ifstream f(path);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

/// The simulated camera at 320x240 (kinect_v1's intrinsics halved) instead of [camera] preset.
inline void setQuarterVgaCamera(RunConfig& cfg) {
  cfg.set("camera", "preset", "");
  for (const auto& [k, v] : std::vector<std::pair<std::string, std::string>>{{"fx", "262.5"},
                                                                             {"fy", "262.5"},
                                                                             {"cx", "159.5"},
                                                                             {"cy", "119.5"},
                                                                             {"width", "320"},
                                                                             {"height", "240"}})
    cfg.set("camera", k, v);
}

}  // namespace rasm::pipeline::testing
