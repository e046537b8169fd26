#pragma once
// Per-segment statistics of the map (III; read by classification, IV, and exploration, V-B):
// surfel counts, centroid, PCA axes and extents, axis-aligned bounding box, last-seen time.
//
// Identity: statistics are computed from the surfel arrays by segment label, so they survive
// fusion's compaction and re-sorting (which move surfels, not their labels); labels change only
// by merging and remapping, which the segmentation stage applies and publishes (its remap
// table). compute() is two passes over the map (O(N), the first parallel); the stage runs it every
// remap_every_n_frames frames and at the end of a run.

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "rasm/surfel_map/SurfelArrays.h"

namespace rasm::segmentation {

struct SegmentStats {
  std::uint32_t id = 0;
  int surfels = 0;
  int stable_surfels = 0;
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  /// Principal axes (columns, unit), by decreasing variance; right-handed.
  Eigen::Matrix3d axes = Eigen::Matrix3d::Identity();
  /// Extent of the surfel centres along each axis (m): between the 1st and 99th percentile of
  /// their projections (256-bin histograms; a few stray surfels do not stretch it).
  Eigen::Vector3d extents = Eigen::Vector3d::Zero();
  /// The upright box of a ground robot's world (z up): the principal directions of the
  /// horizontal spread (columns 0, 1, unit, horizontal, by decreasing variance) and +z, with the
  /// extents along them (same percentiles). PCA of the faces a camera saw tilts `axes` off an
  /// upright object's sides; these follow them.
  Eigen::Matrix3d upright_axes = Eigen::Matrix3d::Identity();
  Eigen::Vector3d upright_extents = Eigen::Vector3d::Zero();
  /// The centre of that upright box: the middle of the same percentile range on each axis (world).
  Eigen::Vector3d upright_centre = Eigen::Vector3d::Zero();
  Eigen::Vector3d bbox_min = Eigen::Vector3d::Zero(), bbox_max = Eigen::Vector3d::Zero();
  float last_seen = 0.0f;  ///< latest t_last of its surfels (map time, s)
};

class SegmentTable {
 public:
  /// Recomputes every segment with at least one live surfel.
  void compute(const maps::SurfelArrays& surfels);
  /// Sorted by id.
  const std::vector<SegmentStats>& segments() const { return m_segments; }
  const SegmentStats* find(std::uint32_t id) const;
  /// Renames the segments after a relabelling of the map (new = table[old]; 0 or out of range:
  /// dropped). Merged labels are not combined: compute() again after merges.
  void renumber(const std::vector<std::uint32_t>& table);
  /// Largest label in the map at the last compute().
  std::uint32_t maxLabel() const { return m_max_label; }

 private:
  std::vector<SegmentStats> m_segments;
  std::uint32_t m_max_label = 0;
};

/// The table that renumbers the labels in use (surfel count > 0) to 1..K in increasing order
/// (new = table[old], 0 for unused labels), for SurfelStore::relabelSegments.
std::vector<std::uint32_t> denseRelabelling(const SegmentTable& table);

}  // namespace rasm::segmentation
