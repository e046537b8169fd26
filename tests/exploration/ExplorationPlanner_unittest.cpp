// The planners behind ExplorationPlanner (issue 18 deliverable 6): makePlanner, the frontier,
// random and lawnmower baselines and the IG planner through the interface, on octrees mapped by
// the real OctoMap from synthetic depth of a 4 x 4 m box room (optionally with door openings
// whose rays return nothing, so the space beyond a door stays unknown), and the new params.

#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <vector>

#include "rasm/core/Error.h"
#include "rasm/core/Params.h"
#include "rasm/exploration/ExplorationPlanners.h"
#include "rasm/exploration/PlanningGrid.h"

namespace rasm::exploration {
namespace {

const Eigen::Vector3d kMin(-2.0, -2.0, 0.0), kMax(2.0, 2.0, 2.5);
const double kDoorHalfWidth = 0.7, kDoorHeight = 2.0;
const CameraIntrinsics kK(60.0, 60.0, 39.5, 29.5, 80, 60);

/// The [robot] mount: 0.1 m forward, 0.55 m up, pitched 10 degrees down (optical frame).
Eigen::Isometry3d mount() {
  Eigen::Matrix3d R_body_optical;
  R_body_optical << 0, 0, 1, -1, 0, 0, 0, -1, 0;
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(10.0 * M_PI / 180, Eigen::Vector3d::UnitY()) * R_body_optical;
  T.translation() = Eigen::Vector3d(0.1, 0.0, 0.55);
  return T;
}

/// Depth of the room seen from inside: the ray's exit from the box, or no return (0) where it
/// leaves through a door (|y| < kDoorHalfWidth, z < kDoorHeight in the x = +2 and/or x = -2 wall).
Image<float> roomDepth(const Eigen::Isometry3d& T, bool door_px, bool door_mx,
                       const Eigen::Vector3d& lo = kMin, const Eigen::Vector3d& hi = kMax) {
  Image<float> depth(kK.width, kK.height, 0.0f);
  const Eigen::Vector3d o = T.translation();
  for (int y = 0; y < kK.height; ++y)
    for (int x = 0; x < kK.width; ++x) {
      const Eigen::Vector3d r =
          T.linear() * Eigen::Vector3d((x - kK.cx) / kK.fx, (y - kK.cy) / kK.fy, 1.0);
      double t = 1e9;
      int face = -1;
      for (int a = 0; a < 3; ++a) {
        if (std::abs(r[a]) < 1e-12) continue;
        const double ta = ((r[a] > 0 ? hi[a] : lo[a]) - o[a]) / r[a];
        if (ta < t) t = ta, face = a;
      }
      const Eigen::Vector3d p = o + t * r;
      const bool in_door = face == 0 && std::abs(p.y()) < kDoorHalfWidth && p.z() < kDoorHeight;
      if (in_door && ((r.x() > 0 && door_px) || (r.x() < 0 && door_mx))) continue;
      depth(x, y) = float(t);
    }
  return depth;
}

TExplorationParams roomParams() {
  TExplorationParams p;
  p.workspace_min_x_m = -2.5, p.workspace_max_x_m = 2.5;
  p.workspace_min_y_m = -2.5, p.workspace_max_y_m = 2.5;
  p.pixel_stride = 1;  // rays ~4 cm apart at the far corners: no unknown speckle between them
  p.predict_width = 80, p.predict_height = 60;
  p.random_candidates = 12;
  return p;
}

/// The robot turns in place at the origin (16 views).
std::unique_ptr<OccupancyOctree> roomOctree(const TExplorationParams& p, bool door_px,
                                            bool door_mx) {
  auto octree = std::make_unique<OccupancyOctree>(p);
  for (int k = 0; k < 16; ++k) {
    const Eigen::Isometry3d T = cameraPoseOf(Eigen::Vector3d(0, 0, k * M_PI / 8), mount());
    octree->insertDepthFrame(roomDepth(T, door_px, door_mx), kK, T);
  }
  return octree;
}

PlannerInputs inputsFor(const OccupancyOctree& octree, const Eigen::Vector3d& robot) {
  PlannerInputs in;
  in.octree = &octree;
  in.robot_pose = robot;
  in.T_base_cam = mount();
  in.K = kK;
  return in;
}

/// Checks every offered goal: reachable, footprint known free, camera pose from the mount.
void expectSoundGoals(const Plan& plan, const TExplorationParams& p) {
  for (const ViewCandidate& c : plan.ranked) {
    EXPECT_TRUE(c.reachable);
    EXPECT_TRUE(footprintFree(plan.grid, c.pose.x(), c.pose.y(), p.footprint_radius_m))
        << c.pose.transpose();
    EXPECT_TRUE(c.T_world_cam.isApprox(cameraPoseOf(c.pose, mount())));
    EXPECT_GT(c.travel_time_s, 0.0);
  }
}

double msSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

// ---- makePlanner and params ----

TEST(ExplorationPlanner, MakePlannerBuildsEachNamedPlannerAndRejectsUnknownNames) {
  TExplorationParams p;
  EXPECT_EQ(makePlanner(p)->name(), "ig");  // the default
  for (const std::string& name : plannerNames()) {
    if (name == "oracle") continue;  // needs a simulated world (below)
    p.planner = name;
    EXPECT_EQ(makePlanner(p)->name(), name);
  }
  p.planner = "astar";
  try {
    makePlanner(p);
    FAIL() << "unknown planner accepted";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("[exploration] planner"), std::string::npos) << what;
    for (const std::string& name : plannerNames())
      EXPECT_NE(what.find(name), std::string::npos) << what;
  }
}

// "oracle" is a valid name, but the planner knows the simulated world: the pipeline builds it.
TEST(ExplorationPlanner, MakePlannerRefusesTheOracleWithoutASimulatedWorld) {
  TExplorationParams p;
  p.planner = "oracle";
  EXPECT_NO_THROW(p.validate());
  try {
    makePlanner(p);
    FAIL() << "the oracle built without a world";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("[exploration] planner"), std::string::npos) << what;
    EXPECT_NE(what.find("simulated world"), std::string::npos) << what;
  }
}

