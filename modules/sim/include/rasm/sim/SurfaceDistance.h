#pragma once
// How far the points of a map lie from a world's ground-truth surface (`rasm sim check-map`,
// docs/sim.md "Checking a map"): surfels fused at wrong poses (a tracking failure, a kidnapping)
// float away from the surfaces they were measured on.
//
// The distance of a point p to the surface is bounded from above by ray casts (RayScene) from p
// along +/- its normal, the six axis directions and the eight cube diagonals: the nearest hit
// is a point of the surface, so the bound never underestimates. It is exact when the nearest
// surface point lies along one of these rays, in particular for a point off a face along that
// face's normal (what a surfel's normal gives when it agrees with the surface). It may
// overestimate where the nearest surface point is on an edge or corner that none of the rays
// passes through (a point beside a convex edge, outside both faces' extents: the rays hit the
// faces further away, or miss), and for a point whose normal is wrong and whose face is not
// along an axis or diagonal. So a count of points beyond a distance is an upper bound.

#include <Eigen/Core>
#include <cstddef>
#include <vector>

#include "rasm/sim/RayScene.h"

namespace rasm::sim {

struct SurfaceDistanceStats {
  std::size_t points = 0;
  std::size_t within = 0;  ///< distance <= max_dist_m
  std::size_t beyond = 0;  ///< distance > max_dist_m (or no surface within cap_m)
  double max_dist_m = 0.0, cap_m = 0.0;
  double fraction_beyond = 0.0;
  /// Percentiles and mean of the distance, each distance capped at cap_m (points with no surface
  /// within cap_m count as cap_m).
  double p50_m = 0.0, p90_m = 0.0, p95_m = 0.0, p99_m = 0.0, max_m = 0.0, mean_m = 0.0;
};

/// Upper bound of the distance (m) from `p` to the nearest surface of `scene` (see above), or
/// cap_m when no ray hits within cap_m. `n` may be zero or non-finite (then only the fixed
/// directions are cast).
float surfaceDistanceBound(const RayScene& scene, const Eigen::Vector3f& p,
                           const Eigen::Vector3f& n, float cap_m);

/// surfaceDistanceBound of every point (parallel over points; the same result for any thread
/// count). `normals` is empty or as long as `positions`. Optionally returns the per-point
/// distances (capped).
SurfaceDistanceStats surfaceDistanceStats(const RayScene& scene,
                                          const std::vector<Eigen::Vector3f>& positions,
                                          const std::vector<Eigen::Vector3f>& normals,
                                          double max_dist_m, double cap_m = 0.5,
                                          std::vector<float>* distances_m = nullptr);

}  // namespace rasm::sim
