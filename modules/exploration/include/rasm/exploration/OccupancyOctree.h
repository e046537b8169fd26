#pragma once
// The coarse occupancy map of section V-A: an octomap::OcTree (Hornung et al. 2013) updated from
// depth frames, its entropy over a bounded workspace, the predicted entropy reduction of a
// candidate view, and its 2-D projection for path planning.
//
// Entropy (V-A): H(m) = -sum_c [p(c) log p(c) + (1 - p(c)) log(1 - p(c))] in nats over the cells
// of the workspace at the octree's resolution; a cell the tree does not hold is unknown
// (p = 0.5, log 2 each). A leaf at a coarser depth (OctoMap prunes eight equal children into
// their parent) counts once for every workspace cell it covers, so the sum runs over the leaves,
// not the cells.
//
// Updates. A frame's rays are turned into the key sets OctoMap's insertPointCloud computes
// (computeDiscreteUpdate: endpoints discretised to cells, one ray per endpoint cell, occupied wins
// over free), then every free key gets the miss log-odds and every occupied key the hit log-odds,
// clamped. The prediction of a view builds the same key sets from the predicted depth and sums
// the entropy change those updates would make, without touching the tree.

#include <octomap/OcTree.h>

#include <Eigen/Geometry>
#include <cstdint>
#include <memory>
#include <vector>

#include "rasm/core/CameraIntrinsics.h"
#include "rasm/core/Image.h"
#include "rasm/exploration/TExplorationParams.h"

namespace mrpt::maps {
class COccupancyGridMap2D;
}

namespace rasm::exploration {

/// The workspace in cells of the octree's grid: keys [min, max] per axis (inclusive), the cells
/// whose centres lie in the params' box.
struct WorkspaceKeys {
  octomap::OcTreeKey min, max;
  std::int64_t cells() const;
  bool contains(const octomap::OcTreeKey& k) const;
};

/// The cells one predicted view's rays would update (OccupancyOctree::predictedEntropyReduction):
/// a dense box of per-cell flags around the camera, clipped to the workspace (a cell outside it
/// changes no entropy of the workspace), in place of OctoMap's hashed key sets, which cost most of
/// a prediction. Reused from view to view by one thread (only the touched cells are cleared).
class ViewCells {
 public:
  /// Empties the cells and sets their box (keys, inclusive).
  void reset(const WorkspaceKeys& box);
  /// Whether this is the first ray endpoint in cell k (`beyond`: of the rays without a return).
  bool firstEndpoint(const octomap::OcTreeKey& k, bool beyond);
  void addFree(const octomap::KeyRay& ray);
  void addOccupied(const octomap::OcTreeKey& k) { mark(k, kOccupied); }
  void finish();
  /// f(key, occupied) once per cell of the box an update reaches; occupied wins over free.
  template <typename F>
  void forEachUpdated(F&& f) const {
    for (const std::uint32_t i : m_touched) {
      const std::uint8_t s = m_state[i];
      if (s & (kFree | kOccupied)) f(keyOf(i), (s & kOccupied) != 0);
    }
  }

 private:
  static constexpr std::uint8_t kFree = 1, kOccupied = 2, kEndpoint = 4, kEndpointBeyond = 8;
  std::int64_t indexOf(const octomap::OcTreeKey& k) const;  ///< -1 outside the box
  octomap::OcTreeKey keyOf(std::uint32_t index) const;
  void mark(const octomap::OcTreeKey& k, std::uint8_t flag);

  octomap::OcTreeKey m_min;
  int m_size[3] = {0, 0, 0};
  std::vector<std::uint8_t> m_state;
  std::vector<std::uint32_t> m_touched;  ///< cells whose state is not 0, in first-touch order
  octomap::KeySet m_outside, m_outside_beyond;  ///< endpoints outside the box already cast
};

/// Binary entropy -[p log p + (1 - p) log(1 - p)] in nats (0 at p = 0 or 1).
double cellEntropy(double p);

class OccupancyOctree {
 public:
  /// Throws InputError when the params are out of range (TExplorationParams' checks).
  explicit OccupancyOctree(const TExplorationParams& params = {});
  /// A deep copy (the planner thread of an exploring run plans on a copy while mapping inserts
  /// into the original; ~1 ms per 10k leaves).
  OccupancyOctree(const OccupancyOctree& other);
  OccupancyOctree& operator=(const OccupancyOctree&) = delete;

