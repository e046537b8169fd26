#include "rasm/pipeline/RunParams.h"

#include <mrpt/config/CConfigFileBase.h>

#include "rasm/core/Error.h"
#include "rasm/core/Params.h"

namespace rasm::pipeline {

void TSourceParams::loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s) {
  MRPT_LOAD_CONFIG_VAR(type, string, c, s);
  MRPT_LOAD_CONFIG_VAR(path, string, c, s);
  MRPT_LOAD_CONFIG_VAR(max_frames, int, c, s);
  MRPT_LOAD_CONFIG_VAR(start_frame, int, c, s);
  MRPT_LOAD_CONFIG_VAR(frame_step, int, c, s);
  MRPT_LOAD_CONFIG_VAR(groundtruth, string, c, s);
  MRPT_LOAD_CONFIG_VAR(prefetch_frames, int, c, s);
  MRPT_LOAD_CONFIG_VAR(preload, bool, c, s);
  MRPT_LOAD_CONFIG_VAR(preload_max_mib, int, c, s);
  if (type != "sim" && type != "rawlog" && type != "tum" && type != "7scenes" && type != "auto")
    throwInputError("[" + s + "] type", "'" + type + "' is not one of sim, rawlog, tum, 7scenes, auto");
  if (type != "sim" && path.empty()) throwInputError("[" + s + "] path", "required for type = " + type);
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
}

void TMapperParams::loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s) {
  MRPT_LOAD_CONFIG_VAR(pyramid_levels, int, c, s);
  MRPT_LOAD_CONFIG_VAR(min_depth_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(max_depth_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(bilateral_filter, bool, c, s);
  MRPT_LOAD_CONFIG_VAR(bilateral_sigma_space_px, double, c, s);
  MRPT_LOAD_CONFIG_VAR(bilateral_sigma_depth_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(normal_max_jump_rel, double, c, s);
  MRPT_LOAD_CONFIG_VAR(max_lost_frames, int, c, s);
  requireInRange(pyramid_levels, 1, 6, s, "pyramid_levels");
  requireInRange(min_depth_m, 0.0, 100.0, s, "min_depth_m");
  requireInRange(max_depth_m, min_depth_m, 100.0, s, "max_depth_m");
  requireInRange(bilateral_sigma_space_px, 0.1, 50.0, s, "bilateral_sigma_space_px");
  requireInRange(bilateral_sigma_depth_m, 1e-4, 1.0, s, "bilateral_sigma_depth_m");
  requireInRange(normal_max_jump_rel, 1e-3, 10.0, s, "normal_max_jump_rel");
  requireInRange(max_lost_frames, 0, 1e9, s, "max_lost_frames");
}

void TMapperParams::saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const {
  MRPT_SAVE_CONFIG_VAR(pyramid_levels, c, s);
  MRPT_SAVE_CONFIG_VAR(min_depth_m, c, s);
  MRPT_SAVE_CONFIG_VAR(max_depth_m, c, s);
  MRPT_SAVE_CONFIG_VAR(bilateral_filter, c, s);
  MRPT_SAVE_CONFIG_VAR(bilateral_sigma_space_px, c, s);
  MRPT_SAVE_CONFIG_VAR(bilateral_sigma_depth_m, c, s);
  MRPT_SAVE_CONFIG_VAR(normal_max_jump_rel, c, s);
  MRPT_SAVE_CONFIG_VAR(max_lost_frames, c, s);
}

void TOutputParams::loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s) {
  MRPT_LOAD_CONFIG_VAR(dir, string, c, s);
  MRPT_LOAD_CONFIG_VAR(write_ply, bool, c, s);
  MRPT_LOAD_CONFIG_VAR(write_3dscene, bool, c, s);
  MRPT_LOAD_CONFIG_VAR(save_map, bool, c, s);
  MRPT_LOAD_CONFIG_VAR(write_rawlog, bool, c, s);
  MRPT_LOAD_CONFIG_VAR(preview_png, bool, c, s);
  MRPT_LOAD_CONFIG_VAR(overwrite, bool, c, s);
  if (dir.empty()) throwInputError("[" + s + "] dir", "must not be empty");
}

void TOutputParams::saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const {
  MRPT_SAVE_CONFIG_VAR(dir, c, s);
  MRPT_SAVE_CONFIG_VAR(write_ply, c, s);
  MRPT_SAVE_CONFIG_VAR(write_3dscene, c, s);
  MRPT_SAVE_CONFIG_VAR(save_map, c, s);
  MRPT_SAVE_CONFIG_VAR(write_rawlog, c, s);
  MRPT_SAVE_CONFIG_VAR(preview_png, c, s);
  MRPT_SAVE_CONFIG_VAR(overwrite, c, s);
}

}  // namespace rasm::pipeline
