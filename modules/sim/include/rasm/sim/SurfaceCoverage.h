#pragma once
// Surface coverage of a simulated world's ground truth by a map (docs/sim.md "Surface
// coverage"): the fraction of the world's *observable* surface area that lies within max_dist_m
// (2 cm) of a map point (e.g. the alive surfels' positions).
//
// Samples. Every triangle of every object (world coordinates, scale applied) gets the points of
// a square lattice of pitch sample_spacing_m laid on it (anchored at its first vertex, along its
// first edge), each weighted by the triangle's area / its lattice points, so the weights of an
// object add up to its surface area exactly. Triangles too small or thin for a lattice point
// pass their area on to the object's next such triangle; once that carry reaches spacing^2 (and
// at the object's end) a sample at that triangle's centroid takes it. Normals are the
// triangles' (winding as in the mesh file; only their line is used below).
//
// Observability (the denominator): a sample counts only when a camera mounted on the robot
// could see it from some pose in the robot's free space:
//  - robot positions: a grid of pitch position_spacing_m over the world's xy bounds; a position
//    is free when the disc of robot_radius_m around it clears the world's geometry in the
//    height band [robot_z_min_m, robot_z_max_m] (OccupancyRaster at raster_cell_m); of the free
//    positions only the largest 8-connected component of the grid is kept (the room's
//    interior: not pockets enclosed by furniture, not the outside of a building);
//  - the robot turns to face the sample: the camera sits camera_forward_m ahead of the
//    position towards the sample, camera_height_m above the floor, with pitch camera_pitch_deg
//    (the sample is then in the image's middle column, so the horizontal field of view never
//    limits);
//  - the sample's depth (along the optical axis, as the sensor measures it) is within
//    [min_range_m, max_range_m]; its elevation seen from the camera is within pitch +/-
//    vertical_fov_deg / 2; the angle between the ray and the surface's normal line is at most
//    max_incidence_deg (the sensor returns nothing beyond 80 deg and little of use near it; with
//    75 deg a horizontal face above the camera needs an elevation of 15 deg, more than the
//    14.6 deg a 0.55 m camera pitched 10 deg down with a 49 deg field of view looks up);
//    surfaces count from either side (a closed mesh's far side is occluded by the mesh itself;
//    open or inconsistently wound meshes, such as the mug, are seen from the camera's side);
//  - the segment from the sample to the camera hits nothing (RayScene; from 1 mm off the
//    sample to 1 mm before the camera).
// So the undersides of tables (above a 0.55 m camera pitched 10 deg down they need an
// elevation over the field of view, or a grazing angle), the tops of tall cabinets, the
// ceiling, faces inside or behind furniture and the floor under closed furniture do not count.
// Positions are tried nearest first (rings of the grid), rays in packets of 8 from the sample.
//
// Coverage: a sample is covered when a map point lies within max_dist_m of it (exact Euclidean
// test against the observable samples of the 2 x 2 x 2 cells of 2 max_dist_m its ball reaches;
// the cells are a dense occupancy bitmap over the observable samples' bounding box, 1.5 bits a
// cell: 0.3 MB for the office). Fractions are area-weighted. Structure = floor, wall, ceiling and
// door classes (models::isStructureClass); everything else (static furniture and objects) is
// furniture_and_objects. Construction and evaluation are parallel (OpenMP) and give the same
// result for any thread count.

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "rasm/sim/RayScene.h"
#include "rasm/sim/World.h"

namespace rasm {
struct CameraIntrinsics;
}

