// Navigator on the real simulator (rasm::sim worlds, SimulatedDiffDriveRobot), no mocks:
// reaching goals around obstacles, near targets, pure rotations, unreachable goals, cancel,
// determinism, and the [navigation] params. Tolerances come from the params and the geometry.
#include <gtest/gtest.h>

#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/core/Clock.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <unistd.h>

#include "rasm/core/Error.h"
#include "rasm/core/Params.h"
#include "rasm/navigation/Navigator.h"
#include "rasm/sim/RayScene.h"
#include "rasm/sim/SimulatedDiffDriveRobot.h"
#include "rasm/sim/World.h"

using namespace rasm;
using namespace rasm::navigation;

namespace {

constexpr double kDeg = M_PI / 180.0;
constexpr double kDt = 0.05;  // the owner's robot step (two per navigation period)

/// Floor (20 x 20 m) plus `extra` YAML object lines.
sim::World floorWorld(const std::string& extra = "") {
  return sim::loadWorldFromString(
      "objects:\n"
      "  - {id: 1, class: floor, primitive: box, size: [20, 20, 0.1], position: [0, 0, -0.05]}\n" +
          extra,
      "navigation_test");
}

/// A 0.6 x 1.2 m box (1 m high) centred on (1.5, 0): straight in the way from (0,0) to (3,0).
const char* kBlock =
    "  - {id: 2, class: box, primitive: box, size: [0.6, 1.2, 1.0], position: [1.5, 0, 0.5]}\n";

/// Walls enclosing (3, 0): a 1.2 m square pen, 0.1 m thick, 1 m high.
const char* kPen =
    "  - {id: 2, class: wall, primitive: box, size: [0.1, 1.3, 1.0], position: [2.4, 0, 0.5]}\n"
    "  - {id: 3, class: wall, primitive: box, size: [0.1, 1.3, 1.0], position: [3.6, 0, 0.5]}\n"
    "  - {id: 4, class: wall, primitive: box, size: [1.3, 0.1, 1.0], position: [3.0, 0.6, 0.5]}\n"
    "  - {id: 5, class: wall, primitive: box, size: [1.3, 0.1, 1.0], position: [3.0, -0.6, "
    "0.5]}\n";

sim::TRobotParams quietRobot() {
  sim::TRobotParams p;
  p.odometry_noise = false;
  return p;
}

/// Per-process PTG cache (tests run as parallel processes under ctest).
TNavigationParams testParams() {
  TNavigationParams p;
  p.ptg_cache_dir =
      (std::filesystem::temp_directory_path() / ("rasm_nav_test_" + std::to_string(getpid())))
          .string();
  return p;
}

struct Outcome {
  NavState state = NavState::Idle;
  std::string reason;
  double time_s = 0.0;  ///< robot time when the goal ended (or the limit)
  bool collided = false;
  std::vector<Eigen::Vector3d> trajectory;  ///< robot pose after every step
};

/// Steps the robot and the navigator until the goal ends or `limit_s` of robot time passed.
Outcome drive(sim::SimulatedDiffDriveRobot& robot, Navigator& nav, double limit_s) {
  Outcome o;
  const double t0 = robot.time_s();
  while (robot.time_s() - t0 < limit_s) {
    robot.step(kDt);
    nav.update();
    o.collided = o.collided || robot.collided();
    o.trajectory.push_back(robot.pose());
    if (nav.state() == NavState::Reached || nav.state() == NavState::Failed) break;
  }
  o.state = nav.state();
  o.reason = nav.failureReason();
  o.time_s = robot.time_s() - t0;
  return o;
}

struct Rig {
  explicit Rig(const sim::World& w, const Eigen::Vector3d& start,
               const TNavigationParams& p = testParams())
      : scene(w), robot(scene, quietRobot(), start),
        nav(robot, p, robot.params().footprintPolygon(), [this] { return robot.pose(); }) {}
  ~Rig() { std::filesystem::remove_all(testParams().ptg_cache_dir); }
  sim::RayScene scene;
  sim::SimulatedDiffDriveRobot robot;
  Navigator nav;
};

double headingError(double a, double b) { return std::abs(std::atan2(std::sin(a - b), std::cos(a - b))); }

}  // namespace

TEST(Navigator, ReachesAGoalThreeMetresAwayAroundAnObstacle) {
  const auto t0 = std::chrono::steady_clock::now();
  Rig rig(floorWorld(kBlock), Eigen::Vector3d(0, 0, 0));
  const double build_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const TNavigationParams p = testParams();
  const Eigen::Vector3d goal(3.0, 0.0, 90 * kDeg);
  rig.nav.setGoal(goal);
  EXPECT_EQ(rig.nav.state(), NavState::Navigating);
  const auto t1 = std::chrono::steady_clock::now();
  const Outcome o = drive(rig.robot, rig.nav, p.goal_timeout_s);
  const double run_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count();
  std::printf("construction %.2f s wall; reached in %.1f s robot time, %.2f s wall, path %.2f m\n",
              build_s, o.time_s, run_s, rig.nav.pathLength_m());
  ASSERT_EQ(o.state, NavState::Reached) << o.reason;
  EXPECT_FALSE(o.collided);
  EXPECT_LE((rig.robot.pose().head<2>() - goal.head<2>()).norm(), p.goal_tolerance_m);
  EXPECT_LE(headingError(rig.robot.pose().z(), goal.z()), p.heading_tolerance_deg * kDeg);
  // It went around the block: the straight line is 3 m; the path must leave |y| < 0.6 + radius.
  EXPECT_GT(rig.nav.pathLength_m(), 3.0);
  // The robot stays stopped once Reached, and the process clock is the real one again.
  EXPECT_EQ(mrpt::Clock::getActiveClock(), mrpt::Clock::Realtime);
  const Eigen::Vector3d at = rig.robot.pose();
  rig.robot.step(0.5);
  rig.nav.update();
  EXPECT_LT((rig.robot.pose() - at).norm(), 1e-9);
}
