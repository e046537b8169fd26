#pragma once
// One interface for the exploration planners: the IG planner of
// section V and the baselines it is compared with on the same worlds, octree, projection,
// reachability and budget. makePlanner builds the one [exploration] planner names:
//   "ig"        the global planner: ViewPlanner's views (V) with frontier views always among
//               them, clustered, visited in the order of a tour that collects the most IG per
//               second over the whole route (TourIgPlanner, ViewTour.h);
//   "ig_greedy" ViewPlanner (V) alone: the best single next view by IG per second (a baseline),
//               plus a GoalBlacklist of failed goals;
//   "frontier"  nearest-frontier exploration (Yamauchi 1997, "A frontier-based approach for
//               autonomous exploration") on the projection: frontier cells are known-free cells
//               4-adjacent to unknown ones, clustered 8-connected; goal = the reachable cell
//               nearest each cluster's centroid, facing the unknown side; nearest path first;
//   "random"    a random reachable known-free cell and heading (params.seed);
//   "lawnmower" a boustrophedon sweep of the workspace's xy (lanes lawnmower_spacing_m apart,
//               waypoints every lawnmower_step_m, snake order), unreachable waypoints retried
//               on later passes.
// Contract: plan() returns the offered goals best first in Plan::ranked; an EMPTY ranked list
// means the planner has nothing left (a baseline is done; for "ig" no reachable view remains).
// The caller reports each goal it drove to through goalOutcome(): failed goals are blacklisted
// (all planners), reached ones too for "frontier" (Yamauchi: a frontier that stays a frontier
// after the robot stood at it is not returned to), reached waypoints are done for "lawnmower".
// Planners keep state between plans (blacklist, rng, sweep progress): one instance per run, not
// thread safe.

#include <mrpt/maps/COccupancyGridMap2D.h>

#include <Eigen/Geometry>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "rasm/core/CameraIntrinsics.h"
#include "rasm/exploration/GoalBlacklist.h"
#include "rasm/exploration/ObjectInformation.h"
#include "rasm/exploration/OccupancyOctree.h"
#include "rasm/exploration/TExplorationParams.h"
#include "rasm/exploration/ViewCandidates.h"
#include "rasm/segmentation/SegmentTable.h"
#include "rasm/surfel_map/SurfelStore.h"

namespace rasm::exploration {

struct PlannerInputs {
  const maps::SurfelStore* store = nullptr;  ///< snapshot with its spatial index rebuilt ("ig")
  const std::vector<segmentation::SegmentStats>* segments = nullptr;  ///< ("ig")
  const OccupancyOctree* octree = nullptr;                            ///< every planner
  Eigen::Vector3d robot_pose = Eigen::Vector3d::Zero();               ///< x, y, yaw of the base now
  Eigen::Isometry3d T_base_cam = Eigen::Isometry3d::Identity();       ///< the camera mount
  CameraIntrinsics K;   ///< the camera's (predicted maps use it scaled to the predict size)
  ViewInfoModel model;  ///< fusion's IC parameters and the map's bin layout
  /// The goal (x, y, yaw) the robot is driving to, if any: "ig" and "ig_greedy" score it in the
  /// same plan, with the same formula and normalisation (Plan::current_goal), so the loop can
  /// ask whether the best new view is clearly better than finishing it.
  std::optional<Eigen::Vector3d> current_goal;
};

/// A frontier of the planning grid as a plan saw it (exploration.json, for the reader).
struct FrontierSummary {
  Eigen::Vector2d centroid = Eigen::Vector2d::Zero();  ///< m
  int cells = 0;
  bool found = false;  ///< a reachable cell for its view was found (frontierViews)
};

struct Plan {
  std::vector<ViewCandidate> ranked;  ///< reachable candidates, best first
  /// The frontiers the plan's frontier views came from ("ig", "frontier").
  std::vector<FrontierSummary> frontiers;
  std::vector<ViewCandidate> unreachable;  ///< pruned by the path planner
  /// Candidates dropped because they lie within blacklist_radius_m of a blacklisted goal.
  std::vector<ViewCandidate> blacklisted;
  mrpt::maps::COccupancyGridMap2D grid;  ///< the projection planned on (robot footprint free)
  /// Largest dH (nats) and dIC over `ranked` ("ig" only; 0 for the baselines): what the best
  /// views could still gain, for a stopping rule.
  double best_entropy_reduction = 0.0, best_information = 0.0;
  /// PlannerInputs::current_goal scored like the ranked views ("ig", "ig_greedy"; reachable
  /// false and gain 0 when no path leads there now); empty for the baselines.
  std::optional<ViewCandidate> current_goal;
  /// "ig": the number of view clusters the tour visits (ranked starts with them, in tour order).
  std::size_t tour_clusters = 0;
  /// "ig": the tour's weight of each of those clusters (in tour order; TourIgPlanner).
  std::vector<double> tour_weights;
  /// Reachable candidates a coarse prediction left out of the full one ([exploration]
  /// predict_screen_keep; not in ranked).
  std::size_t screened_out = 0;
  /// The way to ranked.front() (waypoints before it, as routeTo), when the planner knows the free
  /// space better than `grid` (the oracle knows the world's); otherwise the loop routes on `grid`.
  std::optional<std::vector<Eigen::Vector2d>> route;
};

class ExplorationPlanner {
 public:
  virtual ~ExplorationPlanner() = default;
  /// "ig", "ig_greedy", "frontier", "random" or "lawnmower" (the [exploration] planner value).
  virtual std::string name() const = 0;
  /// Whether the plans carry the paper's IG (best_entropy_reduction / best_information and
  /// current_goal are set: the loop's stopping rule and mid-way switch use them).
  virtual bool scoresInformation() const { return false; }
  /// Goals for the robot at in.robot_pose, best first; empty ranked = nothing left. Throws
  /// InputError when an input the planner needs is null.
  virtual Plan plan(const PlannerInputs& in) = 0;
  /// The outcome of driving to goal_xyyaw (a pose from a previous plan's ranked list). Default:
  /// failed goals are blacklisted.
  virtual void goalOutcome(const Eigen::Vector3d& goal_xyyaw, bool reached);

  /// The goals this planner will not offer again (the lawnmower keeps its own waypoint states
  /// instead and leaves it empty).
  const GoalBlacklist& blacklist() const { return m_blacklist; }

 protected:
  explicit ExplorationPlanner(const GoalBlacklist& blacklist = GoalBlacklist())
      : m_blacklist(blacklist) {}
  GoalBlacklist m_blacklist;
};

/// The planner params.planner names, built with params. Throws InputError naming
/// [exploration] planner and the accepted names for an unknown name (and for any other bad
/// value, as TExplorationParams::validate).
std::unique_ptr<ExplorationPlanner> makePlanner(const TExplorationParams& params);

}  // namespace rasm::exploration