TEST(ExplorationPlanner, NewParamsRoundTripAndBadValuesNameTheirKey) {
  TExplorationParams p;
  p.planner = "lawnmower";
  p.blacklist_radius_m = 0.8;
  p.frontier_min_cells = 9;
  p.frontier_goal_radius_m = 1.7;
  p.lawnmower_spacing_m = 2.25;
  p.lawnmower_step_m = 0.75;
  p.lawnmower_axis = "y";
  mrpt::config::CConfigFileMemory ini;
  p.saveToConfigFile(ini, "exploration");
  TExplorationParams q;
  loadParamsStrict(ini, "exploration", q, "test.ini");
  EXPECT_EQ(q.planner, "lawnmower");
  EXPECT_EQ(q.blacklist_radius_m, 0.8);
  EXPECT_EQ(q.frontier_min_cells, 9);
  EXPECT_EQ(q.frontier_goal_radius_m, 1.7);
  EXPECT_EQ(q.lawnmower_spacing_m, 2.25);
  EXPECT_EQ(q.lawnmower_step_m, 0.75);
  EXPECT_EQ(q.lawnmower_axis, "y");
  const auto expectKeyError = [](const TExplorationParams& bad, const std::string& key) {
    try {
      bad.validate();
      FAIL() << key << " accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(key), std::string::npos) << e.what();
    }
  };
  TExplorationParams bad;
  bad.lawnmower_axis = "z";
  expectKeyError(bad, "lawnmower_axis");
  bad = TExplorationParams(), bad.lawnmower_spacing_m = 0.0;
  expectKeyError(bad, "lawnmower_spacing_m");
  bad = TExplorationParams(), bad.frontier_min_cells = 0;
  expectKeyError(bad, "frontier_min_cells");
  bad = TExplorationParams(), bad.blacklist_radius_m = -1.0;
  expectKeyError(bad, "blacklist_radius_m");
  mrpt::config::CConfigFileMemory wrong;
  wrong.write("exploration", "planner", "bogus");
  TExplorationParams r;
  EXPECT_THROW(loadParamsStrict(wrong, "exploration", r, "test.ini"), InputError);
}

TEST(GoalBlacklist, ContainsWithinTheRadiusAndAgesOutWhenAsked) {
  GoalBlacklist permanent(0.5);
  permanent.add(Eigen::Vector3d(1.0, 1.0, 0.3));
  EXPECT_TRUE(permanent.contains(Eigen::Vector3d(1.3, 1.4, -2.0)));  // 0.5 m away, any heading
  EXPECT_FALSE(permanent.contains(Eigen::Vector3d(1.4, 1.4, 0.3)));
  for (int k = 0; k < 100; ++k) permanent.tick();
  EXPECT_EQ(permanent.size(), 1u);
  GoalBlacklist aging(0.5, 2);
  aging.add(Eigen::Vector3d(0, 0, 0));
  aging.tick();
  EXPECT_TRUE(aging.contains(Eigen::Vector3d(0, 0, 0)));
  aging.tick();
  EXPECT_EQ(aging.size(), 0u);
}

// ---- the shared reachability field ----

TEST(PlanningGrid, ReachableCellsAgreeWithPlannerSimple2D) {
  // A free 6 x 6 m grid with a wall across x = 3 except a 1 m gap at y in [4.5, 5.5].
  mrpt::maps::COccupancyGridMap2D g;
  g.setSize(0.0f, 6.0f, 0.0f, 6.0f, 0.1f, 1.0f);
  for (int iy = 0; iy < 60; ++iy)
    if (iy < 45 || iy > 55) g.setCell(30, iy, 0.0f);
  for (int ix = 40; ix < 60; ++ix) g.setCell(ix, 10, 0.5f);  // an unknown strip: an obstacle
  const TExplorationParams p;
  const Eigen::Vector3d robot(1.0, 1.0, 0.0);
  const ReachableCells reach = reachableCells(g, robot, p.footprint_radius_m);
  EXPECT_FALSE(reach.reachable(g.x2idx(3.0), g.y2idx(1.0)));  // the wall
  EXPECT_FALSE(reach.reachable(g.x2idx(3.2), g.y2idx(1.0)));  // within the footprint of it
  EXPECT_FALSE(reach.reachable(g.x2idx(5.0), g.y2idx(1.2)));  // next to the unknown strip
  // Every 7th reachable cell: PlannerSimple2D finds a path, as long as the field's within 8%.
  std::vector<ViewCandidate> c;
  int k = 0;
  for (int iy = 0; iy < reach.size_y; ++iy)
    for (int ix = 0; ix < reach.size_x; ++ix)
      if (reach.reachable(ix, iy) && ++k % 7 == 0) {
        ViewCandidate v;
        v.pose = Eigen::Vector3d(g.idx2x(ix), g.idx2y(iy), 0.0);
        c.push_back(v);
      }
  ASSERT_GT(c.size(), 100u);
  planPaths(g, robot, p, c);
  for (const ViewCandidate& v : c) {
    ASSERT_TRUE(v.reachable) << v.pose.transpose();
    const float d = reach.distance(g.x2idx(v.pose.x()), g.y2idx(v.pose.y()));
    EXPECT_NEAR(v.path_length_m, d, 0.08 * d + 0.2) << v.pose.transpose();
  }
  // Beyond the wall through the gap: around, not through.
  const float beyond = reach.distance(g.x2idx(4.0), g.y2idx(1.0));
  EXPECT_GT(beyond, std::hypot(2.0, 4.0) + std::hypot(1.0, 4.0) - 0.3);
}

TEST(PlanningGrid, ARobotInsideTheGrownObstaclesBacksOffInsteadOfReachingNothing) {
  // A free 6 x 6 m grid (0.1 m cells) with a wall in column 30 (x in [3.0, 3.1]). The robot
  // stands 0.15 m from its face (after a collision; the octree's 0.1 m cells also bring a wall up
  // to a cell nearer): its cell and every neighbour lie within the 3-cell growth of the 0.25 m
  // footprint, so no neighbour is traversable.
  mrpt::maps::COccupancyGridMap2D g;
  g.setSize(0.0f, 6.0f, 0.0f, 6.0f, 0.1f, 1.0f);
  for (int iy = 0; iy < 60; ++iy) g.setCell(30, iy, 0.0f);
  const TExplorationParams p;
  const Eigen::Vector3d robot(2.85, 3.0, 0.0);
  const Eigen::Vector2d start = planningStart(g, robot, p.footprint_radius_m);
  // The nearest traversable cell: column 26 (centre 2.65; 4 cells from the wall), same row.
  EXPECT_NEAR(start.x(), 2.65, 1e-6);
  EXPECT_NEAR(start.y(), g.idx2y(g.y2idx(3.0)), 1e-6);
  const double leg = std::hypot(start.x() - robot.x(), start.y() - robot.y());
  const ReachableCells reach = reachableCells(g, robot, p.footprint_radius_m);
  ASSERT_TRUE(reach.reachable(g.x2idx(1.0), g.y2idx(3.0)));
  EXPECT_NEAR(reach.distance(g.x2idx(1.0), g.y2idx(3.0)), leg + 2.65 - g.idx2x(g.x2idx(1.0)), 0.1);
  EXPECT_GT(reach.count(), 25 * 55);  // the free half of the room left of the wall
  EXPECT_FALSE(reach.reachable(g.x2idx(4.0), g.y2idx(3.0)));  // not through the wall
  std::vector<ViewCandidate> c(1);
  c[0].pose = Eigen::Vector3d(1.0, 3.0, M_PI);
  planPaths(g, robot, p, c);
  ASSERT_TRUE(c[0].reachable);
  EXPECT_NEAR(c[0].path_length_m, leg + 1.65, 0.15);  // the leg to the start cell included
  // A robot away from obstacles starts where it stands.
  EXPECT_TRUE(planningStart(g, Eigen::Vector3d(1.5, 3.0, 0.0), p.footprint_radius_m)
                  .isApprox(Eigen::Vector2d(1.5, 3.0)));
}

