// "frontier": nearest-frontier exploration (Yamauchi 1997) on the planning grid.
#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>

#include "BaselineCandidates.h"
#include "rasm/exploration/ExplorationPlanners.h"
#include "rasm/exploration/PlanningGrid.h"

namespace rasm::exploration {

namespace {

/// Yamauchi's frontier cell: known free with an unknown 4-neighbour (inside the grid; the
/// grid's border is the workspace's, beyond which nothing is to be explored). Returns the summed
/// directions to those neighbours (zero vector and false when none).
bool frontierCell(const mrpt::maps::COccupancyGridMap2D& g, int ix, int iy, Eigen::Vector2d& out) {
  const int nx = int(g.getSizeX()), ny = int(g.getSizeY());
  if (!knownFreeCell(g.getCell(ix, iy))) return false;
  static const int d[4][2] = {{1, 0}, {-1, 0}, {0, 1}, {0, -1}};
  bool any = false;
  out.setZero();
  for (const auto& s : d) {
    const int jx = ix + s[0], jy = iy + s[1];
    if (jx < 0 || jy < 0 || jx >= nx || jy >= ny || !unknownCell(g.getCell(jx, jy))) continue;
    out += Eigen::Vector2d(s[0], s[1]);
    any = true;
  }
  return any;
}

/// A frontier cell: centre (m) and the summed directions to its unknown neighbours.
struct FrontierCell {
  Eigen::Vector2d at, out;
};

/// `cells` as one cluster, or (their farthest cell more than max_radius_m from their centroid)
/// split in two at the centroid across their principal axis, recursively (FUEL's split of large
/// frontier clusters, Zhou et al. 2021): a room's whole boundary seen through its doorway is one
/// connected frontier whose centroid lies in the middle of the unknown, far from every cell the
/// robot can reach; its pieces each have a view. Pieces under min_cells are dropped.
void splitCluster(std::vector<FrontierCell> cells, double max_radius_m, int min_cells,
                  std::vector<FrontierCluster>& out) {
  if (int(cells.size()) < min_cells) return;
  Eigen::Vector2d centroid = Eigen::Vector2d::Zero(), outward = Eigen::Vector2d::Zero();
  for (const FrontierCell& c : cells) centroid += c.at, outward += c.out;
  centroid /= double(cells.size());
  double radius = 0.0;
  Eigen::Matrix2d cov = Eigen::Matrix2d::Zero();
  for (const FrontierCell& c : cells) {
    const Eigen::Vector2d d = c.at - centroid;
    radius = std::max(radius, d.norm());
    cov += d * d.transpose();
  }
  if (max_radius_m > 0.0 && radius > max_radius_m && cells.size() >= 2) {
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(cov);
    const Eigen::Vector2d axis = eig.eigenvectors().col(1);  // the largest eigenvalue's
    std::vector<FrontierCell> a, b;
    for (const FrontierCell& c : cells) ((c.at - centroid).dot(axis) < 0.0 ? a : b).push_back(c);
    if (!a.empty() && !b.empty()) {
      splitCluster(std::move(a), max_radius_m, min_cells, out);
      splitCluster(std::move(b), max_radius_m, min_cells, out);
      return;
    }
  }
  FrontierCluster f;
  for (const FrontierCell& c : cells) f.cells.push_back(c.at);
  f.centroid = centroid;
  if (outward.norm() > 1e-9) f.outward = outward.normalized();
  out.push_back(std::move(f));
}

}  // namespace

std::vector<FrontierCluster> findFrontiers(const mrpt::maps::COccupancyGridMap2D& grid,
                                           int min_cells, double max_radius_m) {
  const int nx = int(grid.getSizeX()), ny = int(grid.getSizeY());
  std::vector<Eigen::Vector2d> dir(std::size_t(nx) * ny, Eigen::Vector2d::Zero());
  std::vector<std::uint8_t> is_frontier(dir.size(), 0), seen(dir.size(), 0);
  for (int iy = 0; iy < ny; ++iy)
    for (int ix = 0; ix < nx; ++ix)
      is_frontier[std::size_t(iy) * nx + ix] =
          frontierCell(grid, ix, iy, dir[std::size_t(iy) * nx + ix]);
  std::vector<FrontierCluster> clusters;
  std::vector<int> stack;
  for (int start = 0; start < nx * ny; ++start) {
    if (!is_frontier[start] || seen[start]) continue;
    std::vector<FrontierCell> cells;
    stack = {start};
    seen[start] = 1;
    while (!stack.empty()) {  // 8-connected flood fill
      const int cell = stack.back();
      stack.pop_back();
      const int cx = cell % nx, cy = cell / nx;
      cells.push_back({Eigen::Vector2d(grid.idx2x(cx), grid.idx2y(cy)), dir[cell]});
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const int jx = cx + dx, jy = cy + dy, j = jy * nx + jx;
          if (jx < 0 || jy < 0 || jx >= nx || jy >= ny || !is_frontier[j] || seen[j]) continue;
          seen[j] = 1;
          stack.push_back(j);
        }
    }
    if (int(cells.size()) < min_cells) continue;
    splitCluster(std::move(cells), max_radius_m, min_cells, clusters);
  }
  return clusters;
}

