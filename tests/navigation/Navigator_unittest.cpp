// Navigator on the real simulator (rasm::sim worlds, SimulatedDiffDriveRobot), no mocks:
// reaching goals around obstacles, near targets, pure rotations, unreachable goals, cancel,
// determinism, and the [navigation] params. Tolerances come from the params and the geometry.
#include <gtest/gtest.h>

#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/core/Clock.h>

#include <unistd.h>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>

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

/// Removes this process's PTG cache when the tests end (kept between tests: warm constructions).
class CacheCleanup : public ::testing::Environment {
 public:
  void TearDown() override { std::filesystem::remove_all(testParams().ptg_cache_dir); }
};
const auto* const kCleanup = ::testing::AddGlobalTestEnvironment(new CacheCleanup);

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
      : scene(w),
        robot(scene, quietRobot(), start),
        nav(robot, p, robot.params().footprintPolygon(), [this] { return robot.pose(); }) {}
  sim::RayScene scene;
  sim::SimulatedDiffDriveRobot robot;
  Navigator nav;
};

/// After Reached / Failed / cancel the robot does not move on (within MRPT's simulated lag).
void expectStaysStopped(Rig& rig) {
  const Eigen::Vector3d at = rig.robot.pose();
  for (int i = 0; i < 10; ++i) {
    rig.robot.step(kDt);
    rig.nav.update();
  }
  EXPECT_LT((rig.robot.pose() - at).norm(), 1e-3);
  EXPECT_LT(rig.robot.velocity().norm(), 1e-6);
}

double headingError(double a, double b) {
  return std::abs(std::atan2(std::sin(a - b), std::cos(a - b)));
}

}  // namespace

TEST(Navigator, ReachesAGoalThreeMetresAwayAroundAnObstacle) {
  const mrpt::Clock::Source clock_before = mrpt::Clock::getActiveClock();
  const auto t0 = std::chrono::steady_clock::now();
  Rig rig(floorWorld(kBlock), Eigen::Vector3d(0, 0, 0));
  const double build_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const TNavigationParams p = testParams();
  // PTG cache files go to ptg_cache_dir, not the working directory (MRPT trap).
  const auto isCache = [](const std::filesystem::directory_entry& e) {
    return e.path().filename().string().rfind("ReacNavGrid_", 0) == 0;
  };
  int in_cache = 0, in_cwd = 0;
  for (const auto& e : std::filesystem::recursive_directory_iterator(p.ptg_cache_dir))
    in_cache += isCache(e);
  for (const auto& e : std::filesystem::directory_iterator(std::filesystem::current_path()))
    in_cwd += isCache(e);
  EXPECT_GT(in_cache, 0);
  EXPECT_EQ(in_cwd, 0);
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
  // The process clock is the one it was before (the Navigator's simulated clock is scoped).
  EXPECT_EQ(mrpt::Clock::getActiveClock(), clock_before);
  expectStaysStopped(rig);
}

