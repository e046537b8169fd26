#pragma once
// What one simulated view offers a depth tracker (the view check of the generated hand-held
// trajectories, docs/sim.md "Generated worlds"). A depth-only point-to-plane ICP constrains the
// translation only along the normals it sees: a view of one plane (the floor) leaves three of
// the six directions free, two planes (floor and a wall) one. So a view needs, besides enough
// valid pixels, geometry that is not structure (objects, furniture) and normals spread over
// three directions.

#include "rasm/core/RgbdFrame.h"

namespace rasm::sim {

struct ViewStats {
  /// Pixels with a depth in (0, max_depth_m], over all pixels.
  double valid_fraction = 0.0;
  /// Of the valid pixels, those whose ray hits an object or furniture: gt_instance != 0 and
  /// gt_class not structure (floor 85, wall 86, ceiling 87, door 88; SimClasses.h). 0 when the
  /// frame has no labels.
  double object_fraction = 0.0;
  /// Smallest eigenvalue of the mean n n^T over the unit normals of the valid pixels (normals
  /// from the depth image by central differences, where the four neighbours lie on one smooth
  /// surface, within 5 % of the pixel's depth): 0 when all normals lie in a plane (one or two
  /// planes seen: a translation the normals do not constrain), at most 1/3 (normals spread
  /// evenly over three orthogonal directions). It is the smallest eigenvalue of the translational
  /// block of the point-to-plane ICP normal equations per pixel. With noisy depth the finite
  /// differences scatter the normals and raise it: compare it on exact depth.
  double normal_min_eig = 0.0;
  /// Smallest eigenvalue of the whole point-to-plane system per pixel, rows [n; p x n / d]
  /// (camera frame, d the mean depth), normalised as the tracker's degeneracy test
  /// (TrackingResult::min_eigenvalue). For information: the narrow field of view couples
  /// translation and rotation, so it is about 0.01 for most views.
  double icp_min_eig = 0.0;
  /// Pixels that gave a normal, over all pixels.
  double normal_fraction = 0.0;
};

/// Statistics of `frame` (depth_m and, when present, gt_instance / gt_class; intrinsics).
ViewStats viewStats(const RgbdFrame& frame, double max_depth_m = 100.0);

}  // namespace rasm::sim
