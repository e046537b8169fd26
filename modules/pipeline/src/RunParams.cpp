#include "rasm/pipeline/RunParams.h"

#include <mrpt/config/CConfigFileBase.h>

#include <cmath>
#include <sstream>
#include <utility>
#include <vector>

#include "rasm/core/Error.h"
#include "rasm/core/Log.h"
#include "rasm/core/Params.h"
#include "rasm/pipeline/RunFolder.h"

namespace rasm::pipeline {

OverwritePolicy overwritePolicy(const std::string& value) {
  if (value == "auto") return OverwritePolicy::EarlierRun;
  if (value == "false") return OverwritePolicy::Never;
  if (value == "true") return OverwritePolicy::BesideOthers;
  throwInputError("[output] overwrite", "expected auto, true or false, got '" + value + "'");
}

namespace {
/// Parses "a-b,c-d,e" (inclusive ranges of frame indices); throws naming [section] key.
std::vector<std::pair<long long, long long>> parseRanges(const std::string& text,
                                                         const std::string& section,
                                                         const std::string& key) {
  std::vector<std::pair<long long, long long>> out;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ',')) {
    if (item.find_first_not_of(" \t") == std::string::npos) continue;
    long long a = -1, b = -1;
    char dash = 0, rest = 0;
    std::istringstream is(item);
    is >> a;
    if (is >> dash) {
      if (dash != '-' || !(is >> b) || (is >> rest)) a = -1;
    } else {
      b = a;
    }
    if (a < 0 || b < a)
      throwInputError("[" + section + "] " + key,
                      "'" + item + "' is not a frame range 'a-b' with 0 <= a <= b");
    out.emplace_back(a, b);
  }
  return out;
}

bool inRanges(const std::string& text, long long index) {
  for (const auto& [a, b] : parseRanges(text, "source", "ranges"))
    if (index >= a && index <= b) return true;
  return false;
}
}  // namespace

bool TSourceParams::dropped(long long index) const {
  return !drop_frames.empty() && inRanges(drop_frames, index);
}
bool TSourceParams::blanked(long long index) const {
  return !blank_frames.empty() && inRanges(blank_frames, index);
}

void TSourceParams::loadFromConfigFile(const mrpt::config::CConfigFileBase& c,
                                       const std::string& s) {
  MRPT_LOAD_CONFIG_VAR(type, string, c, s);
  MRPT_LOAD_CONFIG_VAR(path, string, c, s);
  MRPT_LOAD_CONFIG_VAR(max_frames, int, c, s);
  MRPT_LOAD_CONFIG_VAR(start_frame, int, c, s);
  MRPT_LOAD_CONFIG_VAR(frame_step, int, c, s);
  MRPT_LOAD_CONFIG_VAR(groundtruth, string, c, s);
  MRPT_LOAD_CONFIG_VAR(prefetch_frames, int, c, s);
  MRPT_LOAD_CONFIG_VAR(preload, bool, c, s);
  MRPT_LOAD_CONFIG_VAR(preload_max_mib, int, c, s);
  MRPT_LOAD_CONFIG_VAR(drop_frames, string, c, s);
  MRPT_LOAD_CONFIG_VAR(blank_frames, string, c, s);
  MRPT_LOAD_CONFIG_VAR(real_time, bool, c, s);
  (void)parseRanges(drop_frames, s, "drop_frames");
  (void)parseRanges(blank_frames, s, "blank_frames");
  if (type != "sim" && type != "rawlog" && type != "tum" && type != "7scenes" && type != "auto" &&
      type != "openni2")
    throwInputError("[" + s + "] type",
                    "'" + type + "' is not one of sim, rawlog, tum, 7scenes, auto, openni2");
  // Real time offers frames by the clock: the frame-index selections below count source frames,
  // which a real-time run drops by its own timing.
  if ((real_time || type == "openni2") &&
      (start_frame != 0 || frame_step != 1 || !drop_frames.empty() || !blank_frames.empty()))
    throwInputError("[" + s + "] real_time",
                    "start_frame, frame_step, drop_frames and blank_frames need a replay at full "
                    "speed (real_time = false, not a live source)");
  if (type != "sim" && type != "openni2" && path.empty())
    throwInputError("[" + s + "] path", "required for type = " + type);
  requireInRange(max_frames, 0, 1e9, s, "max_frames");
  requireInRange(start_frame, 0, 1e9, s, "start_frame");
  requireInRange(frame_step, 1, 1e6, s, "frame_step");
  requireInRange(prefetch_frames, 0, 64, s, "prefetch_frames");
  requireInRange(preload_max_mib, 1, 1 << 20, s, "preload_max_mib");
}

void TSourceParams::saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const {
  MRPT_SAVE_CONFIG_VAR(type, c, s);
  MRPT_SAVE_CONFIG_VAR(path, c, s);
  MRPT_SAVE_CONFIG_VAR(max_frames, c, s);
  MRPT_SAVE_CONFIG_VAR(start_frame, c, s);
  MRPT_SAVE_CONFIG_VAR(frame_step, c, s);
  MRPT_SAVE_CONFIG_VAR(groundtruth, c, s);
  MRPT_SAVE_CONFIG_VAR(prefetch_frames, c, s);
  MRPT_SAVE_CONFIG_VAR(preload, c, s);
  MRPT_SAVE_CONFIG_VAR(preload_max_mib, c, s);
  MRPT_SAVE_CONFIG_VAR(drop_frames, c, s);
  MRPT_SAVE_CONFIG_VAR(blank_frames, c, s);
  MRPT_SAVE_CONFIG_VAR(real_time, c, s);
}

