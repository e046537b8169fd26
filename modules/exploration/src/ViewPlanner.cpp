#include "rasm/exploration/ViewPlanner.h"

#include <algorithm>
#include <cmath>
#include <exception>
#include <random>

#include "rasm/core/Error.h"
#include "rasm/exploration/ExplorationPlanners.h"
#include "rasm/exploration/PlanningGrid.h"

namespace rasm::exploration {

ViewPlanner::ViewPlanner(const TExplorationParams& params) : m_params(params) {
  m_params.validate();
}

namespace {
/// dH and dIC of candidates[which[j]] (their T_world_cam) on `store` at params' predict size:
/// the candidates spread over the threads (one predictor each; the renderer's own parallel loops
/// then run on the calling thread), each predicted by one thread alone, so its dH and dIC do not
/// depend on the thread count.
std::vector<ViewPrediction> predictViews(const TExplorationParams& params,
                                         const maps::SurfelStore& store, const PlannerInputs& in,
                                         const std::vector<ViewCandidate>& candidates,
                                         const std::vector<int>& which) {
  const int n = int(which.size());
  std::vector<ViewPrediction> predicted(static_cast<std::size_t>(n));
  std::exception_ptr failure;  // (an exception must not leave an OpenMP region)
#pragma omp parallel if (n > 1)
  {
    ViewPredictor predictor(params, in.model);
#pragma omp for schedule(dynamic, 1)
    for (int j = 0; j < n; ++j) {
      try {
        predicted[std::size_t(j)] = predictor.predict(
            store, *in.octree, candidates[std::size_t(which[std::size_t(j)])].T_world_cam, in.K);
      } catch (...) {
#pragma omp critical(rasm_view_planner_failure)
        if (!failure) failure = std::current_exception();
      }
    }
  }
  if (failure) std::rethrow_exception(failure);
  return predicted;
}
}  // namespace

/// The candidates predicted in full: all of `reachable`, or (predict_screen_keep > 0 and more
/// reachable candidates than that) the best predict_screen_keep by IG and by IG per travel
/// second (the same IG, on a coarse prediction at predict_screen_width x predict_screen_height),
/// plus every frontier view (the tour's way into unknown space) and the goal being driven to. In
/// candidate order.
std::vector<int> ViewPlanner::screenCandidates(const maps::SurfelStore& store,
                                               const PlannerInputs& in,
                                               const std::vector<ViewCandidate>& candidates,
                                               const std::vector<int>& reachable, int goal_index,
                                               Plan& plan) const {
  const std::size_t keep = std::size_t(std::max(0, m_params.predict_screen_keep));
  if (keep == 0 || reachable.size() <= keep) return reachable;
  TExplorationParams coarse_params = m_params;
  coarse_params.predict_width = m_params.predict_screen_width;
  coarse_params.predict_height = m_params.predict_screen_height;
  // A render costs per surfel in view, not per pixel: the screen's smaller image gets a map
  // thinned in proportion to its pixels (splats as wide in pixels as the full prediction's).
  if (m_params.predict_max_surfels > 0)
    coarse_params.predict_max_surfels =
        std::max<int>(1000, int(std::int64_t(m_params.predict_max_surfels) *
                                coarse_params.predict_width * coarse_params.predict_height /
                                (std::int64_t(m_params.predict_width) * m_params.predict_height)));
  maps::SurfelStore coarse_thinned;
  const std::vector<ViewPrediction> coarse =
      predictViews(coarse_params, predictionStore(store, coarse_params, coarse_thinned), in,
                   candidates, reachable);
  std::vector<ViewCandidate> scored;
  for (std::size_t j = 0; j < reachable.size(); ++j) {
    scored.push_back(candidates[std::size_t(reachable[j])]);
    scored.back().entropy_reduction = coarse[j].entropy_reduction;
    scored.back().information = coarse[j].information.weighted;
  }
  scoreCandidates(m_params, scored);
  // Kept: the best by IG and the best by IG per travel second, alternately, until `keep` views
  // (the tour weighs IG by arrival time, the greedy ranking by rate: a screen by rate alone
  // dropped the far views into two_rooms' second room, and the robot never went there).
  const auto orderBy = [&](auto key) {
    std::vector<std::size_t> order(reachable.size());
    for (std::size_t j = 0; j < order.size(); ++j) order[j] = j;
    std::stable_sort(order.begin(), order.end(),
                     [&](std::size_t a, std::size_t b) { return key(scored[a]) > key(scored[b]); });
    return order;
  };
  const std::vector<std::size_t> by_gain = orderBy([](const ViewCandidate& c) { return c.gain; });
  const std::vector<std::size_t> by_rate = orderBy([](const ViewCandidate& c) { return c.rate; });
  std::vector<char> kept(reachable.size(), 0);
  std::size_t n_kept = 0;
  for (std::size_t r = 0; n_kept < keep && r < reachable.size(); ++r)
    for (const std::size_t j : {by_gain[r], by_rate[r]})
      if (n_kept < keep && !kept[j]) {
        kept[j] = 1;
        ++n_kept;
      }
  std::vector<int> out;
  for (std::size_t j = 0; j < reachable.size(); ++j) {
    const int i = reachable[j];
    if (kept[j] || i == goal_index ||
        candidates[std::size_t(i)].source == ViewCandidate::Source::Frontier)
      out.push_back(i);
  }
  plan.screened_out = reachable.size() - out.size();
  return out;
}

namespace {
/// A view from frontier_behind_m past a frontier (ViewCandidate::entropy_behind).
struct BehindView {
  int frontier = 0;  ///< index of the frontier's view among the candidates
  ViewCandidate view;
};

/// Views from frontier_behind_m past the frontier of `f` (its centroid along the outward
/// normal), facing outward and +-60 deg (the 57-63 deg camera's three views tile ~180 deg: what
/// the robot sees as it turns once through). None when the frontier has no outward side, the spot
/// is outside the workspace, or the way there crosses a cell seen occupied from the floor band up
/// to 1.8 m (a wall, not a way through; a door's lintel is above).
void addBehindViews(const FrontierView& f, int frontier_index, const OccupancyOctree& octree,
                    const TExplorationParams& params, const Eigen::Isometry3d& T_base_cam,
                    std::vector<BehindView>& out) {
  if (params.frontier_behind_m <= 0.0 || f.outward.norm() < 0.5) return;
  const Eigen::Vector2d at = f.view.target_xy + params.frontier_behind_m * f.outward;
  if (at.x() < params.workspace_min_x_m || at.x() > params.workspace_max_x_m ||
      at.y() < params.workspace_min_y_m || at.y() > params.workspace_max_y_m)
    return;
  if (octree.occupiedAlong(f.view.target_xy, at, params.band_min_z_m, 1.8)) return;
  const double yaw = std::atan2(f.outward.y(), f.outward.x());
  for (const double turn_deg : {0.0, 60.0, -60.0}) {
    BehindView b;
    b.frontier = frontier_index;
    b.view.source = ViewCandidate::Source::Frontier;
    b.view.pose = Eigen::Vector3d(at.x(), at.y(), yaw + turn_deg * M_PI / 180.0);
    b.view.T_world_cam = cameraPoseOf(b.view.pose, T_base_cam);
    out.push_back(b);
  }
}

/// Sets entropy_behind of the frontier views among `predicted` (candidate indices) to the summed
/// dH of their views beyond (`behind`), predicted like the candidates.
void predictBehind(const TExplorationParams& params, const maps::SurfelStore& store,
                   const PlannerInputs& in, const std::vector<int>& predicted,
                   const std::vector<BehindView>& behind, std::vector<ViewCandidate>& candidates) {
  std::vector<char> in_plan(candidates.size(), 0);
  for (const int i : predicted) in_plan[std::size_t(i)] = 1;
  std::vector<ViewCandidate> views;
  std::vector<int> owner, which;
  for (const BehindView& b : behind)
    if (in_plan[std::size_t(b.frontier)]) {
      which.push_back(int(views.size()));
      views.push_back(b.view);
      owner.push_back(b.frontier);
    }
  if (views.empty()) return;
  const std::vector<ViewPrediction> dH = predictViews(params, store, in, views, which);
  for (std::size_t k = 0; k < views.size(); ++k)
    candidates[std::size_t(owner[k])].entropy_behind += dH[k].entropy_reduction;
}
}  // namespace

Plan ViewPlanner::plan(const PlannerInputs& in) const {
  if (!in.store || !in.segments || !in.octree)
    throwInputError("exploration planner inputs", "store, segments and octree are required");
  Plan plan;
  planningGrid(*in.octree, in.robot_pose, m_params.footprint_radius_m, plan.grid);

  std::mt19937_64 rng(std::uint64_t(m_params.seed));
  std::vector<ViewCandidate> candidates = sampleRandomViews(plan.grid, m_params, rng);
  const std::vector<ViewCandidate> objects = objectViews(*in.segments, plan.grid, m_params);
  candidates.insert(candidates.end(), objects.begin(), objects.end());
  std::vector<BehindView> behind;      // the views past each frontier (entropy_behind)
  if (m_params.frontier_candidates) {  // (c) views at the map's frontiers, scored like the rest
    const ReachableCells reach =
        reachableCells(plan.grid, in.robot_pose, m_params.footprint_radius_m);
    for (const FrontierView& f : frontierViews(plan.grid, reach, in.robot_pose, m_params)) {
      plan.frontiers.push_back({f.view.target_xy, f.cells, f.found});
      if (f.found) {
        addBehindViews(f, int(candidates.size()), *in.octree, m_params, in.T_base_cam, behind);
        candidates.push_back(f.view);
      }
    }
  }
  // The goal the robot drives to, last: measured and predicted like the candidates, scored
  // alongside them (Plan::current_goal), never offered.
  const int goal_index = in.current_goal ? int(candidates.size()) : -1;
  if (in.current_goal) {
    ViewCandidate g;
    g.pose = *in.current_goal;
    candidates.push_back(g);
  }
  planPaths(plan.grid, in.robot_pose, m_params, candidates);

  std::vector<int> reachable;
  for (int i = 0; i < int(candidates.size()); ++i) {
    ViewCandidate& c = candidates[std::size_t(i)];
    c.T_world_cam = cameraPoseOf(c.pose, in.T_base_cam);
    if (c.reachable)
      reachable.push_back(i);
    else if (i == goal_index)
      plan.current_goal = c;  // not reachable now: gain 0
    else
      plan.unreachable.push_back(c);
  }
  maps::SurfelStore thinned;
  const maps::SurfelStore& store =
      reachable.empty() ? *in.store : predictionStore(*in.store, m_params, thinned);
  reachable = screenCandidates(store, in, candidates, reachable, goal_index, plan);
  const int n = int(reachable.size());
  const std::vector<ViewPrediction> predicted =
      predictViews(m_params, store, in, candidates, reachable);
  predictBehind(m_params, store, in, reachable, behind, candidates);
  for (int j = 0; j < n; ++j) {
    ViewCandidate c = candidates[std::size_t(reachable[std::size_t(j)])];
    c.entropy_reduction = predicted[std::size_t(j)].entropy_reduction;
    c.information = predicted[std::size_t(j)].information.weighted;
    if (reachable[std::size_t(j)] == goal_index)
      plan.current_goal = c;
    else
      plan.ranked.push_back(c);
  }
  rankCandidates(m_params, plan.ranked, plan.current_goal ? &*plan.current_goal : nullptr);
  return plan;
}

double informationGain(const TExplorationParams& params, double entropy_reduction,
                       double information, double max_entropy_reduction, double max_information) {
  // IG(a) = w1 dH + w2 dIC (V), each term over its largest value in this plan.
  return (max_entropy_reduction > 0.0 ? params.w_entropy * entropy_reduction / max_entropy_reduction
                                      : 0.0) +
         (max_information > 0.0 ? params.w_ic * information / max_information : 0.0);
}

double rankingKey(const TExplorationParams& params, const ViewCandidate& c) {
  return params.rank_by_rate ? c.rate : c.gain;
}

void scoreCandidates(const TExplorationParams& params, std::vector<ViewCandidate>& candidates,
                     ViewCandidate* alongside) {
  double max_h = alongside ? alongside->entropy_reduction : 0.0;
  double max_ic = alongside ? alongside->information : 0.0;
  for (const ViewCandidate& c : candidates) {
    max_h = std::max(max_h, c.entropy_reduction);
    max_ic = std::max(max_ic, c.information);
  }
  auto score = [&](ViewCandidate& c) {
    c.gain = informationGain(params, c.entropy_reduction, c.information, max_h, max_ic);
    c.rate = c.gain / (c.travel_time_s + params.min_travel_time_s);
  };
  for (ViewCandidate& c : candidates) score(c);
  if (alongside) score(*alongside);
}

void rankCandidates(const TExplorationParams& params, std::vector<ViewCandidate>& candidates,
                    ViewCandidate* alongside) {
  scoreCandidates(params, candidates, alongside);
  std::stable_sort(candidates.begin(), candidates.end(),
                   [&params](const ViewCandidate& a, const ViewCandidate& b) {
                     return rankingKey(params, a) > rankingKey(params, b);
                   });
}

}  // namespace rasm::exploration
