#include "rasm/tracking/TrackingParams.h"

#include <mrpt/config/CConfigFileBase.h>

#include <string>

#include "ParamsPut.h"
#include "rasm/core/Error.h"
#include "rasm/core/Params.h"

namespace rasm::tracking {

namespace {
using detail::put;
std::string levelKey(const char* base, int level) {
  return std::string(base) + "_level" + std::to_string(level);
}
}  // namespace

const char* toString(MotionModel m) {
  switch (m) {
    case MotionModel::ConstantVelocity:
      return "constant_velocity";
    case MotionModel::PreviousPose:
      return "previous_pose";
  }
  return "?";
}

void TTrackingParams::loadFromConfigFile(const mrpt::config::CConfigFileBase& c,
                                         const std::string& s) {
  MRPT_LOAD_CONFIG_VAR_CS(num_levels, int);
  for (int l = 0; l < kMaxLevels; ++l) {
    iterations[l] = c.read_int(s, levelKey("iterations", l), iterations[l]);
    max_dist_m[l] = c.read_double(s, levelKey("max_dist_m", l), max_dist_m[l]);
    max_normal_angle_deg[l] =
        c.read_double(s, levelKey("max_normal_angle_deg", l), max_normal_angle_deg[l]);
  }
  MRPT_LOAD_CONFIG_VAR_CS(level0_pixel_stride, int);
  MRPT_LOAD_CONFIG_VAR_CS(huber_delta_m, double);
  MRPT_LOAD_CONFIG_VAR_CS(depth_noise_weighting, bool);
  MRPT_LOAD_CONFIG_VAR_CS(depth_noise_incidence, bool);
  MRPT_LOAD_CONFIG_VAR_CS(confidence_full, double);
  MRPT_LOAD_CONFIG_VAR_CS(photometric_weight, double);
  MRPT_LOAD_CONFIG_VAR_CS(photometric_weight_with_prior, double);
  MRPT_LOAD_CONFIG_VAR_CS(photometric_weight_degenerate, double);
  MRPT_LOAD_CONFIG_VAR_CS(photometric_huber, double);
  MRPT_LOAD_CONFIG_VAR_CS(photometric_min_gradient, double);
  MRPT_LOAD_CONFIG_VAR_CS(model_min_confidence, double);
  MRPT_LOAD_CONFIG_VAR_CS(model_level, int);
  MRPT_LOAD_CONFIG_VAR_CS(convergence_translation_m, double);
  MRPT_LOAD_CONFIG_VAR_CS(convergence_rotation_deg, double);
  const std::string mm = c.read_string(s, "motion_model", toString(motion_model));
  if (mm == toString(MotionModel::ConstantVelocity))
    motion_model = MotionModel::ConstantVelocity;
  else if (mm == toString(MotionModel::PreviousPose))
    motion_model = MotionModel::PreviousPose;
  else
    throwInputError("[" + s + "] motion_model",
                    "unknown value '" + mm + "', expected constant_velocity or previous_pose");
  MRPT_LOAD_CONFIG_VAR_CS(lost_velocity_frames, int);
  MRPT_LOAD_CONFIG_VAR_CS(min_inliers, int);
  MRPT_LOAD_CONFIG_VAR_CS(min_inlier_fraction, double);
  MRPT_LOAD_CONFIG_VAR_CS(max_rms_m, double);
  MRPT_LOAD_CONFIG_VAR_CS(max_jump_translation_m, double);
  MRPT_LOAD_CONFIG_VAR_CS(max_jump_rotation_deg, double);
  MRPT_LOAD_CONFIG_VAR_CS(min_eigenvalue, double);
  MRPT_LOAD_CONFIG_VAR_CS(degenerate_min_inlier_fraction, double);
  MRPT_LOAD_CONFIG_VAR_CS(degenerate_max_run_frames, int);
  MRPT_LOAD_CONFIG_VAR_CS(prior_pixel_sigma_m, double);
  MRPT_LOAD_CONFIG_VAR_CS(prior_min_eigenvalue, double);
  MRPT_LOAD_CONFIG_VAR_CS(max_prior_sigmas, double);
  MRPT_LOAD_CONFIG_VAR_CS(max_odometry_sigmas, double);
  MRPT_LOAD_CONFIG_VAR_CS(check_level, int);
  MRPT_LOAD_CONFIG_VAR_CS(check_gate_m, double);
  MRPT_LOAD_CONFIG_VAR_CS(check_noise_sigmas, double);
  MRPT_LOAD_CONFIG_VAR_CS(check_max_normal_angle_deg, double);
  MRPT_LOAD_CONFIG_VAR_CS(check_occluder_margin_m, double);
  MRPT_LOAD_CONFIG_VAR_CS(check_min_agreement, double);
  MRPT_LOAD_CONFIG_VAR_CS(check_max_behind, double);
  MRPT_LOAD_CONFIG_VAR_CS(check_min_overlap, double);
  MRPT_LOAD_CONFIG_VAR_CS(check_max_disagreement_ratio, double);
  MRPT_LOAD_CONFIG_VAR_CS(check_min_disagreement, double);
  MRPT_LOAD_CONFIG_VAR_CS(check_history, int);
  MRPT_LOAD_CONFIG_VAR_CS(check_prior_confirms_sigmas, double);
  MRPT_LOAD_CONFIG_VAR_CS(check_odometry_confirms_sigmas, double);
  MRPT_LOAD_CONFIG_VAR_CS(use_cuda, bool);
  validate(s);
}

void TTrackingParams::saveToConfigFile(mrpt::config::CConfigFileBase& c,
                                       const std::string& s) const {
  put(c, s, "num_levels", num_levels, "pyramid levels (1..3), coarse to fine");
  for (int l = 0; l < kMaxLevels; ++l)
    put(c, s, levelKey("iterations", l), iterations[l],
        "ICP iterations at this level (0 = full res)");
  for (int l = 0; l < kMaxLevels; ++l)
    put(c, s, levelKey("max_dist_m", l), max_dist_m[l], "association distance limit (m)");
  for (int l = 0; l < kMaxLevels; ++l)
    put(c, s, levelKey("max_normal_angle_deg", l), max_normal_angle_deg[l],
        "association normal-angle limit (deg)");
  put(c, s, "level0_pixel_stride", level0_pixel_stride,
      "use every n-th pixel in x and y at level 0");
  put(c, s, "huber_delta_m", huber_delta_m, "Huber threshold (m), 0 = least squares");
  put(c, s, "depth_noise_weighting", depth_noise_weighting,
      "weight residuals by the depth noise model");
  put(c, s, "depth_noise_incidence", depth_noise_incidence,
      "with depth_noise_weighting, the noise at each point's incidence angle too");
  put(c, s, "confidence_full", confidence_full,
      "weight residuals by min(1, surfel confidence / this), 0 = off");
  put(c, s, "photometric_weight", photometric_weight,
      "photometric cost weight (m^2 per intensity^2), 0 = off");
  put(c, s, "photometric_weight_with_prior", photometric_weight_with_prior,
      "photometric cost weight for frames with an odometry prior, 0 = off");
  put(c, s, "photometric_weight_degenerate", photometric_weight_degenerate,
      "no prior: a degenerate frame is aligned again with this photometric weight, 0 = off");
  put(c, s, "photometric_huber", photometric_huber,
      "Huber threshold on intensity residuals, 0 = none");
  put(c, s, "photometric_min_gradient", photometric_min_gradient,
      "skip samples with weaker intensity gradient");
  put(c, s, "model_min_confidence", model_min_confidence,
      "model = surfels with confidence >= this (0 = stable flag)");
  put(c, s, "model_level", model_level,
      "model rendered at this pyramid level (0 = full res, 1 = half)");
  put(c, s, "convergence_translation_m", convergence_translation_m,
      "early stop: increment below (m)");
  put(c, s, "convergence_rotation_deg", convergence_rotation_deg, "early stop: and below (deg)");
  put(c, s, "motion_model", std::string(toString(motion_model)),
      "constant_velocity | previous_pose");
  put(c, s, "lost_velocity_frames", lost_velocity_frames,
      "lost frames through which the constant velocity is extrapolated (0 = zero velocity)");
  put(c, s, "min_inliers", min_inliers, "lost if fewer level-0 inliers");
  put(c, s, "min_inlier_fraction", min_inlier_fraction, "lost if inliers / valid pixels below");
  put(c, s, "max_rms_m", max_rms_m, "lost if RMS point-to-plane residual above (m)");
  put(c, s, "max_jump_translation_m", max_jump_translation_m,
      "lost if result further from guess (m)");
  put(c, s, "max_jump_rotation_deg", max_jump_rotation_deg,
      "lost if result rotated from guess (deg)");
  put(c, s, "min_eigenvalue", min_eigenvalue, "degenerate below (normalised J^T J eigenvalue)");
  put(c, s, "degenerate_min_inlier_fraction", degenerate_min_inlier_fraction,
      "accept degenerate frames above (>1: never)");
  put(c, s, "degenerate_max_run_frames", degenerate_max_run_frames,
      "no prior: consecutive degenerate frames accepted on the constant-velocity guess");
  put(c, s, "prior_pixel_sigma_m", prior_pixel_sigma_m,
      "per-residual sigma (m) weighing ICP against a motion prior");
  put(c, s, "prior_min_eigenvalue", prior_min_eigenvalue,
      "with a prior: data only along directions above this");
  put(c, s, "max_prior_sigmas", max_prior_sigmas,
      "lost if further from the prior (Mahalanobis), 0 = off");
  put(c, s, "max_odometry_sigmas", max_odometry_sigmas,
      "lost if further from the odometry's x, y, yaw (Mahalanobis), 0 = off");
  put(c, s, "check_level", check_level, "pyramid level of the pose check");
  put(c, s, "check_gate_m", check_gate_m, "pose check: agreement gate base (m)");
  put(c, s, "check_noise_sigmas", check_noise_sigmas,
      "pose check: plus this many depth-noise sigmas");
  put(c, s, "check_max_normal_angle_deg", check_max_normal_angle_deg,
      "pose check: normal angle limit (deg)");
  put(c, s, "check_occluder_margin_m", check_occluder_margin_m,
      "frame points this far in front of the model are new objects, not errors (m)");
  put(c, s, "check_min_agreement", check_min_agreement,
      "lost if fewer overlapping pixels agree with the model");
  put(c, s, "check_max_behind", check_max_behind,
      "lost if more overlapping pixels lie behind the model");
  put(c, s, "check_min_overlap", check_min_overlap, "check conclusive above this overlap fraction");
  put(c, s, "check_max_disagreement_ratio", check_max_disagreement_ratio,
      "lost if disagreement > this x recent median (0 = off)");
  put(c, s, "check_min_disagreement", check_min_disagreement,
      "relative rule: disagreement always allowed up to this");
  put(c, s, "check_history", check_history, "relative rule: accepted frames in the median");
  put(c, s, "check_prior_confirms_sigmas", check_prior_confirms_sigmas,
      "relative rule overruled within this many prior sigmas of the odometry (0 = off)");
  put(c, s, "check_odometry_confirms_sigmas", check_odometry_confirms_sigmas,
      "relative rule overruled within this many sigmas of the odometry's x, y, yaw (0 = off)");
  put(c, s, "use_cuda", use_cuda, "ICP reduction on the GPU");
}

void TTrackingParams::validate(const std::string& s) const {
  requireInRange(num_levels, 1, kMaxLevels, s, "num_levels");
  for (int l = 0; l < kMaxLevels; ++l) {
    requireInRange(iterations[l], l == 0 ? 1 : 0, 100, s, levelKey("iterations", l));
    requireInRange(max_dist_m[l], 1e-4, 10.0, s, levelKey("max_dist_m", l));
    requireInRange(max_normal_angle_deg[l], 0.0, 180.0, s, levelKey("max_normal_angle_deg", l));
  }
  requireInRange(level0_pixel_stride, 1, 8, s, "level0_pixel_stride");
  requireInRange(huber_delta_m, 0.0, 10.0, s, "huber_delta_m");
  requireInRange(confidence_full, 0.0, 1e6, s, "confidence_full");
  requireInRange(photometric_weight, 0.0, 100.0, s, "photometric_weight");
  requireInRange(photometric_weight_with_prior, 0.0, 100.0, s, "photometric_weight_with_prior");
  requireInRange(photometric_weight_degenerate, 0.0, 100.0, s, "photometric_weight_degenerate");
  requireInRange(photometric_huber, 0.0, 1.0, s, "photometric_huber");
  requireInRange(photometric_min_gradient, 0.0, 1.0, s, "photometric_min_gradient");
  requireInRange(model_min_confidence, 0.0, 1e6, s, "model_min_confidence");
  requireInRange(model_level, 0, num_levels - 1, s, "model_level");
  requireInRange(convergence_translation_m, 0.0, 1.0, s, "convergence_translation_m");
  requireInRange(convergence_rotation_deg, 0.0, 90.0, s, "convergence_rotation_deg");
  requireInRange(min_inliers, 6, 1e9, s, "min_inliers");
  requireInRange(min_inlier_fraction, 0.0, 1.0, s, "min_inlier_fraction");
  requireInRange(max_rms_m, 0.0, 10.0, s, "max_rms_m");
  requireInRange(max_jump_translation_m, 0.0, 1e3, s, "max_jump_translation_m");
  requireInRange(max_jump_rotation_deg, 0.0, 180.0, s, "max_jump_rotation_deg");
  requireInRange(lost_velocity_frames, 0, 1000, s, "lost_velocity_frames");
  requireInRange(min_eigenvalue, 0.0, 1.0, s, "min_eigenvalue");
  requireInRange(degenerate_min_inlier_fraction, 0.0, 2.0, s, "degenerate_min_inlier_fraction");
  requireInRange(degenerate_max_run_frames, 0, 1000, s, "degenerate_max_run_frames");
  requireInRange(prior_pixel_sigma_m, 1e-5, 10.0, s, "prior_pixel_sigma_m");
  requireInRange(prior_min_eigenvalue, 0.0, 1.0, s, "prior_min_eigenvalue");
  requireInRange(max_prior_sigmas, 0.0, 1e6, s, "max_prior_sigmas");
  requireInRange(max_odometry_sigmas, 0.0, 1e6, s, "max_odometry_sigmas");
  requireInRange(check_level, 0, kMaxLevels - 1, s,
                 "check_level");  // used at min(this, num_levels - 1)
  requireInRange(check_gate_m, 0.0, 1.0, s, "check_gate_m");
  requireInRange(check_noise_sigmas, 0.0, 100.0, s, "check_noise_sigmas");
  requireInRange(check_max_normal_angle_deg, 0.0, 180.0, s, "check_max_normal_angle_deg");
  requireInRange(check_occluder_margin_m, 0.0, 100.0, s, "check_occluder_margin_m");
  requireInRange(check_min_agreement, 0.0, 1.0, s, "check_min_agreement");
  requireInRange(check_max_behind, 0.0, 1.0, s, "check_max_behind");
  requireInRange(check_min_overlap, 0.0, 1.0, s, "check_min_overlap");
  requireInRange(check_max_disagreement_ratio, 0.0, 1e3, s, "check_max_disagreement_ratio");
  requireInRange(check_min_disagreement, 0.0, 1.0, s, "check_min_disagreement");
  requireInRange(check_history, 1, 10000, s, "check_history");
  requireInRange(check_prior_confirms_sigmas, 0.0, 100.0, s, "check_prior_confirms_sigmas");
  requireInRange(check_odometry_confirms_sigmas, 0.0, 100.0, s, "check_odometry_confirms_sigmas");
}

}  // namespace rasm::tracking