void TMapperParams::loadFromConfigFile(const mrpt::config::CConfigFileBase& c,
                                       const std::string& s) {
  MRPT_LOAD_CONFIG_VAR(pyramid_levels, int, c, s);
  MRPT_LOAD_CONFIG_VAR(min_depth_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(max_depth_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(bilateral_filter, bool, c, s);
  MRPT_LOAD_CONFIG_VAR(bilateral_sigma_space_px, double, c, s);
  MRPT_LOAD_CONFIG_VAR(bilateral_sigma_depth_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(normal_max_jump_rel, double, c, s);
  MRPT_LOAD_CONFIG_VAR(load_map, string, c, s);
  MRPT_LOAD_CONFIG_VAR(poses, string, c, s);
  if (poses != "tracked" && poses != "groundtruth")
    throwInputError("[" + s + "] poses", "'" + poses + "' is not one of tracked, groundtruth");
  requireInRange(pyramid_levels, 1, 6, s, "pyramid_levels");
  requireInRange(min_depth_m, 0.0, 100.0, s, "min_depth_m");
  requireInRange(max_depth_m, min_depth_m, 100.0, s, "max_depth_m");
  requireInRange(bilateral_sigma_space_px, 0.1, 50.0, s, "bilateral_sigma_space_px");
  requireInRange(bilateral_sigma_depth_m, 1e-4, 1.0, s, "bilateral_sigma_depth_m");
  requireInRange(normal_max_jump_rel, 1e-3, 10.0, s, "normal_max_jump_rel");
}

void TMapperParams::saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const {
  MRPT_SAVE_CONFIG_VAR(pyramid_levels, c, s);
  MRPT_SAVE_CONFIG_VAR(min_depth_m, c, s);
  MRPT_SAVE_CONFIG_VAR(max_depth_m, c, s);
  MRPT_SAVE_CONFIG_VAR(bilateral_filter, c, s);
  MRPT_SAVE_CONFIG_VAR(bilateral_sigma_space_px, c, s);
  MRPT_SAVE_CONFIG_VAR(bilateral_sigma_depth_m, c, s);
  MRPT_SAVE_CONFIG_VAR(normal_max_jump_rel, c, s);
  MRPT_SAVE_CONFIG_VAR(load_map, c, s);
  MRPT_SAVE_CONFIG_VAR(poses, c, s);
}

void TOutputParams::loadFromConfigFile(const mrpt::config::CConfigFileBase& c,
                                       const std::string& s) {
  MRPT_LOAD_CONFIG_VAR(dir, string, c, s);
  MRPT_LOAD_CONFIG_VAR(write_ply, bool, c, s);
  MRPT_LOAD_CONFIG_VAR(write_3dscene, bool, c, s);
  MRPT_LOAD_CONFIG_VAR(write_mesh, bool, c, s);
  MRPT_LOAD_CONFIG_VAR(save_map, bool, c, s);
  MRPT_LOAD_CONFIG_VAR(write_rawlog, bool, c, s);
  MRPT_LOAD_CONFIG_VAR(preview_png, bool, c, s);
  MRPT_LOAD_CONFIG_VAR(floorplan, bool, c, s);
  MRPT_LOAD_CONFIG_VAR(objects_score_period_s, double, c, s);
  requireInRange(objects_score_period_s, 0.0, 1e6, s, "objects_score_period_s");
  MRPT_LOAD_CONFIG_VAR(overwrite, string, c, s);
  MRPT_LOAD_CONFIG_VAR(log_level, string, c, s);
  (void)log::parseLevel(log_level, "[" + s + "] log_level");
  if (dir.empty()) throwInputError("[" + s + "] dir", "must not be empty");
  (void)overwritePolicy(overwrite);  // validates
}

void TOutputParams::saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const {
  MRPT_SAVE_CONFIG_VAR(dir, c, s);
  MRPT_SAVE_CONFIG_VAR(write_ply, c, s);
  MRPT_SAVE_CONFIG_VAR(write_3dscene, c, s);
  MRPT_SAVE_CONFIG_VAR(write_mesh, c, s);
  MRPT_SAVE_CONFIG_VAR(save_map, c, s);
  MRPT_SAVE_CONFIG_VAR(write_rawlog, c, s);
  MRPT_SAVE_CONFIG_VAR(preview_png, c, s);
  MRPT_SAVE_CONFIG_VAR(floorplan, c, s);
  MRPT_SAVE_CONFIG_VAR(objects_score_period_s, c, s);
  MRPT_SAVE_CONFIG_VAR(overwrite, c, s);
  MRPT_SAVE_CONFIG_VAR(log_level, c, s);
}

}  // namespace rasm::pipeline
