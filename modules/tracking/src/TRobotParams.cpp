#include "rasm/tracking/TRobotParams.h"
#include "rasm/core/Angles.h"

#include <mrpt/config/CConfigFileBase.h>

#include <cmath>

#include "rasm/core/Error.h"
#include "rasm/core/Params.h"

namespace rasm::tracking {

Eigen::Isometry3d TRobotParams::T_base_cam() const {
  // Optical axes in a body frame looking along the base's x: z (forward) = x, x (right) = -y,
  // y (down) = -z; then roll about the viewing direction, pitch (up positive), yaw.
  Eigen::Matrix3d R_body_optical;
  R_body_optical << 0, 0, 1, -1, 0, 0, 0, -1, 0;
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = Eigen::Vector3d(camera_x_m, camera_y_m, camera_z_m);
  T.linear() = (Eigen::AngleAxisd(camera_yaw_deg * kRadPerDeg, Eigen::Vector3d::UnitZ()) *
                Eigen::AngleAxisd(-camera_pitch_deg * kRadPerDeg, Eigen::Vector3d::UnitY()) *
                Eigen::AngleAxisd(camera_roll_deg * kRadPerDeg, Eigen::Vector3d::UnitX()))
                   .toRotationMatrix() *
               R_body_optical;
  return T;
}

void TRobotParams::loadFromConfigFile(const mrpt::config::CConfigFileBase& c,
                                      const std::string& s) {
  MRPT_LOAD_CONFIG_VAR(type, string, c, s);
  MRPT_LOAD_CONFIG_VAR(use_odometry, bool, c, s);
  MRPT_LOAD_CONFIG_VAR(camera_x_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(camera_y_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(camera_z_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(camera_yaw_deg, double, c, s);
  MRPT_LOAD_CONFIG_VAR(camera_pitch_deg, double, c, s);
  MRPT_LOAD_CONFIG_VAR(camera_roll_deg, double, c, s);
  MRPT_LOAD_CONFIG_VAR(odometry_sigma_xy_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(odometry_sigma_xy_per_sqrt_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(odometry_sigma_yaw_deg, double, c, s);
  MRPT_LOAD_CONFIG_VAR(odometry_sigma_yaw_per_sqrt_rad, double, c, s);
  MRPT_LOAD_CONFIG_VAR(odometry_sigma_yaw_per_sqrt_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(odometry_heading, string, c, s);
  MRPT_LOAD_CONFIG_VAR(gyro_sigma_yaw_per_rad, double, c, s);
  MRPT_LOAD_CONFIG_VAR(odometry_sigma_z_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(odometry_sigma_tilt_deg, double, c, s);
  MRPT_LOAD_CONFIG_VAR(heading_drift_window_frames, int, c, s);
  MRPT_LOAD_CONFIG_VAR(heading_drift_max_sigmas, double, c, s);
  MRPT_LOAD_CONFIG_VAR(planar_motion, bool, c, s);
  MRPT_LOAD_CONFIG_VAR(floor_prior, bool, c, s);
  MRPT_LOAD_CONFIG_VAR(floor_prior_sigma_z_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(floor_prior_sigma_tilt_deg, double, c, s);
  MRPT_LOAD_CONFIG_VAR(floor_max_height_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(floor_max_tilt_deg, double, c, s);
  MRPT_LOAD_CONFIG_VAR(floor_target_height_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(floor_target_tilt_deg, double, c, s);
  MRPT_LOAD_CONFIG_VAR(floor_target_max_fraction, double, c, s);
  if (type != "auto" && type != "none" && type != "sim" && type != "segway_rmp")
    throwInputError("[" + s + "] type", "'" + type + "' is not one of auto, none, sim, segway_rmp");
  requireInRange(heading_drift_window_frames, 1, 10000, s, "heading_drift_window_frames");
  requireInRange(heading_drift_max_sigmas, 0.0, 1000.0, s, "heading_drift_max_sigmas");
  requireInRange(floor_max_height_m, 0.0, 10.0, s, "floor_max_height_m");
  requireInRange(floor_max_tilt_deg, 0.0, 90.0, s, "floor_max_tilt_deg");
  requireInRange(floor_target_height_m, 0.0, 10.0, s, "floor_target_height_m");
  requireInRange(floor_target_tilt_deg, 0.0, 90.0, s, "floor_target_tilt_deg");
  requireInRange(floor_target_max_fraction, 0.0, 1.0, s, "floor_target_max_fraction");
  requireInRange(camera_x_m, -10.0, 10.0, s, "camera_x_m");
  requireInRange(camera_y_m, -10.0, 10.0, s, "camera_y_m");
  requireInRange(camera_z_m, -10.0, 10.0, s, "camera_z_m");
  requireInRange(camera_yaw_deg, -180.0, 180.0, s, "camera_yaw_deg");
  requireInRange(camera_pitch_deg, -90.0, 90.0, s, "camera_pitch_deg");
  requireInRange(camera_roll_deg, -180.0, 180.0, s, "camera_roll_deg");
  // Standard deviations: > 0 where they are the only term (a zero would make the prior exact).
  requireInRange(odometry_sigma_xy_m, 1e-6, 1.0, s, "odometry_sigma_xy_m");
  requireInRange(odometry_sigma_xy_per_sqrt_m, 0.0, 1.0, s, "odometry_sigma_xy_per_sqrt_m");
  requireInRange(odometry_sigma_yaw_deg, 1e-6, 90.0, s, "odometry_sigma_yaw_deg");
  requireInRange(odometry_sigma_yaw_per_sqrt_rad, 0.0, 1.0, s, "odometry_sigma_yaw_per_sqrt_rad");
  requireInRange(odometry_sigma_yaw_per_sqrt_m, 0.0, 1.0, s, "odometry_sigma_yaw_per_sqrt_m");
  if (odometry_heading != "auto" && odometry_heading != "gyro" && odometry_heading != "wheels" &&
      odometry_heading != "gyro_when_degenerate")
    throwInputError(
        "[" + s + "] odometry_heading",
        "expected auto, wheels, gyro or gyro_when_degenerate, got '" + odometry_heading + "'");
  if (type == "segway_rmp" && odometry_heading != "wheels" && odometry_heading != "auto")
    throwInputError("[" + s + "] odometry_heading = " + odometry_heading,
                    "the Segway RMP's heading is its wheels' (no gyro is read): use [" + s +
                        "] odometry_heading = wheels (docs/hardware.md)");
  requireInRange(gyro_sigma_yaw_per_rad, 0.0, 1.0, s, "gyro_sigma_yaw_per_rad");
  requireInRange(odometry_sigma_z_m, 1e-6, 1.0, s, "odometry_sigma_z_m");
  requireInRange(odometry_sigma_tilt_deg, 1e-6, 90.0, s, "odometry_sigma_tilt_deg");
  requireInRange(floor_prior_sigma_z_m, 1e-6, 1.0, s, "floor_prior_sigma_z_m");
  requireInRange(floor_prior_sigma_tilt_deg, 1e-6, 90.0, s, "floor_prior_sigma_tilt_deg");
}

void TRobotParams::resolveHeading(bool odometry_from_gyro) {
  if (odometry_heading == "auto")
    odometry_heading = odometry_from_gyro ? "gyro_when_degenerate" : "wheels";
}

void TRobotParams::saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const {
  MRPT_SAVE_CONFIG_VAR(type, c, s);
  MRPT_SAVE_CONFIG_VAR(use_odometry, c, s);
  MRPT_SAVE_CONFIG_VAR(camera_x_m, c, s);
  MRPT_SAVE_CONFIG_VAR(camera_y_m, c, s);
  MRPT_SAVE_CONFIG_VAR(camera_z_m, c, s);
  MRPT_SAVE_CONFIG_VAR(camera_yaw_deg, c, s);
  MRPT_SAVE_CONFIG_VAR(camera_pitch_deg, c, s);
  MRPT_SAVE_CONFIG_VAR(camera_roll_deg, c, s);
  MRPT_SAVE_CONFIG_VAR(odometry_sigma_xy_m, c, s);
  MRPT_SAVE_CONFIG_VAR(odometry_sigma_xy_per_sqrt_m, c, s);
  MRPT_SAVE_CONFIG_VAR(odometry_sigma_yaw_deg, c, s);
  MRPT_SAVE_CONFIG_VAR(odometry_sigma_yaw_per_sqrt_rad, c, s);
  MRPT_SAVE_CONFIG_VAR(odometry_sigma_yaw_per_sqrt_m, c, s);
  MRPT_SAVE_CONFIG_VAR(odometry_heading, c, s);
  MRPT_SAVE_CONFIG_VAR(gyro_sigma_yaw_per_rad, c, s);
  MRPT_SAVE_CONFIG_VAR(odometry_sigma_z_m, c, s);
  MRPT_SAVE_CONFIG_VAR(odometry_sigma_tilt_deg, c, s);
  MRPT_SAVE_CONFIG_VAR(heading_drift_window_frames, c, s);
  MRPT_SAVE_CONFIG_VAR(heading_drift_max_sigmas, c, s);
  MRPT_SAVE_CONFIG_VAR(planar_motion, c, s);
  MRPT_SAVE_CONFIG_VAR(floor_prior, c, s);
  MRPT_SAVE_CONFIG_VAR(floor_prior_sigma_z_m, c, s);
  MRPT_SAVE_CONFIG_VAR(floor_prior_sigma_tilt_deg, c, s);
  MRPT_SAVE_CONFIG_VAR(floor_max_height_m, c, s);
  MRPT_SAVE_CONFIG_VAR(floor_max_tilt_deg, c, s);
  MRPT_SAVE_CONFIG_VAR(floor_target_height_m, c, s);
  MRPT_SAVE_CONFIG_VAR(floor_target_tilt_deg, c, s);
  MRPT_SAVE_CONFIG_VAR(floor_target_max_fraction, c, s);
}

}  // namespace rasm::tracking
