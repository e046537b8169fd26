// The closed loop of issue 18 (sections V, VI) end to end: the simulated robot in the `office`,
// driven by MRPT's reactive navigator to the views the information-gain planner picks, mapped,
// segmented and classified as it goes, through the same MappingRun `rasm run` uses.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "rasm/core/Error.h"
#include "rasm/run/MappingRun.h"
#include "rasm/run/RunScene.h"
#include "run/RunTestFiles.h"

namespace fs = std::filesystem;
using namespace rasm;
using namespace rasm::pipeline;
using namespace rasm::autonomy;
using namespace rasm::run;
using namespace rasm::run::testing;

namespace {

/// The embedded default (the exploring office) at a quarter of VGA and 10 Hz, without the
/// outputs the loop does not need: a closed-loop run of tens of simulated seconds in seconds.
RunConfig smallExploringRun(const std::string& out, double budget_s) {
  RunConfig cfg = RunConfig::embeddedDefault();
  cfg.set("output", "dir", out);
  cfg.set("exploration", "enabled", "true");
  cfg.set("exploration", "time_budget_s", std::to_string(budget_s));
  cfg.set("exploration", "wall_budget_s", "0");  // (the embedded default's 5-minute box: not here)
  cfg.set("exploration", "metrics_period_s", "5");
  cfg.set("sim", "rate_hz", "10");
  setQuarterVgaCamera(cfg);
  cfg.set("output", "write_3dscene", "false");
  cfg.set("output", "write_rawlog", "false");
  return cfg;
}
}  // namespace

// Deliverable 8: a short closed-loop run in `office` increases coverage monotonically and ends by
// its stopping rule (here the time budget); the robot drives and reaches goals. The map is fused
// at the simulator's ground-truth poses ([mapper] poses = groundtruth): this test is about the
// loop (octree, planner, navigator, stopping, metrics); a drifting pose moves surfaces already
// covered by more than the 2 cm of the coverage test, which the next test bounds separately.
TEST(ExplorationLoop, ShortOfficeRunGainsCoverageAndStopsByItsRule) {
  const std::string out = tempDir("explore_short");
  RunConfig cfg = smallExploringRun(out, 60.0);
  cfg.set("mapper", "poses", "groundtruth");
  MappingRun run(cfg);
  const RunSummary s = run.run();
  ASSERT_TRUE(s.explored);
  const nlohmann::json& r = s.report;
  EXPECT_EQ(r.at("stop_reason").get<std::string>(), "time_budget");
  // 60 s at 10 Hz: the budget is checked after each frame, so it ends on the frame at 60 s.
  EXPECT_NEAR(r.at("sim_time_s").get<double>(), 60.0, 0.11);
  EXPECT_GT(r.at("path_length_m").get<double>(), 1.0) << "the robot drove to its views";
  EXPECT_GE(r.at("exploration").at("goals_reached").get<int>(), 1);
  const nlohmann::json ex = readJson(out + "/exploration.json");
  const auto& metrics = ex.at("metrics");
  ASSERT_GE(metrics.size(), 10u);  // every 5 s and at the end
  double prev = 0.0;
  for (const auto& m : metrics) {
    const double c = m.at("coverage").get<double>();
    // Cleaning up (pruning unstable surfels, merging) may drop a sliver of covered surface;
    // 0.5% of the surface between two samples is the most allowed.
    EXPECT_GE(c, prev - 0.005) << "at t = " << m.at("t").get<double>();
    prev = std::max(prev, c);
  }
  const double first = metrics.front().at("coverage").get<double>();
  const double last = metrics.back().at("coverage").get<double>();
  EXPECT_GT(last, first + 0.1) << "a minute of exploring adds at least a tenth of the office";
  EXPECT_TRUE(fs::is_regular_file(out + "/exploration.png"));
  // The views map*.3Dscene and `rasm view` draw as arrows (RunScene.h): the last plan's
  // candidates with their gain, and every goal driven to.
  const std::vector<SceneView> views =
      sceneViewsFromJson(ex.at("candidate_views"), "exploration.json candidate_views");
  std::size_t goals = 0, reachable = 0;
  for (const SceneView& v : views) {
    goals += v.goal;
    reachable += !v.goal && v.reachable;
    EXPECT_NEAR(v.direction.norm(), 1.0, 1e-6);
  }
  EXPECT_EQ(goals, ex.at("goals").size());
  EXPECT_GE(reachable, 1u);
  fs::remove_all(out);
}

