#include "rasm/exploration/ViewTour.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "rasm/core/Error.h"

namespace rasm::exploration {

void TourProblem::validate() const {
  const int n = size();
  if (int(weight.size()) != n || time_s.rows() != n || time_s.cols() != n)
    throwInputError("view tour", "start times, weights and the time matrix must have " +
                                     std::to_string(n) + " entries per side");
  for (int i = 0; i < n; ++i) {
    if (!(start_time_s[std::size_t(i)] >= 0.0) || !std::isfinite(start_time_s[std::size_t(i)]) ||
        !(weight[std::size_t(i)] >= 0.0) || !std::isfinite(weight[std::size_t(i)]))
      throwInputError("view tour", "start times and weights must be finite and >= 0");
    for (int j = 0; j < n; ++j)
      if (i != j && (!(time_s(i, j) >= 0.0) || !std::isfinite(time_s(i, j))))
        throwInputError("view tour", "travel times must be finite and >= 0");
  }
}

double tourLatency(const TourProblem& p, const std::vector<int>& order) {
  double t = 0.0, latency = 0.0;
  for (std::size_t k = 0; k < order.size(); ++k) {
    const int c = order[k];
    t += k == 0 ? p.start_time_s[std::size_t(c)] : p.time_s(order[k - 1], c);
    latency += p.weight[std::size_t(c)] * t;
  }
  return latency;
}

namespace {

/// Held-Karp over subsets: a leg j -> k taken with the clusters of S visited delays every
/// cluster not in S (k included) by its time, so it costs time * weight(not in S).
std::vector<int> exactTour(const TourProblem& p) {
  const int n = p.size();
  const std::size_t full = (std::size_t(1) << n);
  std::vector<double> subset_weight(full, 0.0);
  for (std::size_t s = 1; s < full; ++s) {
    const int low = __builtin_ctzll(s);
    subset_weight[s] = subset_weight[s & (s - 1)] + p.weight[std::size_t(low)];
  }
  const double total = subset_weight[full - 1];
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<double> cost(full * std::size_t(n), inf);
  std::vector<int> parent(full * std::size_t(n), -1);
  for (int k = 0; k < n; ++k)
    cost[(std::size_t(1) << k) * std::size_t(n) + std::size_t(k)] =
        p.start_time_s[std::size_t(k)] * total;
  for (std::size_t s = 1; s < full; ++s) {
    const double remaining = total - subset_weight[s];
    for (int j = 0; j < n; ++j) {
      const double c = cost[s * std::size_t(n) + std::size_t(j)];
      if (!(s >> j & 1) || c == inf) continue;
      for (int k = 0; k < n; ++k) {
        if (s >> k & 1) continue;
        const std::size_t t = (s | (std::size_t(1) << k)) * std::size_t(n) + std::size_t(k);
        const double v = c + p.time_s(j, k) * remaining;
        if (v < cost[t]) {
          cost[t] = v;
          parent[t] = j;
        }
      }
    }
  }
  int last = 0;
  for (int j = 1; j < n; ++j)
    if (cost[(full - 1) * std::size_t(n) + std::size_t(j)] <
        cost[(full - 1) * std::size_t(n) + std::size_t(last)])
      last = j;
  std::vector<int> order;
  for (std::size_t s = full - 1; last >= 0;) {
    order.push_back(last);
    const int prev = parent[s * std::size_t(n) + std::size_t(last)];
    s &= ~(std::size_t(1) << last);
    last = prev;
  }
  std::reverse(order.begin(), order.end());
  return order;
}

/// Greedy construction: from the robot, repeatedly the unvisited cluster with the largest
/// weight per second of travel (by_ratio) or the nearest one.
std::vector<int> greedyTour(const TourProblem& p, bool by_ratio) {
  const int n = p.size();
  std::vector<int> order;
  std::vector<char> used(std::size_t(n), 0);
  for (int step = 0; step < n; ++step) {
    int best = -1;
    double best_key = -std::numeric_limits<double>::infinity();
    for (int k = 0; k < n; ++k) {
      if (used[std::size_t(k)]) continue;
      const double t = order.empty() ? p.start_time_s[std::size_t(k)] : p.time_s(order.back(), k);
      const double key = by_ratio ? p.weight[std::size_t(k)] / (t + 1e-3) : -t;
      if (key > best_key) best_key = key, best = k;
    }
    used[std::size_t(best)] = 1;
    order.push_back(best);
  }
  return order;
}

/// One improving 2-opt move (reverse order[i..j]) or Or-opt move (move a run of 1-3 clusters
/// elsewhere), first improvement; false when none improves L by more than a relative 1e-12.
bool improveOnce(const TourProblem& p, std::vector<int>& order, double& latency) {
  const int n = int(order.size());
  const double eps = 1e-12 * std::max(1.0, std::abs(latency));
  for (int i = 0; i < n - 1; ++i)
    for (int j = i + 1; j < n; ++j) {
      std::vector<int> cand = order;
      std::reverse(cand.begin() + i, cand.begin() + j + 1);
      const double l = tourLatency(p, cand);
      if (l < latency - eps) {
        order = std::move(cand), latency = l;
        return true;
      }
    }
  for (int len = 1; len <= 3 && len < n; ++len)
    for (int i = 0; i + len <= n; ++i)
      for (int to = 0; to <= n - len; ++to) {
        if (to == i) continue;
        std::vector<int> run(order.begin() + i, order.begin() + i + len), cand;
        cand.reserve(std::size_t(n));
        for (int k = 0; k < n; ++k)
          if (k < i || k >= i + len) cand.push_back(order[std::size_t(k)]);
        cand.insert(cand.begin() + to, run.begin(), run.end());
        const double l = tourLatency(p, cand);
        if (l < latency - eps) {
          order = std::move(cand), latency = l;
          return true;
        }
      }
  return false;
}

}  // namespace

std::vector<int> improveTour(const TourProblem& p, std::vector<int> order) {
  double latency = tourLatency(p, order);
  for (int guard = 0; guard < 10000 && improveOnce(p, order, latency); ++guard) {
  }
  return order;
}

std::vector<int> solveTour(const TourProblem& p, int exact_max_nodes) {
  p.validate();
  if (p.size() == 0) return {};
  if (p.size() <= std::min(exact_max_nodes, 16)) return exactTour(p);
  std::vector<int> best;
  double best_latency = std::numeric_limits<double>::infinity();
  for (const bool by_ratio : {true, false}) {
    const std::vector<int> order = improveTour(p, greedyTour(p, by_ratio));
    const double l = tourLatency(p, order);
    if (l < best_latency) best_latency = l, best = order;
  }
  return best;
}

}  // namespace rasm::exploration