TEST(PlanningGrid, TheBackOffNeverCrossesAnObstacle) {
  // The robot in a closed 0.6 m pen (walls at columns 10 and 16, rows 10 and 16): no cell inside
  // is 4 cells from the walls, and the escape does not pass through them.
  mrpt::maps::COccupancyGridMap2D g;
  g.setSize(0.0f, 3.0f, 0.0f, 3.0f, 0.1f, 1.0f);
  for (int k = 10; k <= 16; ++k) {
    g.setCell(10, k, 0.0f), g.setCell(16, k, 0.0f);
    g.setCell(k, 10, 0.0f), g.setCell(k, 16, 0.0f);
  }
  const TExplorationParams p;
  const Eigen::Vector3d robot(1.35, 1.35, 0.0);
  EXPECT_TRUE(planningStart(g, robot, p.footprint_radius_m).isApprox(robot.head<2>()));
  const ReachableCells reach = reachableCells(g, robot, p.footprint_radius_m);
  EXPECT_EQ(reach.count(), 1);  // its own cell only
}

TEST(PlanningGrid, TheRouteToAGoalBehindAWallGoesThroughTheGapInSight) {
  // The wall of ReachableCellsAgreeWithPlannerSimple2D: across x = 3 except y in [4.5, 5.5].
  mrpt::maps::COccupancyGridMap2D g;
  g.setSize(0.0f, 6.0f, 0.0f, 6.0f, 0.1f, 1.0f);
  for (int iy = 0; iy < 60; ++iy)
    if (iy < 45 || iy > 55) g.setCell(30, iy, 0.0f);
  const TExplorationParams p;
  const Eigen::Vector3d robot(1.0, 1.0, 0.0);
  const ReachableCells reach = reachableCells(g, robot, p.footprint_radius_m);
  const Eigen::Vector2d goal(4.0, 1.0);  // behind the wall, 3 m from the robot in a straight line
  const std::vector<Eigen::Vector2d> route = routeTo(g, reach, robot.head<2>(), goal);
  ASSERT_FALSE(route.empty());
  // The corners hug the gap (the path bends there and nowhere else): within 0.6 m of its centre.
  for (const Eigen::Vector2d& c : route)
    EXPECT_LT((c - Eigen::Vector2d(3.05, 5.0)).norm(), 0.6) << c.transpose();
  // No leg (robot, corners, goal) crosses the wall: they pass the gap.
  std::vector<Eigen::Vector2d> legs{robot.head<2>()};
  legs.insert(legs.end(), route.begin(), route.end());
  legs.push_back(goal);
  double length = 0;
  for (std::size_t k = 1; k < legs.size(); ++k) {
    const Eigen::Vector2d a = legs[k - 1], b = legs[k];
    length += (b - a).norm();
    for (double f = 0; f <= 1.0; f += 0.01) {
      const Eigen::Vector2d q = a + f * (b - a);
      EXPECT_GT(g.getCell(g.x2idx(q.x()), g.y2idx(q.y())), 0.5f)
          << "leg " << k << " at " << q.transpose();
    }
  }
  // About the shortest way around: the gap narrowed by the growth is y in [4.8, 5.2].
  const double shortest = std::hypot(2.0, 3.8 - 1.0 + 0.0) + std::hypot(1.0, 3.8);
  EXPECT_GT(length, shortest - 0.3);
  EXPECT_LT(length, 1.15 * shortest + 0.5);
  // A goal in sight needs no corner; a goal far from everything reachable gets no route.
  EXPECT_TRUE(routeTo(g, reach, robot.head<2>(), Eigen::Vector2d(2.0, 4.0)).empty());
  EXPECT_TRUE(routeTo(g, reach, robot.head<2>(), Eigen::Vector2d(3.05, 2.0), 0.1).empty());
}