// A goal behind a wall beside a doorway: the straight line runs into the wall, and the way
// through the doorway first moves away from the goal (the straight-line distance grows by 0.9 m
// over ~10 s, which the stuck check must not take for a lack of progress). The route's two
// waypoints (before and after the doorway) take the robot there.
TEST(Navigator, FollowsARouteThroughADoorwayToAGoalBehindAWall) {
  const std::string wall =  // x = 2, doorway y in [0.6, 1.5]
      "  - {id: 2, class: wall, primitive: box, size: [0.1, 4.6, 1.0], position: [2.0, -1.7, "
      "0.5]}\n"
      "  - {id: 3, class: wall, primitive: box, size: [0.1, 2.5, 1.0], position: [2.0, 2.75, "
      "0.5]}\n";
  const TNavigationParams p = testParams();
  Rig rig(floorWorld(wall), Eigen::Vector3d(0, -1.5, 0), p);
  const Eigen::Vector3d goal(2.6, -2.5, -90 * kDeg);
  rig.nav.setGoal(goal, {Eigen::Vector2d(1.4, 1.05), Eigen::Vector2d(2.6, 1.05)});
  const Outcome o = drive(rig.robot, rig.nav, p.goal_timeout_s);
  std::printf("through the doorway: %s in %.1f s, path %.2f m\n", toString(o.state), o.time_s,
              rig.nav.pathLength_m());
  ASSERT_EQ(o.state, NavState::Reached) << o.reason;
  EXPECT_FALSE(o.collided);
  EXPECT_LE((rig.robot.pose().head<2>() - goal.head<2>()).norm(), p.goal_tolerance_m);
  // It went through the doorway: some pose beyond the wall's plane within the doorway's span.
  bool through = false;
  for (std::size_t k = 1; k < o.trajectory.size(); ++k)
    if (o.trajectory[k - 1].x() < 2.0 && o.trajectory[k].x() >= 2.0)
      through = o.trajectory[k].y() > 0.6 && o.trajectory[k].y() < 1.5;
  EXPECT_TRUE(through);
  // The route's length is ~7.4 m; the path no more than 25% longer.
  EXPECT_LT(rig.nav.pathLength_m(),
            1.25 * ((Eigen::Vector2d(1.4, 1.05) - Eigen::Vector2d(0, -1.5)).norm() + 1.2 + 3.55));
  // A route with a non-finite waypoint is refused.
  EXPECT_THROW(rig.nav.setGoal(goal, {Eigen::Vector2d(NAN, 0)}), InputError);
}

// Room to room along a 1.7 m hallway (flat 2101 of the planners panel, whose corners these
// are): out of one room's 1 m doorway, 3 m west along the hallway, into the next room's doorway.
// The route's corners lie one footprint radius (plus the grid's rounding) from the door jambs
// and the hallway wall, where the margin-grown PTG footprint touches them: the reactive
// navigator stood still in the hallway there and failed "stuck" on four goals in a row.
TEST(Navigator, FollowsARouteAlongAHallwayFromRoomToRoom) {
  const std::string walls =  // hallway y 0..1.7; doorways x 5.866..6.866 and 9.803..10.803
      "  - {id: 2, class: wall, primitive: box, size: [8.2, 0.1, 1.0], position: [8.0, -0.05, "
      "0.5]}\n"
      "  - {id: 3, class: wall, primitive: box, size: [1.966, 0.1, 1.0], position: [4.883, 1.75, "
      "0.5]}\n"
      "  - {id: 4, class: wall, primitive: box, size: [2.937, 0.1, 1.0], position: [8.335, 1.75, "
      "0.5]}\n"
      "  - {id: 5, class: wall, primitive: box, size: [1.297, 0.1, 1.0], position: [11.452, 1.75, "
      "0.5]}\n"
      "  - {id: 6, class: wall, primitive: box, size: [0.1, 5.3, 1.0], position: [8.453, 4.45, "
      "0.5]}\n";
  const TNavigationParams p = testParams();
  Rig rig(floorWorld(walls), Eigen::Vector3d(10.08, 2.6, -90 * kDeg), p);
  const Eigen::Vector3d goal(7.32, 3.05, M_PI);
  const std::vector<Eigen::Vector2d> route = {
      {10.075, 1.55}, {9.825, 1.30}, {6.825, 1.30}, {6.575, 1.55}, {6.575, 2.30}};
  rig.nav.setGoal(goal, route);
  const Outcome o = drive(rig.robot, rig.nav, p.goal_timeout_s);
  std::printf("room to room: %s in %.1f s, path %.2f m\n", toString(o.state), o.time_s,
              rig.nav.pathLength_m());
  ASSERT_EQ(o.state, NavState::Reached) << o.reason;
  EXPECT_FALSE(o.collided);
  // The route is 6.2 m: 18 s at 0.35 m/s, plus turns in place of ~300 degrees in all at each
  // corner (proportional, slowing into the heading: ~40 deg/s, 8 s) and the slowdown onto each
  // of the five corners (~1 s each): 31 s; 35 s leaves room for that, not for a stall (the
  // reactive navigator's was 10 s before each escape).
  EXPECT_LT(o.time_s, 35.0);
  // With the reactive navigator alone on the same route it does not get there within the goal
  // timeout (the stall this controller is for).
  TNavigationParams reactive = testParams();
  reactive.follow_route = false;
  Rig rig2(floorWorld(walls), Eigen::Vector3d(10.08, 2.6, -90 * kDeg), reactive);
  rig2.nav.setGoal(goal, route);
  const Outcome o2 = drive(rig2.robot, rig2.nav, reactive.goal_timeout_s);
  std::printf("room to room, reactive only: %s (%s) in %.1f s\n", toString(o2.state),
              o2.reason.c_str(), o2.time_s);
  EXPECT_TRUE(o2.state != NavState::Reached || o2.time_s > 2.0 * o.time_s);
}

