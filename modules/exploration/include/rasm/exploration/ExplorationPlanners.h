#pragma once
// The four planners behind ExplorationPlanner (ExplorationPlanner.h says what each does and the
// contract). All plan on planningGrid / reachableCells (PlanningGrid.h) and measure what they
// offer with planPaths, so path lengths and travel times compare across planners. Use
// makePlanner; the classes are public for tests and tools that need their state.

#include <Eigen/Core>
#include <random>
#include <string>
#include <vector>

#include "rasm/exploration/ExplorationPlanner.h"
#include "rasm/exploration/PlanningGrid.h"
#include "rasm/exploration/ViewPlanner.h"

namespace rasm::exploration {

/// "ig_greedy": ViewPlanner (V) unchanged; candidates near a failed goal are moved to
/// Plan::blacklisted and the rest re-ranked (rankCandidates: the normalisation runs over what is
/// offered); best_entropy_reduction / best_information are the largest dH / dIC of the ranked
/// views.
class IgPlanner : public ExplorationPlanner {
 public:
  explicit IgPlanner(const TExplorationParams& params);
  std::string name() const override { return "ig_greedy"; }
  bool scoresInformation() const override { return true; }
  Plan plan(const PlannerInputs& in) override;
  /// Failed goals are blacklisted; reached ones become taken views (taken_view_* params).
  void goalOutcome(const Eigen::Vector3d& goal_xyyaw, bool reached) override;
  /// Whether `pose` repeats a taken view (within taken_view_radius_m and taken_view_heading_deg).
  bool isTakenView(const Eigen::Vector3d& pose) const;

 protected:
  TExplorationParams m_params;
  ViewPlanner m_planner;
  std::vector<Eigen::Vector3d> m_taken;  ///< reached goals (x, y, yaw)
};

/// "ig": the global planner. IgPlanner's views with the frontier views always among them
/// (frontier_candidates on: the map's edge is where the unknown rooms are), scored by the same
/// IG; then
///   weights: IG with the object term w2 dIC scaled by the map's saturation 1 - H(m) / H(m) at
///     the first plan (0 at the start, rising as the octree's entropy falls): geometric
///     exploration first, the object views of V-B weighing more as the map fills in; a frontier
///     view's dH at least tour_behind_fraction x entropy_behind (what the views past the frontier
///     would see: a doorway opens a room, the view in front of it sees one cone of it); an object
///     view's weight times the known fraction of the grid within tour_object_context_radius_m of
///     its segment (knownFraction: an object seen through a doorway waits for its room); times
///     tour_revisit_discount per view the robot has taken within tour_revisit_radius_m (the
///     predicted dH of a visited region stays high: voxels inside furniture and behind objects
///     stay unknown whatever the view, so without it the region's crumbs always beat a far room);
///   clusters: views by descending weight, each joining the first cluster whose best view lies
///     within tour_cluster_radius_m, else starting one (at most tour_max_clusters; clusters
///     below tour_min_gain_fraction of the best weight are left out). A cluster is visited at
///     its best view (the local choice);
///   tour: the order of the clusters that collects the most IG per second over the whole route
///     (solveTour, ViewTour.h), on travel times from the planning grid (reachableCells from each
///     cluster's view: path length / speed plus the turns to and from the leg's bearing / turn
///     rate; from the robot: planPaths' travel time);
///   Plan::ranked: the clusters' views in tour order, then the other views by rank.
/// The stopping rule and the mid-way switch of the loop see the same IG as with "ig_greedy".
class TourIgPlanner : public IgPlanner {
 public:
  explicit TourIgPlanner(const TExplorationParams& params);
  std::string name() const override { return "ig"; }
  Plan plan(const PlannerInputs& in) override;

