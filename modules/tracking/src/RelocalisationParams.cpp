#include "rasm/tracking/RelocalisationParams.h"

#include <mrpt/config/CConfigFileBase.h>

#include <string>

#include "ParamsPut.h"
#include "rasm/core/Error.h"
#include "rasm/core/Params.h"

namespace rasm::tracking {

namespace {
using detail::put;
}  // namespace

void TRelocalisationParams::loadFromConfigFile(const mrpt::config::CConfigFileBase& c,
                                               const std::string& s) {
  MRPT_LOAD_CONFIG_VAR_CS(orb_features, int);
  MRPT_LOAD_CONFIG_VAR_CS(orb_levels, int);
  MRPT_LOAD_CONFIG_VAR_CS(orb_scale_factor, double);
  MRPT_LOAD_CONFIG_VAR_CS(orb_fast_threshold, int);
  MRPT_LOAD_CONFIG_VAR_CS(orb_min_image_width, int);
  MRPT_LOAD_CONFIG_VAR_CS(keyframe_translation_m, double);
  MRPT_LOAD_CONFIG_VAR_CS(keyframe_rotation_deg, double);
  MRPT_LOAD_CONFIG_VAR_CS(keyframe_min_interval_frames, int);
  MRPT_LOAD_CONFIG_VAR_CS(keyframe_max_features, int);
  MRPT_LOAD_CONFIG_VAR_CS(keyframe_min_features, int);
  MRPT_LOAD_CONFIG_VAR_CS(max_keyframes, int);
  MRPT_LOAD_CONFIG_VAR_CS(min_depth_m, double);
  MRPT_LOAD_CONFIG_VAR_CS(max_depth_m, double);
  MRPT_LOAD_CONFIG_VAR_CS(max_depth_step_ratio, double);
  MRPT_LOAD_CONFIG_VAR_CS(thumbnail_width, int);
  MRPT_LOAD_CONFIG_VAR_CS(ranking_features, int);
  MRPT_LOAD_CONFIG_VAR_CS(use_last_fused_frame, bool);
  MRPT_LOAD_CONFIG_VAR_CS(last_fused_min_inliers, int);
  MRPT_LOAD_CONFIG_VAR_CS(last_fused_min_inlier_ratio, double);
  MRPT_LOAD_CONFIG_VAR_CS(last_fused_min_depth_agreeing, int);
  MRPT_LOAD_CONFIG_VAR_CS(relocalise_only_after_lost_s, double);
  MRPT_LOAD_CONFIG_VAR_CS(candidate_keyframes, int);
  MRPT_LOAD_CONFIG_VAR_CS(match_ratio, double);
  MRPT_LOAD_CONFIG_VAR_CS(max_hamming_distance, int);
  MRPT_LOAD_CONFIG_VAR_CS(min_matches, int);
  MRPT_LOAD_CONFIG_VAR_CS(neighbour_keyframes, int);
  MRPT_LOAD_CONFIG_VAR_CS(ransac_iterations, int);
  MRPT_LOAD_CONFIG_VAR_CS(ransac_reprojection_px, double);
  MRPT_LOAD_CONFIG_VAR_CS(min_inliers, int);
  MRPT_LOAD_CONFIG_VAR_CS(min_inlier_ratio, double);
  MRPT_LOAD_CONFIG_VAR_CS(depth_check_tolerance_m, double);
  MRPT_LOAD_CONFIG_VAR_CS(depth_check_relative, double);
  MRPT_LOAD_CONFIG_VAR_CS(min_depth_agreement, double);
  MRPT_LOAD_CONFIG_VAR_CS(min_depth_agreeing, int);
  validate(s);
}

void TRelocalisationParams::saveToConfigFile(mrpt::config::CConfigFileBase& c,
                                             const std::string& s) const {
  put(c, s, "orb_features", orb_features, "ORB features detected per frame");
  put(c, s, "orb_levels", orb_levels, "ORB pyramid levels");
  put(c, s, "orb_scale_factor", orb_scale_factor, "ORB pyramid scale step");
  put(c, s, "orb_fast_threshold", orb_fast_threshold, "FAST corner threshold (grey levels)");
  put(c, s, "orb_min_image_width", orb_min_image_width,
      "narrower frames are enlarged for ORB by an integer factor (px; 0 = never)");
  put(c, s, "keyframe_translation_m", keyframe_translation_m,
      "new keyframe when no keyframe within this (m) ...");
  put(c, s, "keyframe_rotation_deg", keyframe_rotation_deg, "... and this rotation (deg)");
  put(c, s, "keyframe_min_interval_frames", keyframe_min_interval_frames,
      "frames between keyframes / attempts, at least");
  put(c, s, "keyframe_max_features", keyframe_max_features,
      "strongest depth-backed features kept per keyframe");
  put(c, s, "keyframe_min_features", keyframe_min_features,
      "no keyframe from a frame with fewer features");
  put(c, s, "max_keyframes", max_keyframes,
      "database size; when full the most redundant is replaced");
  put(c, s, "min_depth_m", min_depth_m, "keypoint depth accepted from (m)");
  put(c, s, "max_depth_m", max_depth_m, "keypoint depth accepted up to (m)");
  put(c, s, "max_depth_step_ratio", max_depth_step_ratio,
      "skip keypoints on depth edges (3x3 range / depth)");
  put(c, s, "thumbnail_width", thumbnail_width, "grey thumbnail width per keyframe (px), 0 = none");
  put(c, s, "ranking_features", ranking_features, "frame features used to rank keyframes");
  put(c, s, "use_last_fused_frame", use_last_fused_frame,
      "try the last fused frame before the map's keyframes");
  put(c, s, "last_fused_min_inliers", last_fused_min_inliers, "min_inliers against that frame");
  put(c, s, "last_fused_min_inlier_ratio", last_fused_min_inlier_ratio,
      "min_inlier_ratio against that frame");
  put(c, s, "last_fused_min_depth_agreeing", last_fused_min_depth_agreeing,
      "min_depth_agreeing against that frame");
  put(c, s, "relocalise_only_after_lost_s", relocalise_only_after_lost_s,
      "lost longer than this without odometry: relocalisation only (s; 0 = never)");
  put(c, s, "candidate_keyframes", candidate_keyframes, "best-ranked keyframes tried with PnP");
  put(c, s, "match_ratio", match_ratio, "Lowe ratio test (best / second-best distance)");
  put(c, s, "max_hamming_distance", max_hamming_distance, "discard matches above (bits of 256)");
  put(c, s, "min_matches", min_matches, "candidates with fewer matches are not tried");
  put(c, s, "neighbour_keyframes", neighbour_keyframes,
      "nearest keyframes whose matches join verification");
  put(c, s, "ransac_iterations", ransac_iterations, "RANSAC PnP iterations");
  put(c, s, "ransac_reprojection_px", ransac_reprojection_px, "RANSAC PnP inlier threshold (px)");
  put(c, s, "min_inliers", min_inliers, "reject poses with fewer PnP inliers");
  put(c, s, "min_inlier_ratio", min_inlier_ratio, "reject poses with fewer inliers / matches");
  put(c, s, "depth_check_tolerance_m", depth_check_tolerance_m,
      "depth check: agreement distance (m) ...");
  put(c, s, "depth_check_relative", depth_check_relative, "... plus this fraction of the depth");
  put(c, s, "min_depth_agreement", min_depth_agreement,
      "reject if fewer depth-checked inliers agree (fraction)");
  put(c, s, "min_depth_agreeing", min_depth_agreeing,
      "reject if fewer inliers agree with the frame depth");
}

void TRelocalisationParams::validate(const std::string& s) const {
  requireInRange(orb_features, 10, 100000, s, "orb_features");
  requireInRange(orb_levels, 1, 16, s, "orb_levels");
  requireInRange(orb_scale_factor, 1.01, 2.0, s, "orb_scale_factor");
  requireInRange(orb_fast_threshold, 1, 255, s, "orb_fast_threshold");
  requireInRange(orb_min_image_width, 0, 8192, s, "orb_min_image_width");
  requireInRange(keyframe_translation_m, 0.0, 1e3, s, "keyframe_translation_m");
  requireInRange(keyframe_rotation_deg, 0.0, 180.0, s, "keyframe_rotation_deg");
  requireInRange(keyframe_min_interval_frames, 1, 1e9, s, "keyframe_min_interval_frames");
  requireInRange(keyframe_max_features, 10, 100000, s, "keyframe_max_features");
  requireInRange(keyframe_min_features, 6, keyframe_max_features, s, "keyframe_min_features");
  requireInRange(max_keyframes, 1, 1e6, s, "max_keyframes");
  requireInRange(min_depth_m, 0.0, 100.0, s, "min_depth_m");
  requireInRange(max_depth_m, min_depth_m, 100.0, s, "max_depth_m");
  requireInRange(max_depth_step_ratio, 0.0, 10.0, s, "max_depth_step_ratio");
  requireInRange(thumbnail_width, 0, 1024, s, "thumbnail_width");
  requireInRange(ranking_features, 10, orb_features, s, "ranking_features");
  requireInRange(candidate_keyframes, 1, 100, s, "candidate_keyframes");
  requireInRange(match_ratio, 0.0, 1.0, s, "match_ratio");
  requireInRange(max_hamming_distance, 1, 256, s, "max_hamming_distance");
  requireInRange(min_matches, 6, 1e6, s, "min_matches");
  requireInRange(neighbour_keyframes, 0, 100, s, "neighbour_keyframes");
  requireInRange(ransac_iterations, 1, 1e6, s, "ransac_iterations");
  requireInRange(ransac_reprojection_px, 0.1, 100.0, s, "ransac_reprojection_px");
  requireInRange(min_inliers, 6, 1e6, s, "min_inliers");
  requireInRange(min_inlier_ratio, 0.0, 1.0, s, "min_inlier_ratio");
  requireInRange(depth_check_tolerance_m, 0.0, 10.0, s, "depth_check_tolerance_m");
  requireInRange(depth_check_relative, 0.0, 1.0, s, "depth_check_relative");
  requireInRange(min_depth_agreement, 0.0, 1.0, s, "min_depth_agreement");
  requireInRange(min_depth_agreeing, 0, 1e6, s, "min_depth_agreeing");
  requireInRange(last_fused_min_inliers, 6, 1e6, s, "last_fused_min_inliers");
  requireInRange(last_fused_min_inlier_ratio, 0.0, 1.0, s, "last_fused_min_inlier_ratio");
  requireInRange(last_fused_min_depth_agreeing, 0, 1e6, s, "last_fused_min_depth_agreeing");
  requireInRange(relocalise_only_after_lost_s, 0.0, 1e9, s, "relocalise_only_after_lost_s");
}

TRelocalisationParams TRelocalisationParams::forLastFusedFrame() const {
  TRelocalisationParams p = *this;
  p.min_inliers = last_fused_min_inliers;
  p.min_inlier_ratio = last_fused_min_inlier_ratio;
  p.min_depth_agreeing = last_fused_min_depth_agreeing;
  return p;
}

}  // namespace rasm::tracking