TEST(Navigator, ReachesANearTargetWithItsOwnController) {
  // 0.3 m: nearer than the PTGs' reach (MRPT trap), so the direct controller drives there.
  Rig rig(floorWorld(), Eigen::Vector3d(0, 0, 0));
  const TNavigationParams p = testParams();
  const Eigen::Vector3d goal(0.25, 0.15, 0.0);
  ASSERT_LT(goal.head<2>().norm(), p.direct_range_m);
  rig.nav.setGoal(goal);
  const Outcome o = drive(rig.robot, rig.nav, p.goal_timeout_s);
  ASSERT_EQ(o.state, NavState::Reached) << o.reason;
  EXPECT_FALSE(o.collided);
  EXPECT_LE((rig.robot.pose().head<2>() - goal.head<2>()).norm(), p.goal_tolerance_m);
  EXPECT_LE(headingError(rig.robot.pose().z(), goal.z()), p.heading_tolerance_deg * kDeg);
  // 0.3 m at up to 0.35 m/s plus turning about 60 deg twice: well under 10 s.
  EXPECT_LT(o.time_s, 10.0);
}

// A goal just beyond the goal tolerance with an obstacle just past it (an object view next to a
// chair, seen in the office): the direct controller creeps up to 1 cm of clearance instead of
// stopping a few cm short for good (it used to keep clearance >= one period's travel + 2 cm).
TEST(Navigator, CreepsUpToAnObstacleNextToItsGoal) {
  // Box face at x = 0.37: the margin-grown footprint (0.25 + 0.05 m) has 2 cm left when the
  // robot is at x = 0.05, where it is within the 0.15 m tolerance of the goal at x = 0.2.
  Rig rig(floorWorld("  - {id: 2, class: box, primitive: box, size: [0.2, 1.0, 1.0], "
                     "position: [0.47, 0, 0.5]}\n"),
          Eigen::Vector3d(0, 0, 0));
  const TNavigationParams p = testParams();
  const Eigen::Vector3d goal(0.2, 0.0, 0.0);
  rig.nav.setGoal(goal);
  const Outcome o = drive(rig.robot, rig.nav, p.goal_timeout_s);
  ASSERT_EQ(o.state, NavState::Reached) << o.reason;
  EXPECT_FALSE(o.collided);
  EXPECT_LE((rig.robot.pose().head<2>() - goal.head<2>()).norm(), p.goal_tolerance_m);
}

// No progress (a wall between the robot and a goal the direct controller heads for): before
// failing "stuck" the navigator escapes once (turns toward the most open direction of the scan
// and drives escape_distance_m along it) and tries again; with escape_attempts = 0 it fails at
// the wall. Here the direct controller meets the wall again after the escape, so both fail; the
// escape shows as the extra path driven without a collision.
TEST(Navigator, EscapesOnceBeforeFailingStuck) {
  // A 1 m wall across the straight line at x = 0.45; the goal 1 m ahead, behind it.
  const std::string wall =
      "  - {id: 2, class: wall, primitive: box, size: [0.1, 1.0, 1.0], position: [0.5, 0, 0.5]}\n";
  TNavigationParams p = testParams();
  p.direct_range_m = 1.5;  // the direct controller drives straight at the wall: no progress
  const Eigen::Vector3d goal(1.0, 0.0, 0.0);
  double path_m[2] = {0, 0}, time_s[2] = {0, 0};
  for (int attempts : {0, 1}) {
    p.escape_attempts = attempts;
    Rig rig(floorWorld(wall), Eigen::Vector3d(0, 0, 0), p);
    rig.nav.setGoal(goal);
    const Outcome o = drive(rig.robot, rig.nav, p.goal_timeout_s);
    EXPECT_EQ(o.state, NavState::Failed);
    EXPECT_EQ(o.reason, "stuck");
    EXPECT_FALSE(o.collided);
    path_m[attempts] = rig.nav.pathLength_m();
    time_s[attempts] = o.time_s;
  }
  // Without escape: up to the wall (x = 0.45 - 0.3 of margin-grown footprint, ~0.15 m).
  EXPECT_LT(path_m[0], 0.3);
  // The escape drove out escape_distance_m and (facing the goal again) back toward the wall.
  EXPECT_GT(path_m[1], path_m[0] + p.escape_distance_m);
  EXPECT_GT(time_s[1], time_s[0] + p.stuck_timeout_s);  // a second no-progress period
}

