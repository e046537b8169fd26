#include "rasm/exploration/PlanningGrid.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <queue>

#include "rasm/exploration/ViewCandidates.h"

namespace rasm::exploration {

namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

/// 1 where a cell is blocked for the robot's centre: a non-free cell (<= 0.5) within the square of
/// r cells (PlannerSimple2D's growth), or the grid's outer ring. Separable max filter, O(n r).
std::vector<std::uint8_t> blockedCells(const mrpt::maps::COccupancyGridMap2D& grid, int r) {
  const int nx = int(grid.getSizeX()), ny = int(grid.getSizeY());
  std::vector<std::uint8_t> obstacle(std::size_t(nx) * ny), rows(obstacle.size());
  for (int iy = 0; iy < ny; ++iy)
    for (int ix = 0; ix < nx; ++ix)
      obstacle[std::size_t(iy) * nx + ix] = !(grid.getCell(ix, iy) > 0.5f);
  for (int iy = 0; iy < ny; ++iy)
    for (int ix = 0; ix < nx; ++ix) {
      std::uint8_t v = 0;
      for (int k = std::max(0, ix - r); k <= std::min(nx - 1, ix + r) && !v; ++k)
        v = obstacle[std::size_t(iy) * nx + k];
      rows[std::size_t(iy) * nx + ix] = v;
    }
  std::vector<std::uint8_t> blocked(obstacle.size());
  for (int iy = 0; iy < ny; ++iy)
    for (int ix = 0; ix < nx; ++ix) {
      std::uint8_t v = ix == 0 || iy == 0 || ix == nx - 1 || iy == ny - 1;
      for (int k = std::max(0, iy - r); k <= std::min(ny - 1, iy + r) && !v; ++k)
        v = rows[std::size_t(k) * nx + ix];
      blocked[std::size_t(iy) * nx + ix] = v;
    }
  return blocked;
}

/// The cell plans start from (planningStart): (sx, sy) when a neighbour of it is traversable,
/// else the traversable cell nearest the robot among those reached from it within
/// `escape_cells` through cells that are not obstacles themselves; (sx, sy) when none is.
std::pair<int, int> startCell(const mrpt::maps::COccupancyGridMap2D& grid,
                              const std::vector<std::uint8_t>& blocked, int sx, int sy,
                              int escape_cells) {
  const int nx = int(grid.getSizeX()), ny = int(grid.getSizeY());
  const auto inside = [&](int x, int y) { return x >= 0 && y >= 0 && x < nx && y < ny; };
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx)
      if ((dx || dy) && inside(sx + dx, sy + dy) && !blocked[std::size_t(sy + dy) * nx + sx + dx])
        return {sx, sy};
  std::vector<std::uint8_t> seen(blocked.size(), 0);
  std::queue<std::pair<int, int>> open;
  open.push({sx, sy});
  seen[std::size_t(sy) * nx + sx] = 1;
  std::pair<int, int> best{sx, sy};
  int best_d2 = std::numeric_limits<int>::max();
  while (!open.empty()) {
    const auto [cx, cy] = open.front();
    open.pop();
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        const int x = cx + dx, y = cy + dy;
        if (!inside(x, y) || std::max(std::abs(x - sx), std::abs(y - sy)) > escape_cells) continue;
        const std::size_t n = std::size_t(y) * nx + x;
        if (seen[n] || !(grid.getCell(x, y) > 0.5f)) continue;  // obstacles and unknown stop it
        seen[n] = 1;
        const int d2 = (x - sx) * (x - sx) + (y - sy) * (y - sy);
        if (!blocked[n]) {
          if (d2 < best_d2) best = {x, y}, best_d2 = d2;
          continue;  // the escape ends at the first traversable cell of a path
        }
        open.push({x, y});
      }
  }
  return best;
}

int growthCells(const mrpt::maps::COccupancyGridMap2D& grid, double footprint_radius_m) {
  return int(std::ceil(footprint_radius_m / grid.getResolution()));
}

}  // namespace

Eigen::Vector2d planningStart(const mrpt::maps::COccupancyGridMap2D& grid,
                              const Eigen::Vector3d& robot_pose, double footprint_radius_m) {
  const int sx = grid.x2idx(robot_pose.x()), sy = grid.y2idx(robot_pose.y());
  if (sx < 0 || sy < 0 || sx >= int(grid.getSizeX()) || sy >= int(grid.getSizeY()))
    return robot_pose.head<2>();
  const int r = growthCells(grid, footprint_radius_m);
  const auto [ix, iy] = startCell(grid, blockedCells(grid, r), sx, sy, 2 * r);
  if (ix == sx && iy == sy) return robot_pose.head<2>();
  return {grid.idx2x(ix), grid.idx2y(iy)};
}