std::vector<FrontierView> frontierViews(const mrpt::maps::COccupancyGridMap2D& grid,
                                        const ReachableCells& reach,
                                        const Eigen::Vector3d& robot_pose,
                                        const TExplorationParams& params) {
  std::vector<FrontierView> views;
  for (const FrontierCluster& f :
       findFrontiers(grid, params.frontier_min_cells, params.frontier_max_radius_m)) {
    const std::optional<Eigen::Vector2d> goal =
        nearestReachableCell(grid, reach, f.centroid.x(), f.centroid.y(),
                             params.frontier_goal_radius_m, params.footprint_radius_m);
    // Face the unknown side: a point 0.5 m past the centroid along the frontier's outward normal.
    const Eigen::Vector2d at = goal ? *goal : f.centroid;
    Eigen::Vector2d look = f.centroid + 0.5 * f.outward - at;
    if (look.norm() < 1e-6)
      look = Eigen::Vector2d(std::cos(robot_pose.z()), std::sin(robot_pose.z()));
    FrontierView v;
    v.view.source = ViewCandidate::Source::Frontier;
    v.view.pose = Eigen::Vector3d(at.x(), at.y(), std::atan2(look.y(), look.x()));
    v.view.target_xy = f.centroid;
    v.outward = f.outward;
    v.cells = int(f.cells.size());
    v.found = goal.has_value();
    views.push_back(v);
  }
  return views;
}

FrontierPlanner::FrontierPlanner(const TExplorationParams& params)
    : ExplorationPlanner(GoalBlacklist(params.blacklist_radius_m)), m_params(params) {
  m_params.validate();
}

void FrontierPlanner::goalOutcome(const Eigen::Vector3d& goal_xyyaw, bool /*reached*/) {
  // Yamauchi: a frontier still there after the robot stood at it (glass, a dropout, a gap the
  // camera cannot see into) must not pull the robot back forever.
  m_blacklist.add(goal_xyyaw);
}

Plan FrontierPlanner::plan(const PlannerInputs& in) {
  detail::requireOctree(in, name());
  m_blacklist.tick();
  Plan plan;
  planningGrid(*in.octree, in.robot_pose, m_params.footprint_radius_m, plan.grid);
  const ReachableCells reach =
      reachableCells(plan.grid, in.robot_pose, m_params.footprint_radius_m);
  std::vector<ViewCandidate> candidates;
  for (const FrontierView& f : frontierViews(plan.grid, reach, in.robot_pose, m_params)) {
    plan.frontiers.push_back({f.view.target_xy, f.cells, f.found});
    const ViewCandidate c = detail::baselineCandidate(f.view.pose.head<2>(), f.view.pose.z(),
                                                      ViewCandidate::Source::Frontier, in);
    if (!f.found)
      plan.unreachable.push_back(c);
    else if (m_blacklist.contains(c.pose))
      plan.blacklisted.push_back(c);
    else
      candidates.push_back(c);
  }
  detail::measureInto(m_params, in, std::move(candidates), plan);
  std::stable_sort(plan.ranked.begin(), plan.ranked.end(),
                   [](const ViewCandidate& a, const ViewCandidate& b) {
                     return a.path_length_m < b.path_length_m;  // nearest frontier first
                   });
  return plan;
}

}  // namespace rasm::exploration
