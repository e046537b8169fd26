#include "rasm/navigation/TNavigationParams.h"

#include <mrpt/config/CConfigFileBase.h>

#include <sys/stat.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>

#include "rasm/core/Error.h"
#include "rasm/core/Params.h"

namespace rasm::navigation {

std::string TNavigationParams::effectiveCacheDir() const {
  namespace fs = std::filesystem;
  if (!ptg_cache_dir.empty()) return ptg_cache_dir;
  // The user's own cache folder (XDG base directories); a shared temporary folder only as the
  // last resort, under a name of this user's (ensurePrivateCacheDir checks whose it is).
  if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg && fs::path(xdg).is_absolute())
    return (fs::path(xdg) / "rasm" / "ptg").string();
  if (const char* home = std::getenv("HOME"); home && fs::path(home).is_absolute())
    return (fs::path(home) / ".cache" / "rasm" / "ptg").string();
  return (fs::temp_directory_path() / ("rasm_ptg_cache_" + std::to_string(::getuid()))).string();
}

void ensurePrivateCacheDir(const std::string& dir) {
  std::filesystem::create_directories(dir);
  struct stat st {};
  if (::lstat(dir.c_str(), &st) != 0 || !S_ISDIR(st.st_mode))
    throwInputError("[navigation] ptg_cache_dir " + dir,
                    "a folder (not a link), got something else");
  if (st.st_uid != ::getuid())
    throwInputError("[navigation] ptg_cache_dir " + dir,
                    "a folder of this user's, it belongs to uid " + std::to_string(st.st_uid));
  if ((st.st_mode & (S_IWGRP | S_IWOTH)) != 0)
    throwInputError("[navigation] ptg_cache_dir " + dir,
                    "a folder only its owner can write to (others could plant PTG tables there)");
}

