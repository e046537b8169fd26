#pragma once
// The 2-D world every exploration planner plans on (ViewPlanner and the baselines share it, so a
// baseline sees exactly the free space and reachability the IG planner sees):
//   planningGrid: the octree's projection of the robot's height band (V-A) with the robot's own
//     footprint marked free (it stands there, whatever the camera has seen);
//   reachableCells: one Dijkstra over that grid from the robot, with PlannerSimple2D's model of
//     the robot (VI): a cell is traversable when it is known free and no cell within the square of
//     ceil(footprint / cell) cells around it is occupied or unknown, 8-connected moves. One field
//     answers "reachable?" and "how far?" for every cell, where planPaths runs one wavefront per
//     candidate; the baselines pick goals with it and planPaths then measures the few they offer
//     (the same path length and travel time as the IG planner's candidates).

#include <mrpt/maps/COccupancyGridMap2D.h>

#include <Eigen/Core>
#include <optional>
#include <vector>

#include "rasm/exploration/OccupancyOctree.h"

namespace rasm::exploration {

/// What a planning grid's cell holds (MRPT grids store P(free): occupied near 0, unknown 0.5,
/// known free near 1; unknownDoesNotGrow's 0.55 counts as unknown).
inline bool knownFreeCell(float p_free) {
  return p_free > 0.6f;
}
inline bool unknownCell(float p_free) {
  return p_free >= 0.4f && p_free <= 0.6f;
}

/// The octree's projection (projectToGrid) with the footprint disc at robot_pose marked free,
/// written into `grid` (an output argument: MRPT grids copy slowly; Plan::grid is filled in place).
/// Unless the octree's params say clearance_from_unknown, the unknown cells within the obstacle
/// growth of a known free cell hold 0.55: not obstacles, so the robot keeps its clearance from
/// occupied cells only, and paths still run over known free cells (a cell next to those would
/// have unknown 0.5 cells in its growth square); footprintFree and the frontiers still see them as
/// unknown (<= 0.6).
void planningGrid(const OccupancyOctree& octree, const Eigen::Vector3d& robot_pose,
                  double footprint_radius_m, mrpt::maps::COccupancyGridMap2D& grid);

/// Sets the unknown cells (P(free) in [0.4, 0.6]) within the growth square (ceil(radius / cell)
/// cells) of a known free cell (> 0.6) to 0.55: above 0.5, so neither obstacles nor grown
/// (PlannerSimple2D, reachableCells), and not above the 0.6 that footprintFree and the frontiers
/// call known free.
void unknownDoesNotGrow(mrpt::maps::COccupancyGridMap2D& grid, double footprint_radius_m);

/// Where plans start: the robot's position, or, when the grown obstacles leave its cell no
/// traversable neighbour (the robot stands closer to an obstacle than its footprint radius: after
/// a collision, or squeezed past a chair by the reactive navigator, which sees the real
/// obstacles), the centre of the nearest traversable cell within 2 growth radii that it reaches
/// through cells which are not obstacles or unknown themselves. Without this every view was
/// unreachable from such a spot and the exploring run stopped (no_reachable_views) where the
/// robot could have backed off (seen at 145 s of the office run after a collision).
Eigen::Vector2d planningStart(const mrpt::maps::COccupancyGridMap2D& grid,
                              const Eigen::Vector3d& robot_pose, double footprint_radius_m);

/// Shortest 8-connected path lengths (m) from the robot's cell over the traversable cells (and
/// from planningStart's cell, at its straight-line distance, when that differs).
struct ReachableCells {
  int size_x = 0, size_y = 0;
  std::vector<float> distance_m;  ///< row-major; +infinity where not reachable

  bool inside(int ix, int iy) const { return ix >= 0 && iy >= 0 && ix < size_x && iy < size_y; }
  bool reachable(int ix, int iy) const;
  /// Path length from the robot (+infinity when not reachable).
  float distance(int ix, int iy) const;
  /// Number of reachable cells.
  int count() const;
};

/// Traversable as PlannerSimple2D sees it: value > 0.5 (unknown 0.5 is an obstacle), the
/// obstacles grown by a square of ceil(radius / resolution) cells, the grid's outer ring excluded.
/// The robot's own cell counts as traversable (PlannerSimple2D starts there whatever it holds).
ReachableCells reachableCells(const mrpt::maps::COccupancyGridMap2D& grid,
                              const Eigen::Vector3d& robot_pose, double footprint_radius_m);

/// The centre of the reachable cell nearest (x, y) whose centre is within radius_m of it (ties:
/// the shorter path from the robot, then row-major order), and, with footprint_radius_m > 0,
/// whose footprint disc is known free (footprintFree: a goal to stand on, not only to pass);
/// none when no such cell.
std::optional<Eigen::Vector2d> nearestReachableCell(const mrpt::maps::COccupancyGridMap2D& grid,
                                                    const ReachableCells& reach, double x, double y,
                                                    double radius_m,
                                                    double footprint_radius_m = 0.0);

/// The way to `goal` (x, y) for a navigator that steers straight at its target (the reactive
/// one of section VI sees obstacles but not rooms: a goal behind a wall beside a doorway drives it
/// into the wall): the shortest path over `reach` from the robot (steepest descent of its distance
/// field from the goal's cell, or, when that cell is not reachable, from the reachable cell
/// nearest the goal within search_radius_m), cut at the corners where the line of sight over
/// reachable cells from the previous corner ends. Returns the corners in travel order, without
/// the start and the goal: empty when the robot sees the goal's cell over reachable cells, when
/// the goal is far from every reachable cell, or when the robot's cell is not in `reach`.
/// routeTo on cells: the corners (cell indices) of the path over `reach` from cell `start` to cell
/// `goal`, the distance field being `reach`'s from `start` (any grid: the oracle's free-space grid
/// too); empty when either cell is not reachable or the goal is in sight.
std::vector<Eigen::Vector2i> routeCorners(const ReachableCells& reach, const Eigen::Vector2i& start,
                                          const Eigen::Vector2i& goal);
std::vector<Eigen::Vector2d> routeTo(const mrpt::maps::COccupancyGridMap2D& grid,
                                     const ReachableCells& reach, const Eigen::Vector2d& start,
                                     const Eigen::Vector2d& goal, double search_radius_m = 1.0);
}  // namespace rasm::exploration
