#pragma once
// Internal: what the baseline planners share (ExplorationPlanners.h).

#include <string>
#include <vector>

#include "rasm/exploration/ExplorationPlanner.h"

namespace rasm::exploration::detail {

/// Throws InputError naming the planner when in.octree is null (the baselines need nothing else).
void requireOctree(const PlannerInputs& in, const std::string& planner);

/// A candidate at (x, y, yaw) with its camera pose.
ViewCandidate baselineCandidate(const Eigen::Vector2d& xy, double yaw, ViewCandidate::Source source,
                                const PlannerInputs& in);

/// Measures the candidates with planPaths (the IG planner's path length and travel time); the
/// reachable ones are appended to plan.ranked with gain = rate = 1 / (1 + path_length_m) (an
/// ordering key), the others to plan.unreachable.
void measureInto(const TExplorationParams& params, const PlannerInputs& in,
                 std::vector<ViewCandidate> candidates, Plan& plan);

}  // namespace rasm::exploration::detail