namespace rasm::sim {

struct TRobotParams;

struct CoverageOptions {
  double sample_spacing_m = 0.03;  ///< lattice pitch of the surface samples (~1 per spacing^2)
  double max_dist_m = 0.02;        ///< a sample is covered when a map point lies within this
  // --- observability: the robot-mounted camera (defaults: TRobotParams, kinect_v1) ---
  double camera_height_m = 0.55;    ///< camera centre above the floor
  double camera_pitch_deg = -10.0;  ///< optical axis elevation (negative = looking down)
  double camera_forward_m = 0.10;   ///< camera ahead of the robot's rotation centre
  double vertical_fov_deg = 49.1;   ///< full vertical field of view (kinect_v1: 480 px, f 525)
  double min_range_m = 0.4, max_range_m = 4.0;  ///< depth of the sample in the camera
  double max_incidence_deg = 75.0;  ///< largest angle between the ray and the normal line
  // --- the robot's free space ---
  double robot_radius_m = 0.25;  ///< disc footprint (a polygon: its circumradius)
  double robot_z_min_m = 0.03, robot_z_max_m = 0.6;  ///< collision height band
  double raster_cell_m = 0.02;                       ///< occupancy raster cell
  double position_spacing_m = 0.25;                  ///< grid of candidate robot positions
};

/// Options for a robot's camera: height, pitch and forward offset of the mount (TRobotParams'
/// camera_height_m, camera_pitch_deg, camera_x_m, from which T_base_cam() is built), the vertical
/// field of view of the intrinsics (rows 0 and height - 1 at their pixel edges about cy), the
/// robot's footprint (footprint_radius_m, else the largest vertex distance of the polygon),
/// collision band and cell, and max_range_m. The other fields keep their defaults.
CoverageOptions coverageOptionsForRobot(const TRobotParams& robot, const CameraIntrinsics& K,
                                        double max_range_m = 4.0);

class SurfaceCoverage {
 public:
  struct Result {
    double fraction = 0;               ///< covered observable area / observable area
    double structure = 0;              ///< same over static structure (floor, walls, doors)
    double furniture_and_objects = 0;  ///< same over furniture and objects
    /// Per World::objects entry: covered / observable area of that object; -1 when it has no
    /// observable sample.
    std::vector<double> per_object;
    std::size_t samples = 0, observable = 0, covered = 0;  ///< sample counts
    double observable_area_m2 = 0, covered_area_m2 = 0;
  };

  /// One surface sample (world frame).
  struct Sample {
    Eigen::Vector3f position = Eigen::Vector3f::Zero();
    Eigen::Vector3f normal = Eigen::Vector3f::UnitZ();  ///< unit, the triangle's winding
    float area_m2 = 0.f;                                ///< surface area it stands for
    int object = -1;                                    ///< index into World::objects
    bool observable = false;
  };

  /// Samples `world`'s surface and decides which samples are observable (ray casts in
  /// `scene`, which must be built from the same world; only used here, not kept).
  SurfaceCoverage(const World& world, const RayScene& scene, const CoverageOptions& opts = {});

  /// Coverage of the samples by `map_points` (non-finite points are ignored). With
  /// `covered_samples`, also which samples are covered: one byte per samples() entry, 1 when
  /// covered (always 0 for samples that are not observable).
  Result evaluate(const std::vector<Eigen::Vector3f>& map_points,
                  std::vector<std::uint8_t>* covered_samples = nullptr) const;

  std::size_t observableSamples() const { return m_observable; }
  const std::vector<Sample>& samples() const { return m_samples; }
  const CoverageOptions& options() const { return m_opts; }
  /// Free robot positions used for observability (x, y), for inspection.
  const std::vector<Eigen::Vector2f>& robotPositions() const { return m_positions; }

 private:
  /// The constructor's steps: samples every sample_spacing_m over each object's triangles
  /// (m_samples), marks those a robot's camera can observe, and indexes the observable ones by
  /// cell.
  void sampleSurfaces(const World& world);
  void markObservable(const World& world, const RayScene& scene);
  void indexObservableSamples();

  CoverageOptions m_opts;
  std::vector<Sample> m_samples;
  std::vector<Eigen::Vector2f> m_positions;
  std::size_t m_observable = 0;
  std::vector<bool> m_is_structure;  ///< per object
  std::size_t m_num_objects = 0;
  // The observable samples sorted by cell (cells of 2 max_dist_m over their bounding box, plus
  // one cell): positions and indices into m_samples; an occupancy bit per cell with the count of
  // set bits before each 64-bit word, so a cell's rank among the occupied cells (its range in
  // m_cell_start) is one popcount away.
  float m_cell = 0.04f;
  Eigen::Vector3f m_grid_origin = Eigen::Vector3f::Zero();
  Eigen::Vector3i m_grid_dims = Eigen::Vector3i::Zero();
  std::vector<std::uint64_t> m_cell_bits;
  std::vector<std::uint32_t> m_cell_rank;   ///< per word of m_cell_bits
  std::vector<std::uint32_t> m_cell_start;  ///< per occupied cell, and the end
  std::vector<Eigen::Vector3f> m_sorted_pos;
  std::vector<std::uint32_t> m_sorted_idx;
};

}  // namespace rasm::sim
