// "random": a random reachable known-free cell and heading per plan.
#include <cmath>

#include "BaselineCandidates.h"
#include "rasm/exploration/ExplorationPlanners.h"
#include "rasm/exploration/PlanningGrid.h"

namespace rasm::exploration {

namespace {
/// Draws per plan before giving up when planPaths disagrees with the reachability field (it
/// should not: the field's traversable cells are a subset of PlannerSimple2D's free ones).
constexpr int kDraws = 8;
}  // namespace

RandomPlanner::RandomPlanner(const TExplorationParams& params)
    : ExplorationPlanner(GoalBlacklist(params.blacklist_radius_m)),
      m_params(params),
      m_rng(std::uint64_t(params.seed)) {
  m_params.validate();
}

Plan RandomPlanner::plan(const PlannerInputs& in) {
  detail::requireOctree(in, name());
  m_blacklist.tick();
  Plan plan;
  planningGrid(*in.octree, in.robot_pose, m_params.footprint_radius_m, plan.grid);
  const ReachableCells reach =
      reachableCells(plan.grid, in.robot_pose, m_params.footprint_radius_m);
  // Reachable cells not near a failed goal, row-major (the draw depends on the seed only).
  std::vector<Eigen::Vector2d> cells;
  for (int iy = 0; iy < reach.size_y; ++iy)
    for (int ix = 0; ix < reach.size_x; ++ix) {
      if (!reach.reachable(ix, iy)) continue;
      const Eigen::Vector2d xy(plan.grid.idx2x(ix), plan.grid.idx2y(iy));
      if (!m_blacklist.contains(Eigen::Vector3d(xy.x(), xy.y(), 0.0))) cells.push_back(xy);
    }
  if (cells.empty()) return plan;
  std::uniform_int_distribution<std::size_t> pick(0, cells.size() - 1);
  std::uniform_real_distribution<double> heading(-M_PI, M_PI);
  for (int k = 0; k < kDraws && plan.ranked.empty(); ++k) {
    const Eigen::Vector2d xy = cells[pick(m_rng)];
    const double yaw = heading(m_rng);
    detail::measureInto(m_params, in,
                        {detail::baselineCandidate(xy, yaw, ViewCandidate::Source::Random, in)},
                        plan);
  }
  return plan;
}

}  // namespace rasm::exploration
