#include "rasm/exploration/ExplorationPlanner.h"

#include <mrpt/math/wrap2pi.h>

#include <algorithm>

#include "BaselineCandidates.h"
#include "rasm/core/Error.h"
#include "rasm/exploration/ExplorationPlanners.h"

namespace rasm::exploration {

void ExplorationPlanner::goalOutcome(const Eigen::Vector3d& goal_xyyaw, bool reached) {
  if (!reached) m_blacklist.add(goal_xyyaw);
}

std::unique_ptr<ExplorationPlanner> makePlanner(const TExplorationParams& params) {
  params.validate();  // names [exploration] planner and the accepted names for an unknown one
  if (params.planner == "ig") return std::make_unique<TourIgPlanner>(params);
  if (params.planner == "ig_greedy") return std::make_unique<IgPlanner>(params);
  if (params.planner == "frontier") return std::make_unique<FrontierPlanner>(params);
  if (params.planner == "random") return std::make_unique<RandomPlanner>(params);
  if (params.planner == "lawnmower") return std::make_unique<LawnmowerPlanner>(params);
  if (params.planner == "oracle")
    throwInputError("[exploration] planner",
                    "'oracle' needs a simulated world (it plans on the ground truth): only an "
                    "exploring run of [source] type = sim builds it");
  throwInputError("[exploration] planner", "'" + params.planner + "' is not a planner");
}

// ---- "ig_greedy" ----

IgPlanner::IgPlanner(const TExplorationParams& params)
    : ExplorationPlanner(GoalBlacklist(params.blacklist_radius_m)),
      m_params(params),
      m_planner(params) {}

void IgPlanner::goalOutcome(const Eigen::Vector3d& goal_xyyaw, bool reached) {
  if (reached)
    m_taken.push_back(goal_xyyaw);
  else
    m_blacklist.add(goal_xyyaw);
}

bool IgPlanner::isTakenView(const Eigen::Vector3d& pose) const {
  if (m_params.taken_view_radius_m <= 0.0) return false;
  const double max_dyaw = m_params.taken_view_heading_deg * M_PI / 180.0;
  for (const Eigen::Vector3d& t : m_taken) {
    const double dyaw = std::abs(mrpt::math::wrapToPi(pose.z() - t.z()));
    if ((pose.head<2>() - t.head<2>()).norm() <= m_params.taken_view_radius_m && dyaw <= max_dyaw)
      return true;
  }
  return false;
}

Plan IgPlanner::plan(const PlannerInputs& in) {
  m_blacklist.tick();
  Plan plan = m_planner.plan(in);
  if (m_blacklist.size() > 0 || !m_taken.empty()) {
    std::vector<ViewCandidate> kept;
    for (const ViewCandidate& c : plan.ranked)
      (m_blacklist.contains(c.pose) || isTakenView(c.pose) ? plan.blacklisted : kept).push_back(c);
    // Re-rank what is offered: IG's normalisation (max dH, max dIC) runs over these views.
    if (!plan.blacklisted.empty())
      rankCandidates(m_params, kept, plan.current_goal ? &*plan.current_goal : nullptr);
    plan.ranked = std::move(kept);
  }
  for (const ViewCandidate& c : plan.ranked) {
    plan.best_entropy_reduction = std::max(plan.best_entropy_reduction, c.entropy_reduction);
    plan.best_information = std::max(plan.best_information, c.information);
  }
  return plan;
}

// ---- shared by the baselines ----

namespace detail {

void requireOctree(const PlannerInputs& in, const std::string& planner) {
  if (!in.octree)
    throwInputError("exploration planner '" + planner + "' inputs", "octree is required");
}

ViewCandidate baselineCandidate(const Eigen::Vector2d& xy, double yaw, ViewCandidate::Source source,
                                const PlannerInputs& in) {
  ViewCandidate c;
  c.source = source;
  c.pose = Eigen::Vector3d(xy.x(), xy.y(), mrpt::math::wrapToPi(yaw));
  c.T_world_cam = cameraPoseOf(c.pose, in.T_base_cam);
  return c;
}

void measureInto(const TExplorationParams& params, const PlannerInputs& in,
                 std::vector<ViewCandidate> candidates, Plan& plan) {
  planPaths(plan.grid, in.robot_pose, params, candidates);
  for (ViewCandidate& c : candidates) {
    if (!c.reachable) {
      plan.unreachable.push_back(c);
      continue;
    }
    c.gain = c.rate = 1.0 / (1.0 + c.path_length_m);
    plan.ranked.push_back(c);
  }
}

}  // namespace detail

}  // namespace rasm::exploration