// A 10 x 3 m hall whose far half lies beyond the sensor's 4 m: the robot has turned in place at
// one end, so views of what it knows are near and cheap, and the unknown far half can only be
// seen from its edge, ~3.5 m away. The global planner schedules the edge early (the greedy
// one-step ranking of earlier versions kept choosing near views).
TEST(TourIgPlanner, AHallWhoseFarHalfIsUnknownGetsAGoalThereAlthoughNearViewsExist) {
  const Eigen::Vector3d lo(-5.0, -1.5, 0.0), hi(5.0, 1.5, 2.5);
  TExplorationParams p = roomParams();
  p.workspace_min_x_m = -5.5, p.workspace_max_x_m = 5.5;
  p.workspace_min_y_m = -2.0, p.workspace_max_y_m = 2.0;
  p.random_candidates = 24;
  auto octree = std::make_unique<OccupancyOctree>(p);
  const Eigen::Vector3d robot(-4.0, 0.0, 0.0);
  for (int k = 0; k < 16; ++k) {
    const Eigen::Isometry3d T =
        cameraPoseOf(Eigen::Vector3d(robot.x(), robot.y(), k * M_PI / 8), mount());
    octree->insertDepthFrame(roomDepth(T, false, false, lo, hi), kK, T);
  }
  maps::SurfelStore store;
  const std::vector<segmentation::SegmentStats> segments;
  PlannerInputs in = inputsFor(*octree, robot);
  in.store = &store;
  in.segments = &segments;
  TourIgPlanner planner(p);
  const Plan plan = planner.plan(in);
  expectSoundGoals(plan, p);
  ASSERT_FALSE(plan.ranked.empty());
  const auto near_views = std::count_if(
      plan.ranked.begin(), plan.ranked.end(),
      [&](const ViewCandidate& c) { return (c.pose.head<2>() - robot.head<2>()).norm() < 1.5; });
  EXPECT_GT(near_views, 0) << "no near view to prefer: the test shows nothing";
  for (std::size_t k = 0; k < plan.tour_clusters; ++k)
    std::printf("tour %zu: (%.2f, %.2f, %.0f deg) gain %.3f, dH %.0f nats, travel %.1f s\n", k,
                plan.ranked[k].pose.x(), plan.ranked[k].pose.y(),
                plan.ranked[k].pose.z() * 180 / M_PI, plan.ranked[k].gain,
                plan.ranked[k].entropy_reduction, plan.ranked[k].travel_time_s);
  // The best view of the plan is at the edge of the known half facing the unknown one, and the
  // tour goes there within its first three stops (near crumbs on the way may come first).
  const auto best = std::max_element(
      plan.ranked.begin(), plan.ranked.end(),
      [](const ViewCandidate& a, const ViewCandidate& b) { return a.gain < b.gain; });
  EXPECT_GT(best->pose.x(), robot.x() + 2.5) << best->pose.transpose();
  EXPECT_GT(std::cos(best->pose.z()), 0.5);
  bool far_early = false;
  for (std::size_t k = 0; k < std::min<std::size_t>(3, plan.tour_clusters); ++k)
    far_early = far_early || (plan.ranked[k].pose.x() > robot.x() + 2.5 &&
                              std::cos(plan.ranked[k].pose.z()) > 0.5);
  EXPECT_TRUE(far_early) << "the unknown half is not among the tour's first three stops";
}

// A doorway's frontier view sees the space behind it through the door only; the views from
// frontier_behind_m past the door (in the unknown) are what going through would gain, and they
// raise the door's weight in the tour. The guard: a way that crosses a wall is not a way through.
TEST(TourIgPlanner, ADoorwaysFrontierViewWeighsWhatLiesPastItWhereverTheRobotHasBeen) {
  TExplorationParams p = roomParams();
  p.workspace_max_x_m = 6.5;  // room for the space behind the +x door
  p.random_candidates = 6;
  const auto octree = roomOctree(p, /*door_px=*/true, /*door_mx=*/false);
  // The room's walls were seen at every height; the door (|y| < 0.7, z < 2) is a gap in them.
  EXPECT_TRUE(octree->occupiedAlong({0.0, 1.5}, {3.0, 1.5}, p.band_min_z_m, 1.8));
  EXPECT_FALSE(octree->occupiedAlong({0.0, 0.0}, {3.0, 0.0}, p.band_min_z_m, 1.8));
  EXPECT_FALSE(octree->occupiedAlong({0.0, 0.0}, {1.0, 0.5}, p.band_min_z_m, 1.8));

  // The room's walls as surfels (5 cm apart, facing in), the door a gap: the predictions see
  // the walls and, through the door, the unknown.
  maps::SurfelStore store;
  for (int side = 0; side < 4; ++side)
    for (int i = 0; i < 80; ++i)
      for (int k = 0; k < 50; ++k) {
        const float u = -2.0f + 0.05f * float(i) + 0.025f, z = 0.05f * float(k) + 0.025f;
        const float sign = side % 2 ? -1.0f : 1.0f;  // walls at x = +-2 (side 0, 1), y = +-2
        maps::Surfel sf;
        sf.position = side < 2 ? Vec3f(2.0f * sign, u, z) : Vec3f(u, 2.0f * sign, z);
        sf.normal = side < 2 ? Vec3f(-sign, 0, 0) : Vec3f(0, -sign, 0);
        sf.basis = Vec3f(0, 0, 1);
        if (side == 0 && std::abs(u) < kDoorHalfWidth && z < kDoorHeight) continue;
        sf.radius = 0.04f;
        sf.confidence = 10.0f;
        sf.stable = true;
        store.append(sf);
      }
  store.rebuildIndex();
  const std::vector<segmentation::SegmentStats> segments;
  PlannerInputs in = inputsFor(*octree, Eigen::Vector3d::Zero());
  in.store = &store;
  in.segments = &segments;
  const auto door_of = [](const Plan& plan) -> std::pair<const ViewCandidate*, double> {
    for (std::size_t k = 0; k < plan.ranked.size(); ++k)
      if (plan.ranked[k].source == ViewCandidate::Source::Frontier && plan.ranked[k].pose.x() > 1.0)
        return {&plan.ranked[k], k < plan.tour_weights.size() ? plan.tour_weights[k] : -1.0};
    return {nullptr, -1.0};
  };
  const Plan with = TourIgPlanner(p).plan(in);
  const auto [door, weight] = door_of(with);
  ASSERT_NE(door, nullptr);
  EXPECT_GT(door->target_xy.x(), 1.5);  // the frontier: the free cells at the door (x = 2)
  EXPECT_LT(std::abs(door->target_xy.y()), kDoorHalfWidth);
  // The door view sees the unknown through the door in one cone; the three views past it
  // (~180 deg) see three cones of it.
  EXPECT_GT(door->entropy_reduction, 0.0);
  EXPECT_GT(door->entropy_behind, 1.5 * door->entropy_reduction);
  ASSERT_GT(weight, 0.0) << "the door's view heads a cluster of the tour";
  EXPECT_EQ(with.tour_weights.size(), with.tour_clusters);

  p.frontier_behind_m = 0.0;
  const Plan without = TourIgPlanner(p).plan(in);
  const auto [door0, weight0] = door_of(without);
  ASSERT_NE(door0, nullptr);
  EXPECT_EQ(door0->entropy_behind, 0.0);
  ASSERT_GT(weight0, 0.0);
  EXPECT_GT(weight, weight0 * 1.2);

  // Views taken near the door leave its weight alone (a frontier borders unknown space however
  // often the robot stood near it); with tour_revisit_frontiers the discount applies as to the
  // other views (tour_revisit_discount per view taken within tour_revisit_radius_m).
  p.frontier_behind_m = 1.5;
  const auto after_two_views = [&](bool discount_frontiers) {
    TExplorationParams q = p;
    q.tour_revisit_frontiers = discount_frontiers;
    TourIgPlanner visited(q);
    visited.goalOutcome({0.8, 0.6, 0.0}, true);
    visited.goalOutcome({0.8, -0.6, 0.0}, true);
    return door_of(visited.plan(in)).second;
  };
  EXPECT_DOUBLE_EQ(after_two_views(false), weight);
  EXPECT_NEAR(after_two_views(true), weight * p.tour_revisit_discount * p.tour_revisit_discount,
              1e-9);

  // The room is known around its centre, the space past the door is not (knownFraction).
  EXPECT_GT(knownFraction(with.grid, {0.0, 0.0}, 1.5), 0.7);
  EXPECT_LT(knownFraction(with.grid, {4.0, 0.0}, 1.0), 0.1);
  EXPECT_EQ(knownFraction(with.grid, {20.0, 0.0}, 1.0), 0.0);  // outside the grid
}

