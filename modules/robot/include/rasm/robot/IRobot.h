#pragma once
// What the exploration / navigation side needs from a ground robot, simulated or real (the
// simulator's SimulatedDiffDriveRobot, the Segway RMP's SegwayRmpRobot): velocity
// commands, pose and velocity, odometry, obstacle points for the reactive navigator, the camera
// pose, and a time step. navigation/ adapts it to mrpt::nav::CRobot2NavInterface (whose
// senseObstacles() wants points in the ROBOT frame, z within the obstacle height band).
//
// Frames: world z up; robot base frame x forward, y left, z up, origin on the floor at the
// rotation centre. Planar poses are (x, y, yaw rad).
//
// Time: a simulated robot advances only in step(dt). When it drives mrpt::nav, the adapter must
// also switch MRPT to the simulated clock (mrpt::Clock::setActiveClock(mrpt::Clock::Simulated))
// and advance it by the same dt (mrpt::Clock::setSimulatedTime), or the navigator's alignment
// waits never complete (MRPT-NOTES "Reactive navigation").

#include <Eigen/Geometry>
#include <vector>

namespace rasm::robot {

class IRobot {
 public:
  virtual ~IRobot() = default;

  /// Velocity command in the robot frame (v forward m/s, w counter-clockwise rad/s), held until
  /// the next command. Values beyond the robot's limits are clamped.
  virtual void setVelocityCommand(double v_mps, double w_radps) = 0;
  void stop() { setVelocityCommand(0.0, 0.0); }

  /// Advances by dt seconds (simulated time). A real robot's implementation waits dt of wall
  /// time and throws when it has lost its link to the base.
  virtual void step(double dt_s) = 0;
  /// Seconds since start (simulated time for the simulator).
  virtual double time_s() const = 0;

  /// Base pose in the world (ground truth in simulation).
  virtual Eigen::Vector3d pose() const = 0;
  /// Current velocity (v m/s, w rad/s) in the robot frame.
  virtual Eigen::Vector2d velocity() const = 0;
  /// Odometry pose (x, y, yaw): starts at the initial pose and drifts with the odometry noise.
  virtual Eigen::Vector3d odometry() const = 0;

  /// Obstacle points in the ROBOT frame (x forward, y left, z up), e.g. from a planar scan.
  virtual void senseObstacles(std::vector<Eigen::Vector3f>& points_robot) const = 0;
  /// True when the robot stopped against an obstacle since the last velocity command (latched,
  /// so a controller stepping slower than the robot still sees the contact).
  virtual bool collided() const = 0;

  /// T_world_cam of the robot's RGB-D camera (optical frame), from the current pose.
  virtual Eigen::Isometry3d cameraPose() const = 0;

  /// True when time_s() is wall time and step() waits it out (a real robot): the navigator then
  /// leaves MRPT's process-wide clock alone (other threads, e.g. a camera's, stamp with it).
  virtual bool wallClock() const { return false; }
};

}  // namespace rasm::robot