// The same loop on tracked poses (the mission's own scenario): the robot's turns in place and
// drives stay within the robot target of issue 14 (ATE <= 2 cm), and the frames the tracker
// rejects (the camera a few decimetres from a blank wall or desk side while the navigator turns
// there: statuses degenerate / inconsistent) are detected, not fused: at most 5% of them.
TEST(ExplorationLoop, TrackedOfficeRunStaysWithinTheRobotTarget) {
  const std::string out = tempDir("explore_tracked");
  RunConfig cfg = smallExploringRun(out, 40.0);
  // The path these bounds were set on: the plans' predictions on the whole map, unscreened. The
  // default since 2026-12-07 (thinned map, coarse screen) drives another path, on which this
  // run's world-frame max is 3.3 cm (over the 3 cm target; the tracked panel measures the
  // defaults over many paths: docs/results-worldframe.md). This test guards tracking on a fixed
  // path, not the planner.
  cfg.set("exploration", "predict_max_surfels", "0");
  cfg.set("exploration", "predict_screen_keep", "0");
  // ... and the odometry then: the wheels' heading. The simulated gyro (the default since
  // 2026-12-07) draws other noise and the robot drives another path (world-frame max 3.8 cm on
  // it, the tracked panel's median 3.6 cm: docs/results-worldframe.md "A gyro").
  // The shipped spec, its robot's heading set to the wheels'.
  std::string text = readText(RASM_SOURCE_DIR "/modules/sim/trajectories/office_robot_loop.yaml");
  const std::string pitch = "camera_pitch_deg: -10}";
  const std::size_t at = text.find(pitch);
  ASSERT_NE(at, std::string::npos) << "office_robot_loop.yaml's robot line changed:\n" << text;
  text.replace(at, pitch.size(), "camera_pitch_deg: -10, odometry_heading: wheels}");
  const std::string spec = out + "_office_robot_loop_wheels.yaml";
  std::ofstream(spec) << text;
  cfg.set("sim", "trajectory", spec);
  MappingRun run(cfg);
  const RunSummary s = run.run();
  fs::remove(spec);
  EXPECT_EQ(s.report.at("stop_reason").get<std::string>(), "time_budget");
  EXPECT_LE(double(s.lost), 0.05 * double(s.frames)) << s.lost << " of " << s.frames;
  ASSERT_TRUE(s.ate_rmse_m.has_value());
  EXPECT_LT(*s.ate_rmse_m, 0.02);
  EXPECT_GT(s.report.at("path_length_m").get<double>(), 1.0);
  // In the world frame, no alignment (the run starts at the true pose): the map's targets for a
  // ground robot, 3 cm of position and 0.15 deg of tilt at most over every frame, and the floor
  // is not reported drifted (the floor prior holds height and tilt; sensor noise on).
  const auto& wf = s.report.at("world_frame_error").at("all");
  EXPECT_LT(wf.at("position_m").at("max").get<double>(), 0.03);
  EXPECT_LT(wf.at("tilt_deg").at("max").get<double>(), 0.15);
  EXPECT_FALSE(s.report.at("floor_drift").at("drifted").get<bool>());
  fs::remove_all(out);
}