// A box lower than the robot's scan plane (0.2 m high, scan at 0.3 m) is invisible to the
// navigator but inside the footprint's height band: the robot drives into it and the goal fails
// "collision". The next goal first backs the robot up along the path it came by, for
// escape_distance_m, in reverse (heading kept), without touching anything; then it navigates.
TEST(Navigator, RetreatsAlongItsPathAfterACollision) {
  const std::string low_box =
      "  - {id: 2, class: box, primitive: box, size: [0.2, 1.0, 0.2], position: [1.1, 0, 0.1]}\n";
  const TNavigationParams p = testParams();
  Rig rig(floorWorld(low_box), Eigen::Vector3d(0, 0, 0), p);
  ASSERT_LT(0.2, rig.robot.params().scan_height_m);
  ASSERT_GT(0.2, rig.robot.params().ground_clearance_m);
  rig.nav.setGoal(Eigen::Vector3d(2.0, 0.0, 0.0));
  const Outcome hit = drive(rig.robot, rig.nav, p.goal_timeout_s);
  ASSERT_EQ(hit.state, NavState::Failed);
  ASSERT_EQ(hit.reason, "collision");
  const Eigen::Vector3d at = rig.robot.pose();
  // The disc (0.25 m) touches the box face at x = 1.0.
  EXPECT_NEAR(at.x(), 0.75, 0.05);
  rig.nav.setGoal(Eigen::Vector3d(0.2, 1.5, M_PI / 2));
  Outcome next;
  double min_x = at.x();
  int steps = 0;
  for (; steps < int(p.stuck_timeout_s / kDt); ++steps) {
    rig.robot.step(kDt);
    rig.nav.update();
    ASSERT_FALSE(rig.robot.collided()) << "at step " << steps;
    const Eigen::Vector3d q = rig.robot.pose();
    if (q.x() < min_x) {
      min_x = q.x();
      EXPECT_LT(headingError(q.z(), at.z()), 10 * kDeg) << "reversing, not turning around";
      EXPECT_NEAR(q.y(), at.y(), 0.05) << "along the path it came by";
    }
    if (std::abs(q.z() - at.z()) > 20 * kDeg) break;  // the retreat is over: facing the goal
  }
  EXPECT_NEAR(at.x() - min_x, p.escape_distance_m, 0.06);
  const Outcome reached = drive(rig.robot, rig.nav, p.goal_timeout_s);
  EXPECT_EQ(reached.state, NavState::Reached) << reached.reason;
  EXPECT_FALSE(reached.collided);
}

TEST(Navigator, ReachesAPureRotationGoal) {
  Rig rig(floorWorld(), Eigen::Vector3d(1.0, -0.5, 0.2));
  const TNavigationParams p = testParams();
  const Eigen::Vector3d goal(1.0, -0.5, 0.2 + 120 * kDeg);
  rig.nav.setGoal(goal);
  const Outcome o = drive(rig.robot, rig.nav, p.goal_timeout_s);
  ASSERT_EQ(o.state, NavState::Reached) << o.reason;
  EXPECT_LT((rig.robot.pose().head<2>() - goal.head<2>()).norm(), 1e-6);  // turned in place
  EXPECT_LE(headingError(rig.robot.pose().z(), goal.z()), p.heading_tolerance_deg * kDeg);
  // 120 deg at align_w_degps = 40 deg/s is 3 s, plus the slow-down near the goal.
  EXPECT_LT(o.time_s, 120.0 / p.align_w_degps + 3.0);
  expectStaysStopped(rig);
}

