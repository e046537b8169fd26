#include "rasm/exploration/ViewPlanner.h"

#include <algorithm>
#include <exception>
#include <random>

#include "rasm/core/Error.h"
#include "rasm/exploration/ExplorationPlanners.h"
#include "rasm/exploration/PlanningGrid.h"

namespace rasm::exploration {

ViewPlanner::ViewPlanner(const TExplorationParams& params) : m_params(params) {
  m_params.validate();
}

Plan ViewPlanner::plan(const PlannerInputs& in) const {
  if (!in.store || !in.segments || !in.octree)
    throwInputError("exploration planner inputs", "store, segments and octree are required");
  Plan plan;
  planningGrid(*in.octree, in.robot_pose, m_params.footprint_radius_m, plan.grid);

  std::mt19937_64 rng(std::uint64_t(m_params.seed));
  std::vector<ViewCandidate> candidates = sampleRandomViews(plan.grid, m_params, rng);
  const std::vector<ViewCandidate> objects = objectViews(*in.segments, plan.grid, m_params);
  candidates.insert(candidates.end(), objects.begin(), objects.end());
  if (m_params.frontier_candidates) {  // (c) views at the map's frontiers, scored like the rest
    const ReachableCells reach =
        reachableCells(plan.grid, in.robot_pose, m_params.footprint_radius_m);
    for (const FrontierView& f : frontierViews(plan.grid, reach, in.robot_pose, m_params))
      if (f.found) candidates.push_back(f.view);
  }
  planPaths(plan.grid, in.robot_pose, m_params, candidates);

  std::vector<int> reachable;
  for (int i = 0; i < int(candidates.size()); ++i) {
    ViewCandidate& c = candidates[std::size_t(i)];
    c.T_world_cam = cameraPoseOf(c.pose, in.T_base_cam);
    if (c.reachable)
      reachable.push_back(i);
    else
      plan.unreachable.push_back(c);
  }
  // The predictions, candidates spread over the threads (one predictor each; the renderer's own
  // parallel loops then run on the calling thread): each candidate is predicted by one thread
  // alone, so its dH and dIC do not depend on the thread count.
  const int n = int(reachable.size());
  std::vector<ViewPrediction> predicted(static_cast<std::size_t>(n));
  std::exception_ptr failure;  // (an exception must not leave an OpenMP region)
#pragma omp parallel if (n > 1)
  {
    ViewPredictor predictor(m_params, in.model);
#pragma omp for schedule(dynamic, 1)
    for (int j = 0; j < n; ++j) {
      try {
        predicted[std::size_t(j)] = predictor.predict(
            *in.store, *in.octree, candidates[std::size_t(reachable[std::size_t(j)])].T_world_cam,
            in.K);
      } catch (...) {
#pragma omp critical(rasm_view_planner_failure)
        if (!failure) failure = std::current_exception();
      }
    }
  }
  if (failure) std::rethrow_exception(failure);
  for (int j = 0; j < n; ++j) {
    ViewCandidate c = candidates[std::size_t(reachable[std::size_t(j)])];
    c.entropy_reduction = predicted[std::size_t(j)].entropy_reduction;
    c.information = predicted[std::size_t(j)].information.weighted;
    plan.ranked.push_back(c);
  }
  rankCandidates(m_params, plan.ranked);
  return plan;
}

void rankCandidates(const TExplorationParams& params, std::vector<ViewCandidate>& candidates) {
  double max_h = 0.0, max_ic = 0.0;
  for (const ViewCandidate& c : candidates) {
    max_h = std::max(max_h, c.entropy_reduction);
    max_ic = std::max(max_ic, c.information);
  }
  for (ViewCandidate& c : candidates) {
    // IG(a) = w1 dH + w2 dIC (V), each term over its largest value in this plan.
    c.gain = (max_h > 0.0 ? params.w_entropy * c.entropy_reduction / max_h : 0.0) +
             (max_ic > 0.0 ? params.w_ic * c.information / max_ic : 0.0);
    c.rate = c.gain / (c.travel_time_s + params.min_travel_time_s);
  }
  const bool by_rate = params.rank_by_rate;
  std::stable_sort(candidates.begin(), candidates.end(),
                   [by_rate](const ViewCandidate& a, const ViewCandidate& b) {
                     return by_rate ? a.rate > b.rate : a.gain > b.gain;
                   });
}

}  // namespace rasm::exploration
