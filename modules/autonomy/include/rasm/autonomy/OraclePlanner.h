#pragma once
// "oracle" ([exploration] planner = oracle): an exploration planner that KNOWS the simulated
// world, the reference the other planners are reported against. It lives in autonomy because it
// needs sim (the world's surface samples and its ray scene); exploration::makePlanner refuses it,
// ExplorationLoop builds it for a simulated sequence.
//
// Precomputed once per world (the constructor; ray casts on all cores, the same result for any
// thread count):
//   candidates  every free robot position of sim::SurfaceCoverage (the world's free space on
//               its 0.25 m grid, largest connected component) x oracle_headings headings
//               (k * 360 / headings degrees), candidate c = position * headings + k;
//   targets     the observable SurfaceCoverage samples thinned to one per cube of
//               oracle_target_spacing_m (the first sample of a cube, in sample order, represents
//               it; its cube's observable samples are its members);
//   view sets   per candidate the targets its camera sees (sorted uint32 indices): the camera
//               pose is exploration::cameraPoseOf(pose, T_base_cam); a target is seen when it
//               projects inside the image of K (the horizontal and vertical field of view), its
//               depth lies in [min_range_m, max_range_m] of the CoverageOptions (max_range_m
//               capped by oracle_max_range_m), the angle between the ray and its surface's
//               normal line is at most max_incidence_deg, and the segment to the camera hits
//               nothing (RayScene, as SurfaceCoverage's observability test).
// reachableFraction(): the observable area whose target some candidate sees / the observable
// area (what any of the oracle's views could map at all). Views are OFFERED only at interior
// free positions (all eight neighbours free): on the edge of the free space the robot's disc
// touches furniture and the navigator, which grows obstacles by more, gets stuck or collides on
// the way (tens of seconds a goal); edge positions stay on the paths. coverableSamples(): the
// observable samples some offered view sees.
//
// Covered samples come from the MAP: each plan evaluates the snapshot's alive stable surfels
// with SurfaceCoverage (the run's coverage metric). Besides, every target a reached view sees
// counts as done: the map counts a surfel only once it is stable (several views), and without
// this the next cover chose the views beside the one just reached (hops of 0.25-0.5 m). A
// target's weight is the number of its members not yet covered. A view the robot reached, and
// every view within blacklist_radius_m of a goal it failed to reach, is not offered again.
//
// Plan: while a tour is pending, its remaining views (those still seeing at least
// oracle_min_view_samples uncovered samples) in tour order. Otherwise a new cover: the greedy set
// cover weighted by travel time picks, from the robot's pose on, the view maximising
//   uncovered samples it sees / (travel time from the previous view + oracle_goal_overhead_s),
//   travel time = path length on the free positions' 8-connected grid / speed_mps
//                 + heading change / turn_rate_degps,
//   heading change = the turn to the straight line to the view plus the turn from it to the
//                 view's heading (a view facing along its approach is seen for many frames on
//                 the way; a surfel becomes stable, and counts as covered, only after several),
// until its views see oracle_cover_fraction of the coverable samples left (those some offered
// view sees), oracle_max_views are chosen or no view sees oracle_min_view_samples any more. The
// tour through them is the one that collects the samples soonest (exploration::solveTour on the
// weighted latency, ViewTour.h: weights = what each view adds to the cover before it, times =
// travel time + oracle_tour_overhead_s per goal): a cover takes longer than the run, so the
// order that minimises the total travel time (the first version) spent the run on near views of
// little gain. Plan::route: the way to the next view over the free positions (routeCorners):
// the navigator's waypoints through doorways. Empty plan (done): no view left that sees
// oracle_min_view_samples uncovered samples, or the map covers all but 1 -
// oracle_cover_fraction of the coverable samples.

#include <Eigen/Geometry>
#include <cstdint>
#include <vector>

#include "rasm/core/CameraIntrinsics.h"
#include "rasm/exploration/ExplorationPlanner.h"
#include "rasm/exploration/TExplorationParams.h"

namespace rasm::sim {
class RayScene;
class SurfaceCoverage;
}  // namespace rasm::sim

namespace rasm::autonomy {

class OraclePlanner : public exploration::ExplorationPlanner {
 public:
  /// Precomputes the candidates and their view sets. `coverage` must outlive the planner and be
  /// built on `scene`'s world; `K` and `T_base_cam` are the robot's camera and mount.
  OraclePlanner(const sim::SurfaceCoverage& coverage, const sim::RayScene& scene,
                const exploration::TExplorationParams& params, const Eigen::Isometry3d& T_base_cam,
                const CameraIntrinsics& K);

  std::string name() const override { return "oracle"; }
  /// Marks the samples in.store covers (when given), then offers the tour's remaining views.
  exploration::Plan plan(const exploration::PlannerInputs& in) override;
  /// Reached: that view is done; failed: every view within blacklist_radius_m of it is done.
  void goalOutcome(const Eigen::Vector3d& goal_xyyaw, bool reached) override;

