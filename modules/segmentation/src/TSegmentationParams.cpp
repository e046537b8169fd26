#include "rasm/segmentation/TSegmentationParams.h"

#include <mrpt/config/CConfigFileBase.h>

#include "rasm/core/Params.h"

namespace rasm::segmentation {

void TSegmentationParams::loadFromConfigFile(const mrpt::config::CConfigFileBase& c,
                                             const std::string& s) {
  MRPT_LOAD_CONFIG_VAR(enabled, bool, c, s);
  MRPT_LOAD_CONFIG_VAR(level, int, c, s);
  MRPT_LOAD_CONFIG_VAR(concavity_threshold, double, c, s);
  MRPT_LOAD_CONFIG_VAR(concave_margin_per_z2, double, c, s);
  MRPT_LOAD_CONFIG_VAR(depth_jump_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(depth_jump_per_z2, double, c, s);
  MRPT_LOAD_CONFIG_VAR(neighbour_reach_px, int, c, s);
  MRPT_LOAD_CONFIG_VAR(neighbour_step_px, int, c, s);
  MRPT_LOAD_CONFIG_VAR(normal_filter_diameter_px, int, c, s);
  MRPT_LOAD_CONFIG_VAR(normal_filter_sigma, double, c, s);
  MRPT_LOAD_CONFIG_VAR(normal_filter_sigma_space_px, double, c, s);
  MRPT_LOAD_CONFIG_VAR(morphology_close_iterations, int, c, s);
  MRPT_LOAD_CONFIG_VAR(morphology_open_iterations, int, c, s);
  MRPT_LOAD_CONFIG_VAR(colour_edges, bool, c, s);
  MRPT_LOAD_CONFIG_VAR(colour_edge_low, double, c, s);
  MRPT_LOAD_CONFIG_VAR(colour_edge_high, double, c, s);
  MRPT_LOAD_CONFIG_VAR(colour_edge_max_depth_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(min_component_px, int, c, s);
  MRPT_LOAD_CONFIG_VAR(edge_fill_iterations, int, c, s);
  MRPT_LOAD_CONFIG_VAR(propagation_min_overlap, double, c, s);
  MRPT_LOAD_CONFIG_VAR(propagation_min_overlap_px, int, c, s);
  MRPT_LOAD_CONFIG_VAR(render_depth_gate_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(propagation_step_px, int, c, s);
  MRPT_LOAD_CONFIG_VAR(render_depth_gate_rel, double, c, s);
  MRPT_LOAD_CONFIG_VAR(merge_min_fraction, double, c, s);
  MRPT_LOAD_CONFIG_VAR(merge_max_depth_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(split_max_share, double, c, s);
  MRPT_LOAD_CONFIG_VAR(split_min_px, int, c, s);
  MRPT_LOAD_CONFIG_VAR(merge_threshold, int, c, s);
  MRPT_LOAD_CONFIG_VAR(remap_every_n_frames, int, c, s);
  requireInRange(level, 0, 3, s, "level");
  requireInRange(concavity_threshold, -1.0, 1.0, s, "concavity_threshold");
  requireInRange(concave_margin_per_z2, 0.0, 1.0, s, "concave_margin_per_z2");
  requireInRange(depth_jump_m, 0.0, 1.0, s, "depth_jump_m");
  requireInRange(depth_jump_per_z2, 0.0, 1.0, s, "depth_jump_per_z2");
  requireInRange(neighbour_reach_px, 1, 64, s, "neighbour_reach_px");
  requireInRange(neighbour_step_px, 1, 8, s, "neighbour_step_px");
  requireInRange(normal_filter_diameter_px, 0, 31, s, "normal_filter_diameter_px");
  requireInRange(normal_filter_sigma, 1e-3, 10.0, s, "normal_filter_sigma");
  requireInRange(normal_filter_sigma_space_px, 0.1, 50.0, s, "normal_filter_sigma_space_px");
  requireInRange(morphology_close_iterations, 0, 10, s, "morphology_close_iterations");
  requireInRange(morphology_open_iterations, 0, 10, s, "morphology_open_iterations");
  requireInRange(colour_edge_low, 0.0, 2000.0, s, "colour_edge_low");
  requireInRange(colour_edge_high, colour_edge_low, 2000.0, s, "colour_edge_high");
  requireInRange(colour_edge_max_depth_m, 0.0, 100.0, s, "colour_edge_max_depth_m");
  requireInRange(min_component_px, 1, 1e7, s, "min_component_px");
  requireInRange(edge_fill_iterations, 0, 32, s, "edge_fill_iterations");
  requireInRange(propagation_min_overlap, 0.0, 1.0, s, "propagation_min_overlap");
  requireInRange(propagation_min_overlap_px, 1, 1e7, s, "propagation_min_overlap_px");
  requireInRange(render_depth_gate_m, 0.0, 1.0, s, "render_depth_gate_m");
  requireInRange(propagation_step_px, 1, 8, s, "propagation_step_px");
  requireInRange(render_depth_gate_rel, 0.0, 1.0, s, "render_depth_gate_rel");
  requireInRange(merge_min_fraction, 0.0, 1.0, s, "merge_min_fraction");
  requireInRange(merge_max_depth_m, 0.0, 100.0, s, "merge_max_depth_m");
  requireInRange(split_max_share, 0.0, 1.0, s, "split_max_share");
  requireInRange(split_min_px, 0, 1 << 24, s, "split_min_px");
  requireInRange(merge_threshold, 1, 1e6, s, "merge_threshold");
  requireInRange(remap_every_n_frames, 1, 1e6, s, "remap_every_n_frames");
}

void TSegmentationParams::saveToConfigFile(mrpt::config::CConfigFileBase& c,
                                           const std::string& s) const {
  MRPT_SAVE_CONFIG_VAR(enabled, c, s);
  MRPT_SAVE_CONFIG_VAR(level, c, s);
  MRPT_SAVE_CONFIG_VAR(concavity_threshold, c, s);
  MRPT_SAVE_CONFIG_VAR(concave_margin_per_z2, c, s);
  MRPT_SAVE_CONFIG_VAR(depth_jump_m, c, s);
  MRPT_SAVE_CONFIG_VAR(depth_jump_per_z2, c, s);
  MRPT_SAVE_CONFIG_VAR(neighbour_reach_px, c, s);
  MRPT_SAVE_CONFIG_VAR(neighbour_step_px, c, s);
  MRPT_SAVE_CONFIG_VAR(normal_filter_diameter_px, c, s);
  MRPT_SAVE_CONFIG_VAR(normal_filter_sigma, c, s);
  MRPT_SAVE_CONFIG_VAR(normal_filter_sigma_space_px, c, s);
  MRPT_SAVE_CONFIG_VAR(morphology_close_iterations, c, s);
  MRPT_SAVE_CONFIG_VAR(morphology_open_iterations, c, s);
  MRPT_SAVE_CONFIG_VAR(colour_edges, c, s);
  MRPT_SAVE_CONFIG_VAR(colour_edge_low, c, s);
  MRPT_SAVE_CONFIG_VAR(colour_edge_high, c, s);
  MRPT_SAVE_CONFIG_VAR(colour_edge_max_depth_m, c, s);
  MRPT_SAVE_CONFIG_VAR(min_component_px, c, s);
  MRPT_SAVE_CONFIG_VAR(edge_fill_iterations, c, s);
  MRPT_SAVE_CONFIG_VAR(propagation_min_overlap, c, s);
  MRPT_SAVE_CONFIG_VAR(propagation_min_overlap_px, c, s);
  MRPT_SAVE_CONFIG_VAR(render_depth_gate_m, c, s);
  MRPT_SAVE_CONFIG_VAR(propagation_step_px, c, s);
  MRPT_SAVE_CONFIG_VAR(render_depth_gate_rel, c, s);
  MRPT_SAVE_CONFIG_VAR(merge_min_fraction, c, s);
  MRPT_SAVE_CONFIG_VAR(merge_max_depth_m, c, s);
  MRPT_SAVE_CONFIG_VAR(split_max_share, c, s);
  MRPT_SAVE_CONFIG_VAR(split_min_px, c, s);
  MRPT_SAVE_CONFIG_VAR(merge_threshold, c, s);
  MRPT_SAVE_CONFIG_VAR(remap_every_n_frames, c, s);
}

}  // namespace rasm::segmentation
