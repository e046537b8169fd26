#include "rasm/exploration/TExplorationParams.h"

#include <mrpt/config/CConfigFileBase.h>

#include <algorithm>

#include "rasm/core/Error.h"
#include "rasm/core/Params.h"

namespace rasm::exploration {

void TExplorationParams::loadFromConfigFile(const mrpt::config::CConfigFileBase& c,
                                            const std::string& s) {
  MRPT_LOAD_CONFIG_VAR(resolution_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(max_range_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(min_depth_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(pixel_stride, int, c, s);
  MRPT_LOAD_CONFIG_VAR(no_return_free_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(prob_hit, double, c, s);
  MRPT_LOAD_CONFIG_VAR(prob_miss, double, c, s);
  MRPT_LOAD_CONFIG_VAR(clamp_min, double, c, s);
  MRPT_LOAD_CONFIG_VAR(clamp_max, double, c, s);
  MRPT_LOAD_CONFIG_VAR(workspace_min_x_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(workspace_min_y_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(workspace_min_z_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(workspace_max_x_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(workspace_max_y_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(workspace_max_z_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(band_min_z_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(band_max_z_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(ic_weight_floor, double, c, s);
  MRPT_LOAD_CONFIG_VAR(random_candidates, int, c, s);
  MRPT_LOAD_CONFIG_VAR(seed, int, c, s);
  MRPT_LOAD_CONFIG_VAR(footprint_radius_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(object_min_extent_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(object_max_extent_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(object_standoff_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(predict_width, int, c, s);
  MRPT_LOAD_CONFIG_VAR(predict_height, int, c, s);
  MRPT_LOAD_CONFIG_VAR(predict_max_surfels, int, c, s);
  MRPT_LOAD_CONFIG_VAR(predict_screen_keep, int, c, s);
  MRPT_LOAD_CONFIG_VAR(predict_screen_width, int, c, s);
  MRPT_LOAD_CONFIG_VAR(predict_screen_height, int, c, s);
  MRPT_LOAD_CONFIG_VAR(w_entropy, double, c, s);
  MRPT_LOAD_CONFIG_VAR(w_ic, double, c, s);
  MRPT_LOAD_CONFIG_VAR(rank_by_rate, bool, c, s);
  MRPT_LOAD_CONFIG_VAR(speed_mps, double, c, s);
  MRPT_LOAD_CONFIG_VAR(turn_rate_degps, double, c, s);
  MRPT_LOAD_CONFIG_VAR(min_travel_time_s, double, c, s);
  MRPT_LOAD_CONFIG_VAR(planner, string, c, s);
  MRPT_LOAD_CONFIG_VAR(blacklist_radius_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(taken_view_radius_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(frontier_candidates, bool, c, s);
  MRPT_LOAD_CONFIG_VAR(taken_view_heading_deg, double, c, s);
  MRPT_LOAD_CONFIG_VAR(frontier_min_cells, int, c, s);
  MRPT_LOAD_CONFIG_VAR(frontier_goal_radius_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(frontier_max_radius_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(clearance_from_unknown, bool, c, s);
  MRPT_LOAD_CONFIG_VAR(lawnmower_spacing_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(lawnmower_step_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(lawnmower_axis, string, c, s);
  MRPT_LOAD_CONFIG_VAR(tour_cluster_radius_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(tour_max_clusters, int, c, s);
  MRPT_LOAD_CONFIG_VAR(tour_min_gain_fraction, double, c, s);
  MRPT_LOAD_CONFIG_VAR(tour_revisit_radius_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(tour_revisit_discount, double, c, s);
  MRPT_LOAD_CONFIG_VAR(tour_revisit_frontiers, bool, c, s);
  MRPT_LOAD_CONFIG_VAR(frontier_behind_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(tour_behind_fraction, double, c, s);
  MRPT_LOAD_CONFIG_VAR(tour_object_context_radius_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(oracle_target_spacing_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(oracle_headings, int, c, s);
  MRPT_LOAD_CONFIG_VAR(oracle_cover_fraction, double, c, s);
  MRPT_LOAD_CONFIG_VAR(oracle_max_views, int, c, s);
  MRPT_LOAD_CONFIG_VAR(oracle_goal_overhead_s, double, c, s);
  MRPT_LOAD_CONFIG_VAR(oracle_tour_overhead_s, double, c, s);
  MRPT_LOAD_CONFIG_VAR(oracle_max_range_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(oracle_min_view_samples, int, c, s);
  validate(s);
}

void TExplorationParams::validate(const std::string& s) const {
  requireInRange(resolution_m, 0.01, 1.0, s, "resolution_m");
  requireInRange(max_range_m, 0.5, 20.0, s, "max_range_m");
  requireInRange(min_depth_m, 0.0, 5.0, s, "min_depth_m");
  requireInRange(pixel_stride, 1, 64, s, "pixel_stride");
  requireInRange(no_return_free_m, 0.0, 20.0, s, "no_return_free_m");
  requireInRange(prob_hit, 0.5, 1.0, s, "prob_hit");
  requireInRange(prob_miss, 0.0, 0.5, s, "prob_miss");
  requireInRange(clamp_min, 0.0, 0.5, s, "clamp_min");
  requireInRange(clamp_max, 0.5, 1.0, s, "clamp_max");
  requireInRange(workspace_min_x_m, -10000.0, 10000.0, s, "workspace_min_x_m");
  requireInRange(workspace_min_y_m, -10000.0, 10000.0, s, "workspace_min_y_m");
  requireInRange(workspace_min_z_m, -10000.0, 10000.0, s, "workspace_min_z_m");
  requireInRange(workspace_max_x_m, -10000.0, 10000.0, s, "workspace_max_x_m");
  requireInRange(workspace_max_y_m, -10000.0, 10000.0, s, "workspace_max_y_m");
  requireInRange(workspace_max_z_m, -10000.0, 10000.0, s, "workspace_max_z_m");
  requireInRange(band_min_z_m, -10, 10, s, "band_min_z_m");
  requireInRange(band_max_z_m, -10, 10, s, "band_max_z_m");
  requireInRange(ic_weight_floor, 0.0, 1.0, s, "ic_weight_floor");
  requireInRange(random_candidates, 0, 100000, s, "random_candidates");
  requireInRange(seed, 0, 2147483647, s, "seed");
  requireInRange(footprint_radius_m, 0.0, 5.0, s, "footprint_radius_m");
  requireInRange(object_min_extent_m, 0.0, 100.0, s, "object_min_extent_m");
  requireInRange(object_max_extent_m, 0.0, 100.0, s, "object_max_extent_m");
  requireInRange(object_standoff_m, 0.0, 20.0, s, "object_standoff_m");
  requireInRange(predict_width, 8, 4096, s, "predict_width");
  requireInRange(predict_height, 8, 4096, s, "predict_height");
  requireInRange(predict_max_surfels, 0, 1000000000, s, "predict_max_surfels");
  requireInRange(predict_screen_keep, 0, 100000, s, "predict_screen_keep");
  requireInRange(predict_screen_width, 8, 4096, s, "predict_screen_width");
  requireInRange(predict_screen_height, 8, 4096, s, "predict_screen_height");
  requireInRange(w_entropy, 0.0, 1000000.0, s, "w_entropy");
  requireInRange(w_ic, 0.0, 1000000.0, s, "w_ic");
  requireInRange(speed_mps, 0.001, 10.0, s, "speed_mps");
  requireInRange(turn_rate_degps, 0.001, 3600.0, s, "turn_rate_degps");
  requireInRange(min_travel_time_s, 0.001, 1000000.0, s, "min_travel_time_s");
  const std::vector<std::string> names = plannerNames();
  if (std::find(names.begin(), names.end(), planner) == names.end()) {
    std::string accepted;
    for (const std::string& n : names) accepted += (accepted.empty() ? "" : ", ") + n;
    throwInputError("[" + s + "] planner",
                    "'" + planner + "' is not a planner; accepted: " + accepted);
  }
  requireInRange(blacklist_radius_m, 0.0, 100.0, s, "blacklist_radius_m");
  requireInRange(taken_view_radius_m, 0.0, 100.0, s, "taken_view_radius_m");
  requireInRange(taken_view_heading_deg, 0.0, 180.0, s, "taken_view_heading_deg");
  requireInRange(frontier_min_cells, 1, 1000000, s, "frontier_min_cells");
  requireInRange(frontier_goal_radius_m, 0.0, 100.0, s, "frontier_goal_radius_m");
  requireInRange(frontier_max_radius_m, 0.0, 100.0, s, "frontier_max_radius_m");
  requireInRange(lawnmower_spacing_m, 0.05, 1000.0, s, "lawnmower_spacing_m");
  requireInRange(lawnmower_step_m, 0.05, 1000.0, s, "lawnmower_step_m");
  if (lawnmower_axis != "x" && lawnmower_axis != "y")
    throwInputError("[" + s + "] lawnmower_axis", "'" + lawnmower_axis + "' must be x or y");
  requireInRange(tour_cluster_radius_m, 0.0, 100.0, s, "tour_cluster_radius_m");
  requireInRange(tour_max_clusters, 1, 64, s, "tour_max_clusters");
  requireInRange(tour_min_gain_fraction, 0.0, 1.0, s, "tour_min_gain_fraction");
  requireInRange(tour_revisit_radius_m, 0.0, 100.0, s, "tour_revisit_radius_m");
  requireInRange(tour_revisit_discount, 0.0, 1.0, s, "tour_revisit_discount");
  requireInRange(frontier_behind_m, 0.0, 10.0, s, "frontier_behind_m");
  requireInRange(tour_behind_fraction, 0.0, 10.0, s, "tour_behind_fraction");
  requireInRange(tour_object_context_radius_m, 0.0, 10.0, s, "tour_object_context_radius_m");
  requireInRange(oracle_target_spacing_m, 0.0, 10.0, s, "oracle_target_spacing_m");
  requireInRange(oracle_headings, 1, 360, s, "oracle_headings");
  requireInRange(oracle_cover_fraction, 0.0, 1.0, s, "oracle_cover_fraction");
  requireInRange(oracle_max_views, 1, 100000, s, "oracle_max_views");
  requireInRange(oracle_goal_overhead_s, 0.001, 1000000.0, s, "oracle_goal_overhead_s");
  requireInRange(oracle_tour_overhead_s, 0.0, 1000000.0, s, "oracle_tour_overhead_s");
  requireInRange(oracle_max_range_m, 0.0, 100.0, s, "oracle_max_range_m");
  requireInRange(oracle_min_view_samples, 1, 100000000, s, "oracle_min_view_samples");
  const auto requireBelow = [&s](double lo, double hi, const std::string& keys) {
    if (!(lo < hi)) throwInputError("[" + s + "] " + keys, "the minimum must be below the maximum");
  };
  requireBelow(workspace_min_x_m, workspace_max_x_m, "workspace_min_x_m / workspace_max_x_m");
  requireBelow(workspace_min_y_m, workspace_max_y_m, "workspace_min_y_m / workspace_max_y_m");
  requireBelow(workspace_min_z_m, workspace_max_z_m, "workspace_min_z_m / workspace_max_z_m");
  requireBelow(band_min_z_m, band_max_z_m, "band_min_z_m / band_max_z_m");
  requireBelow(object_min_extent_m, object_max_extent_m,
               "object_min_extent_m / object_max_extent_m");
  requireBelow(clamp_min, clamp_max, "clamp_min / clamp_max");
}

void TExplorationParams::saveToConfigFile(mrpt::config::CConfigFileBase& c,
                                          const std::string& s) const {
  MRPT_SAVE_CONFIG_VAR(resolution_m, c, s);
  MRPT_SAVE_CONFIG_VAR(max_range_m, c, s);
  MRPT_SAVE_CONFIG_VAR(min_depth_m, c, s);
  MRPT_SAVE_CONFIG_VAR(pixel_stride, c, s);
  MRPT_SAVE_CONFIG_VAR(no_return_free_m, c, s);
  MRPT_SAVE_CONFIG_VAR(prob_hit, c, s);
  MRPT_SAVE_CONFIG_VAR(prob_miss, c, s);
  MRPT_SAVE_CONFIG_VAR(clamp_min, c, s);
  MRPT_SAVE_CONFIG_VAR(clamp_max, c, s);
  MRPT_SAVE_CONFIG_VAR(workspace_min_x_m, c, s);
  MRPT_SAVE_CONFIG_VAR(workspace_min_y_m, c, s);
  MRPT_SAVE_CONFIG_VAR(workspace_min_z_m, c, s);
  MRPT_SAVE_CONFIG_VAR(workspace_max_x_m, c, s);
  MRPT_SAVE_CONFIG_VAR(workspace_max_y_m, c, s);
  MRPT_SAVE_CONFIG_VAR(workspace_max_z_m, c, s);
  MRPT_SAVE_CONFIG_VAR(band_min_z_m, c, s);
  MRPT_SAVE_CONFIG_VAR(band_max_z_m, c, s);
  MRPT_SAVE_CONFIG_VAR(ic_weight_floor, c, s);
  MRPT_SAVE_CONFIG_VAR(random_candidates, c, s);
  MRPT_SAVE_CONFIG_VAR(seed, c, s);
  MRPT_SAVE_CONFIG_VAR(footprint_radius_m, c, s);
  MRPT_SAVE_CONFIG_VAR(object_min_extent_m, c, s);
  MRPT_SAVE_CONFIG_VAR(object_max_extent_m, c, s);
  MRPT_SAVE_CONFIG_VAR(object_standoff_m, c, s);
  MRPT_SAVE_CONFIG_VAR(predict_width, c, s);
  MRPT_SAVE_CONFIG_VAR(predict_height, c, s);
  MRPT_SAVE_CONFIG_VAR(predict_max_surfels, c, s);
  MRPT_SAVE_CONFIG_VAR(predict_screen_keep, c, s);
  MRPT_SAVE_CONFIG_VAR(predict_screen_width, c, s);
  MRPT_SAVE_CONFIG_VAR(predict_screen_height, c, s);
  MRPT_SAVE_CONFIG_VAR(w_entropy, c, s);
  MRPT_SAVE_CONFIG_VAR(w_ic, c, s);
  MRPT_SAVE_CONFIG_VAR(rank_by_rate, c, s);
  MRPT_SAVE_CONFIG_VAR(speed_mps, c, s);
  MRPT_SAVE_CONFIG_VAR(turn_rate_degps, c, s);
  MRPT_SAVE_CONFIG_VAR(min_travel_time_s, c, s);
  MRPT_SAVE_CONFIG_VAR(planner, c, s);
  MRPT_SAVE_CONFIG_VAR(blacklist_radius_m, c, s);
  MRPT_SAVE_CONFIG_VAR(taken_view_radius_m, c, s);
  MRPT_SAVE_CONFIG_VAR(frontier_candidates, c, s);
  MRPT_SAVE_CONFIG_VAR(taken_view_heading_deg, c, s);
  MRPT_SAVE_CONFIG_VAR(frontier_min_cells, c, s);
  MRPT_SAVE_CONFIG_VAR(frontier_goal_radius_m, c, s);
  MRPT_SAVE_CONFIG_VAR(frontier_max_radius_m, c, s);
  MRPT_SAVE_CONFIG_VAR(clearance_from_unknown, c, s);
  MRPT_SAVE_CONFIG_VAR(lawnmower_spacing_m, c, s);
  MRPT_SAVE_CONFIG_VAR(lawnmower_step_m, c, s);
  MRPT_SAVE_CONFIG_VAR(lawnmower_axis, c, s);
  MRPT_SAVE_CONFIG_VAR(tour_cluster_radius_m, c, s);
  MRPT_SAVE_CONFIG_VAR(tour_max_clusters, c, s);
  MRPT_SAVE_CONFIG_VAR(tour_min_gain_fraction, c, s);
  MRPT_SAVE_CONFIG_VAR(tour_revisit_radius_m, c, s);
  MRPT_SAVE_CONFIG_VAR(tour_revisit_discount, c, s);
  MRPT_SAVE_CONFIG_VAR(tour_revisit_frontiers, c, s);
  MRPT_SAVE_CONFIG_VAR(frontier_behind_m, c, s);
  MRPT_SAVE_CONFIG_VAR(tour_behind_fraction, c, s);
  MRPT_SAVE_CONFIG_VAR(tour_object_context_radius_m, c, s);
  MRPT_SAVE_CONFIG_VAR(oracle_target_spacing_m, c, s);
  MRPT_SAVE_CONFIG_VAR(oracle_headings, c, s);
  MRPT_SAVE_CONFIG_VAR(oracle_cover_fraction, c, s);
  MRPT_SAVE_CONFIG_VAR(oracle_max_views, c, s);
  MRPT_SAVE_CONFIG_VAR(oracle_goal_overhead_s, c, s);
  MRPT_SAVE_CONFIG_VAR(oracle_tour_overhead_s, c, s);
  MRPT_SAVE_CONFIG_VAR(oracle_max_range_m, c, s);
  MRPT_SAVE_CONFIG_VAR(oracle_min_view_samples, c, s);
}

std::vector<std::string> plannerNames() {
  return {"ig", "ig_greedy", "frontier", "random", "lawnmower", "oracle"};
}

}  // namespace rasm::exploration