// A hallway, a wall with a 1 m doorway, and beyond it the cone a camera in the doorway saw: its
// apex, right behind the door, is narrower than the footprint plus its growth. With the unknown
// grown (PlannerSimple2D's model) the room is unreachable; with the clearance kept from occupied
// cells only (unknownDoesNotGrow) paths enter it, over known free cells, and PlannerSimple2D
// agrees; the jambs still keep the robot's clearance, and unknown space is never entered.
TEST(PlanningGrid, TheConeSeenThroughADoorwayIsReachableWhenUnknownDoesNotGrow) {
  mrpt::maps::COccupancyGridMap2D grid;
  grid.setSize(0.0f, 6.0f, 0.0f, 6.0f, 0.1f, 0.5f);
  for (int iy = 0; iy < 60; ++iy)
    for (int ix = 0; ix < 60; ++ix) {
      const double x = grid.idx2x(ix), y = grid.idx2y(iy);
      if (y < 1.5)
        grid.setCell(ix, iy, 1.0f);  // the hallway
      else if (y < 1.7)
        grid.setCell(ix, iy, std::abs(x - 3.0) < 0.5 ? 1.0f : 0.0f);  // wall, door
      else if (std::abs(x - 3.0) < 0.15 + 0.55 * (y - 1.7))
        grid.setCell(ix, iy, 1.0f);  // cone
    }
  const Eigen::Vector3d robot(3.0, 1.2, M_PI / 2);
  const Eigen::Vector2d inside(3.0, 4.0);
  mrpt::maps::COccupancyGridMap2D grown = grid;
  EXPECT_FALSE(reachableCells(grown, robot, 0.25)
                   .reachable(grown.x2idx(inside.x()), grown.y2idx(inside.y())));
  unknownDoesNotGrow(grid, 0.25);
  const ReachableCells reach = reachableCells(grid, robot, 0.25);
  EXPECT_TRUE(reach.reachable(grid.x2idx(inside.x()), grid.y2idx(inside.y())));
  // Paths run over known free cells, and over unknown ones only where a strip of unknown no
  // wider than the growth lies between known free cells (here beside the cone's apex).
  int reachable = 0, reachable_not_free = 0, unknown_left_free = 0;
  for (int iy = 0; iy < 60; ++iy)
    for (int ix = 0; ix < 60; ++ix) {
      reachable += reach.reachable(ix, iy);
      unknown_left_free += grid.getCell(ix, iy) > 0.6f && grown.getCell(ix, iy) <= 0.6f;
      if (!reach.reachable(ix, iy) || grid.getCell(ix, iy) > 0.6f) continue;
      ++reachable_not_free;
      int free_near = 0;
      for (int y = iy - 3; y <= iy + 3; ++y)
        for (int x = ix - 3; x <= ix + 3; ++x)
          free_near += x >= 0 && y >= 0 && x < 60 && y < 60 && grid.getCell(x, y) > 0.6f;
      EXPECT_GT(free_near, 0) << ix << " " << iy;
    }
  EXPECT_LT(reachable_not_free, reachable / 50);
  EXPECT_EQ(unknown_left_free, 0) << "no unknown cell became known free";
  // The jambs (|x - 3| >= 0.5 at y 1.5-1.7) keep their growth: the doorway's passable cells are
  // those >= 0.3 m from both.
  for (int ix = 0; ix < 60; ++ix) {
    const double x = grid.idx2x(ix);
    if (reach.reachable(ix, grid.y2idx(1.6))) EXPECT_LT(std::abs(x - 3.0), 0.5 - 0.25);
  }
  TExplorationParams p;
  std::vector<ViewCandidate> c(1);
  c[0].pose = Eigen::Vector3d(inside.x(), inside.y(), M_PI / 2);
  planPaths(grid, robot, p, c);
  EXPECT_TRUE(c[0].reachable) << "PlannerSimple2D agrees";
  EXPECT_NEAR(c[0].path_length_m, 2.8, 0.3);
}

// ---- frontier ----

// A U of known free corridors (1 m wide) around an unknown block: its frontier is one connected
// cluster whose centroid lies in the block, ~2 m from every reachable cell, so it had no view.
// Split into pieces of at most frontier_max_radius_m, each piece gets one next to it.
TEST(FrontierPlanner, ALargeFrontierIsSplitIntoPiecesThatEachHaveAView) {
  mrpt::maps::COccupancyGridMap2D grid;
  grid.setSize(0.0f, 10.0f, 0.0f, 10.0f, 0.1f, 0.5f);
  const auto free_box = [&](double x0, double x1, double y0, double y1) {
    for (double y = y0 + 0.05; y < y1; y += 0.1)
      for (double x = x0 + 0.05; x < x1; x += 0.1) grid.setCell(grid.x2idx(x), grid.y2idx(y), 1.0f);
  };
  free_box(1, 2, 1, 9);
  free_box(1, 9, 1, 2);
  free_box(8, 9, 1, 9);
  const Eigen::Vector3d robot(1.5, 1.5, 0.0);
  const ReachableCells reach = reachableCells(grid, robot, 0.25);
  TExplorationParams p;
  p.frontier_max_radius_m = 0.0;
  const std::vector<FrontierCluster> whole = findFrontiers(grid, p.frontier_min_cells);
  ASSERT_EQ(whole.size(), 1u);
  EXPECT_NEAR(whole[0].centroid.x(), 5.0, 0.3);
  EXPECT_GT(whole[0].centroid.y(), 2.5) << "the centroid lies in the unknown block";
  const std::vector<FrontierView> unsplit = frontierViews(grid, reach, robot, p);
  ASSERT_EQ(unsplit.size(), 1u);
  EXPECT_FALSE(unsplit[0].found);

  p.frontier_max_radius_m = 1.5;
  const std::vector<FrontierCluster> pieces =
      findFrontiers(grid, p.frontier_min_cells, p.frontier_max_radius_m);
  std::size_t cells = 0;
  for (const FrontierCluster& f : pieces) {
    cells += f.cells.size();
    for (const Eigen::Vector2d& c : f.cells) EXPECT_LE((c - f.centroid).norm(), 1.5 + 1e-9);
  }
  EXPECT_GE(pieces.size(), 8u);  // ~28 m of frontier in pieces at most 3 m long
  EXPECT_LE(cells, whole[0].cells.size());
  EXPECT_GE(cells, whole[0].cells.size() - pieces.size() * p.frontier_min_cells);
  int found = 0;
  for (const FrontierView& v : frontierViews(grid, reach, robot, p)) {
    if (!v.found) continue;
    ++found;
    EXPECT_TRUE(reach.reachable(grid.x2idx(v.view.pose.x()), grid.y2idx(v.view.pose.y())));
    EXPECT_LE((v.view.pose.head<2>() - v.view.target_xy).norm(), p.frontier_goal_radius_m + 0.1);
  }
  EXPECT_GE(found, int(pieces.size()) / 2);
}

