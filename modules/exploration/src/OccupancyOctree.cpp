#include "rasm/exploration/OccupancyOctree.h"

#include <mrpt/maps/COccupancyGridMap2D.h>

#include <algorithm>
#include <cmath>
#include <iterator>
#include <string>
#include <vector>

#include "rasm/core/Error.h"

namespace rasm::exploration {

namespace {

/// Where castRays puts its keys: the free and occupied key sets of OctoMap's computeUpdate (the
/// tree's insertion: every key, in or out of the workspace).
struct KeySetCells {
  octomap::KeySet free, occupied, endpoints, endpoints_beyond;
  bool firstEndpoint(const octomap::OcTreeKey& k, bool beyond) {
    return (beyond ? endpoints_beyond : endpoints).insert(k).second;
  }
  void addFree(const octomap::KeyRay& ray) { free.insert(ray.begin(), ray.end()); }
  void addOccupied(const octomap::OcTreeKey& k) { occupied.insert(k); }
  /// Occupied wins over free.
  void finish() {
    for (auto it = free.begin(); it != free.end();)
      it = occupied.count(*it) ? free.erase(it) : std::next(it);
  }
};

/// Rays from `origin` to the points of `scan` into `cells`, as OctoMap's
/// OccupancyOcTreeBase::computeUpdate without a bounding box (a ray longer than max_range_m frees
/// its first max_range_m only, and `no_endpoint` rays free space and mark nothing occupied), with
/// a KeyRay of the caller's: OctoMap's own keeps one ray buffer in the tree, so two threads
/// casting through one tree (the planner's candidates, ViewPlanner.cpp) would share it.
template <typename Cells>
void castRays(const octomap::OcTree& tree, const octomap::Pointcloud& scan,
              const octomap::point3d& origin, double max_range_m, bool no_endpoint, Cells& cells) {
  octomap::KeyRay ray;
  for (std::size_t i = 0; i < scan.size(); ++i) {
    const octomap::point3d& p = scan[i];
    if (max_range_m < 0.0 || (p - origin).norm() <= max_range_m) {
      if (tree.computeRayKeys(origin, p, ray)) cells.addFree(ray);
      octomap::OcTreeKey key;
      if (!no_endpoint && tree.coordToKeyChecked(p, key)) cells.addOccupied(key);
    } else {
      const octomap::point3d end = origin + (p - origin).normalized() * float(max_range_m);
      if (tree.computeRayKeys(origin, end, ray)) cells.addFree(ray);
    }
  }
}

/// castRays to the centres of the distinct cells of the points, as OctoMap's
/// computeDiscreteUpdate (the first point of a cell stands for it). Rays without a return
/// (`no_endpoint`) are thinned the same way: rays to one far cell free the same cells.
template <typename Cells>
void castRaysToCells(const octomap::OcTree& tree, const octomap::Pointcloud& scan,
                     const octomap::point3d& origin, double max_range_m, bool no_endpoint,
                     Cells& cells) {
  octomap::Pointcloud centres;
  centres.reserve(scan.size());
  for (std::size_t i = 0; i < scan.size(); ++i) {
    const octomap::OcTreeKey k = tree.coordToKey(scan[i]);
    if (cells.firstEndpoint(k, no_endpoint)) centres.push_back(tree.keyToCoord(k));
  }
  castRays(tree, centres, origin, max_range_m, no_endpoint, cells);
}

/// Log-odds after one update of `delta`, clamped as OctoMap's updateNode does.
float updatedLogOdds(float l, float delta, float clamp_min, float clamp_max) {
  return std::min(std::max(l + delta, clamp_min), clamp_max);
}

}  // namespace

double cellEntropy(double p) {
  if (!(p > 0.0 && p < 1.0)) return 0.0;
  return -(p * std::log(p) + (1.0 - p) * std::log(1.0 - p));
}

std::int64_t WorkspaceKeys::cells() const {
  std::int64_t n = 1;
  for (int a = 0; a < 3; ++a) n *= std::int64_t(max[a]) - std::int64_t(min[a]) + 1;
  return n;
}

bool WorkspaceKeys::contains(const octomap::OcTreeKey& k) const {
  for (int a = 0; a < 3; ++a)
    if (k[a] < min[a] || k[a] > max[a]) return false;
  return true;
}

OccupancyOctree::OccupancyOctree(const OccupancyOctree& other)
    : m_params(other.m_params),
      m_tree(std::make_unique<octomap::OcTree>(*other.m_tree)),
      m_workspace(other.m_workspace) {}

OccupancyOctree::OccupancyOctree(const TExplorationParams& params)
    : m_params(params), m_tree(std::make_unique<octomap::OcTree>(params.resolution_m)) {
  m_params.validate();
  m_tree->setProbHit(m_params.prob_hit);
  m_tree->setProbMiss(m_params.prob_miss);
  m_tree->setClampingThresMin(m_params.clamp_min);
  m_tree->setClampingThresMax(m_params.clamp_max);
  // Cells whose centres lie in the box: centre of key k is (k - 2^15 + 0.5) res on each axis.
  const double res = m_params.resolution_m;
  const double lo[3] = {m_params.workspace_min_x_m, m_params.workspace_min_y_m,
                        m_params.workspace_min_z_m};
  const double hi[3] = {m_params.workspace_max_x_m, m_params.workspace_max_y_m,
                        m_params.workspace_max_z_m};
  for (int a = 0; a < 3; ++a) {
    const double first = std::ceil(lo[a] / res - 0.5), last = std::floor(hi[a] / res - 0.5);
    if (last < first || std::abs(first) > 30000 || std::abs(last) > 30000)
      throwInputError("[exploration] workspace", "holds no cell or exceeds the octree's range");
    m_workspace.min[a] = octomap::key_type(first + 32768);
    m_workspace.max[a] = octomap::key_type(last + 32768);
  }
}

template <typename Cells>
void OccupancyOctree::collectUpdateCells(const Image<float>& depth_m, const CameraIntrinsics& K,
                                         const Eigen::Isometry3d& T_world_cam, int stride,
                                         double no_return_free_m, Cells& cells) const {
  if (depth_m.width() != K.width || depth_m.height() != K.height)
    throwInputError("depth image", std::to_string(depth_m.width()) + "x" +
                                       std::to_string(depth_m.height()) +
                                       " does not match the intrinsics " + K.toString());
  const Eigen::Vector3d o = T_world_cam.translation();
  const octomap::point3d origin(float(o.x()), float(o.y()), float(o.z()));
  const double beyond = no_return_free_m + 2.0 * m_params.resolution_m;  // truncated to the range
  octomap::Pointcloud returns, no_returns;
  for (int y = 0; y < K.height; y += stride)
    for (int x = 0; x < K.width; x += stride) {
      const float z = depth_m(x, y);
      if (!std::isfinite(z) || z < 0.0f)
        throwInputError("depth image pixel (" + std::to_string(x) + ", " + std::to_string(y) + ")",
                        "depth must be finite and >= 0");
      const Eigen::Vector3d ray((x - K.cx) / K.fx, (y - K.cy) / K.fy, 1.0);
      Eigen::Vector3d p;
      if (z > 0.0f && z >= m_params.min_depth_m) {
        p = T_world_cam * (ray * double(z));
        returns.push_back(float(p.x()), float(p.y()), float(p.z()));
      } else if (z == 0.0f && no_return_free_m > 0.0) {
        p = T_world_cam * (ray.normalized() * beyond);
        no_returns.push_back(float(p.x()), float(p.y()), float(p.z()));
      }
    }
  castRaysToCells(*m_tree, returns, origin, m_params.max_range_m, false, cells);
  castRaysToCells(*m_tree, no_returns, origin, no_return_free_m, true, cells);
  cells.finish();
}

void OccupancyOctree::insertDepthFrame(const Image<float>& depth_m, const CameraIntrinsics& K,
                                       const Eigen::Isometry3d& T_world_cam) {
  KeySetCells cells;
  collectUpdateCells(depth_m, K, T_world_cam, m_params.pixel_stride, m_params.no_return_free_m,
                     cells);
  // As OccupancyOcTreeBase::insertPointCloud: free first, then occupied.
  for (const auto& k : cells.free) m_tree->updateNode(k, false);
  for (const auto& k : cells.occupied) m_tree->updateNode(k, true);
}

std::int64_t OccupancyOctree::coveredCells(const octomap::OcTree::leaf_bbx_iterator& it) const {
  const double half = 0.5 * it.getSize() - 0.5 * m_params.resolution_m;
  const octomap::point3d c = it.getCoordinate();
  std::int64_t n = 1;
  for (int a = 0; a < 3; ++a) {
    const std::int64_t lo =
        std::max<std::int64_t>(m_tree->coordToKey(c(a) - half), m_workspace.min[a]);
    const std::int64_t hi =
        std::min<std::int64_t>(m_tree->coordToKey(c(a) + half), m_workspace.max[a]);
    if (hi < lo) return 0;
    n *= hi - lo + 1;
  }
  return n;
}

double OccupancyOctree::entropy() const {
  // V-A: unknown cells at p = 0.5 contribute log 2 each; a known leaf h(p) per covered cell.
  std::int64_t known = 0;
  double h_known = 0.0;
  for (auto it = m_tree->begin_leafs_bbx(m_workspace.min, m_workspace.max),
            end = m_tree->end_leafs_bbx();
       it != end; ++it) {
    const std::int64_t n = coveredCells(it);
    known += n;
    h_known += double(n) * cellEntropy(it->getOccupancy());
  }
  return double(workspaceCells() - known) * std::log(2.0) + h_known;
}

OccupancyOctree::CellCounts OccupancyOctree::countCells() const {
  CellCounts c;
  for (auto it = m_tree->begin_leafs_bbx(m_workspace.min, m_workspace.max),
            end = m_tree->end_leafs_bbx();
       it != end; ++it)
    (m_tree->isNodeOccupied(*it) ? c.occupied : c.free) += coveredCells(it);
  c.unknown = workspaceCells() - c.occupied - c.free;
  return c;
}

void ViewCells::reset(const WorkspaceKeys& box) {
  for (int a = 0; a < 3; ++a) {
    m_min[a] = box.min[a];
    m_size[a] = int(box.max[a]) - int(box.min[a]) + 1;
  }
  const std::size_t n = std::size_t(m_size[0]) * m_size[1] * m_size[2];
  if (m_state.size() < n) {
    m_state.assign(n, 0);
  } else {
    for (const std::uint32_t i : m_touched) m_state[i] = 0;
  }
  m_touched.clear();
}

std::int64_t ViewCells::indexOf(const octomap::OcTreeKey& k) const {
  std::int64_t i = 0;
  for (int a = 2; a >= 0; --a) {
    const int d = int(k[a]) - int(m_min[a]);
    if (d < 0 || d >= m_size[a]) return -1;
    i = i * m_size[a] + d;
  }
  return i;
}

octomap::OcTreeKey ViewCells::keyOf(std::uint32_t index) const {
  octomap::OcTreeKey k;
  for (int a = 0; a < 3; ++a) {
    k[a] = octomap::key_type(int(m_min[a]) + int(index % std::uint32_t(m_size[a])));
    index /= std::uint32_t(m_size[a]);
  }
  return k;
}

void ViewCells::mark(const octomap::OcTreeKey& k, std::uint8_t flag) {
  const std::int64_t i = indexOf(k);
  if (i < 0) return;  // outside the box: changes no entropy of the workspace
  std::uint8_t& s = m_state[std::size_t(i)];
  if (s == 0) m_touched.push_back(std::uint32_t(i));
  s |= flag;
}

bool ViewCells::firstEndpoint(const octomap::OcTreeKey& k, bool beyond) {
  const std::uint8_t flag = beyond ? kEndpointBeyond : kEndpoint;
  const std::int64_t i = indexOf(k);
  if (i < 0) {  // a ray to a cell outside the box may still cross it: keep it, once per cell
    return (beyond ? m_outside_beyond : m_outside).insert(k).second;
  }
  const bool first = !(m_state[std::size_t(i)] & flag);
  mark(k, flag);
  return first;
}

void ViewCells::addFree(const octomap::KeyRay& ray) {
  for (const auto& k : ray) mark(k, kFree);
}

void ViewCells::finish() {
  m_outside.clear();
  m_outside_beyond.clear();
}

/// The box of cells within reach of rays of `range_m` from `origin`, clipped to the workspace.
WorkspaceKeys OccupancyOctree::reachBox(const octomap::point3d& origin, double range_m) const {
  const int reach = int(std::ceil(range_m / m_params.resolution_m)) + 2;
  const octomap::OcTreeKey c = m_tree->coordToKey(origin);
  WorkspaceKeys box;
  for (int a = 0; a < 3; ++a) {
    box.min[a] = octomap::key_type(std::max(int(m_workspace.min[a]), int(c[a]) - reach));
    box.max[a] = octomap::key_type(std::min(int(m_workspace.max[a]), int(c[a]) + reach));
    if (box.max[a] < box.min[a]) box.max[a] = box.min[a];  // (origin far outside: nothing inside)
  }
  return box;
}

double OccupancyOctree::predictedEntropyReduction(const Eigen::Isometry3d& T_world_cam,
                                                  const CameraIntrinsics& K,
                                                  const Image<float>& predicted_depth_m,
                                                  ViewCells& cells) const {
  const Eigen::Vector3d o = T_world_cam.translation();
  cells.reset(
      reachBox(octomap::point3d(float(o.x()), float(o.y()), float(o.z())), m_params.max_range_m));
  collectUpdateCells(predicted_depth_m, K, T_world_cam, 1, m_params.max_range_m, cells);
  const float lo = m_tree->getClampingThresMinLog(), hi = m_tree->getClampingThresMaxLog();
  const float miss = m_tree->getProbMissLog(), hit = m_tree->getProbHitLog();
  // Unknown cells (the most of a view into new space) at p = 0.5: one reduction each.
  const double h_unknown = cellEntropy(0.5);
  const double unknown_free =
      h_unknown - cellEntropy(octomap::probability(updatedLogOdds(0.0f, miss, lo, hi)));
  const double unknown_occupied =
      h_unknown - cellEntropy(octomap::probability(updatedLogOdds(0.0f, hit, lo, hi)));
  double sum = 0.0;
  cells.forEachUpdated([&](const octomap::OcTreeKey& k, bool occupied) {
    if (!m_workspace.contains(k)) return;
    const octomap::OcTreeNode* node = m_tree->search(k);
    if (!node) {
      sum += occupied ? unknown_occupied : unknown_free;
      return;
    }
    const float l = node->getLogOdds();
    sum += cellEntropy(octomap::probability(l)) -
           cellEntropy(octomap::probability(updatedLogOdds(l, occupied ? hit : miss, lo, hi)));
  });
  return sum;
}

double OccupancyOctree::predictedEntropyReduction(const Eigen::Isometry3d& T_world_cam,
                                                  const CameraIntrinsics& K,
                                                  const Image<float>& predicted_depth_m) const {
  ViewCells cells;
  return predictedEntropyReduction(T_world_cam, K, predicted_depth_m, cells);
}

bool OccupancyOctree::occupiedAlong(const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                                    double z_min_m, double z_max_m) const {
  const double res = m_params.resolution_m;
  const int steps = std::max(1, int(std::ceil(2.0 * (b - a).norm() / res)));  // half a cell
  for (int i = 0; i <= steps; ++i) {
    const Eigen::Vector2d p = a + (b - a) * (double(i) / steps);
    for (double z = z_min_m + 0.5 * res; z <= z_max_m; z += res) {  // (cells, as projectToGrid)
      const octomap::OcTreeNode* node = m_tree->search(p.x(), p.y(), z);
      if (node && m_tree->isNodeOccupied(node)) return true;
    }
  }
  return false;
}

void OccupancyOctree::projectToGrid(mrpt::maps::COccupancyGridMap2D& grid) const {
  const double res = m_params.resolution_m;
  const auto coord = [&](octomap::key_type k) { return (double(k) - 32768.0) * res; };
  const int nx = m_workspace.max[0] - m_workspace.min[0] + 1;
  const int ny = m_workspace.max[1] - m_workspace.min[1] + 1;
  grid.setSize(float(coord(m_workspace.min[0])), float(coord(m_workspace.max[0]) + res),
               float(coord(m_workspace.min[1])), float(coord(m_workspace.max[1]) + res), float(res),
               0.5f);
  // Per column: 2 = an occupied cell in the band, 1 = only free cells seen, 0 = unknown.
  std::vector<std::uint8_t> column(std::size_t(nx) * ny, 0);
  octomap::OcTreeKey band_min = m_workspace.min, band_max = m_workspace.max;
  band_min[2] = std::max(band_min[2], m_tree->coordToKey(m_params.band_min_z_m + 0.5 * res));
  band_max[2] = std::min(band_max[2], m_tree->coordToKey(m_params.band_max_z_m - 0.5 * res));
  for (auto it = m_tree->begin_leafs_bbx(band_min, band_max), end = m_tree->end_leafs_bbx();
       it != end; ++it) {
    const std::uint8_t v = m_tree->isNodeOccupied(*it) ? 2 : 1;
    const double half = 0.5 * it.getSize() - 0.5 * res;
    const octomap::point3d c = it.getCoordinate();
    const int x0 = std::max(0, int(m_tree->coordToKey(c.x() - half)) - int(m_workspace.min[0]));
    const int x1 =
        std::min(nx - 1, int(m_tree->coordToKey(c.x() + half)) - int(m_workspace.min[0]));
    const int y0 = std::max(0, int(m_tree->coordToKey(c.y() - half)) - int(m_workspace.min[1]));
    const int y1 =
        std::min(ny - 1, int(m_tree->coordToKey(c.y() + half)) - int(m_workspace.min[1]));
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x) {
        std::uint8_t& col = column[std::size_t(y) * nx + x];
        col = std::max(col, v);
      }
  }
  for (int y = 0; y < std::min(ny, int(grid.getSizeY())); ++y)
    for (int x = 0; x < std::min(nx, int(grid.getSizeX())); ++x) {
      const std::uint8_t col = column[std::size_t(y) * nx + x];
      if (col != 0) grid.setCell(x, y, col == 2 ? 0.0f : 1.0f);
    }
}

}  // namespace rasm::exploration
