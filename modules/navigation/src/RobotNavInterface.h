#pragma once
// mrpt::nav::CRobot2NavInterface over a rasm::robot::IRobot (internal to navigation/). Pose from
// the owner's localisation, velocity and odometry from the robot, obstacles from its planar scan
// (robot frame), time from the robot's clock. MRPT's event callbacks only set flags that the
// Navigator reads after each navigationStep().

#include <mrpt/nav/reactive/CRobot2NavInterface.h>

#include <Eigen/Core>
#include <functional>

#include "rasm/robot/IRobot.h"

namespace rasm::navigation {

class RobotNavInterface : public mrpt::nav::CRobot2NavInterface {
 public:
  RobotNavInterface(robot::IRobot& robot, std::function<Eigen::Vector3d()> localisation)
      : m_robot(robot), m_localisation(std::move(localisation)) {}

  bool getCurrentPoseAndSpeeds(mrpt::math::TPose2D& pose, mrpt::math::TTwist2D& vel_global,
                               mrpt::system::TTimeStamp& timestamp, mrpt::math::TPose2D& odometry,
                               std::string& frame_id) override;
  bool changeSpeeds(const mrpt::kinematics::CVehicleVelCmd& cmd) override;
  bool stop(bool is_emergency_stop) override;
  mrpt::kinematics::CVehicleVelCmd::Ptr getEmergencyStopCmd() override;
  mrpt::kinematics::CVehicleVelCmd::Ptr getStopCmd() override;
  bool senseObstacles(mrpt::maps::CSimplePointsMap& obstacles,
                      mrpt::system::TTimeStamp& timestamp) override;
  // Simulated time: the robot's clock, not CTicTac's wall clock.
  double getNavigationTime() override { return m_robot.time_s() - m_timer_start_s; }
  void resetNavigationTimer() override { m_timer_start_s = m_robot.time_s(); }
  // Events, read by the Navigator after each step.
  void sendNavigationEndEvent() override { ended = true; }
  void sendNavigationEndDueToErrorEvent() override { error = true; }
  void sendWaySeemsBlockedEvent() override { way_blocked = true; }
  void sendApparentCollisionEvent() override { apparent_collision = true; }
  void sendCannotGetCloserToBlockedTargetEvent() override { target_blocked = true; }
  void clearEvents() { ended = error = way_blocked = apparent_collision = target_blocked = false; }

  bool ended = false, error = false, way_blocked = false, apparent_collision = false,
       target_blocked = false;

 private:
  robot::IRobot& m_robot;
  std::function<Eigen::Vector3d()> m_localisation;
  double m_timer_start_s = 0.0;
};

}  // namespace rasm::navigation
