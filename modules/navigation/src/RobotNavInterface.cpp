#include "RobotNavInterface.h"

#include <mrpt/core/Clock.h>
#include <mrpt/kinematics/CVehicleVelCmd_DiffDriven.h>
#include <mrpt/maps/CSimplePointsMap.h>

#include <cmath>
#include <vector>

namespace rasm::navigation {

using mrpt::kinematics::CVehicleVelCmd_DiffDriven;

bool RobotNavInterface::getCurrentPoseAndSpeeds(mrpt::math::TPose2D& pose,
                                                mrpt::math::TTwist2D& vel_global,
                                                mrpt::system::TTimeStamp& timestamp,
                                                mrpt::math::TPose2D& odometry,
                                                std::string& /*frame_id*/) {
  const Eigen::Vector3d p = m_localisation();
  const Eigen::Vector2d v = m_robot.velocity();
  const Eigen::Vector3d o = m_robot.odometry();
  pose = mrpt::math::TPose2D(p.x(), p.y(), p.z());
  // MRPT wants the velocity in world coordinates.
  vel_global = mrpt::math::TTwist2D(v.x() * std::cos(p.z()), v.x() * std::sin(p.z()), v.y());
  odometry = mrpt::math::TPose2D(o.x(), o.y(), o.z());
  timestamp = mrpt::Clock::now();  // the simulated clock the Navigator set to the robot's time
  return true;
}

bool RobotNavInterface::changeSpeeds(const mrpt::kinematics::CVehicleVelCmd& cmd) {
  const auto* dd = dynamic_cast<const CVehicleVelCmd_DiffDriven*>(&cmd);
  if (!dd) return false;  // only diff-drive PTGs are configured
  m_robot.setVelocityCommand(dd->lin_vel, dd->ang_vel);
  return true;
}

bool RobotNavInterface::stop(bool /*is_emergency_stop*/) {
  m_robot.stop();
  return true;
}

mrpt::kinematics::CVehicleVelCmd::Ptr RobotNavInterface::getEmergencyStopCmd() {
  return getStopCmd();
}

mrpt::kinematics::CVehicleVelCmd::Ptr RobotNavInterface::getStopCmd() {
  return std::make_shared<CVehicleVelCmd_DiffDriven>();  // v = w = 0
}

bool RobotNavInterface::senseObstacles(mrpt::maps::CSimplePointsMap& obstacles,
                                       mrpt::system::TTimeStamp& timestamp) {
  std::vector<Eigen::Vector3f> pts;
  m_robot.senseObstacles(pts);
  obstacles.clear();
  obstacles.reserve(pts.size());
  for (const Eigen::Vector3f& q : pts) obstacles.insertPointFast(q.x(), q.y(), q.z());
  obstacles.mark_as_modified();
  timestamp = mrpt::Clock::now();
  return true;
}

}  // namespace rasm::navigation