// [exploration] wall_budget_s (the embedded default's 5 minutes on a slow machine): exploring ends
// by the wall clock, long before the simulated budget, and the run still writes every output.
TEST(ExplorationLoop, WallBudgetEndsTheRunByTheClock) {
  const std::string out = tempDir("explore_wall");
  RunConfig cfg = smallExploringRun(out, 600.0);
  cfg.set("exploration", "wall_budget_s", "4");
  cfg.set("mapper", "poses", "groundtruth");
  MappingRun run(cfg);
  const RunSummary s = run.run();
  EXPECT_EQ(s.report.at("stop_reason").get<std::string>(), "wall_budget");
  EXPECT_EQ(s.report.at("status").get<std::string>(), "ok");
  EXPECT_LT(s.report.at("sim_time_s").get<double>(), 600.0);
  EXPECT_GE(s.report.at("seconds").get<double>(), 4.0) << "it ran its four seconds";
  EXPECT_TRUE(fs::is_regular_file(out + "/exploration.json"));
  EXPECT_TRUE(fs::is_regular_file(out + "/trajectory.txt"));
  fs::remove_all(out);
  // A negative budget is named.
  RunConfig bad = smallExploringRun(tempDir("explore_wall_bad"), 10.0);
  bad.set("exploration", "wall_budget_s", "-1");
  try {
    MappingRun r(bad);
    r.run();
    FAIL() << "wall_budget_s = -1 accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("wall_budget_s"), std::string::npos) << e.what();
  }
}

// Deliverable 5: the information-gain rule. With thresholds no view can fall under, the run
// ends after stop_plans consecutive plans, before its budget.
TEST(ExplorationLoop, StopsWhenTheBestViewGainsTooLittle) {
  const std::string out = tempDir("explore_threshold");
  RunConfig cfg = smallExploringRun(out, 120.0);
  cfg.set("exploration", "stop_entropy_nats", "1e12");
  cfg.set("exploration", "stop_information", "1e12");
  cfg.set("exploration", "stop_plans", "2");
  MappingRun run(cfg);
  const RunSummary s = run.run();
  EXPECT_EQ(s.report.at("stop_reason").get<std::string>(), "information_gain_below_threshold");
  EXPECT_LT(s.report.at("sim_time_s").get<double>(), 120.0);
  // Every plan was low, and the run stopped at the first plan made with the robot idle once
  // stop_plans low plans had come in a row (a plan made while driving counts, but the robot
  // first finishes its goal).
  const nlohmann::json ex = readJson(out + "/exploration.json");
  const nlohmann::json& plans = ex.at("plans");
  ASSERT_GE(plans.size(), 2u);
  for (std::size_t k = 0; k < plans.size(); ++k) {
    EXPECT_TRUE(plans[k].at("low").get<bool>()) << "plan " << k;
    const bool idle = !plans[k].at("while_driving").get<bool>();
    if (k + 1 < plans.size()) {
      EXPECT_FALSE(idle && k + 1 >= 2) << "plan " << k << " could stop";
    }
  }
  EXPECT_FALSE(plans.back().at("while_driving").get<bool>());
  fs::remove_all(out);
}

// Deliverable 3/8: the same seed gives the same run (simulated clock, planner on the mapping
// thread, seeded candidates, seeded sensor and odometry noise).
TEST(ExplorationLoop, SameSeedGivesTheSameRun) {
  std::string traj[2], goals[2];
  for (int k = 0; k < 2; ++k) {
    const std::string out = tempDir("explore_seed" + std::to_string(k));
    MappingRun run(smallExploringRun(out, 15.0));  // the spin and the first plans and goals
    run.run();
    traj[k] = readText(out + "/trajectory.txt");
    goals[k] = readJson(out + "/exploration.json").at("goals").dump();
    fs::remove_all(out);
  }
  EXPECT_FALSE(traj[0].empty());
  EXPECT_EQ(traj[0], traj[1]);
  EXPECT_EQ(goals[0], goals[1]);
}

