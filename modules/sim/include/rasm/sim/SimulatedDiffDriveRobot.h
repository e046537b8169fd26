#pragma once
// Simulated differential-drive ground robot: kinematics and velocity dynamics of
// mrpt::kinematics::CVehicleSimul_DiffDriven, collision against the world's geometry in the
// robot's height band (OccupancyRaster: the robot stops and reports a collision), seeded
// odometry noise, a planar obstacle scan ray-cast in the world, and the camera mount.

#include <mrpt/config/CLoadableOptions.h>

#include <memory>
#include <random>
#include <string>
#include <vector>

#include "rasm/core/RgbdFrame.h"
#include "rasm/robot/IRobot.h"
#include "rasm/sim/OccupancyRaster.h"
#include "rasm/sim/RayScene.h"

namespace rasm::sim {

/// INI section [sim_robot] (keys as the member names).
struct TRobotParams : public mrpt::config::CLoadableOptions {
  /// Footprint: a disc of this radius when > 0, else the polygon footprint_xs / footprint_ys
  /// (robot frame, metres, counter-clockwise; MRPT's RobotModel_shape2D_xs/ys convention).
  double footprint_radius_m = 0.25;
  std::vector<double> footprint_xs, footprint_ys;
  /// Height band checked for collisions: [ground_clearance_m, height_m] above the floor.
  double ground_clearance_m = 0.03;
  double height_m = 0.6;
  double collision_cell_m = 0.02;
  // Camera mount on the base: forward offset, height, pitch (negative = looking down).
  double camera_x_m = 0.10;
  double camera_height_m = 0.55;
  double camera_pitch_deg = -10.0;
  // Velocity limits (commands are clamped) and the first-order velocity lag of MRPT's simulator.
  double max_v_mps = 0.6;
  double max_w_degps = 90.0;
  double velocity_tau_s = 0.0;
  /// Longest internal step: step(dt) is split so collisions are caught within this much travel.
  double max_substep_s = 0.01;
  // Odometry noise as random walks: std of the accumulated error after 1 m / 1 rad of motion.
  bool odometry_noise = true;
  double odo_sigma_xy_per_sqrt_m = 0.01;     ///< m per sqrt(m travelled)
  double odo_sigma_yaw_per_sqrt_rad = 0.02;  ///< rad per sqrt(rad turned)
  double odo_sigma_yaw_per_sqrt_m = 0.005;   ///< rad per sqrt(m travelled)
  /// Where the odometry's heading comes from: "wheels" (the yaw noise above) or "gyro" (a yaw
  /// rate gyro integrated, as gyro-aided odometry of ground robots reports it: Kobuki, Husky;
  /// the wheels still give x and y). The gyro's heading error: a scale factor error and a bias,
  /// each drawn once per run (normal, these standard deviations), plus angle random walk. The
  /// defaults are a calibrated consumer MEMS gyro: 0.2% scale, 0.005 deg/s (18 deg/h) of bias
  /// left after calibration at rest, 0.01 deg/sqrt(s) (0.6 deg/sqrt(h)) of random walk. Through a
  /// half turn: ~0.4 deg (1 sigma) against the wheels' 2 deg.
  std::string odometry_heading = "gyro";
  double gyro_scale_error = 0.002;
  double gyro_bias_degps = 0.005;
  double gyro_arw_deg_per_sqrt_s = 0.01;
  // Planar obstacle scan (for the reactive navigator).
  double scan_height_m = 0.3;
  int scan_rays = 360;
  double scan_max_range_m = 6.0;

  /// Footprint polygon in the robot frame (a 16-gon for a disc footprint).
  std::vector<Eigen::Vector2f> footprintPolygon() const;
  /// T_base_cam (optical camera frame in the base frame).
  Eigen::Isometry3d T_base_cam() const;

  void loadFromConfigFile(const mrpt::config::CConfigFileBase& cfg,
                          const std::string& section) override;
  void saveToConfigFile(mrpt::config::CConfigFileBase& cfg,
                        const std::string& section) const override;
  void validate(const std::string& section = "sim_robot") const;
};

class SimulatedDiffDriveRobot : public robot::IRobot {
 public:
  /// The robot starts at `start_pose` (x, y, yaw); `seed` drives the odometry noise. Throws
  /// InputError when the start pose collides with the world.
  SimulatedDiffDriveRobot(const RayScene& scene, const TRobotParams& params,
                          const Eigen::Vector3d& start_pose, std::uint64_t seed = 0);
  ~SimulatedDiffDriveRobot() override;

  void setVelocityCommand(double v_mps, double w_radps) override;
  void step(double dt_s) override;
  double time_s() const override;
  Eigen::Vector3d pose() const override;
  Eigen::Vector2d velocity() const override;
  Eigen::Vector3d odometry() const override;
  void senseObstacles(std::vector<Eigen::Vector3f>& points_robot) const override;
  bool collided() const override { return m_collided; }
  Eigen::Isometry3d cameraPose() const override;

  /// Planar scan ranges (m), ray i at angle 2 pi i / n from the robot's x axis, counter-clockwise;
  /// max range where nothing is hit.
  std::vector<float> scanRanges() const;
  /// Whether the footprint at `pose` (x, y, yaw) overlaps the world's geometry.
  bool collidesAt(const Eigen::Vector3d& pose) const;
  /// Teleports the robot (ground truth and odometry), clearing the collision flag.
  void setPose(const Eigen::Vector3d& pose);

  const TRobotParams& params() const { return m_params; }
  const OccupancyRaster& raster() const { return m_raster; }

 private:
  /// Noise of one odometry increment d (x, y, yaw in the base frame at its start) over dt s.
  void addOdometryNoise(Eigen::Vector3d& d, double dt);

  const RayScene& m_scene;
  TRobotParams m_params;
  OccupancyRaster m_raster;
  std::vector<Eigen::Vector2f> m_footprint;
  class ExactStepSimulator;  // mrpt::kinematics::CVehicleSimul_DiffDriven with exact steps
  std::unique_ptr<ExactStepSimulator> m_sim;
  double m_time_s = 0.0;
  Eigen::Vector3d m_odometry = Eigen::Vector3d::Zero();
  std::mt19937_64 m_rng;
  double m_gyro_scale = 0.0, m_gyro_bias_radps = 0.0;  ///< this run's draws (odometry_heading gyro)
  bool m_collided = false;
  double m_cmd_v = 0.0, m_cmd_w = 0.0;
};

}  // namespace rasm::sim