  // ---- the precomputed world (inspection, tests, report) ----
  std::size_t numCandidates() const { return m_poses.size(); }
  const Eigen::Vector3d& candidatePose(std::size_t c) const { return m_poses[c]; }
  /// The targets candidate c sees (sorted indices).
  const std::vector<std::uint32_t>& candidateTargets(std::size_t c) const { return m_sees[c]; }
  std::size_t numTargets() const { return m_target_start.empty() ? 0 : m_target_start.size() - 1; }
  /// Observable samples whose target some offered view sees (the coverable ones).
  std::size_t coverableSamples() const { return m_coverable_samples; }
  /// Whether candidate c is ever offered (not at a cramped position).
  bool offered(std::size_t c) const { return m_offered[c] != 0; }
  /// Area fraction of the observable surface some candidate sees.
  double reachableFraction() const { return m_reachable_fraction; }
  /// Wall time of the precomputation (ms).
  double precomputeMs() const { return m_precompute_ms; }
  /// Free positions on the edge of the free space (a neighbour not free): no view is offered
  /// there (they stay on the paths).
  std::size_t crampedPositions() const { return m_cramped_positions; }

  // ---- the steps of a plan (plan() runs them; public for tests) ----
  /// Which samples are covered: one byte per SurfaceCoverage::samples() entry.
  void setCoveredSamples(const std::vector<std::uint8_t>& covered);
  /// Uncovered samples candidate c sees now.
  std::uint64_t gain(std::size_t c) const;
  /// Uncovered samples the views see together (each counted once).
  std::uint64_t gain(const std::vector<int>& views) const;
  /// The greedy cover from `start` (x, y, yaw) over the views not done: candidates in the order
  /// chosen (empty when done).
  std::vector<int> greedyCover(const Eigen::Vector3d& start) const;
  /// `views` (in cover order) ordered into the tour from `start` that collects their samples
  /// soonest (solveTour on the weighted latency).
  std::vector<int> tourThrough(const Eigen::Vector3d& start, const std::vector<int>& views) const;
  /// The pending tour (views in order; the next goal first).
  const std::vector<int>& tour() const { return m_tour; }

 private:
  void buildTargets(double spacing_m);
  void buildViewSets(const sim::RayScene& scene, const Eigen::Isometry3d& T_base_cam,
                     const CameraIntrinsics& K);
  void excludeCrampedViews();
  void updateCoverage(const maps::SurfelStore& store);
  /// Shortest path lengths (m) from position `from` over the 8-connected free positions
  /// (+infinity where not connected).
  std::vector<float> distanceField(int from) const;
  /// The free position nearest (x, y).
  int nearestPosition(const Eigen::Vector2d& xy) const;
  /// Travel time to candidate c from (from_xy, from_yaw), `field` the distance field from there.
  double travelTime(const std::vector<float>& field, const Eigen::Vector2d& from_xy,
                    double from_yaw, std::size_t c) const;
  /// The way to candidate c over the free positions (exploration::routeCorners), `field` the
  /// distance field from the robot's position.
  std::vector<Eigen::Vector2d> routeTo(const std::vector<float>& field,
                                       const Eigen::Vector2d& robot_xy, std::size_t c) const;
  exploration::ViewCandidate candidate(std::size_t c, const std::vector<float>& field,
                                       const Eigen::Vector3d& robot) const;

  const sim::SurfaceCoverage& m_coverage;
  exploration::TExplorationParams m_params;
  Eigen::Isometry3d m_T_base_cam;
  int m_headings = 8;
  // Free positions on their grid (SurfaceCoverage::robotPositions()).
  std::vector<Eigen::Vector2f> m_positions;
  Eigen::Vector2f m_grid_org = Eigen::Vector2f::Zero();
  float m_spacing = 0.25f;
  int m_nx = 0, m_ny = 0;
  std::vector<int> m_position_at;          ///< per grid cell (row-major): position index or -1
  std::vector<Eigen::Vector2i> m_cell_of;  ///< per position: its grid cell
  // Candidates and view sets.
  std::vector<Eigen::Vector3d> m_poses;
  std::vector<std::vector<std::uint32_t>> m_sees;
  // Targets: representative sample and members (CSR over sample indices).
  std::vector<std::uint32_t> m_target_sample;
  std::vector<std::uint32_t> m_target_start, m_target_members;
  std::vector<std::uint32_t> m_left;  ///< per target: members not yet covered
  std::size_t m_coverable_samples = 0;
  double m_reachable_fraction = 0.0, m_precompute_ms = 0.0;
  // State between plans.
  std::vector<std::uint8_t> m_done;  ///< per candidate: reached, near a failed goal, or cramped
  std::vector<std::uint8_t> m_reached_target;  ///< per target: seen from a view reached
  std::size_t m_cramped_positions = 0;
  std::vector<std::uint8_t> m_offered;  ///< per candidate: not at a cramped position
  std::vector<int> m_tour;
  std::vector<Eigen::Vector3f> m_points;  ///< map points of the last coverage update (reused)
};

}  // namespace rasm::autonomy
