#include "rasm/exploration/ViewPlanner.h"

#include <algorithm>
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

  ViewPredictor predictor(m_params, in.model);
  for (ViewCandidate& c : candidates) {
    c.T_world_cam = cameraPoseOf(c.pose, in.T_base_cam);
    if (!c.reachable) {
      plan.unreachable.push_back(c);
      continue;
    }
    const ViewPrediction p = predictor.predict(*in.store, *in.octree, c.T_world_cam, in.K);
    c.entropy_reduction = p.entropy_reduction;
    c.information = p.information.weighted;
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