void TNavigationParams::loadFromConfigFile(const mrpt::config::CConfigFileBase& c,
                                           const std::string& s) {
  MRPT_LOAD_CONFIG_VAR(period_s, double, c, s);
  MRPT_LOAD_CONFIG_VAR(max_v_mps, double, c, s);
  MRPT_LOAD_CONFIG_VAR(max_w_degps, double, c, s);
  MRPT_LOAD_CONFIG_VAR(goal_tolerance_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(heading_tolerance_deg, double, c, s);
  MRPT_LOAD_CONFIG_VAR(align_w_degps, double, c, s);
  MRPT_LOAD_CONFIG_VAR(goal_timeout_s, double, c, s);
  MRPT_LOAD_CONFIG_VAR(stuck_timeout_s, double, c, s);
  MRPT_LOAD_CONFIG_VAR(stuck_distance_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(escape_attempts, int, c, s);
  MRPT_LOAD_CONFIG_VAR(escape_distance_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(direct_range_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(via_reach_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(follow_route, bool, c, s);
  MRPT_LOAD_CONFIG_VAR(follow_reach_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(face_goal_deg, double, c, s);
  MRPT_LOAD_CONFIG_VAR(ptg_ref_distance_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(ptg_resolution_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(ptg_num_paths, int, c, s);
  MRPT_LOAD_CONFIG_VAR(allow_reverse, bool, c, s);
  MRPT_LOAD_CONFIG_VAR(footprint_margin_m, double, c, s);
  holonomic_method = c.read_string(s, "holonomic_method", holonomic_method);
  ptg_cache_dir = c.read_string(s, "ptg_cache_dir", ptg_cache_dir);
  validate(s);
}

void TNavigationParams::validate(const std::string& s) const {
  requireInRange(period_s, 0.01, 1.0, s, "period_s");
  requireInRange(max_v_mps, 0.01, 5.0, s, "max_v_mps");
  requireInRange(max_w_degps, 1.0, 720.0, s, "max_w_degps");
  requireInRange(goal_tolerance_m, 0.01, 2.0, s, "goal_tolerance_m");
  requireInRange(heading_tolerance_deg, 0.5, 180.0, s, "heading_tolerance_deg");
  requireInRange(align_w_degps, 1.0, 720.0, s, "align_w_degps");
  requireInRange(goal_timeout_s, 1.0, 1e6, s, "goal_timeout_s");
  requireInRange(stuck_timeout_s, 0.5, 1e6, s, "stuck_timeout_s");
  requireInRange(stuck_distance_m, 0.0, 10.0, s, "stuck_distance_m");
  requireInRange(escape_attempts, 0, 10, s, "escape_attempts");
  requireInRange(escape_distance_m, 0.0, 5.0, s, "escape_distance_m");
  requireInRange(direct_range_m, 0.0, 5.0, s, "direct_range_m");
  requireInRange(via_reach_m, 0.05, 5.0, s, "via_reach_m");
  requireInRange(follow_reach_m, 0.02, 5.0, s, "follow_reach_m");
  requireInRange(face_goal_deg, 0.0, 180.0, s, "face_goal_deg");
  requireInRange(ptg_ref_distance_m, 0.5, 20.0, s, "ptg_ref_distance_m");
  requireInRange(ptg_resolution_m, 0.01, 0.5, s, "ptg_resolution_m");
  requireInRange(ptg_num_paths, 11, 1001, s, "ptg_num_paths");
  requireInRange(footprint_margin_m, 0.0, 1.0, s, "footprint_margin_m");
  if (direct_range_m < goal_tolerance_m)
    throwInputError("[" + s + "] direct_range_m",
                    "must be at least goal_tolerance_m (the own controller finishes the approach)");
  if (holonomic_method != "CHolonomicFullEval" && holonomic_method != "CHolonomicND" &&
      holonomic_method != "CHolonomicVFF")
    throwInputError(
        "[" + s + "] holonomic_method",
        "'" + holonomic_method + "' is not one of CHolonomicFullEval, CHolonomicND, CHolonomicVFF");
}

void TNavigationParams::saveToConfigFile(mrpt::config::CConfigFileBase& c,
                                         const std::string& s) const {
  MRPT_SAVE_CONFIG_VAR(period_s, c, s);
  MRPT_SAVE_CONFIG_VAR(max_v_mps, c, s);
  MRPT_SAVE_CONFIG_VAR(max_w_degps, c, s);
  MRPT_SAVE_CONFIG_VAR(goal_tolerance_m, c, s);
  MRPT_SAVE_CONFIG_VAR(heading_tolerance_deg, c, s);
  MRPT_SAVE_CONFIG_VAR(align_w_degps, c, s);
  MRPT_SAVE_CONFIG_VAR(goal_timeout_s, c, s);
  MRPT_SAVE_CONFIG_VAR(stuck_timeout_s, c, s);
  MRPT_SAVE_CONFIG_VAR(stuck_distance_m, c, s);
  MRPT_SAVE_CONFIG_VAR(escape_attempts, c, s);
  MRPT_SAVE_CONFIG_VAR(escape_distance_m, c, s);
  MRPT_SAVE_CONFIG_VAR(direct_range_m, c, s);
  MRPT_SAVE_CONFIG_VAR(via_reach_m, c, s);
  MRPT_SAVE_CONFIG_VAR(follow_route, c, s);
  MRPT_SAVE_CONFIG_VAR(follow_reach_m, c, s);
  MRPT_SAVE_CONFIG_VAR(face_goal_deg, c, s);
  MRPT_SAVE_CONFIG_VAR(ptg_ref_distance_m, c, s);
  MRPT_SAVE_CONFIG_VAR(ptg_resolution_m, c, s);
  MRPT_SAVE_CONFIG_VAR(ptg_num_paths, c, s);
  MRPT_SAVE_CONFIG_VAR(allow_reverse, c, s);
  MRPT_SAVE_CONFIG_VAR(footprint_margin_m, c, s);
  MRPT_SAVE_CONFIG_VAR(holonomic_method, c, s);
  MRPT_SAVE_CONFIG_VAR(ptg_cache_dir, c, s);
}

}  // namespace rasm::navigation
