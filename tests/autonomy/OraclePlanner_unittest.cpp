// The "oracle" exploration planner (OraclePlanner.h) on the shipped two_rooms world: its greedy
// cover sees >= 95% of the coverable samples, its tour visits each chosen view once, the same
// inputs give the same plan for any thread count, the map's coverage retires views, and a short
// exploring run with it covers at least as much as the random baseline's with the same seed and
// budget.
#include "rasm/autonomy/OraclePlanner.h"

#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <filesystem>
#include <memory>
#include <set>

#include "rasm/core/Error.h"
#include "rasm/run/MappingRun.h"
#include "rasm/sim/RayScene.h"
#include "rasm/sim/SimulatedDiffDriveRobot.h"
#include "rasm/sim/SurfaceCoverage.h"
#include "run/RunTestFiles.h"

namespace fs = std::filesystem;
using namespace rasm;
using namespace rasm::pipeline;
using namespace rasm::autonomy;
using namespace rasm::run;
using namespace rasm::run::testing;

namespace {

/// two_rooms, its coverage for the default robot, and an oracle built on it.
struct TwoRooms {
  sim::World world = sim::loadWorld("two_rooms");
  sim::RayScene scene{world};
  sim::TRobotParams robot;
  sim::SurfaceCoverage cov{world, scene, sim::coverageOptionsForRobot(robot, camera160x120(), 4.0)};
  exploration::TExplorationParams params;
  std::unique_ptr<OraclePlanner> oracle;
  Eigen::Vector3d start{2.5, 2.5, M_PI / 4};  ///< two_rooms_robot's start pose

  TwoRooms() { oracle = make(); }
  std::unique_ptr<OraclePlanner> make() const {
    return std::make_unique<OraclePlanner>(cov, scene, params, robot.T_base_cam(), camera160x120());
  }
};

/// Built once for the suite.
TwoRooms& twoRooms() {
  static const std::unique_ptr<TwoRooms> w = std::make_unique<TwoRooms>();
  return *w;
}

/// An exploring run of two_rooms from its robot spec at 160x120 and 10 Hz, mapped at the
/// ground-truth poses (the planners are compared, not the tracker), deterministic planning.
RunConfig twoRoomsRun(const std::string& out, const std::string& planner, double budget_s) {
  RunConfig cfg = RunConfig::embeddedDefault();
  cfg.set("output", "dir", out);
  cfg.set("source", "type", "sim");
  cfg.set("sim", "world", "two_rooms");
  cfg.set("sim", "trajectory", "two_rooms_robot");
  cfg.set("sim", "seed", "1");
  cfg.set("sim", "rate_hz", "10");
  cfg.set("exploration", "seed", "1");
  cfg.set("exploration", "planner", planner);
  cfg.set("exploration", "enabled", "true");
  cfg.set("exploration", "planner_thread", "false");
  cfg.set("exploration", "time_budget_s", std::to_string(budget_s));
  cfg.set("exploration", "wall_budget_s", "0");
  cfg.set("mapper", "poses", "groundtruth");
  setRunCamera(cfg, camera160x120());
  for (const char* k : {"write_3dscene", "write_rawlog", "write_ply", "preview_png", "save_map"})
    cfg.set("output", k, "false");
  return cfg;
}

}  // namespace

TEST(OraclePlanner, ViewsReachMostOfTheObservableSurface) {
  const TwoRooms& w = twoRooms();
  const OraclePlanner& o = *w.oracle;
  std::printf(
      "two_rooms: %zu views, %zu targets, %zu coverable of %zu observable samples, "
      "reachable fraction %.4f, precomputed in %.1f s\n",
      o.numCandidates(), o.numTargets(), o.coverableSamples(), w.cov.observableSamples(),
      o.reachableFraction(), o.precomputeMs() / 1000.0);
  EXPECT_EQ(o.numCandidates(), w.cov.robotPositions().size() * 8);
  EXPECT_GT(o.reachableFraction(), 0.8);
  EXPECT_LE(o.reachableFraction(), 1.0);
  EXPECT_LE(o.coverableSamples(), w.cov.observableSamples());
}

TEST(OraclePlanner, GreedyViewsCoverTheCoverableSamples) {
  TwoRooms& w = twoRooms();
  OraclePlanner& o = *w.oracle;
  o.setCoveredSamples(std::vector<std::uint8_t>(w.cov.samples().size(), 0));
  std::vector<int> all;  // every view offered (none at a cramped position on the free space's edge)
  for (std::size_t c = 0; c < o.numCandidates(); ++c)
    if (o.offered(c)) all.push_back(int(c));
  EXPECT_GT(all.size(), o.numCandidates() / 3);
  EXPECT_LT(all.size(), o.numCandidates());
  EXPECT_EQ(o.gain(all), o.coverableSamples());
  const std::vector<int> chosen = o.greedyCover(w.start);
  std::printf("greedy cover: %zu views see %llu of %zu coverable samples\n", chosen.size(),
              (unsigned long long)o.gain(chosen), o.coverableSamples());
  ASSERT_FALSE(chosen.empty());
  EXPECT_LE(int(chosen.size()), w.params.oracle_max_views);
  EXPECT_GE(double(o.gain(chosen)), 0.95 * double(o.coverableSamples()));
  // Each view adds at least oracle_min_view_samples samples the earlier ones did not see.
  std::vector<int> prefix;
  std::uint64_t before = 0;
  for (const int c : chosen) {
    prefix.push_back(c);
    const std::uint64_t now = o.gain(prefix);
    EXPECT_GE(now - before, std::uint64_t(w.params.oracle_min_view_samples));
    before = now;
  }
}