TEST(FrontierPlanner, GoalIsNextToTheOpeningIntoUnknownSpaceAndReachable) {
  TExplorationParams p = roomParams();
  p.planner = "frontier";
  const auto octree = roomOctree(p, /*door_px=*/true, /*door_mx=*/false);
  auto planner = makePlanner(p);
  const auto t0 = std::chrono::steady_clock::now();
  const Plan plan = planner->plan(inputsFor(*octree, Eigen::Vector3d::Zero()));
  std::printf("frontier plan: %.1f ms, %zu offered, %zu unreachable\n", msSince(t0),
              plan.ranked.size(), plan.unreachable.size());
  ASSERT_FALSE(plan.ranked.empty());
  expectSoundGoals(plan, p);
  const ViewCandidate& g = plan.ranked.front();
  EXPECT_EQ(g.source, ViewCandidate::Source::Frontier);
  // Within the goal radius of the door's frontier (the free cells along x = 1.95, |y| < 0.7), on
  // the room's side, facing out through it.
  EXPECT_LE((g.pose.head<2>() - Eigen::Vector2d(1.95, 0.0)).norm(), p.frontier_goal_radius_m + 0.1);
  EXPECT_LT(g.pose.x(), kMax.x());
  EXPECT_LT(std::abs(g.pose.y()), kDoorHalfWidth);
  EXPECT_LT(std::abs(g.pose.z()), 0.5);
  EXPECT_GE(g.path_length_m, g.pose.head<2>().norm() - 0.1);
  for (std::size_t k = 1; k < plan.ranked.size(); ++k)
    EXPECT_GE(plan.ranked[k].path_length_m, plan.ranked[k - 1].path_length_m);
  // The frontiers found are the door's only: the room's walls close everything else.
  for (const FrontierCluster& f : findFrontiers(plan.grid, p.frontier_min_cells))
    EXPECT_GT(f.centroid.x(), 1.5) << f.centroid.transpose();
}

// ig with frontier_candidates: the door's frontier view joins the random views and is scored by
// IG like them (the empty surfel store predicts no surface, so no ranking between views is
// asserted here: every predicted ray runs to max range).
TEST(IgPlanner, FrontierCandidatesJoinTheViewsAndAreScored) {
  TExplorationParams p = roomParams();
  p.random_candidates = 8;
  const auto octree = roomOctree(p, /*door_px=*/true, /*door_mx=*/false);
  maps::SurfelStore store;
  const std::vector<segmentation::SegmentStats> segments;
  PlannerInputs in = inputsFor(*octree, Eigen::Vector3d::Zero());
  in.store = &store;
  in.segments = &segments;
  const Plan without = ViewPlanner(p).plan(in);
  p.frontier_candidates = true;
  const Plan with = ViewPlanner(p).plan(in);
  EXPECT_EQ(with.ranked.size(), without.ranked.size() + 1);  // one frontier: the door
  const ViewCandidate* door = nullptr;
  for (const ViewCandidate& c : with.ranked)
    if (c.source == ViewCandidate::Source::Frontier) door = &c;
  ASSERT_NE(door, nullptr);
  EXPECT_GT(door->pose.x(), 1.0);  // at the door (x = 2), facing out through it
  EXPECT_LT(std::abs(door->pose.z()), 0.5);
  EXPECT_GT(door->entropy_reduction, 0.0);  // the unknown beyond the door
  EXPECT_GT(door->gain, 0.0);
  EXPECT_TRUE(door->reachable);
}

// "ig": the global planner offers its clusters first, in tour order, each at least the cluster
// radius from the others; the door's frontier view is among the views although no key says so;
// the same inputs give the same plan; the goal being driven to is scored alongside (same IG).
TEST(TourIgPlanner, OffersClustersInTourOrderWithTheFrontierViewsAndIsDeterministic) {
  TExplorationParams p = roomParams();
  p.random_candidates = 10;
  ASSERT_FALSE(p.frontier_candidates);
  const auto octree = roomOctree(p, /*door_px=*/true, /*door_mx=*/false);
  maps::SurfelStore store;
  const std::vector<segmentation::SegmentStats> segments;
  PlannerInputs in = inputsFor(*octree, Eigen::Vector3d::Zero());
  in.store = &store;
  in.segments = &segments;
  in.current_goal = Eigen::Vector3d(-1.0, 0.0, M_PI);
  TourIgPlanner planner(p);
  EXPECT_EQ(planner.name(), "ig");
  EXPECT_TRUE(planner.scoresInformation());
  const Plan plan = planner.plan(in);
  expectSoundGoals(plan, p);
  ASSERT_GE(plan.tour_clusters, 1u);
  ASSERT_LE(plan.tour_clusters, std::size_t(p.tour_max_clusters));
  for (std::size_t i = 0; i < plan.tour_clusters; ++i)
    for (std::size_t j = i + 1; j < plan.tour_clusters; ++j)
      EXPECT_GT((plan.ranked[i].pose.head<2>() - plan.ranked[j].pose.head<2>()).norm(),
                p.tour_cluster_radius_m);
  const bool door = std::any_of(plan.ranked.begin(), plan.ranked.end(), [](const ViewCandidate& c) {
    return c.source == ViewCandidate::Source::Frontier && c.pose.x() > 1.0;
  });
  EXPECT_TRUE(door) << "the frontier view at the door is a candidate";
  ASSERT_TRUE(plan.current_goal.has_value());
  EXPECT_TRUE(plan.current_goal->reachable);
  EXPECT_GE(plan.current_goal->gain, 0.0);
  EXPECT_LE(plan.current_goal->gain, p.w_entropy + p.w_ic + 1e-12);
  EXPECT_NEAR(plan.current_goal->rate,
              plan.current_goal->gain / (plan.current_goal->travel_time_s + p.min_travel_time_s),
              1e-12);

  TourIgPlanner again(p);
  const Plan plan2 = again.plan(in);
  ASSERT_EQ(plan2.ranked.size(), plan.ranked.size());
  for (std::size_t i = 0; i < plan.ranked.size(); ++i)
    EXPECT_TRUE(plan2.ranked[i].pose.isApprox(plan.ranked[i].pose)) << i;
}