namespace {
/// (0.51 reads back as 0.5: MRPT quantises log-odds.)
constexpr float kClearanceOnly = 0.55f;
}  // namespace

void unknownDoesNotGrow(mrpt::maps::COccupancyGridMap2D& grid, double footprint_radius_m) {
  const int g = int(std::ceil(footprint_radius_m / grid.getResolution()));
  const int nx = int(grid.getSizeX()), ny = int(grid.getSizeY());
  std::vector<std::uint8_t> near_free(std::size_t(nx) * ny, 0);
  for (int iy = 0; iy < ny; ++iy)
    for (int ix = 0; ix < nx; ++ix) {
      if (!knownFreeCell(grid.getCell(ix, iy))) continue;
      for (int y = std::max(0, iy - g); y <= std::min(ny - 1, iy + g); ++y)
        for (int x = std::max(0, ix - g); x <= std::min(nx - 1, ix + g); ++x)
          near_free[std::size_t(y) * nx + x] = 1;
    }
  for (int iy = 0; iy < ny; ++iy)
    for (int ix = 0; ix < nx; ++ix) {
      if (near_free[std::size_t(iy) * nx + ix] && unknownCell(grid.getCell(ix, iy)))
        grid.setCell(ix, iy, kClearanceOnly);
    }
}

void planningGrid(const OccupancyOctree& octree, const Eigen::Vector3d& robot_pose,
                  double footprint_radius_m, mrpt::maps::COccupancyGridMap2D& grid) {
  octree.projectToGrid(grid);
  // The robot stands on its footprint: those cells are free whatever the camera has seen.
  markFootprintFree(grid, robot_pose.x(), robot_pose.y(), footprint_radius_m);
  if (!octree.params().clearance_from_unknown) unknownDoesNotGrow(grid, footprint_radius_m);
}

bool ReachableCells::reachable(int ix, int iy) const {
  return inside(ix, iy) && distance_m[std::size_t(iy) * size_x + ix] < kInf;
}

float ReachableCells::distance(int ix, int iy) const {
  return inside(ix, iy) ? distance_m[std::size_t(iy) * size_x + ix] : kInf;
}

int ReachableCells::count() const {
  return int(std::count_if(distance_m.begin(), distance_m.end(), [](float d) { return d < kInf; }));
}

ReachableCells reachableCells(const mrpt::maps::COccupancyGridMap2D& grid,
                              const Eigen::Vector3d& robot_pose, double footprint_radius_m) {
  ReachableCells out;
  out.size_x = int(grid.getSizeX()), out.size_y = int(grid.getSizeY());
  out.distance_m.assign(std::size_t(out.size_x) * out.size_y, kInf);
  const int sx = grid.x2idx(robot_pose.x()), sy = grid.y2idx(robot_pose.y());
  if (!out.inside(sx, sy)) return out;
  const int r = growthCells(grid, footprint_radius_m);
  const std::vector<std::uint8_t> blocked = blockedCells(grid, r);
  // Dijkstra, 8-connected (PlannerSimple2D's wavefront weighs diagonals 3/2; exact sqrt 2 here),
  // from the robot's cell and, when the robot stands inside the grown obstacles, from the cell
  // it escapes to (planningStart).
  const float res = grid.getResolution(), diag = float(M_SQRT2) * res;
  using Item = std::pair<float, int>;
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> open;
  out.distance_m[std::size_t(sy) * out.size_x + sx] = 0.0f;
  open.push({0.0f, sy * out.size_x + sx});
  const auto [ex, ey] = startCell(grid, blocked, sx, sy, 2 * r);
  if (ex != sx || ey != sy) {
    const float d = res * float(std::hypot(ex - sx, ey - sy));
    out.distance_m[std::size_t(ey) * out.size_x + ex] = d;
    open.push({d, ey * out.size_x + ex});
  }
  while (!open.empty()) {
    const auto [d, cell] = open.top();
    open.pop();
    if (d > out.distance_m[cell]) continue;
    const int cx = cell % out.size_x, cy = cell / out.size_x;
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        const int nx = cx + dx, ny = cy + dy;
        if ((dx == 0 && dy == 0) || !out.inside(nx, ny)) continue;
        const int n = ny * out.size_x + nx;
        if (blocked[n]) continue;
        const float nd = d + (dx != 0 && dy != 0 ? diag : res);
        if (nd < out.distance_m[n]) {
          out.distance_m[n] = nd;
          open.push({nd, n});
        }
      }
  }
  return out;
}