TEST(OraclePlanner, TheTourVisitsEachChosenViewOnce) {
  TwoRooms& w = twoRooms();
  OraclePlanner& o = *w.oracle;
  o.setCoveredSamples(std::vector<std::uint8_t>(w.cov.samples().size(), 0));
  const std::vector<int> chosen = o.greedyCover(w.start);
  std::vector<int> tour = o.tourThrough(w.start, chosen);
  ASSERT_EQ(tour.size(), chosen.size());
  std::vector<int> a = chosen, b = tour;
  std::sort(a.begin(), a.end());
  std::sort(b.begin(), b.end());
  EXPECT_EQ(a, b);
  EXPECT_EQ(std::adjacent_find(b.begin(), b.end()), b.end()) << "a view visited twice";
}

TEST(OraclePlanner, SameInputsGiveTheSamePlanForAnyThreadCount) {
  TwoRooms& w = twoRooms();
  const int threads = omp_get_max_threads();
  omp_set_num_threads(1);
  const std::unique_ptr<OraclePlanner> one = w.make();
  omp_set_num_threads(threads);
  const std::unique_ptr<OraclePlanner> many = w.make();
  ASSERT_EQ(one->numCandidates(), many->numCandidates());
  for (std::size_t c = 0; c < one->numCandidates(); ++c) {
    ASSERT_EQ(one->candidatePose(c), many->candidatePose(c));
    ASSERT_EQ(one->candidateTargets(c), many->candidateTargets(c)) << "view " << c;
  }
  exploration::PlannerInputs in;
  in.robot_pose = w.start;
  const exploration::Plan p1 = one->plan(in), p2 = many->plan(in);
  ASSERT_FALSE(p1.ranked.empty());
  ASSERT_EQ(p1.ranked.size(), p2.ranked.size());
  for (std::size_t i = 0; i < p1.ranked.size(); ++i) {
    EXPECT_EQ(p1.ranked[i].pose, p2.ranked[i].pose);
    EXPECT_EQ(p1.ranked[i].source, exploration::ViewCandidate::Source::Oracle);
  }
  // The plan is the tour, the next goal first.
  ASSERT_EQ(p1.ranked.size(), one->tour().size());
  for (std::size_t i = 0; i < p1.ranked.size(); ++i)
    EXPECT_EQ(p1.ranked[i].pose, one->candidatePose(std::size_t(one->tour()[i])));
}

TEST(OraclePlanner, ReachedViewsAndTheMapsCoverageRetireViews) {
  TwoRooms& w = twoRooms();
  std::unique_ptr<OraclePlanner> o = w.make();
  exploration::PlannerInputs in;
  in.robot_pose = w.start;
  const exploration::Plan first = o->plan(in);
  ASSERT_GE(first.ranked.size(), 2u);
  o->goalOutcome(first.ranked.front().pose, true);
  const exploration::Plan second = o->plan(in);
  ASSERT_FALSE(second.ranked.empty());
  EXPECT_EQ(second.ranked.front().pose, first.ranked[1].pose) << "the tour goes on";
  // A failed goal retires every view within blacklist_radius_m of it.
  const Eigen::Vector3d failed = second.ranked.front().pose;
  o->goalOutcome(failed, false);
  for (const auto& v : o->plan(in).ranked)
    EXPECT_GT((v.pose.head<2>() - failed.head<2>()).norm(), w.params.blacklist_radius_m);
  // Per-sample coverage (SurfaceCoverage::evaluate) agrees with its count; a map covering every
  // sample leaves nothing to plan.
  std::vector<Eigen::Vector3f> pts;
  for (const auto& s : w.cov.samples()) pts.push_back(s.position);
  std::vector<std::uint8_t> covered;
  const sim::SurfaceCoverage::Result r = w.cov.evaluate(pts, &covered);
  EXPECT_EQ(std::size_t(std::count(covered.begin(), covered.end(), 1)), r.covered);
  EXPECT_EQ(r.covered, r.observable);
  o->setCoveredSamples(covered);
  EXPECT_TRUE(o->plan(in).ranked.empty()) << "everything covered: done";
}

// End to end: `rasm run`'s MappingRun with planner = oracle on two_rooms covers at least as much
// as the random baseline with the same seed and budget.
TEST(OraclePlanner, ExploringRunCoversAtLeastAsMuchAsRandom) {
  constexpr double kBudgetS = 120.0;  // (at 60 s both are near 0.25 of two_rooms, within noise)
  double coverage[2] = {0, 0};
  const char* planners[2] = {"oracle", "random"};
  for (int i = 0; i < 2; ++i) {
    const std::string out = rasm::run::testing::tempDir(std::string("oracle_vs_") + planners[i]);
    MappingRun run(twoRoomsRun(out, planners[i], kBudgetS));
    const RunSummary s = run.run();
    ASSERT_TRUE(s.explored);
    const nlohmann::json& r = s.report;
    coverage[i] = r.at("coverage_fraction").get<double>();
    std::printf("%s: coverage %.3f after %.0f s (%s), %d goals reached\n", planners[i], coverage[i],
                r.at("sim_time_s").get<double>(), r.at("stop_reason").get<std::string>().c_str(),
                r.at("exploration").at("goals_reached").get<int>());
    if (i == 0) {
      EXPECT_EQ(r.at("exploration").at("planner").get<std::string>(), "oracle");
      const double reach = r.at("exploration").at("oracle_reachable_fraction").get<double>();
      EXPECT_GT(reach, 0.8);
      EXPECT_LE(reach, 1.0);
    }
    fs::remove_all(out);
  }
  EXPECT_GE(coverage[0], coverage[1]) << "the oracle below the random baseline";
}