// Deliverable 3: the planner in a thread of its own (map snapshots, a copy of the octree) while
// mapping goes on; goals are planned, driven to and reached, and the run ends by its budget.
// Not deterministic (the plan arrives after as many frames as the machine's speed gives).
TEST(ExplorationLoop, PlannerThreadPlansWhileMappingGoesOn) {
  const std::string out = tempDir("explore_thread");
  // 50 s (was 30): the global planner's first goal may lie further than the greedy one's, and on
  // a loaded machine the first plan arrives ~10 simulated s after its request; 30 s left a goal
  // still being driven to at the end (seen under ctest -j2).
  RunConfig cfg = smallExploringRun(out, 50.0);
  cfg.set("exploration", "planner_thread", "true");
  cfg.set("mapper", "poses", "groundtruth");
  MappingRun run(cfg);
  const RunSummary s = run.run();
  EXPECT_EQ(s.report.at("stop_reason").get<std::string>(), "time_budget");
  const nlohmann::json ex = readJson(out + "/exploration.json");
  ASSERT_GE(ex.at("plans").size(), 1u);
  // A plan is applied on a later frame than it was requested on (mapping went on meanwhile).
  bool later = false;
  for (const auto& p : ex.at("plans"))
    later = later || p.at("applied_t").get<double>() > p.at("t").get<double>();
  EXPECT_TRUE(later);
  EXPECT_GE(s.report.at("exploration").at("goals_reached").get<int>(), 1);
  EXPECT_GT(s.report.at("path_length_m").get<double>(), 0.5);
  fs::remove_all(out);
}

// The global planner takes the robot from room A of `two_rooms` through both 0.9 m doorways and
// the corridor into room B (x > 6.5 m) within 120 simulated seconds (true poses: this is about
// the planner). It was 90 s with the simulator's old floor noise; with the floor measured as a
// real sensor does (docs/sim.md "Depth error on a floor") the tour first finishes room A's far
// side (goals at x 1.2-3.2 m at 45-73 s) and reaches room B at 105-115 s.
TEST(ExplorationLoop, IgGoesThroughTheDoorwaysIntoTheSecondRoom) {
  const std::string out = tempDir("explore_two_rooms");
  RunConfig cfg = smallExploringRun(out, 120.0);
  cfg.set("sim", "world", "two_rooms");
  cfg.set("sim", "trajectory", "two_rooms_robot");
  cfg.set("mapper", "poses", "groundtruth");
  cfg.set("exploration", "planner", "ig");
  // 160x120: the planner sees the same octree, only sparser (the scoreboard's --planners panel).
  setRunCamera(cfg, camera160x120());
  MappingRun run(cfg);
  const RunSummary s = run.run();
  ASSERT_TRUE(s.explored);
  const nlohmann::json ex = readJson(out + "/exploration.json");
  double max_reached_x = -1e9;
  for (const auto& g : ex.at("goals"))
    if (g.at("outcome").get<std::string>() == "reached")
      max_reached_x = std::max(max_reached_x, g.at("goal")[0].get<double>());
  // Room B's interior starts at x = 6.5 (its doorway); half a metre in, past the footprint.
  EXPECT_GT(max_reached_x, 7.0) << "no goal reached in room B";
  fs::remove_all(out);
}

TEST(ExplorationLoop, NeedsARobotItCanDrive) {
  {
    RunConfig cfg = RunConfig::fromString("[source]\ntype = rawlog\npath = " RASM_MRPT_TEST_RAWLOG
                                          "\n[exploration]\nenabled = true\n",
                                          "test");
    try {
      MappingRun run(cfg);
      FAIL() << "a rawlog cannot be driven";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("[exploration] enabled"), std::string::npos) << e.what();
    }
  }
  {
    RunConfig cfg = smallExploringRun(tempDir("explore_handheld"), 10.0);
    cfg.set("sim", "trajectory", "office_handheld");
    MappingRun run(cfg);
    try {
      run.run();
      FAIL() << "a hand-held spec has no robot";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("robot spec"), std::string::npos) << e.what();
    }
    fs::remove_all(tempDir("explore_handheld"));
  }
}
