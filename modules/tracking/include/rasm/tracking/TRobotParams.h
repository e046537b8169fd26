#pragma once
// [robot]: the platform the camera rides on (its type, the camera mount, the wheel odometry's
// noise and the floor), read by the tracking stage for the odometry prior (OdometryPrior.h).

#include <mrpt/config/CLoadableOptions.h>

#include <Eigen/Geometry>
#include <string>

namespace rasm::tracking {

/// [robot]: the platform the camera rides on, for the odometry prior of tracking:
/// the camera's mounting pose on the base and the wheel odometry's noise. Used when the source
/// gives odometry (the simulated robot's CObservationOdometry in its rawlogs, later the
/// Segway's); hand-held sources have none and track with the motion model alone.
/// Base frame: x forward, y left, z up, on the floor at the rotation centre (MRPT's planar-robot
/// convention). The defaults are the simulated robot's mount ([sim_robot] camera_x_m,
/// camera_height_m, camera_pitch_deg), so its rawlogs track without an INI.
struct TRobotParams : mrpt::config::CLoadableOptions {
  /// The robot the camera rides on: auto (the simulated robot of a [source] type = sim robot
  /// spec, none otherwise), none (hand-held or a replay: nothing to drive, no exploration), sim
  /// (the simulator's), segway_rmp (a Segway RMP over UDP, section [segway_rmp]: its odometry
  /// stamps each live frame; docs/hardware.md).
  std::string type = "auto";
  bool use_odometry = true;  ///< false: ignore the source's odometry
  // Camera mount: position (m) and yaw, pitch (positive = looking up), roll (deg) of the camera's
  // viewing direction in the base frame.
  double camera_x_m = 0.10, camera_y_m = 0.0, camera_z_m = 0.55;
  double camera_yaw_deg = 0.0, camera_pitch_deg = -10.0, camera_roll_deg = 0.0;
  // Odometry noise of one frame's increment (d m travelled, a rad turned): standard deviations
  // sigma_xy = odometry_sigma_xy_m + odometry_sigma_xy_per_sqrt_m sqrt(d) along x and y, and
  // sigma_yaw = odometry_sigma_yaw_deg + odometry_sigma_yaw_per_sqrt_rad sqrt(a) [rad]
  // + odometry_sigma_yaw_per_sqrt_m sqrt(d) [rad]: random walks as the simulated robot's
  // ([sim_robot] odo_sigma_*), twice its values, plus a floor.
  double odometry_sigma_xy_m = 0.0005;
  double odometry_sigma_xy_per_sqrt_m = 0.02;
  double odometry_sigma_yaw_deg = 0.05;
  double odometry_sigma_yaw_per_sqrt_rad = 0.04;
  double odometry_sigma_yaw_per_sqrt_m = 0.01;
  /// The noise model of the odometry's heading:
  /// - "wheels": the random walks above, in the prior and in every check;
  /// - "gyro": a yaw-rate gyro's, one increment's yaw sigma odometry_sigma_yaw_deg +
  ///   gyro_sigma_yaw_per_rad x the turn (rad), twice the simulated gyro's 0.2% scale error, in
  ///   the prior and every check: it refuses the frames in which ICP turns the camera back onto
  ///   the map after a heading error (docs/results-worldframe.md "A gyro": not adopted);
  /// - "gyro_when_degenerate": the wheels' sigmas in the prior and in the check of a frame the
  ///   geometry constrains; the gyro's in the check of a frame whose geometry leaves a direction
  ///   free (MotionPrior::odometry_information_degenerate), and a conflict there is solved again
  ///   with the heading held at the gyro's precision (IcpTracker): ICP may re-align the camera
  ///   where the data hold the heading, and may not slip where they do not
  ///   (docs/results-worldframe.md "The gyro's sigmas in degenerate frames only");
  /// - "auto": gyro_when_degenerate for the simulated robot whose heading is a gyro's
  ///   ([sim_robot] odometry_heading, its default), wheels for any other robot (the Segway's
  ///   heading is its wheels'; a rawlog does not say). resolveHeading() decides it.
  std::string odometry_heading = "auto";
  double gyro_sigma_yaw_per_rad = 0.004;
  /// A ground robot's base stays on the floor: the increment's height, roll and pitch have these
  /// standard deviations (bumps, suspension).
  double odometry_sigma_z_m = 0.005;
  double odometry_sigma_tilt_deg = 0.3;
  /// Heading drift test (OdometryPrior::addHeadingResidual): over this many frames, the sum of
  /// the tracked-minus-odometry heading differences may reach heading_drift_max_sigmas standard
  /// deviations of the summed odometry noise; beyond, the frame is not fused (prior_conflict)
  /// and the pose takes the odometry's heading. 0 sigmas = off.
  int heading_drift_window_frames = 30;
  double heading_drift_max_sigmas = 3.0;
  /// Constrain the camera to the SE(2) motion of a ground robot: every tracked pose is projected
  /// to the floor plane of the first frame's base (fixed height, roll and pitch of the mount).
  bool planar_motion = false;
  /// The floor as an absolute measurement (OdometryPrior::floorMeasurement): for a base on a
  /// flat floor the camera's height above the first frame's floor and its roll and pitch are the
  /// mount's, whatever the map did. With odometry, the prior ICP fuses then takes x, y and yaw
  /// from the odometry increment (relative) and height, roll and pitch from the mount on the
  /// first floor (absolute) with the sigmas below. Soft: the data still weigh in, unlike
  /// planar_motion. On by default: on the simulated robot it holds the floor within the
  /// floor_target_* with the horizontal error no larger (docs/slam-eval.md "Floor prior").
  bool floor_prior = true;
  /// Height (m) and roll/pitch (deg) standard deviations of the floor measurement. Tighter than
  /// a real floor's unevenness (about 1 cm, 0.2 deg) because ICP weighs the map-relative data as
  /// if the map had no error ([tracking] prior_pixel_sigma_m over thousands of inliers): at a
  /// real floor's sigmas the height still drifts; at these it stays within floor_target_*.
  double floor_prior_sigma_z_m = 0.002;
  double floor_prior_sigma_tilt_deg = 0.05;
  /// Per-frame drift flag: a tracked camera with odometry more than this far above or below the
  /// mount's height over the first frame's floor, or tilted more than this from the mount, is
  /// counted in report.json (frames_off_floor): the map's floor has drifted (measured: 5-9 cm of
  /// height and 2-3 deg of tilt over simulated robot runs, with every frame agreeing with the
  /// map). It is reported, not refused: later frames agree with the drifted map. 0 = off.
  double floor_max_height_m = 0.03;
  double floor_max_tilt_deg = 1.5;
  /// Run-level floor drift (report.json floor_drift, the run's warning): the map's floor counts
  /// as drifted when more than floor_target_max_fraction of the tracked frames with odometry
  /// have their camera further than floor_target_height_m from the mount's height or tilted more
  /// than floor_target_tilt_deg. The targets are those a map must meet for surfaces fused a few
  /// centimetres off not to count as unseen (docs/slam-eval.md "Floor drift").
  double floor_target_height_m = 0.015;
  double floor_target_tilt_deg = 0.15;
  double floor_target_max_fraction = 0.05;

  /// odometry_heading = auto made definite: gyro_when_degenerate when `odometry_from_gyro` (the
  /// frames' odometry heading is a gyro's), else wheels; other values are kept.
  void resolveHeading(bool odometry_from_gyro);
  /// T_base_cam of the mount (optical camera frame in the base frame).
  Eigen::Isometry3d T_base_cam() const;
  void loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s) override;
  void saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const override;
};

}  // namespace rasm::tracking
