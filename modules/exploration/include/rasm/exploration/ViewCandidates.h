#pragma once
// Candidate views of section V and their reachability. A candidate is an SE(2) pose of the robot
// (x, y, yaw; the paper's a in SE(2), VI) whose camera pose is the base pose composed with the
// camera's mounting pose T_base_cam (the run's [robot] mount, tracking TRobotParams::T_base_cam).
//   (a) random: uniform over the cells of the 2-D projection that are known free with the whole
//       robot footprint (a disc) known free, with a uniform heading;
//   (b) object views: for each segment of plausible object size (largest upright extent in
//       [object_min_extent_m, object_max_extent_m]), one view along each of its horizontal upright
//       principal directions, both signs, object_standoff_m beyond the segment's side, facing its
//       centroid (PCA of the segment's surfels, III / V).
// Reachability (VI: the paper filters waypoints with the robot's path planner): MRPT's
// PlannerSimple2D (wavefront on the occupancy grid, obstacles grown by the footprint radius;
// unknown cells are obstacles) from the robot's pose; candidates without a path are pruned.

#include <mrpt/maps/COccupancyGridMap2D.h>

#include <Eigen/Geometry>
#include <cstdint>
#include <random>
#include <vector>

#include "rasm/exploration/TExplorationParams.h"
#include "rasm/segmentation/SegmentTable.h"

namespace rasm::exploration {

struct ViewCandidate {
  /// Random and Object: the IG planner's (a) and (b); Frontier, Sweep: the "frontier" and
  /// "lawnmower" baselines' goals ("random" offers Random ones); Oracle: the "oracle"'s views.
  enum class Source { Random, Object, Frontier, Sweep, Oracle };
  Source source = Source::Random;
  std::uint32_t segment = 0;  ///< the segment an object view looks at
  /// Object: the centroid (x, y, m) of the segment it looks at; Frontier: the frontier's centroid.
  Eigen::Vector2d target_xy = Eigen::Vector2d::Zero();
  Eigen::Vector3d pose = Eigen::Vector3d::Zero();  ///< robot base (x m, y m, yaw rad)
  Eigen::Isometry3d T_world_cam = Eigen::Isometry3d::Identity();  ///< optical frame

  bool reachable = false;
  double path_length_m = 0.0;
  double rotation_rad = 0.0;   ///< heading changes along the path, the final turn included
  double travel_time_s = 0.0;  ///< path_length_m / speed + rotation_rad / turn rate

  double entropy_reduction = 0.0;  ///< dH (nats), V-A
  double information = 0.0;        ///< dIC (class-weighted), V-B
  /// Frontier views of "ig": the summed dH (nats) of the three views from frontier_behind_m past
  /// the frontier (ViewPlanner.cpp: what the robot sees once through it, turning from one side
  /// to the other; 0 when none was predicted).
  double entropy_behind = 0.0;
  /// IG(a) = w1 dH / max dH + w2 dIC / max dIC ("ig"); the baselines set gain = rate =
  /// 1 / (1 + path_length_m), an ordering key only.
  double gain = 0.0;
  double rate = 0.0;  ///< gain / (travel_time_s + min_travel_time_s) ("ig")
};

/// Base pose (x, y, yaw) on the floor (z = 0, base frame x forward, z up) composed with T_base_cam.
Eigen::Isometry3d cameraPoseOf(const Eigen::Vector3d& pose, const Eigen::Isometry3d& T_base_cam);

/// Every grid cell whose centre is within radius_m of (x, y) is inside the grid and known free.
bool footprintFree(const mrpt::maps::COccupancyGridMap2D& grid, double x, double y,
                   double radius_m);

/// Marks the cells under the footprint disc at (x, y) free (the robot stands there).
void markFootprintFree(mrpt::maps::COccupancyGridMap2D& grid, double x, double y, double radius_m);

/// (a) params.random_candidates random views (fewer when no cell qualifies); the same rng state
/// gives the same views.
std::vector<ViewCandidate> sampleRandomViews(const mrpt::maps::COccupancyGridMap2D& grid,
                                             const TExplorationParams& params,
                                             std::mt19937_64& rng);

/// (b) views of the object-sized segments whose footprint is free.
std::vector<ViewCandidate> objectViews(const std::vector<segmentation::SegmentStats>& segments,
                                       const mrpt::maps::COccupancyGridMap2D& grid,
                                       const TExplorationParams& params);

/// Plans a path from `robot_pose` to each candidate (PlannerSimple2D, footprint radius) and sets
/// reachable, path_length_m, rotation_rad and travel_time_s. Sequential: PlannerSimple2D keeps
/// static state while tracing its path.
void planPaths(const mrpt::maps::COccupancyGridMap2D& grid, const Eigen::Vector3d& robot_pose,
               const TExplorationParams& params, std::vector<ViewCandidate>& candidates);

}  // namespace rasm::exploration
