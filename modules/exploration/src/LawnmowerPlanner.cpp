// "lawnmower": a boustrophedon sweep of the workspace's xy box.
#include <algorithm>
#include <cmath>

#include "BaselineCandidates.h"
#include "rasm/exploration/ExplorationPlanners.h"
#include "rasm/exploration/PlanningGrid.h"

namespace rasm::exploration {

namespace {

/// round((hi - lo) / d) positions (at least one) d apart, centred in [lo, hi].
std::vector<double> centredPositions(double lo, double hi, double d) {
  const int n = std::max(1, int(std::floor((hi - lo) / d + 0.5)));
  std::vector<double> v;
  for (int k = 0; k < n; ++k) v.push_back(0.5 * (lo + hi) + (k - 0.5 * (n - 1)) * d);
  return v;
}

/// The sweep in snake order: lanes along `axis`, alternating direction, heading along the lane.
std::vector<Eigen::Vector3d> sweepWaypoints(const TExplorationParams& p) {
  const bool along_x = p.lawnmower_axis == "x";
  const double u_lo = along_x ? p.workspace_min_x_m : p.workspace_min_y_m;
  const double u_hi = along_x ? p.workspace_max_x_m : p.workspace_max_y_m;
  const double v_lo = along_x ? p.workspace_min_y_m : p.workspace_min_x_m;
  const double v_hi = along_x ? p.workspace_max_y_m : p.workspace_max_x_m;
  const std::vector<double> lanes = centredPositions(v_lo, v_hi, p.lawnmower_spacing_m);
  std::vector<double> along = centredPositions(u_lo, u_hi, p.lawnmower_step_m);
  std::vector<Eigen::Vector3d> w;
  for (std::size_t k = 0; k < lanes.size(); ++k) {
    const bool forward = k % 2 == 0;
    const double heading = along_x ? (forward ? 0.0 : M_PI) : (forward ? M_PI / 2 : -M_PI / 2);
    for (std::size_t j = 0; j < along.size(); ++j) {
      const double u = forward ? along[j] : along[along.size() - 1 - j];
      w.push_back(along_x ? Eigen::Vector3d(u, lanes[k], heading)
                          : Eigen::Vector3d(lanes[k], u, heading));
    }
  }
  return w;
}

}  // namespace

LawnmowerPlanner::LawnmowerPlanner(const TExplorationParams& params, int max_skips)
    : m_params(params), m_max_skips(std::max(1, max_skips)) {
  m_params.validate();
  m_waypoints = sweepWaypoints(m_params);
  m_states.assign(m_waypoints.size(), State::Pending);
  m_skips.assign(m_waypoints.size(), 0);
}

void LawnmowerPlanner::skip(std::size_t i) {
  if (++m_skips[i] >= m_max_skips) m_states[i] = State::Abandoned;
}

Plan LawnmowerPlanner::plan(const PlannerInputs& in) {
  detail::requireOctree(in, name());
  Plan plan;
  planningGrid(*in.octree, in.robot_pose, m_params.footprint_radius_m, plan.grid);
  const ReachableCells reach =
      reachableCells(plan.grid, in.robot_pose, m_params.footprint_radius_m);
  const double snap = 0.5 * std::min(m_params.lawnmower_spacing_m, m_params.lawnmower_step_m);
  const std::size_t n = m_waypoints.size();
  m_offered = false;
  // From the sweep's current waypoint on, wrapping to the start (a later pass over the skipped).
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t i = (m_cursor + k) % n;
    if (m_states[i] != State::Pending) continue;
    const Eigen::Vector3d& w = m_waypoints[i];
    if (const auto goal = nearestReachableCell(plan.grid, reach, w.x(), w.y(), snap,
                                               m_params.footprint_radius_m)) {
      detail::measureInto(
          m_params, in, {detail::baselineCandidate(*goal, w.z(), ViewCandidate::Source::Sweep, in)},
          plan);
      if (!plan.ranked.empty()) {
        m_cursor = i, m_offered = true, m_offered_xy = *goal;
        return plan;
      }
    }
    skip(i);
  }
  // Nothing reachable from here: the robot cannot move, so it cannot see more; the sweep ends.
  for (State& s : m_states)
    if (s == State::Pending) s = State::Abandoned;
  return plan;
}

void LawnmowerPlanner::goalOutcome(const Eigen::Vector3d& goal_xyyaw, bool reached) {
  // Only the goal the last plan offered moves the sweep (a stale goal changes nothing).
  if (!m_offered || (goal_xyyaw.head<2>() - m_offered_xy).norm() > 1e-6) return;
  m_offered = false;
  if (reached) {
    m_states[m_cursor] = State::Visited;
    return;
  }
  skip(m_cursor);
  m_cursor = (m_cursor + 1) % m_waypoints.size();  // move on; a later pass retries it
}

}  // namespace rasm::exploration