TEST(FrontierPlanner, ClosedKnownRoomHasNoFrontierAndAnEmptyPlan) {
  TExplorationParams p = roomParams();
  const auto octree = roomOctree(p, false, false);
  FrontierPlanner planner(p);
  const Plan plan = planner.plan(inputsFor(*octree, Eigen::Vector3d::Zero()));
  EXPECT_TRUE(plan.ranked.empty());
  EXPECT_TRUE(plan.blacklisted.empty());
  EXPECT_TRUE(findFrontiers(plan.grid, p.frontier_min_cells).empty());
}

TEST(FrontierPlanner, BlacklistedGoalMakesTheNextPlanChooseTheOtherFrontier) {
  TExplorationParams p = roomParams();
  const auto octree = roomOctree(p, true, true);  // doors at both ends
  FrontierPlanner planner(p);
  const PlannerInputs in = inputsFor(*octree, Eigen::Vector3d(0.6, 0.0, 0.0));  // nearer +x
  const Plan first = planner.plan(in);
  ASSERT_FALSE(first.ranked.empty());
  EXPECT_GT(first.ranked.front().pose.x(), 1.0);
  planner.goalOutcome(first.ranked.front().pose, true);  // reached: still blacklisted
  const Plan second = planner.plan(in);
  ASSERT_FALSE(second.ranked.empty());
  EXPECT_LT(second.ranked.front().pose.x(), -1.0);
  ASSERT_EQ(second.blacklisted.size(), 1u);
  EXPECT_GT(second.blacklisted.front().pose.x(), 1.0);
  planner.goalOutcome(second.ranked.front().pose, false);
  EXPECT_TRUE(planner.plan(in).ranked.empty());  // both frontiers visited: done
}

// ---- random ----

TEST(RandomPlanner, SameSeedSameGoalsInReachableKnownFreeSpace) {
  TExplorationParams p = roomParams();
  p.seed = 7;
  const auto octree = roomOctree(p, false, false);
  const PlannerInputs in = inputsFor(*octree, Eigen::Vector3d::Zero());
  RandomPlanner a(p), b(p);
  p.seed = 8;
  RandomPlanner other(p);
  int moved = 0;
  for (int k = 0; k < 4; ++k) {
    const Plan pa = a.plan(in), pb = b.plan(in), po = other.plan(in);
    ASSERT_EQ(pa.ranked.size(), 1u);
    ASSERT_EQ(pb.ranked.size(), 1u);
    ASSERT_EQ(po.ranked.size(), 1u);
    EXPECT_EQ(pa.ranked[0].pose, pb.ranked[0].pose);
    moved += pa.ranked[0].pose != po.ranked[0].pose;
    expectSoundGoals(pa, p);
    const Eigen::Vector3d& g = pa.ranked[0].pose;
    EXPECT_EQ(pa.ranked[0].source, ViewCandidate::Source::Random);
    EXPECT_GT(g.x(), kMin.x() + p.footprint_radius_m);
    EXPECT_LT(g.x(), kMax.x() - p.footprint_radius_m);
    EXPECT_GT(g.y(), kMin.y() + p.footprint_radius_m);
    EXPECT_LT(g.y(), kMax.y() - p.footprint_radius_m);
  }
  EXPECT_GT(moved, 0);
  // A failed goal is not drawn again.
  const Eigen::Vector3d failed = a.plan(in).ranked[0].pose;
  a.goalOutcome(failed, false);
  for (int k = 0; k < 5; ++k)
    EXPECT_GT((a.plan(in).ranked[0].pose - failed).head<2>().norm(), p.blacklist_radius_m);
}

// ---- lawnmower ----

TEST(LawnmowerPlanner, VisitsWaypointsInSnakeOrderRetriesAFailedOneAndEnds) {
  TExplorationParams p = roomParams();
  p.lawnmower_spacing_m = 1.5, p.lawnmower_step_m = 1.5, p.lawnmower_axis = "x";
  const auto octree = roomOctree(p, false, false);
  LawnmowerPlanner planner(p);
  // 5 m box, 1.5 m: 3 lanes at y = -1.5, 0, 1.5 and 3 waypoints at x = -1.5, 0, 1.5 on each.
  const std::vector<Eigen::Vector2d> snake = {{-1.5, -1.5}, {0, -1.5}, {1.5, -1.5},
                                              {1.5, 0},     {0, 0},    {-1.5, 0},
                                              {-1.5, 1.5},  {0, 1.5},  {1.5, 1.5}};
  ASSERT_EQ(planner.waypoints().size(), snake.size());
  for (std::size_t k = 0; k < snake.size(); ++k) {
    EXPECT_NEAR((planner.waypoints()[k].head<2>() - snake[k]).norm(), 0.0, 1e-9) << k;
    EXPECT_NEAR(std::abs(planner.waypoints()[k].z()), (k / 3) % 2 ? M_PI : 0.0, 1e-9);
  }
  Eigen::Vector3d robot = Eigen::Vector3d::Zero();
  std::vector<Eigen::Vector2d> goals;
  for (int k = 0; k < 20; ++k) {
    const Plan plan = planner.plan(inputsFor(*octree, robot));
    if (plan.ranked.empty()) break;
    ASSERT_EQ(plan.ranked.size(), 1u);
    expectSoundGoals(plan, p);
    const ViewCandidate& g = plan.ranked[0];
    EXPECT_EQ(g.source, ViewCandidate::Source::Sweep);
    goals.push_back(g.pose.head<2>());
    const bool fail_first = goals.size() == 1;  // the first waypoint fails once
    planner.goalOutcome(g.pose, !fail_first);
    if (!fail_first) robot = g.pose;
  }
  // Waypoints 1..8 in snake order, then waypoint 0 again on the second pass; each within a cell
  // of its waypoint (the room's free space holds all of them with the footprint).
  ASSERT_EQ(goals.size(), snake.size() + 1);
  for (std::size_t k = 0; k < goals.size(); ++k) {
    const Eigen::Vector2d& want = k == 0 || k == snake.size() ? snake[0] : snake[k];
    EXPECT_LE((goals[k] - want).norm(), 0.15) << k << ": " << goals[k].transpose();
  }
  for (const auto s : planner.states()) EXPECT_EQ(s, LawnmowerPlanner::State::Visited);
  EXPECT_TRUE(planner.plan(inputsFor(*octree, robot)).ranked.empty());
}