TEST(Navigator, UnreachableGoalsFailWithAReasonWithinTheTimeout) {
  TNavigationParams p = testParams();
  p.goal_timeout_s = 30.0;
  for (const Eigen::Vector3d& goal : {Eigen::Vector3d(3.0, 0.0, 0.0),     // inside the pen
                                      Eigen::Vector3d(2.4, 0.0, 0.0)}) {  // inside a pen wall
    Rig rig(floorWorld(kPen), Eigen::Vector3d(0, 0, 0), p);
    rig.nav.setGoal(goal);
    const Outcome o = drive(rig.robot, rig.nav, p.goal_timeout_s + 5.0);
    std::printf("goal (%.1f, %.1f): %s '%s' after %.1f s\n", goal.x(), goal.y(), toString(o.state),
                o.reason.c_str(), o.time_s);
    EXPECT_EQ(o.state, NavState::Failed);
    EXPECT_FALSE(o.reason.empty());
    EXPECT_LE(o.time_s, p.goal_timeout_s + p.period_s + 1e-6);
    EXPECT_FALSE(o.collided);
    expectStaysStopped(rig);
  }
}

TEST(Navigator, CancelStopsTheRobot) {
  Rig rig(floorWorld(), Eigen::Vector3d(0, 0, 0));
  rig.nav.setGoal(Eigen::Vector3d(3.0, 0.0, 0.0));
  const Outcome o = drive(rig.robot, rig.nav, 2.0);
  ASSERT_EQ(o.state, NavState::Navigating);
  ASSERT_GT(rig.robot.velocity().x(), 0.1);  // it was driving
  rig.nav.cancel();
  EXPECT_EQ(rig.nav.state(), NavState::Idle);
  EXPECT_TRUE(rig.nav.failureReason().empty());
  expectStaysStopped(rig);
  // A new goal after cancel works (one Navigator reused across goals).
  rig.nav.setGoal(Eigen::Vector3d(rig.robot.pose().x(), rig.robot.pose().y(), M_PI / 2));
  EXPECT_EQ(drive(rig.robot, rig.nav, 20.0).state, NavState::Reached);
}

TEST(Navigator, SameInputsGiveTheSameTrajectory) {
  std::vector<Eigen::Vector3d> first;
  for (int run = 0; run < 2; ++run) {  // one Navigator at a time (global MRPT clock)
    const auto t0 = std::chrono::steady_clock::now();
    Rig rig(floorWorld(kBlock), Eigen::Vector3d(0, 0, 0));
    std::printf("construction %.2f s wall (%s PTG cache)\n",
                std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(),
                run == 0 ? "cold or warm" : "warm");
    rig.nav.setGoal(Eigen::Vector3d(3.0, 0.0, 0.0));
    const Outcome o = drive(rig.robot, rig.nav, 8.0);
    if (run == 0) {
      first = o.trajectory;
      continue;
    }
    ASSERT_EQ(o.trajectory.size(), first.size());
    for (size_t i = 0; i < first.size(); ++i) ASSERT_EQ(o.trajectory[i], first[i]) << "step " << i;
  }
}

TEST(TNavigationParams, RejectsUnknownAndOutOfRangeKeysByName) {
  TNavigationParams p;
  mrpt::config::CConfigFileMemory unknown("[navigation]\nmax_v_mps = 0.3\nmax_speed = 1\n");
  try {
    loadParamsStrict(unknown, "navigation", p, "test.ini");
    FAIL() << "unknown key accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("max_speed"), std::string::npos) << e.what();
  }
  mrpt::config::CConfigFileMemory bad("[navigation]\ngoal_tolerance_m = -1\n");
  try {
    loadParamsStrict(bad, "navigation", p, "test.ini");
    FAIL() << "negative tolerance accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("[navigation] goal_tolerance_m"), std::string::npos)
        << e.what();
  }
  p = TNavigationParams();
  p.holonomic_method = "CHolonomicMagic";
  EXPECT_THROW(p.validate(), InputError);
  EXPECT_NO_THROW(TNavigationParams().validate());
}

