#include "rasm/fusion/TFusionParams.h"

#include <mrpt/config/CConfigFileBase.h>

#include "rasm/core/Params.h"

namespace rasm::fusion {

void TFusionParams::loadFromConfigFile(const mrpt::config::CConfigFileBase& c,
                                       const std::string& s) {
  MRPT_LOAD_CONFIG_VAR(confidence_sigma, float, c, s);
  MRPT_LOAD_CONFIG_VAR(min_depth_m, float, c, s);
  MRPT_LOAD_CONFIG_VAR(max_depth_m, float, c, s);
  MRPT_LOAD_CONFIG_VAR(max_incidence_deg, float, c, s);
  MRPT_LOAD_CONFIG_VAR(assoc_max_depth_diff_m, float, c, s);
  MRPT_LOAD_CONFIG_VAR(assoc_max_depth_diff_rel, float, c, s);
  MRPT_LOAD_CONFIG_VAR(assoc_max_normal_angle_deg, float, c, s);
  MRPT_LOAD_CONFIG_VAR(radius_update_ratio, float, c, s);
  MRPT_LOAD_CONFIG_VAR(average_radius, bool, c, s);
  MRPT_LOAD_CONFIG_VAR(neighbour_coverage_check, bool, c, s);
  MRPT_LOAD_CONFIG_VAR(stable_confidence, float, c, s);
  MRPT_LOAD_CONFIG_VAR(max_confidence, float, c, s);
  MRPT_LOAD_CONFIG_VAR(unstable_max_age_s, double, c, s);
  MRPT_LOAD_CONFIG_VAR(unstable_max_idle_s, double, c, s);
  MRPT_LOAD_CONFIG_VAR(carve_free_space, bool, c, s);
  MRPT_LOAD_CONFIG_VAR(carve_margin_m, float, c, s);
  MRPT_LOAD_CONFIG_VAR(carve_margin_rel, float, c, s);
  MRPT_LOAD_CONFIG_VAR(carve_stable_decay, float, c, s);
  MRPT_LOAD_CONFIG_VAR(merge_redundant, bool, c, s);
  MRPT_LOAD_CONFIG_VAR(merge_max_normal_angle_deg, float, c, s);
  MRPT_LOAD_CONFIG_VAR(merge_row_stride, int, c, s);
  MRPT_LOAD_CONFIG_VAR(resort_unsorted_fraction, float, c, s);
  MRPT_LOAD_CONFIG_VAR(update_segments, bool, c, s);
  MRPT_LOAD_CONFIG_VAR(update_view_bins, bool, c, s);
  MRPT_LOAD_CONFIG_VAR(ic_lambda1, float, c, s);
  MRPT_LOAD_CONFIG_VAR(ic_d_min_m, float, c, s);

  requireInRange(confidence_sigma, 1e-3, 100.0, s, "confidence_sigma");
  requireInRange(min_depth_m, 0.0, 100.0, s, "min_depth_m");
  requireInRange(max_depth_m, min_depth_m, 100.0, s, "max_depth_m");
  requireInRange(max_incidence_deg, 0.0, 90.0, s, "max_incidence_deg");
  requireInRange(assoc_max_depth_diff_m, 0.0, 10.0, s, "assoc_max_depth_diff_m");
  requireInRange(assoc_max_depth_diff_rel, 0.0, 1.0, s, "assoc_max_depth_diff_rel");
  requireInRange(assoc_max_normal_angle_deg, 0.0, 180.0, s, "assoc_max_normal_angle_deg");
  requireInRange(radius_update_ratio, 0.0, 100.0, s, "radius_update_ratio");
  requireInRange(stable_confidence, 0.0, 1e9, s, "stable_confidence");
  requireInRange(max_confidence, 0.0, 1e9, s, "max_confidence");
  requireInRange(unstable_max_age_s, 0.0, 1e9, s, "unstable_max_age_s");
  requireInRange(unstable_max_idle_s, 0.0, 1e9, s, "unstable_max_idle_s");
  requireInRange(carve_margin_m, 0.0, 10.0, s, "carve_margin_m");
  requireInRange(carve_margin_rel, 0.0, 1.0, s, "carve_margin_rel");
  requireInRange(carve_stable_decay, 0.0, 1.0, s, "carve_stable_decay");
  requireInRange(merge_max_normal_angle_deg, 0.0, 90.0, s, "merge_max_normal_angle_deg");
  requireInRange(merge_row_stride, 1, 64, s, "merge_row_stride");
  requireInRange(resort_unsorted_fraction, 0.0f, 1.0f, s, "resort_unsorted_fraction");
  requireInRange(ic_lambda1, 0.0, 100.0, s, "ic_lambda1");
  requireInRange(ic_d_min_m, 0.0, 100.0, s, "ic_d_min_m");
}

void TFusionParams::saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const {
  c.write(s, "confidence_sigma", confidence_sigma);
  c.write(s, "min_depth_m", min_depth_m);
  c.write(s, "max_depth_m", max_depth_m);
  c.write(s, "max_incidence_deg", max_incidence_deg);
  c.write(s, "assoc_max_depth_diff_m", assoc_max_depth_diff_m);
  c.write(s, "assoc_max_depth_diff_rel", assoc_max_depth_diff_rel);
  c.write(s, "assoc_max_normal_angle_deg", assoc_max_normal_angle_deg);
  c.write(s, "radius_update_ratio", radius_update_ratio);
  c.write(s, "average_radius", average_radius);
  c.write(s, "neighbour_coverage_check", neighbour_coverage_check);
  c.write(s, "stable_confidence", stable_confidence);
  c.write(s, "max_confidence", max_confidence);
  c.write(s, "unstable_max_age_s", unstable_max_age_s);
  c.write(s, "unstable_max_idle_s", unstable_max_idle_s);
  c.write(s, "carve_free_space", carve_free_space);
  c.write(s, "carve_margin_m", carve_margin_m);
  c.write(s, "carve_margin_rel", carve_margin_rel);
  c.write(s, "carve_stable_decay", carve_stable_decay);
  c.write(s, "merge_redundant", merge_redundant);
  c.write(s, "merge_max_normal_angle_deg", merge_max_normal_angle_deg);
  c.write(s, "merge_row_stride", merge_row_stride);
  c.write(s, "resort_unsorted_fraction", resort_unsorted_fraction);
  c.write(s, "update_segments", update_segments);
  c.write(s, "update_view_bins", update_view_bins);
  c.write(s, "ic_lambda1", ic_lambda1);
  c.write(s, "ic_d_min_m", ic_d_min_m);
}

}  // namespace rasm::fusion