TEST(LawnmowerPlanner, AxisYLanesRunAlongY) {
  TExplorationParams p = roomParams();
  p.lawnmower_axis = "y";
  p.lawnmower_spacing_m = 2.5, p.lawnmower_step_m = 2.5;  // 2 lanes at x = -1.25, 1.25
  const LawnmowerPlanner planner(p);
  const std::vector<Eigen::Vector3d> want = {{-1.25, -1.25, M_PI / 2},
                                             {-1.25, 1.25, M_PI / 2},
                                             {1.25, 1.25, -M_PI / 2},
                                             {1.25, -1.25, -M_PI / 2}};
  ASSERT_EQ(planner.waypoints().size(), want.size());
  for (std::size_t k = 0; k < want.size(); ++k)
    EXPECT_NEAR((planner.waypoints()[k] - want[k]).norm(), 0.0, 1e-9) << k;
}

TEST(LawnmowerPlanner, WaypointsNeverReachableAreAbandonedAndTheSweepEnds) {
  TExplorationParams p = roomParams();
  p.workspace_max_x_m = 6.5;  // a 9 m box: the lanes' last waypoints lie beyond the room's wall
  const auto octree = roomOctree(p, false, false);
  LawnmowerPlanner planner(p);
  Eigen::Vector3d robot = Eigen::Vector3d::Zero();
  int offered = 0;
  for (int k = 0; k < 60; ++k) {
    const Plan plan = planner.plan(inputsFor(*octree, robot));
    if (plan.ranked.empty()) break;
    EXPECT_LT(plan.ranked[0].pose.x(), kMax.x());
    planner.goalOutcome(plan.ranked[0].pose, true);
    robot = plan.ranked[0].pose;
    ++offered;
  }
  int visited = 0, abandoned = 0;
  for (const auto s : planner.states()) {
    visited += s == LawnmowerPlanner::State::Visited;
    abandoned += s == LawnmowerPlanner::State::Abandoned;
  }
  EXPECT_EQ(visited, offered);
  EXPECT_EQ(visited + abandoned, int(planner.states().size()));
  EXPECT_GT(abandoned, 0);
  EXPECT_TRUE(planner.plan(inputsFor(*octree, robot)).ranked.empty());
}

// ---- ig_greedy through the interface ----

TEST(IgPlanner, SameRankingAsViewPlannerAndFailedGoalsAreBlacklisted) {
  TExplorationParams p = roomParams();
  p.planner = "ig_greedy";
  p.pixel_stride = 4;
  p.random_candidates = 8;  // each IG candidate costs a render and a ray cast
  const auto octree = roomOctree(p, false, false);
  maps::SurfelStore store;
  segmentation::SegmentStats object;
  object.id = 3;
  object.centroid = Eigen::Vector3d(1.0, 0.0, 0.4);
  object.upright_extents = Eigen::Vector3d(0.4, 0.3, 0.8);
  const std::vector<segmentation::SegmentStats> segments = {object};
  PlannerInputs in = inputsFor(*octree, Eigen::Vector3d::Zero());
  in.store = &store;
  in.segments = &segments;
  auto ig = makePlanner(p);
  const Plan direct = ViewPlanner(p).plan(in);
  const Plan through = ig->plan(in);
  ASSERT_FALSE(direct.ranked.empty());
  ASSERT_EQ(through.ranked.size(), direct.ranked.size());
  double best_h = 0.0;
  for (std::size_t k = 0; k < direct.ranked.size(); ++k) {
    EXPECT_EQ(through.ranked[k].pose, direct.ranked[k].pose);
    EXPECT_EQ(through.ranked[k].rate, direct.ranked[k].rate);
    best_h = std::max(best_h, direct.ranked[k].entropy_reduction);
  }
  EXPECT_TRUE(through.blacklisted.empty());
  EXPECT_EQ(through.best_entropy_reduction, best_h);
  EXPECT_GT(best_h, 0.0);
  EXPECT_EQ(through.best_information, 0.0);  // no surfels

  const Eigen::Vector3d failed = through.ranked.front().pose;
  ig->goalOutcome(failed, false);
  const Plan after = ig->plan(in);
  ASSERT_FALSE(after.blacklisted.empty());
  EXPECT_EQ(after.ranked.size() + after.blacklisted.size(), through.ranked.size());
  for (const ViewCandidate& c : after.ranked)
    EXPECT_GT((c.pose - failed).head<2>().norm(), p.blacklist_radius_m);
  for (std::size_t k = 1; k < after.ranked.size(); ++k)
    EXPECT_GE(after.ranked[k - 1].rate, after.ranked[k].rate);

  // A reached goal is a taken view: the same place facing the same way (within the params) is
  // not offered again, the same place facing elsewhere still is.
  const Eigen::Vector3d taken = after.ranked.front().pose;
  ig->goalOutcome(taken, true);
  auto* igp = dynamic_cast<IgPlanner*>(ig.get());
  ASSERT_NE(igp, nullptr);
  const double r = p.taken_view_radius_m, a = p.taken_view_heading_deg * M_PI / 180.0;
  EXPECT_TRUE(igp->isTakenView(taken + Eigen::Vector3d(0.9 * r, 0.0, 0.9 * a)));
  EXPECT_FALSE(igp->isTakenView(taken + Eigen::Vector3d(1.1 * r, 0.0, 0.0)));
  EXPECT_FALSE(igp->isTakenView(taken + Eigen::Vector3d(0.0, 0.0, 1.1 * a)));
  const Plan later = ig->plan(in);
  for (const ViewCandidate& c : later.ranked) EXPECT_FALSE(igp->isTakenView(c.pose));
  EXPECT_EQ(later.ranked.size() + later.blacklisted.size(), through.ranked.size());

  in.octree = nullptr;
  EXPECT_THROW(ig->plan(in), InputError);
  p.planner = "frontier";
  EXPECT_THROW(makePlanner(p)->plan(in), InputError);
}

}  // namespace
}  // namespace rasm::exploration