TEST(TNavigationParams, SaveLoadRoundTrip) {
  TNavigationParams a;
  a.period_s = 0.2;
  a.max_v_mps = 0.5;
  a.goal_timeout_s = 42;
  a.allow_reverse = true;
  a.follow_route = false;
  a.follow_reach_m = 0.07;
  a.ptg_num_paths = 61;
  a.holonomic_method = "CHolonomicFullEval";
  a.ptg_cache_dir = "/tmp/some cache";
  mrpt::config::CConfigFileMemory c;
  a.saveToConfigFile(c, "navigation");
  TNavigationParams b;
  loadParamsStrict(c, "navigation", b, "roundtrip");
  mrpt::config::CConfigFileMemory c2;
  b.saveToConfigFile(c2, "navigation");
  EXPECT_EQ(c.getContent(), c2.getContent());
  EXPECT_EQ(b.holonomic_method, a.holonomic_method);
  EXPECT_EQ(b.ptg_cache_dir, a.ptg_cache_dir);
  EXPECT_TRUE(b.allow_reverse);
  EXPECT_FALSE(b.follow_route);
  EXPECT_DOUBLE_EQ(b.follow_reach_m, 0.07);
  EXPECT_DOUBLE_EQ(b.goal_timeout_s, 42);
  EXPECT_EQ(knownKeys(a, "navigation").size(), 23u);  // every key written
}

// The PTG cache never goes to a fixed name in a shared folder (issue: another user's link planted
// at <temp>/rasm_ptg_cache received the tables): the user's cache folder, else a per-uid name;
// a folder that is a link, someone else's or writable by others is refused by name.
TEST(TNavigationParams, ThePtgCacheIsTheUsersOwnFolder) {
  namespace fs = std::filesystem;
  const auto restore = [](const char* name, const char* old) {
    if (old)
      ::setenv(name, old, 1);
    else
      ::unsetenv(name);
  };
  const char* old_xdg = std::getenv("XDG_CACHE_HOME");
  const char* old_home = std::getenv("HOME");
  const std::string xdg = old_xdg ? old_xdg : "", home = old_home ? old_home : "";
  ::setenv("XDG_CACHE_HOME", "/x/cache", 1);
  EXPECT_EQ(TNavigationParams().effectiveCacheDir(), "/x/cache/rasm/ptg");
  ::unsetenv("XDG_CACHE_HOME");
  ::setenv("HOME", "/home/someone", 1);
  EXPECT_EQ(TNavigationParams().effectiveCacheDir(), "/home/someone/.cache/rasm/ptg");
  ::unsetenv("HOME");
  EXPECT_EQ(
      TNavigationParams().effectiveCacheDir(),
      (fs::temp_directory_path() / ("rasm_ptg_cache_" + std::to_string(::getuid()))).string());
  restore("XDG_CACHE_HOME", old_xdg ? xdg.c_str() : nullptr);
  restore("HOME", old_home ? home.c_str() : nullptr);
  TNavigationParams given;
  given.ptg_cache_dir = "/somewhere/ptg";
  EXPECT_EQ(given.effectiveCacheDir(), "/somewhere/ptg");

  const fs::path root = fs::temp_directory_path() / ("rasm_ptg_test_" + std::to_string(::getpid()));
  fs::remove_all(root);
  fs::create_directories(root / "victim");
  EXPECT_NO_THROW(ensurePrivateCacheDir((root / "own" / "ptg").string()));
  EXPECT_TRUE(fs::is_directory(root / "own" / "ptg"));
  fs::create_directory_symlink(root / "victim", root / "link");
  try {
    ensurePrivateCacheDir((root / "link").string());
    ADD_FAILURE() << "a link was accepted as the PTG cache";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find((root / "link").string()), std::string::npos) << e.what();
  }
  fs::permissions(root / "victim", fs::perms::others_write, fs::perm_options::add);
  EXPECT_THROW(ensurePrivateCacheDir((root / "victim").string()), InputError);
  fs::remove_all(root);
}
