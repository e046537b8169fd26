#include "rasm/exploration/ViewCandidates.h"

#include "rasm/exploration/PlanningGrid.h"

#include <mrpt/math/wrap2pi.h>
#include <mrpt/nav/planners/PlannerSimple2D.h>
#include <mrpt/poses/CPose2D.h>

#include <algorithm>
#include <cmath>
#include <deque>

namespace rasm::exploration {

namespace {

bool insideGrid(const mrpt::maps::COccupancyGridMap2D& g, double x, double y) {
  return x > g.getXMin() && x < g.getXMax() && y > g.getYMin() && y < g.getYMax();
}

/// Calls f(cx, cy) for every cell whose centre is within radius_m of (x, y); false when such a
/// cell is outside the grid.
template <typename F>
bool forEachFootprintCell(const mrpt::maps::COccupancyGridMap2D& grid, double x, double y,
                          double radius_m, F&& f) {
  const double res = grid.getResolution();
  const int r = int(std::ceil(radius_m / res));
  const int cx = grid.x2idx(x), cy = grid.y2idx(y);
  for (int iy = cy - r; iy <= cy + r; ++iy)
    for (int ix = cx - r; ix <= cx + r; ++ix) {
      if (std::hypot(grid.idx2x(ix) - x, grid.idx2y(iy) - y) > radius_m) continue;
      if (ix < 0 || iy < 0 || ix >= int(grid.getSizeX()) || iy >= int(grid.getSizeY()))
        return false;
      if (!f(ix, iy)) return false;
    }
  return true;
}

ViewCandidate candidateAt(double x, double y, double yaw, ViewCandidate::Source source) {
  ViewCandidate c;
  c.source = source;
  c.pose = Eigen::Vector3d(x, y, mrpt::math::wrapToPi(yaw));
  return c;
}

}  // namespace

Eigen::Isometry3d cameraPoseOf(const Eigen::Vector3d& pose, const Eigen::Isometry3d& T_base_cam) {
  Eigen::Isometry3d T_world_base = Eigen::Isometry3d::Identity();
  T_world_base.linear() = Eigen::AngleAxisd(pose.z(), Eigen::Vector3d::UnitZ()).toRotationMatrix();
  T_world_base.translation() = Eigen::Vector3d(pose.x(), pose.y(), 0.0);
  return T_world_base * T_base_cam;
}

bool footprintFree(const mrpt::maps::COccupancyGridMap2D& grid, double x, double y,
                   double radius_m) {
  if (!insideGrid(grid, x, y)) return false;
  return forEachFootprintCell(grid, x, y, radius_m,
                              [&](int ix, int iy) { return knownFreeCell(grid.getCell(ix, iy)); });
}

void markFootprintFree(mrpt::maps::COccupancyGridMap2D& grid, double x, double y, double radius_m) {
  forEachFootprintCell(grid, x, y, radius_m, [&](int ix, int iy) {
    grid.setCell(ix, iy, 1.0f);
    return true;
  });
}

std::vector<ViewCandidate> sampleRandomViews(const mrpt::maps::COccupancyGridMap2D& grid,
                                             const TExplorationParams& params,
                                             std::mt19937_64& rng) {
  // Cells the robot can stand on (row-major: the draw depends on the seed only).
  std::vector<int> cells;
  const int nx = int(grid.getSizeX()), ny = int(grid.getSizeY());
  for (int iy = 0; iy < ny; ++iy)
    for (int ix = 0; ix < nx; ++ix)
      if (knownFreeCell(grid.getCell(ix, iy)) &&
          footprintFree(grid, grid.idx2x(ix), grid.idx2y(iy), params.footprint_radius_m))
        cells.push_back(iy * nx + ix);
  std::vector<ViewCandidate> views;
  if (cells.empty()) return views;
  std::uniform_int_distribution<std::size_t> pick(0, cells.size() - 1);
  std::uniform_real_distribution<double> heading(-M_PI, M_PI);
  for (int k = 0; k < params.random_candidates; ++k) {
    const int cell = cells[pick(rng)];
    const double yaw = heading(rng);
    views.push_back(candidateAt(grid.idx2x(cell % nx), grid.idx2y(cell / nx), yaw,
                                ViewCandidate::Source::Random));
  }
  return views;
}

std::vector<ViewCandidate> objectViews(const std::vector<segmentation::SegmentStats>& segments,
                                       const mrpt::maps::COccupancyGridMap2D& grid,
                                       const TExplorationParams& params) {
  std::vector<ViewCandidate> views;
  for (const segmentation::SegmentStats& s : segments) {
    const double largest = s.upright_extents.maxCoeff();
    if (largest < params.object_min_extent_m || largest > params.object_max_extent_m) continue;
    for (int axis = 0; axis < 2; ++axis) {  // the horizontal upright principal directions
      const Eigen::Vector2d dir = s.upright_axes.col(axis).head<2>().normalized();
      if (!dir.allFinite()) continue;
      const double reach = 0.5 * s.upright_extents[axis] + params.object_standoff_m;
      for (const double sign : {1.0, -1.0}) {
        const Eigen::Vector2d at = s.centroid.head<2>() + sign * reach * dir;
        if (!footprintFree(grid, at.x(), at.y(), params.footprint_radius_m)) continue;
        const Eigen::Vector2d look = s.centroid.head<2>() - at;  // face the centroid
        ViewCandidate c = candidateAt(at.x(), at.y(), std::atan2(look.y(), look.x()),
                                      ViewCandidate::Source::Object);
        c.segment = s.id;
        c.target_xy = s.centroid.head<2>();
        views.push_back(c);
      }
    }
  }
  return views;
}

namespace {

/// Length and heading changes of the path start -> points -> (final turn to yaw).
void measurePath(const Eigen::Vector3d& start, const std::deque<mrpt::math::TPoint2D>& path,
                 double final_yaw, ViewCandidate& c) {
  double x = start.x(), y = start.y(), heading = start.z();
  c.path_length_m = 0.0;
  c.rotation_rad = 0.0;
  for (const mrpt::math::TPoint2D& p : path) {
    const double dx = p.x - x, dy = p.y - y, len = std::hypot(dx, dy);
    if (len < 1e-9) continue;
    const double h = std::atan2(dy, dx);
    c.rotation_rad += std::abs(mrpt::math::wrapToPi(h - heading));
    c.path_length_m += len;
    x = p.x, y = p.y, heading = h;
  }
  c.rotation_rad += std::abs(mrpt::math::wrapToPi(final_yaw - heading));
}

}  // namespace

void planPaths(const mrpt::maps::COccupancyGridMap2D& grid, const Eigen::Vector3d& robot_pose,
               const TExplorationParams& params, std::vector<ViewCandidate>& candidates) {
  mrpt::nav::PlannerSimple2D planner;
  planner.robotRadius = float(params.footprint_radius_m);
  planner.occupancyThreshold = 0.5f;  // unknown (0.5) counts as an obstacle
  planner.minStepInReturnedPath = float(2.0 * grid.getResolution());
  // From the robot, or from the cell it backs off to when it stands inside the grown obstacles
  // (planningStart): that first leg is part of the path measured.
  const Eigen::Vector2d start = planningStart(grid, robot_pose, params.footprint_radius_m);
  const bool escape = (start - robot_pose.head<2>()).norm() > 1e-9;
  const mrpt::poses::CPose2D origin(start.x(), start.y(), robot_pose.z());
  const double turn_rate = params.turn_rate_degps * M_PI / 180.0;
  for (ViewCandidate& c : candidates) {
    c.reachable = false;
    if (!insideGrid(grid, c.pose.x(), c.pose.y()) ||
        !insideGrid(grid, robot_pose.x(), robot_pose.y()))
      continue;
    std::deque<mrpt::math::TPoint2D> path;
    bool not_found = true;
    planner.computePath(grid, origin, mrpt::poses::CPose2D(c.pose.x(), c.pose.y(), c.pose.z()),
                        path, not_found);
    if (not_found) continue;
    if (escape) path.push_front({start.x(), start.y()});
    c.reachable = true;
    measurePath(robot_pose, path, c.pose.z(), c);
    c.travel_time_s = c.path_length_m / params.speed_mps + c.rotation_rad / turn_rate;
  }
}

}  // namespace rasm::exploration
