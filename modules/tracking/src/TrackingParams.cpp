#include "rasm/tracking/TrackingParams.h"

#include <mrpt/config/CConfigFileBase.h>

#include <string>

#include "rasm/core/Error.h"
#include "rasm/core/Params.h"

namespace rasm::tracking {

namespace {
std::string levelKey(const char* base, int level) { return std::string(base) + "_level" + std::to_string(level); }
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

void TTrackingParams::loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s) {
  MRPT_LOAD_CONFIG_VAR_CS(num_levels, int);
  for (int l = 0; l < kMaxLevels; ++l) {
    iterations[l] = c.read_int(s, levelKey("iterations", l), iterations[l]);
    max_dist_m[l] = c.read_double(s, levelKey("max_dist_m", l), max_dist_m[l]);
  }
  MRPT_LOAD_CONFIG_VAR_CS(max_normal_angle_deg, double);
  MRPT_LOAD_CONFIG_VAR_CS(level0_pixel_stride, int);
  MRPT_LOAD_CONFIG_VAR_CS(huber_delta_m, double);
  MRPT_LOAD_CONFIG_VAR_CS(convergence_translation_m, double);
  MRPT_LOAD_CONFIG_VAR_CS(convergence_rotation_deg, double);
  const std::string mm = c.read_string(s, "motion_model", toString(motion_model));
  if (mm == toString(MotionModel::ConstantVelocity))
    motion_model = MotionModel::ConstantVelocity;
  else if (mm == toString(MotionModel::PreviousPose))
    motion_model = MotionModel::PreviousPose;
  else
    throwInputError("[" + s + "] motion_model", "unknown value '" + mm +
                                                    "', expected constant_velocity or previous_pose");
  MRPT_LOAD_CONFIG_VAR_CS(min_inliers, int);
  MRPT_LOAD_CONFIG_VAR_CS(min_inlier_fraction, double);
  MRPT_LOAD_CONFIG_VAR_CS(max_rms_m, double);
  MRPT_LOAD_CONFIG_VAR_CS(max_jump_translation_m, double);
  MRPT_LOAD_CONFIG_VAR_CS(max_jump_rotation_deg, double);
  MRPT_LOAD_CONFIG_VAR_CS(min_eigenvalue, double);
  MRPT_LOAD_CONFIG_VAR_CS(degenerate_min_inlier_fraction, double);
  MRPT_LOAD_CONFIG_VAR_CS(use_cuda, bool);
  validate(s);
}

void TTrackingParams::saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const {
  MRPT_SAVE_CONFIG_VAR_COMMENT(num_levels, "pyramid levels (1..3), coarse to fine");
  for (int l = 0; l < kMaxLevels; ++l)
    c.write(s, levelKey("iterations", l), iterations[l], mrpt::config::MRPT_SAVE_NAME_PADDING(),
            mrpt::config::MRPT_SAVE_VALUE_PADDING(), "ICP iterations at this level (0 = full res)");
  for (int l = 0; l < kMaxLevels; ++l)
    c.write(s, levelKey("max_dist_m", l), max_dist_m[l], mrpt::config::MRPT_SAVE_NAME_PADDING(),
            mrpt::config::MRPT_SAVE_VALUE_PADDING(), "association distance limit (m)");
  MRPT_SAVE_CONFIG_VAR_COMMENT(max_normal_angle_deg, "association normal-angle limit (deg)");
  MRPT_SAVE_CONFIG_VAR_COMMENT(level0_pixel_stride, "use every n-th pixel in x and y at level 0");
  MRPT_SAVE_CONFIG_VAR_COMMENT(huber_delta_m, "Huber threshold (m), 0 = least squares");
  MRPT_SAVE_CONFIG_VAR_COMMENT(convergence_translation_m, "early stop: increment below (m)");
  MRPT_SAVE_CONFIG_VAR_COMMENT(convergence_rotation_deg, "early stop: and below (deg)");
  c.write(s, "motion_model", std::string(toString(motion_model)), mrpt::config::MRPT_SAVE_NAME_PADDING(),
          mrpt::config::MRPT_SAVE_VALUE_PADDING(), "constant_velocity | previous_pose");
  MRPT_SAVE_CONFIG_VAR_COMMENT(min_inliers, "lost if fewer level-0 inliers");
  MRPT_SAVE_CONFIG_VAR_COMMENT(min_inlier_fraction, "lost if inliers / valid pixels below");
  MRPT_SAVE_CONFIG_VAR_COMMENT(max_rms_m, "lost if RMS point-to-plane residual above (m)");
  MRPT_SAVE_CONFIG_VAR_COMMENT(max_jump_translation_m, "lost if result further from guess (m)");
  MRPT_SAVE_CONFIG_VAR_COMMENT(max_jump_rotation_deg, "lost if result rotated from guess (deg)");
  MRPT_SAVE_CONFIG_VAR_COMMENT(min_eigenvalue, "degenerate below (normalised J^T J eigenvalue)");
  MRPT_SAVE_CONFIG_VAR_COMMENT(degenerate_min_inlier_fraction, "accept degenerate frames above (>1: never)");
  MRPT_SAVE_CONFIG_VAR_COMMENT(use_cuda, "ICP reduction on the GPU");
}

void TTrackingParams::validate(const std::string& s) const {
  requireInRange(num_levels, 1, kMaxLevels, s, "num_levels");
  for (int l = 0; l < kMaxLevels; ++l) {
    requireInRange(iterations[l], l == 0 ? 1 : 0, 100, s, levelKey("iterations", l));
    requireInRange(max_dist_m[l], 1e-4, 10.0, s, levelKey("max_dist_m", l));
  }
  requireInRange(max_normal_angle_deg, 0.0, 180.0, s, "max_normal_angle_deg");
  requireInRange(level0_pixel_stride, 1, 8, s, "level0_pixel_stride");
  requireInRange(huber_delta_m, 0.0, 10.0, s, "huber_delta_m");
  requireInRange(convergence_translation_m, 0.0, 1.0, s, "convergence_translation_m");
  requireInRange(convergence_rotation_deg, 0.0, 90.0, s, "convergence_rotation_deg");
  requireInRange(min_inliers, 6, 1e9, s, "min_inliers");
  requireInRange(min_inlier_fraction, 0.0, 1.0, s, "min_inlier_fraction");
  requireInRange(max_rms_m, 0.0, 10.0, s, "max_rms_m");
  requireInRange(max_jump_translation_m, 0.0, 1e3, s, "max_jump_translation_m");
  requireInRange(max_jump_rotation_deg, 0.0, 180.0, s, "max_jump_rotation_deg");
  requireInRange(min_eigenvalue, 0.0, 1.0, s, "min_eigenvalue");
  requireInRange(degenerate_min_inlier_fraction, 0.0, 2.0, s, "degenerate_min_inlier_fraction");
}

}  // namespace rasm::tracking