std::optional<Eigen::Vector2d> nearestReachableCell(const mrpt::maps::COccupancyGridMap2D& grid,
                                                    const ReachableCells& reach, double x, double y,
                                                    double radius_m, double footprint_radius_m) {
  const int r = int(std::ceil(radius_m / grid.getResolution())) + 1;
  const int cx = grid.x2idx(x), cy = grid.y2idx(y);
  std::optional<Eigen::Vector2d> best;
  double best_d = std::numeric_limits<double>::infinity(), best_path = best_d;
  for (int iy = cy - r; iy <= cy + r; ++iy)
    for (int ix = cx - r; ix <= cx + r; ++ix) {
      if (!reach.reachable(ix, iy)) continue;
      const Eigen::Vector2d c(grid.idx2x(ix), grid.idx2y(iy));
      const double d = std::hypot(c.x() - x, c.y() - y);
      if (d > radius_m) continue;
      if (footprint_radius_m > 0.0 && !footprintFree(grid, c.x(), c.y(), footprint_radius_m))
        continue;
      const double path = reach.distance(ix, iy);
      if (d < best_d - 1e-9 || (d < best_d + 1e-9 && path < best_path)) {
        best = c, best_d = d, best_path = path;
      }
    }
  return best;
}

namespace {
/// Whether every cell the segment between two cell centres crosses is reachable (sampled at a
/// quarter cell).
bool lineOfSight(const ReachableCells& reach, int ax, int ay, int bx, int by) {
  const int n = 4 * std::max(std::abs(bx - ax), std::abs(by - ay));
  for (int k = 0; k <= n; ++k) {
    const double f = n == 0 ? 0.0 : double(k) / n;
    const int ix = int(std::lround(ax + f * (bx - ax))), iy = int(std::lround(ay + f * (by - ay)));
    if (!reach.reachable(ix, iy)) return false;
  }
  return true;
}

/// The cells of the shortest path from the robot (distance 0) to (gx, gy), robot first: steepest
/// descent of the distance field (strictly decreasing, so it ends).
std::vector<std::pair<int, int>> descend(const ReachableCells& reach, int gx, int gy) {
  std::vector<std::pair<int, int>> cells{{gx, gy}};
  for (;;) {
    const auto [cx, cy] = cells.back();
    const float here = reach.distance(cx, cy);
    int bx = cx, by = cy;
    float best = here;
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        const float d = reach.distance(cx + dx, cy + dy);
        if (d < best) best = d, bx = cx + dx, by = cy + dy;
      }
    if (bx == cx && by == cy) break;
    cells.emplace_back(bx, by);
  }
  std::reverse(cells.begin(), cells.end());
  return cells;
}
}  // namespace

std::vector<Eigen::Vector2i> routeCorners(const ReachableCells& reach, const Eigen::Vector2i& start,
                                          const Eigen::Vector2i& goal) {
  if (!reach.reachable(start.x(), start.y()) || !reach.reachable(goal.x(), goal.y())) return {};
  const std::vector<std::pair<int, int>> cells = descend(reach, goal.x(), goal.y());
  // Corners: from each corner the farthest path cell still in sight becomes the next one.
  std::vector<Eigen::Vector2i> corners;
  std::size_t from = 0;
  int ax = start.x(), ay = start.y();
  while (!lineOfSight(reach, ax, ay, goal.x(), goal.y())) {
    std::size_t next = from + 1;
    for (std::size_t j = cells.size() - 1; j > from + 1; --j)
      if (lineOfSight(reach, ax, ay, cells[j].first, cells[j].second)) {
        next = j;
        break;
      }
    if (next >= cells.size() - 1) break;
    from = next;
    ax = cells[from].first, ay = cells[from].second;
    corners.emplace_back(ax, ay);
  }
  return corners;
}

std::vector<Eigen::Vector2d> routeTo(const mrpt::maps::COccupancyGridMap2D& grid,
                                     const ReachableCells& reach, const Eigen::Vector2d& start,
                                     const Eigen::Vector2d& goal, double search_radius_m) {
  Eigen::Vector2i g(grid.x2idx(goal.x()), grid.y2idx(goal.y()));
  if (!reach.reachable(g.x(), g.y())) {
    const auto near = nearestReachableCell(grid, reach, goal.x(), goal.y(), search_radius_m);
    if (!near) return {};
    g = Eigen::Vector2i(grid.x2idx(near->x()), grid.y2idx(near->y()));
  }
  std::vector<Eigen::Vector2d> route;
  for (const Eigen::Vector2i& c :
       routeCorners(reach, Eigen::Vector2i(grid.x2idx(start.x()), grid.y2idx(start.y())), g))
    route.emplace_back(grid.idx2x(c.x()), grid.idx2y(c.y()));
  return route;
}

}  // namespace rasm::exploration
