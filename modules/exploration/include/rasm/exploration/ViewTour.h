#pragma once
// The order in which the global planner ("ig", TourIgPlanner) visits its view clusters: an open
// tour from the robot through every cluster once, on asymmetric travel times (the heading the
// robot arrives with and the heading it leaves in differ), minimising the weighted latency
//   L(order) = sum_k w_order(k) * A_k,   A_k = arrival time at the k-th cluster visited.
// With w = each cluster's information gain this is the area above the gain-against-time curve:
// if cluster k adds w_k at A_k, the gain collected by a horizon T is sum_k w_k (T - A_k), so the
// order with the least L collects the most gain-seconds (the area under the coverage curve the
// evaluation reports). With equal weights it is the travelling repairman's problem; as a weight
// dominates, its cluster comes first. Like FUEL's global tour (Zhou et al., RA-L 2021, an
// asymmetric TSP over frontier clusters) it is a whole route and not a one-step choice, so a far
// room with a large gain is scheduled where the route passes it, and near crumbs are collected
// on the way instead of pulling the robot back and forth.
//
// Solver: exact dynamic programming over subsets (Held-Karp; O(2^n n^2)) up to exact_max_nodes
// clusters; beyond it the best of greedy constructions improved by 2-opt (segment reversal) and
// Or-opt (moving runs of 1-3 clusters) until no move improves L. Deterministic.

#include <Eigen/Core>
#include <vector>

namespace rasm::exploration {

struct TourProblem {
  /// Travel time (s) from the robot to each cluster.
  std::vector<double> start_time_s;
  /// time_s(i, j): travel time (s) from cluster i to cluster j (asymmetric; diagonal unused).
  Eigen::MatrixXd time_s;
  /// Weight of each cluster (>= 0; the planner adds a small floor so that zero-gain clusters
  /// still go in the cheapest place).
  std::vector<double> weight;

  int size() const { return int(start_time_s.size()); }
  /// Throws InputError when the sizes disagree or a time or weight is negative or not finite.
  void validate() const;
};

/// L(order) of the header (order: every cluster index once).
double tourLatency(const TourProblem& problem, const std::vector<int>& order);

/// The order that minimises L: exact for size() <= exact_max_nodes, local search beyond.
std::vector<int> solveTour(const TourProblem& problem, int exact_max_nodes = 11);

/// The local search alone from `order` (2-opt and Or-opt until no move improves L).
std::vector<int> improveTour(const TourProblem& problem, std::vector<int> order);

}  // namespace rasm::exploration
