#pragma once
// Random trajectory specs for a generated world (`rasm sim generate`, docs/sim.md):
//  - hand-held: keyframes every 3-5 s at 1.2-1.7 m, each looking at furniture or objects 1-3 m
//    away, 20-30 s; the fast variant holds and swings about the camera's x, y and z axes with
//    peaks of 120-150 deg/s, pivoting around look-at targets on objects and furniture;
//  - robot: a loop through the world's free area with turns in place; the fast variant turns at
//    90 deg/s and adds a spur with a 180 deg turn.
// In a flat (WorldLayout::Flat) the robot loops along the hallway (GeneratedWorld::free_area, so it
// starts there) and the hand-held camera walks in one room, the one with the most view targets.
// Every spec is checked before it is returned: the robot is driven through the world by the
// recorder's own pure pursuit and collision raster (no collision, the loop completes), and the
// camera's view is ray-cast at a low resolution along the path (enough of each image within
// 0.4-4 m; hand-held, also enough of it on objects and furniture and normals in three
// directions: ViewStats.h). Candidates that fail are redrawn from the same seeded stream, so the
// result stays deterministic.

#include <cstdint>
#include <string>
#include <vector>

#include "rasm/sim/WorldGenerator.h"

namespace rasm::sim {

struct World;

struct TTrajectoryGenParams {
  std::uint64_t seed = 0;
  bool fast = false;
  /// Written as the spec's `world:` (the path of the world file, relative to the spec's folder).
  std::string world_ref;
  double rate_hz = 30.0;
  /// View check: the fraction of the pixels of every checked image with a depth in
  /// [0.4, max_view_depth_m] (exact depth, the sensor's dropouts applied) is at least this. The
  /// robot's camera (0.55 m, pitched 10 deg down) looking along a long room sees the floor to
  /// about 3 m (beyond, the floor is at a grazing angle) and little else: about half the image.
  double min_valid_handheld = 0.6;
  double min_valid_robot = 0.5;
  /// Hand-held view check, besides min_valid_handheld: of the valid pixels of every checked
  /// image, at least this fraction on objects and furniture (ViewStats::object_fraction: not
  /// floor, wall, ceiling, door), and normals spread over three directions
  /// (ViewStats::normal_min_eig at least min_normal_eig_handheld), so that a depth-only ICP is
  /// constrained in all six directions (a view of the floor alone constrains three).
  double min_object_fraction_handheld = 0.25;
  double min_normal_eig_handheld = 0.005;
  double max_view_depth_m = 4.0;
};

struct GeneratedTrajectory {
  std::string yaml;
  /// One line on what was generated and checked (duration, peaks, worst view fraction).
  std::string summary;
  double duration_s = 0.0;
  /// Lowest view fraction over the checked images.
  double min_valid_fraction = 0.0;
  /// Hand-held: lowest object fraction and normal spread over the checked images (each its own
  /// minimum; ViewStats).
  double min_object_fraction = 0.0;
  double min_normal_eig = 0.0;
  /// Peak angular speed about the camera's x, y, z axes (deg/s) of the smooth path.
  Eigen::Vector3d peak_rate_degps = Eigen::Vector3d::Zero();
};

/// `world` is `gen` loaded (loadWorldFromString(gen.yaml, ...)).
GeneratedTrajectory generateHandheldTrajectory(const GeneratedWorld& gen, const World& world,
                                               const TTrajectoryGenParams& params);
GeneratedTrajectory generateRobotTrajectory(const GeneratedWorld& gen, const World& world,
                                            const TTrajectoryGenParams& params);

/// `rasm sim generate`: writes the world to `out_yaml` and the trajectories next to it,
/// <stem>_handheld.yaml and <stem>_robot.yaml (with `fast`, also _handheld_fast.yaml and
/// _robot_fast.yaml). `trajectories`, when set, is a folder (existing, or ending in '/') for
/// them, or a path prefix (<prefix>_handheld.yaml, ...). Files are written atomically
/// (rasm/core/AtomicFile.h: a temporary beside each, renamed over it).
struct GenerateFilesResult {
  std::string world_path;
  std::vector<std::string> trajectory_paths;
  std::vector<std::string> summary;  ///< one line per file
};
GenerateFilesResult generateWorldFiles(const TWorldGenParams& world_params,
                                       const std::string& out_yaml,
                                       const std::string& trajectories = {}, bool fast = false);

}  // namespace rasm::sim
