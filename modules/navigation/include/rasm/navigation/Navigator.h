#pragma once
// Drives a rasm::robot::IRobot to an SE(2) goal (paper section VI): MRPT's PTG-based reactive
// navigator (mrpt::nav::CReactiveNavigationSystem) for the approach, an own controller for targets
// nearer than the PTGs' reach, and rotation in place for the final heading. MRPT stays out of
// this header.
//
// Call pattern: construct once per run (PTG tables take ~1 s), then setGoal(); the owner steps
// the robot and calls update() after EVERY robot.step(dt); update() runs one navigation step
// whenever period_s of robot time has passed, and the owner polls state(). On Reached / Failed
// the robot has been stopped; the owner calls cancel() or setGoal().
//
// Clock: MRPT's navigator reads mrpt::Clock. update() switches it to the simulated clock, set to
// the robot's time, for the duration of the call and restores the previous clock source after,
// so the rest of the process is unaffected. Only one Navigator at a time per process. A
// wall-clock robot (IRobot::wallClock(): the Segway) keeps MRPT's real clock. The Navigator is
// not thread-safe: an owner stepping it in a thread of its own serialises every call.

#include <Eigen/Core>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "rasm/navigation/TNavigationParams.h"
#include "rasm/robot/IRobot.h"

namespace rasm::navigation {

enum class NavState { Idle, Navigating, Aligning, Reached, Failed };
const char* toString(NavState s);

class Navigator {
 public:
  /// `footprint`: robot-frame polygon (counter-clockwise, metres). `localisation` returns the base
  /// pose (x, y, yaw) the navigator should believe (the mapper's estimate; in tests robot.pose()).
  /// Throws InputError on invalid params or a footprint of fewer than 3 vertices.
  Navigator(robot::IRobot& robot, const TNavigationParams& params,
            const std::vector<Eigen::Vector2f>& footprint,
            std::function<Eigen::Vector3d()> localisation);
  ~Navigator();
  Navigator(const Navigator&) = delete;
  Navigator& operator=(const Navigator&) = delete;

  /// Replaces any current goal (x, y, yaw); state -> Navigating. `via`: a route's waypoints
  /// (x, y) to pass first, in order (exploration::routeTo: the corners of a path around walls,
  /// which the reactive navigator does not see beyond its range); each counts as passed within
  /// via_reach_m, and progress (the stuck check) is the distance left along the route.
  void setGoal(const Eigen::Vector3d& goal_xyyaw, const std::vector<Eigen::Vector2d>& via = {});
  /// Stops the robot; state -> Idle.
  void cancel();
  /// After every robot.step(dt): one navigation step whenever period_s of robot time has passed.
  void update();

  NavState state() const;
  /// "timeout", "stuck", "collision", "unreachable", "mrpt: <message>" when Failed, else "".
  const std::string& failureReason() const;
  const Eigen::Vector3d& goal() const;
  /// Distance driven since construction (from the localisation poses at each navigation step).
  double pathLength_m() const;

  struct Impl;

 private:
  std::unique_ptr<Impl> m_impl;
};

}  // namespace rasm::navigation