 private:
  /// The factor on w2 for the tour's weights: 1 - H(m) now / H(m) at the first plan, in [0, 1].
  double objectWeight(const OccupancyOctree& octree);
  /// tour_revisit_discount ^ (taken views within tour_revisit_radius_m of pose).
  double revisitDiscount(const Eigen::Vector3d& pose) const;
  /// The tour's weight of a view (the class comment; best_* of `plan` normalise the terms).
  double tourWeight(const ViewCandidate& v, const Plan& plan,
                    const TExplorationParams& tour_params) const;
  double m_first_entropy_nats = -1.0;
};

/// The fraction of `grid`'s cells within radius_m of `at` that are known (free or occupied;
/// cells outside the grid count as unknown).
double knownFraction(const mrpt::maps::COccupancyGridMap2D& grid, const Eigen::Vector2d& at,
                     double radius_m);

/// The cluster heads of `views` (indices, by descending gains[i]; TourIgPlanner's clustering).
std::vector<int> clusterViews(const std::vector<ViewCandidate>& views,
                              const std::vector<double>& gains, double radius_m, int max_clusters,
                              double min_gain_fraction);

/// The travel-time matrix between `views` on `grid` (TourIgPlanner's legs; the diagonal is 0).
Eigen::MatrixXd legTimes(const mrpt::maps::COccupancyGridMap2D& grid,
                         const std::vector<ViewCandidate>& views, const TExplorationParams& params);

/// A frontier of the projection: 8-connected known-free cells that are 4-adjacent to unknown.
struct FrontierCluster {
  std::vector<Eigen::Vector2d> cells;  ///< cell centres (m)
  Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
  /// Unit vector from the cells towards their unknown neighbours (zero when they cancel out).
  Eigen::Vector2d outward = Eigen::Vector2d::Zero();
};

/// The frontiers of `grid` with at least min_cells cells (row-major discovery order).
/// One view per frontier of `grid` (frontier_min_cells): the base at the reachable cell nearest
/// the cluster's centroid within frontier_goal_radius_m (at the centroid when there is none:
/// `found` false), facing a point 0.5 m past the centroid on the unknown side. Only pose and
/// source (Frontier) are set.
struct FrontierView {
  ViewCandidate view;                                 ///< view.target_xy: the cluster's centroid
  int cells = 0;                                      ///< the cluster's
  Eigen::Vector2d outward = Eigen::Vector2d::Zero();  ///< the cluster's (FrontierCluster)
  bool found = false;
};
std::vector<FrontierView> frontierViews(const mrpt::maps::COccupancyGridMap2D& grid,
                                        const ReachableCells& reach,
                                        const Eigen::Vector3d& robot_pose,
                                        const TExplorationParams& params);

/// Clusters whose cells lie farther than max_radius_m (> 0) from their centroid are split in
/// two across their principal axis, recursively (pieces under min_cells dropped).
std::vector<FrontierCluster> findFrontiers(const mrpt::maps::COccupancyGridMap2D& grid,
                                           int min_cells, double max_radius_m = 0.0);

/// "frontier": nearest-frontier exploration (Yamauchi 1997). One goal per frontier cluster: the
/// reachable cell nearest its centroid within frontier_goal_radius_m, facing a point 0.5 m past
/// the centroid on the unknown side (the centroid itself when the goal is on it); ranked by path
/// length, nearest first. Goals near a visited (reached or failed) goal are blacklisted.
class FrontierPlanner : public ExplorationPlanner {
 public:
  explicit FrontierPlanner(const TExplorationParams& params);
  std::string name() const override { return "frontier"; }
  Plan plan(const PlannerInputs& in) override;
  /// Reached and failed goals alike are blacklisted.
  void goalOutcome(const Eigen::Vector3d& goal_xyyaw, bool reached) override;

 private:
  TExplorationParams m_params;
};

/// "random": one goal per plan, a uniformly drawn reachable known-free cell (footprint included)
/// not near a failed goal, with a uniform heading; std::mt19937_64(params.seed) lives as long as
/// the planner, so the same seed and the same inputs give the same sequence of goals. Empty only
/// when no such cell is reachable.
class RandomPlanner : public ExplorationPlanner {
 public:
  explicit RandomPlanner(const TExplorationParams& params);
  std::string name() const override { return "random"; }
  Plan plan(const PlannerInputs& in) override;

 private:
  TExplorationParams m_params;
  std::mt19937_64 m_rng;
};

/// "lawnmower": a boustrophedon sweep of the workspace's xy box. round(width / spacing) lanes
/// (at least one) lawnmower_spacing_m apart and centred in the box run along lawnmower_axis,
/// round(length / step) waypoints lawnmower_step_m apart and centred on each, lanes alternating
/// direction (snake order), the heading along the lane. A waypoint is reached at the reachable cell
/// nearest it within half the smaller of spacing and step (furniture or a wall may stand on the
/// exact point). plan(): from the current waypoint on in snake order (then wrapping to the start: a
/// later pass), the first pending waypoint reachable now is offered; each pending one walked past
/// as unreachable counts a skip, and after max_skips skips it is abandoned. A waypoint is done when
/// reached (goalOutcome(true)); a failed one counts a skip and the sweep moves on. Empty plan:
/// every waypoint is done or abandoned, or none is reachable now (the robot cannot move, so it
/// cannot see more). Does not use the blacklist.
class LawnmowerPlanner : public ExplorationPlanner {
 public:
  enum class State { Pending, Visited, Abandoned };
  static constexpr int kDefaultMaxSkips = 3;

  explicit LawnmowerPlanner(const TExplorationParams& params, int max_skips = kDefaultMaxSkips);
  std::string name() const override { return "lawnmower"; }
  Plan plan(const PlannerInputs& in) override;
  void goalOutcome(const Eigen::Vector3d& goal_xyyaw, bool reached) override;

  /// The sweep's waypoints (x, y, heading) in snake order, and their states.
  const std::vector<Eigen::Vector3d>& waypoints() const { return m_waypoints; }
  const std::vector<State>& states() const { return m_states; }

 private:
  void skip(std::size_t i);

  TExplorationParams m_params;
  int m_max_skips;
  std::vector<Eigen::Vector3d> m_waypoints;
  std::vector<State> m_states;
  std::vector<int> m_skips;
  std::size_t m_cursor = 0;  ///< the waypoint the sweep is at
  bool m_offered = false;    ///< m_cursor's waypoint was offered by the last plan ...
  Eigen::Vector2d m_offered_xy = Eigen::Vector2d::Zero();  ///< ... at this cell
};

}  // namespace rasm::exploration
