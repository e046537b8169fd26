#pragma once
// The odometry prior of tracking (DESIGN.md "Stages, threads and the map they share"):
// wheel odometry of the robot base (x, y, yaw in the odometry frame, RgbdFrame::odometry_xyyaw)
// turned into a prediction of the camera pose through the camera's mounting pose, with the
// odometry's noise, for IcpTracker::track's MotionPrior:
//     T_world_cam(t) = T_world_cam(t-1) * T_cam_base * (T_odom_base(t-1)^-1 T_odom_base(t)) *
//     T_base_cam
// The increment is relative, so odometry drift never enters the map; its covariance is that of
// one frame's increment (TRobotParams), along the base's axes at t-1.
//
// The floor measurement (TRobotParams::floor_prior, floorMeasurement): a base on a flat floor
// also knows three coordinates absolutely, the camera's height above the first frame's floor and
// its roll and pitch (the mount's). The prior then keeps x, y and yaw of the relative prediction
// and takes height, roll and pitch from the mount, with the floor's own uncertainty, so these
// three no longer random-walk with the ICP errors. ICP fuses it with the data like any prior.
//
// The optional planar constraint (TRobotParams::planar_motion) projects a pose onto the SE(2)
// motion of the base on the floor of the first frame: height, roll and pitch of the mount fixed.

#include <Eigen/Geometry>
#include <deque>
#include <optional>
#include <utility>

#include "rasm/tracking/MotionPrior.h"
#include "rasm/tracking/TRobotParams.h"

namespace rasm::tracking {

class OdometryPrior {
 public:
  explicit OdometryPrior(const TRobotParams& params);

  /// First frame: its pose defines the floor plane (the base under the camera at t = 0).
  void start(const Eigen::Isometry3d& T_world_cam0, const std::optional<Eigen::Vector3d>& odometry);

  /// The prior of a frame with odometry reading `odometry` (nullopt: none), given the pose of
  /// the previous frame (estimated or propagated). nullopt when odometry is off or this or the
  /// previous frame has no reading.
  std::optional<MotionPrior> predict(const std::optional<Eigen::Vector3d>& odometry,
                                     const Eigen::Isometry3d& T_world_cam_prev);

  /// Whether the frame of the last predict() was tracked. While frames are lost, their poses
  /// are odometry propagations, so the next prediction's uncertainty is the increments' summed
  /// (without this, a turn lost for a few frames left the odometry 3-5 degrees off and every
  /// right ICP result after it was refused as prior_conflict).
  void frameDone(bool tracked);

  /// Heading drift: the disagreement of the tracked heading with the odometry's,
  /// accumulated over the last TRobotParams::heading_drift_window_frames frames with a prior.
  /// Each frame passes the per-frame prior test, but a turn under-rotated by a fraction of a
  /// degree per frame adds up; the sum, in standard deviations of the summed odometry noise,
  /// exposes it. Call once per tracked frame that had `prior`; returns that statistic and sets
  /// `correction_rad` to the accumulated residual (rotate the pose about the floor normal by
  /// -correction_rad to take the odometry's heading).
  double addHeadingResidual(const MotionPrior& prior, const Eigen::Isometry3d& T_tracked,
                            double& correction_rad);
  /// Forgets the accumulated residuals (after a correction, when lost).
  void resetHeadingWindow() { m_heading.clear(); }
  /// The floor normal in world coordinates.
  Eigen::Vector3d up() const { return m_T_world_floor.linear().col(2); }

  /// How far a camera pose is off the first frame's floor: its height above the mount's (m, the
  /// floor normal's direction) and the angle (rad) between its orientation and the mount's at
  /// the same heading. A ground robot on a flat floor keeps both near 0; a map whose floor
  /// bends or rises (slow drift no single frame shows) moves them.
  std::pair<double, double> floorDeviation(const Eigen::Isometry3d& T_world_cam) const;

  /// The pose moved onto the floor plane (SE(2) of the base at the mount's height and tilt).
  Eigen::Isometry3d projectToFloor(const Eigen::Isometry3d& T_world_cam) const;

  /// The floor measurement: the relative prediction T_world_cam_pred moved onto the first
  /// frame's floor (projectToFloor: its camera position in the floor plane and its yaw kept,
  /// height, roll and pitch the mount's), with standard deviations along the floor frame at the
  /// base's heading: sigma_xy_m (x, y) and sigma_yaw_rad (yaw) of the relative prediction,
  /// TRobotParams::floor_prior_sigma_z_m and floor_prior_sigma_tilt_deg (height, roll, pitch).
  MotionPrior floorMeasurement(const Eigen::Isometry3d& T_world_cam_pred, double sigma_xy_m,
                               double sigma_yaw_rad) const;

  const Eigen::Isometry3d& T_base_cam() const { return m_T_base_cam; }

 private:
  TRobotParams m_params;
  Eigen::Isometry3d m_T_base_cam;
  /// TRobotParams::odometry_heading.
  enum class HeadingModel { Wheels, Gyro, GyroWhenDegenerate } m_heading_model;
  Eigen::Isometry3d m_T_world_floor = Eigen::Isometry3d::Identity();
  std::optional<Eigen::Vector3d> m_last;  ///< reading of the previous frame
  double m_last_sigma_yaw = 0.0;          ///< of the last predict()
  struct Variances {                      ///< of the predicted pose, along the base's axes
    double xy = 0, z = 0, tilt = 0, yaw = 0;
    double yaw_gyro = 0;  ///< the yaw's at the gyro's noise (odometry_heading gyro_when_degenerate)
  };
  Variances m_pending;  ///< of the last predict()
  Variances m_lost;     ///< of the last propagated (lost) pose; zero after a tracked frame
  /// (heading residual rad, its variance rad^2) of the frames in the window, oldest first.
  std::deque<std::pair<double, double>> m_heading;
};

}  // namespace rasm::tracking
