// The global planner's tour (ViewTour.h): the weighted latency it minimises, the exact solver
// against brute force, the local search within 10% of the optimum, and the clustering of views.

#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <numeric>
#include <random>
#include <vector>

#include "rasm/core/Error.h"
#include "rasm/exploration/ExplorationPlanners.h"
#include "rasm/exploration/ViewTour.h"

namespace rasm::exploration {
namespace {

/// Clusters at random places in a 10 x 10 m flat; times = distance / 0.3 m/s plus an asymmetric
/// turn term (0-4 s, different each way); weights in [0.05, 2].
TourProblem randomProblem(int n, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> pos(0.0, 10.0), turn(0.0, 4.0), w(0.05, 2.0);
  std::vector<Eigen::Vector2d> xy(std::size_t(n) + 1);
  for (auto& p : xy) p = Eigen::Vector2d(pos(rng), pos(rng));  // xy[n]: the robot
  TourProblem p;
  p.time_s = Eigen::MatrixXd::Zero(n, n);
  for (int i = 0; i < n; ++i) {
    p.start_time_s.push_back((xy[std::size_t(i)] - xy[std::size_t(n)]).norm() / 0.3 + turn(rng));
    p.weight.push_back(w(rng));
    for (int j = 0; j < n; ++j)
      if (i != j)
        p.time_s(i, j) = (xy[std::size_t(i)] - xy[std::size_t(j)]).norm() / 0.3 + turn(rng);
  }
  return p;
}

double bruteForceOptimum(const TourProblem& p) {
  std::vector<int> order(std::size_t(p.size()));
  std::iota(order.begin(), order.end(), 0);
  double best = std::numeric_limits<double>::infinity();
  do best = std::min(best, tourLatency(p, order));
  while (std::next_permutation(order.begin(), order.end()));
  return best;
}

void expectPermutation(const std::vector<int>& order, int n) {
  std::vector<int> sorted = order;
  std::sort(sorted.begin(), sorted.end());
  std::vector<int> all(static_cast<std::size_t>(n));
  std::iota(all.begin(), all.end(), 0);
  EXPECT_EQ(sorted, all) << "every cluster exactly once";
}

TEST(ViewTour, LatencyIsTheWeightedSumOfArrivalTimes) {
  TourProblem p;
  p.start_time_s = {2.0, 10.0};
  p.time_s = Eigen::MatrixXd::Zero(2, 2);
  p.time_s(0, 1) = 5.0;  // asymmetric: 0 -> 1 takes 5 s, 1 -> 0 takes 7 s
  p.time_s(1, 0) = 7.0;
  p.weight = {1.0, 3.0};
  EXPECT_DOUBLE_EQ(tourLatency(p, {0, 1}), 1.0 * 2.0 + 3.0 * 7.0);
  EXPECT_DOUBLE_EQ(tourLatency(p, {1, 0}), 3.0 * 10.0 + 1.0 * 17.0);
  EXPECT_EQ(solveTour(p), (std::vector<int>{0, 1}));  // 23 < 47
  // A near crumb on the far side of the robot: the large gain goes first (3 x 10 + 0.1 x 17 =
  // 31.7 against 0.1 x 2 + 3 x 22 = 66.2), although the crumb is nearer.
  p.weight = {0.1, 3.0};
  p.time_s(0, 1) = 20.0;
  EXPECT_EQ(solveTour(p), (std::vector<int>{1, 0}));
}

TEST(ViewTour, ExactSolverMatchesBruteForce) {
  std::mt19937_64 rng(7);
  for (int n = 1; n <= 7; ++n)
    for (int trial = 0; trial < 5; ++trial) {
      const TourProblem p = randomProblem(n, rng);
      const std::vector<int> order = solveTour(p);
      expectPermutation(order, n);
      EXPECT_NEAR(tourLatency(p, order), bruteForceOptimum(p), 1e-9 * bruteForceOptimum(p))
          << "n " << n << " trial " << trial;
    }
}

// Beyond the exact solver's size the local search is used; on instances small enough for brute
// force it stays within 10% of the optimum (the bound) on every instance.
TEST(ViewTour, LocalSearchIsWithinTenPercentOfTheOptimum) {
  std::mt19937_64 rng(11);
  double worst = 1.0;
  for (int trial = 0; trial < 20; ++trial) {
    const int n = 6 + trial % 3;
    const TourProblem p = randomProblem(n, rng);
    const std::vector<int> order = solveTour(p, /*exact_max_nodes=*/0);
    expectPermutation(order, n);
    const double ratio = tourLatency(p, order) / bruteForceOptimum(p);
    worst = std::max(worst, ratio);
    EXPECT_LE(ratio, 1.1) << "n " << n << " trial " << trial;
  }
  RecordProperty("worst_ratio", std::to_string(worst));
}

TEST(ViewTour, LargeInstancesAreSolvedDeterministically) {
  std::mt19937_64 rng(3);
  const TourProblem p = randomProblem(30, rng);
  const std::vector<int> a = solveTour(p), b = solveTour(p);
  expectPermutation(a, 30);
  EXPECT_EQ(a, b);
  // A local optimum: no 2-opt or Or-opt move improves it.
  EXPECT_EQ(improveTour(p, a), a);
  std::vector<int> identity(30);
  std::iota(identity.begin(), identity.end(), 0);
  EXPECT_LT(tourLatency(p, a), tourLatency(p, identity));
}

TEST(ViewTour, BadProblemIsAnInputError) {
  TourProblem p;
  p.start_time_s = {1.0, 2.0};
  p.weight = {1.0};
  p.time_s = Eigen::MatrixXd::Zero(2, 2);
  EXPECT_THROW(solveTour(p), InputError);
  p.weight = {1.0, -1.0};
  EXPECT_THROW(solveTour(p), InputError);
  p.weight = {1.0, 1.0};
  p.time_s(0, 1) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(solveTour(p), InputError);
}

ViewCandidate viewAt(double x, double y) {
  ViewCandidate c;
  c.pose = Eigen::Vector3d(x, y, 0.0);
  return c;
}

TEST(ViewTour, ClustersJoinViewsWithinTheRadiusAtTheirBestViewAndDropCrumbs) {
  const std::vector<ViewCandidate> views = {viewAt(0, 0),     viewAt(0.5, 0), viewAt(5, 0),
                                            viewAt(5.2, 0.3), viewAt(9, 0),   viewAt(3, 3)};
  const std::vector<double> gains = {0.5, 0.9, 0.4, 0.3, 0.05, 0.0};
  // Heads by descending gain: 1 (0.9), then 0 is within 1 m of it, 2 (0.4) starts a cluster,
  // 3 joins it; 4 is below 0.1 x 0.9; 5 has no gain.
  EXPECT_EQ(clusterViews(views, gains, 1.0, 12, 0.1), (std::vector<int>{1, 2}));
  EXPECT_EQ(clusterViews(views, gains, 1.0, 1, 0.1), (std::vector<int>{1}));
  EXPECT_EQ(clusterViews(views, gains, 1.0, 12, 0.0), (std::vector<int>{1, 2, 4}));
  EXPECT_TRUE(clusterViews({}, {}, 1.0, 12, 0.1).empty());
}

}  // namespace
}  // namespace rasm::exploration