  const TExplorationParams& params() const { return m_params; }
  const octomap::OcTree& tree() const { return *m_tree; }
  const WorkspaceKeys& workspace() const { return m_workspace; }
  /// Cells of the workspace (known or not).
  std::int64_t workspaceCells() const { return m_workspace.cells(); }

  /// Inserts one depth frame (metres, 0 = no return) seen from T_world_cam (optical frame) with
  /// intrinsics K: every pixel_stride-th pixel in x and y; returns within [min_depth_m,
  /// max_range_m] mark their cell occupied and the cells before it free; longer rays mark free
  /// space up to max_range_m; pixels without a return free space up to no_return_free_m (or
  /// nothing). Throws InputError when the image size does not match K or depth is not finite.
  void insertDepthFrame(const Image<float>& depth_m, const CameraIntrinsics& K,
                        const Eigen::Isometry3d& T_world_cam);

  /// H(m) over the workspace (nats).
  double entropy() const;

  /// The entropy reduction (nats, >= 0 up to rounding) the workspace would see if a frame with
  /// depth `predicted_depth_m` were inserted from T_world_cam: the same rays and cells as
  /// insertDepthFrame, but every pixel is used (the predicted map is rendered small: its size
  /// sets the ray count) and empty pixels count as free space up to max_range_m (the unknown
  /// beyond the map is assumed seen through). Unknown cells start from p = 0.5.
  double predictedEntropyReduction(const Eigen::Isometry3d& T_world_cam, const CameraIntrinsics& K,
                                   const Image<float>& predicted_depth_m) const;
  /// The same with the caller's cell buffer (one per thread, reused from view to view).
  double predictedEntropyReduction(const Eigen::Isometry3d& T_world_cam, const CameraIntrinsics& K,
                                   const Image<float>& predicted_depth_m, ViewCells& cells) const;

  /// Whether an occupied cell lies in a column crossed by the segment a -> b (x, y in m), between
  /// heights z_min_m and z_max_m (the cells from the one above z_min_m, as projectToGrid's band:
  /// the floor's cell is not an obstacle): a wall seen at any height, not only in the band.
  bool occupiedAlong(const Eigen::Vector2d& a, const Eigen::Vector2d& b, double z_min_m,
                     double z_max_m) const;

  /// Known cells of the workspace and their counts (for tests and reports).
  struct CellCounts {
    std::int64_t occupied = 0, free = 0, unknown = 0;
  };
  CellCounts countCells() const;

  /// The 2-D projection of the height band [band_min_z_m, band_max_z_m] over the workspace's xy,
  /// one cell per octree column: occupied (0: MRPT grids store the probability of being free)
  /// when any cell of the band is occupied, free (1) when none is and at least one is known free,
  /// unknown (0.5) otherwise.
  void projectToGrid(mrpt::maps::COccupancyGridMap2D& grid) const;

 private:
  /// The cells a frame would update into `cells` (KeySetCells or ViewCells; occupied wins over
  /// free): every stride-th pixel's ray, returns to their cells' centres, pixels without a return
  /// freeing space up to no_return_free_m.
  template <typename Cells>
  void collectUpdateCells(const Image<float>& depth_m, const CameraIntrinsics& K,
                          const Eigen::Isometry3d& T_world_cam, int stride, double no_return_free_m,
                          Cells& cells) const;
  /// The workspace's cells within range_m (plus two cells) of `origin` on every axis.
  WorkspaceKeys reachBox(const octomap::point3d& origin, double range_m) const;
  /// Cells of the workspace a leaf covers.
  std::int64_t coveredCells(const octomap::OcTree::leaf_bbx_iterator& it) const;

  TExplorationParams m_params;
  std::unique_ptr<octomap::OcTree> m_tree;
  WorkspaceKeys m_workspace;
};

}  // namespace rasm::exploration
