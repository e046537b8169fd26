#pragma once
// [exploration]: information-gain exploration of section V (occupancy octree V-A, object-centric
// view information V-B, candidate views and their score IG(a) = w1 dH + w2 dIC). Defaults and the
// reasons for them: docs/exploration.md. The camera mount is not repeated here: candidates take
// T_base_cam from the run's [robot] section (tracking TRobotParams::T_base_cam()).

#include <mrpt/config/CLoadableOptions.h>

#include <string>
#include <vector>

namespace rasm::exploration {

struct TExplorationParams : mrpt::config::CLoadableOptions {
  // ---- occupancy octree (V-A) ----
  double resolution_m = 0.1;  ///< leaf edge of the octree (and cell of the 2-D projection)
  /// Rays longer than this insert free space up to it and no endpoint (Kinect-class depth beyond
  /// 4 m is too noisy to mark cells occupied; the mapper's [mapper] max_depth_m is 4 m too).
  double max_range_m = 4.0;
  double min_depth_m = 0.3;  ///< nearer depth is ignored (as [mapper] min_depth_m)
  /// Every n-th pixel in x and y is inserted (4: 160x120 rays of a 640x480 frame).
  int pixel_stride = 4;
  /// Pixels without a return (depth 0) insert free space up to this range along their ray when
  /// > 0; 0 = not at all: a dropout (glass, black, too close) is no evidence of free space. A
  /// *predicted* depth map always treats its empty pixels as free up to max_range_m (V-A:
  /// unknown space is assumed seen through).
  double no_return_free_m = 0.0;
  /// Sensor model: P(occupied | hit), P(occupied | miss), and the clamping of the cell log-odds
  /// (OctoMap's clamping defaults, Hornung et al. 2013). Not OctoMap's 0.7 / 0.4: with those a
  /// first observation lowers a cell's entropy less than a second one (h(p) is flat at 0.5:
  /// log 2 - h(0.4) = 0.020 nats, h(0.4) - h(0.31) = 0.054), so an entropy-gain planner would
  /// rather look again at seen space than into unknown space. With 0.9 / 0.2 (one RGB-D ray is
  /// strong evidence) the first observation is the largest drop for hits and misses alike
  /// (0.368 then 0.194; 0.193 then 0.135 nats) and two reach the clamp.
  double prob_hit = 0.9, prob_miss = 0.2;
  double clamp_min = 0.1192, clamp_max = 0.971;
  /// Workspace: the axis-aligned box whose cells the entropy H(m) sums over (m, world frame).
  double workspace_min_x_m = -10.0, workspace_min_y_m = -10.0, workspace_min_z_m = 0.0;
  double workspace_max_x_m = 10.0, workspace_max_y_m = 10.0, workspace_max_z_m = 2.5;
  /// Height band of the 2-D projection (the robot's body above the floor): a column is occupied
  /// when any cell of the band is, free when none is and at least one is seen free.
  double band_min_z_m = 0.05, band_max_z_m = 0.6;

  // ---- object-centric information (V-B) ----
  /// Gain weight of surfels without class evidence; surfels with evidence weigh
  /// max(floor, 1 - |2 p_best - 1|) (ObjectInformation.h).
  double ic_weight_floor = 0.25;

  // ---- candidate views (V) ----
  int random_candidates = 40;  ///< (a) SE(2) samples in known free space
  int seed = 1;                ///< of the random candidates: the same seed gives the same plan
  double footprint_radius_m = 0.25;  ///< robot disc (as [sim_robot] footprint_radius_m)
  /// (b) object views: segments whose largest upright extent is within [min, max] m.
  double object_min_extent_m = 0.15, object_max_extent_m = 2.0;
  double object_standoff_m = 1.0;  ///< distance from the segment's side to the robot centre
  /// (c) also a view at each frontier of the projection (as the frontier baseline's goals,
  /// frontier_min_cells / frontier_goal_radius_m), scored by IG like the others: random views
  /// lie in known free space only, so without these the planner never proposes the map's edge.
  bool frontier_candidates = false;
  /// Predicted maps (depth for dH, surfel index for dIC) are rendered at this size (the camera's
  /// intrinsics scaled).
  int predict_width = 160, predict_height = 120;
  /// The predictions render a thinned copy of the map when it holds more alive surfels than
  /// this: every k-th surfel, k = ceil(alive / predict_max_surfels), its radius times sqrt(k)
  /// (SurfelStore::copyThinnedFrom), built once per plan. A render's cost grows with the map's
  /// surfels, not with the predicted image's pixels (docs/exploration.md "Costs"). 0 = the
  /// whole map. 200 k: the plans rank the views as the whole map's do (Spearman 0.994, the same
  /// best view on bench_exploration's 1.7 M-surfel office) at a third of the cost.
  int predict_max_surfels = 200000;
  /// A plan with more reachable candidates than predict_screen_keep (> 0) first predicts every
  /// one at predict_screen_width x predict_screen_height and predicts in full only the best
  /// predict_screen_keep of that screen (same IG and ranking), every frontier view and the goal
  /// being driven to; the others are left out of the plan (Plan::screened_out). 0 = predict
  /// every candidate in full. Object views (one per uncertain segment) take a room's plans from
  /// ~50 to ~280 candidates (docs/exploration.md "Costs"). The screen renders a map thinned
  /// further, in proportion to its pixels. 40: a plan of 270 candidates within 0.3 s on 2 cores
  /// (bench_exploration run_sized), no coverage lost on the panels measured ("Costs").
  int predict_screen_keep = 40;
  int predict_screen_width = 40, predict_screen_height = 30;

  // ---- score (V) ----
  double w_entropy = 1.0;  ///< w1 of IG(a); dH is divided by the largest dH of the candidates
  double w_ic = 1.0;       ///< w2 of IG(a); dIC is divided by the largest dIC of the candidates
  /// Rank by IG / (travel time + min_travel_time_s) (true) or by IG alone (false).
  bool rank_by_rate = true;
  double speed_mps = 0.3, turn_rate_degps = 45.0;
  double min_travel_time_s = 2.0;

  // ---- planner and baselines (ExplorationPlanner.h) ----
  /// Which planner makePlanner builds: "ig" (the IG planner of V with a global tour over view
  /// clusters), "ig_greedy" (the IG planner's best next view alone), "frontier" (nearest
  /// frontier, Yamauchi 1997), "random" (random reachable free cells), "lawnmower"
  /// (boustrophedon sweep). The baselines run on the same octree, projection, reachability and
  /// budget as "ig".
  /// "oracle" knows the simulated world's surface (pipeline OraclePlanner): only an exploring run
  /// of a simulated world builds it; makePlanner refuses it.
  std::string planner = "ig";
  /// A goal the robot failed to reach (and, for "frontier", a goal it reached) is blacklisted:
  /// candidates whose base lies within this distance (m) of it are not offered again. 0.5 m is
  /// two footprint radii: the same spot up to the navigation's goal tolerance.
  double blacklist_radius_m = 0.5;
  /// ig: a view the robot has taken (a goal it reached) is not offered again: candidates within
  /// taken_view_radius_m of it whose heading is within taken_view_heading_deg. What the view gives
  /// is fused; its predicted gain stays above zero (the octree's pixel stride, depth dropouts,
  /// view bins that fill over several frames), and with rate ranking the pose the robot stands at
  /// has the shortest travel time, so without this the planner offers it again and again
  /// (seen in the office: 20 plans in 2 s at one spot). 0 = off.
  double taken_view_radius_m = 0.3, taken_view_heading_deg = 30.0;
  /// Frontier clusters (8-connected known-free cells next to unknown ones) with fewer cells are
  /// ignored: 5 cells at 10 cm are a 0.5 m gap, less is speckle between the rays of a frame.
  int frontier_min_cells = 5;
  /// The frontier goal is the reachable cell nearest the cluster's centroid within this radius
  /// (m); the footprint keeps goals ~footprint_radius_m + 1 cell from unknown space, and 1 m still
  /// sees the frontier well inside the 4 m depth range.
  double frontier_goal_radius_m = 1.0;
  /// Frontiers whose cells lie farther than this (m) from their centroid are split across their
  /// principal axis until none does (FUEL's split of large clusters): a room's boundary seen
  /// through its doorway is one frontier whose centroid lies in the unknown, more than
  /// frontier_goal_radius_m from every reachable cell, so it had no view (flat 2101 at 22 s: 99
  /// cells, the room beside the robot). 1.5 m: a piece's view 1 m from its centroid sees all of
  /// it in the 57-63 deg camera. 0 = no split.
  double frontier_max_radius_m = 1.5;
  /// Whether the robot's clearance on the planning grid is kept from unknown cells too (as
  /// PlannerSimple2D grows every cell that is not known free). false: from occupied cells only
  /// (planningGrid), paths still on known free cells. What the camera sees through a doorway is a
  /// cone whose apex, near the robot, is narrower than the footprint plus its growth: with the
  /// unknown grown, the room beyond was never reachable from the doorway (flat 2101 at 22 s: the
  /// frontiers of the room beside the robot, 0.9-3.5 m in, all without a view).
  bool clearance_from_unknown = false;
  /// Lawnmower: lanes this far apart (m) along lawnmower_axis ("x" or "y"), a waypoint every
  /// lawnmower_step_m (m) on each lane. 1.5 m: the 63-degree camera sees ~1.8 m across at 1.5 m,
  /// so neighbouring lanes overlap a little.
  double lawnmower_spacing_m = 1.5, lawnmower_step_m = 1.5;
  std::string lawnmower_axis = "x";

  // ---- the global tour of "ig" (TourIgPlanner, ViewTour.h) ----
  /// Views whose bases lie within this distance (m) of a better view join its cluster; the
  /// cluster is visited at its best view. 1 m: two views 1 m apart see most of the same surface
  /// at the 4 m depth range, and the robot turns in place faster than it drives 1 m.
  double tour_cluster_radius_m = 1.0;
  /// The tour visits at most this many clusters (the best by IG): the exact solver is
  /// exponential in it up to 11, a local search beyond.
  int tour_max_clusters = 12;
  /// Clusters whose IG is below this fraction of the best cluster's are left out of the tour
  /// (crumbs the route would detour for; they come back when the big gains are collected).
  double tour_min_gain_fraction = 0.1;
  /// A view's tour weight is multiplied by tour_revisit_discount for every view the robot has
  /// taken (reached goal) within tour_revisit_radius_m of it. The predicted dH of a region the
  /// robot has looked around in stays high (voxels inside furniture, under desks and behind
  /// objects stay unknown from every view), so its nearby views would always be scheduled before
  /// a far room; halving per view taken within 2 m (about a room's half-width) moves the tour on
  /// after a few views. 1 = off.
  double tour_revisit_radius_m = 2.0, tour_revisit_discount = 0.5;
  /// Whether the revisit discount also applies to frontier views. false: a frontier borders
  /// unknown space however many views were taken near it (flat 2101: the doorway of the room
  /// beside the start, dH the plan's best, weighed 0.5 after two hallway views within 2 m, and the
  /// robot drove past it for 200 s). true: as before (for comparisons).
  bool tour_revisit_frontiers = false;
  /// A frontier view's dH term in the tour's weight is the larger of its own predicted dH and
  /// tour_behind_fraction x the summed dH of three views from frontier_behind_m past the
  /// frontier's centroid along its outward normal (headings outward and +-60 deg, ~180 deg
  /// together; the segment there crosses no occupied cell below 1.8 m). The view in front of a
  /// doorway sees one cone through it; the room (or the hallway's rest) is what going through
  /// gains. 0 = off (the view's own dH alone).
  double frontier_behind_m = 1.5, tour_behind_fraction = 1.0;
  /// An object view's tour weight is multiplied by the fraction of the planning grid's cells
  /// within tour_object_context_radius_m of its segment's centroid that are known: an object
  /// seen through a doorway waits until the room it stands in is mapped (the room's views come
  /// first, and they see it too). 0 = off.
  double tour_object_context_radius_m = 1.5;
  // ---- oracle (pipeline OraclePlanner.h: the reference with the world's ground truth) ----
  /// The surface samples are thinned to one target per cube of this edge (m) for the view sets
  /// (each target stands for its cube's samples); 0 = every sample a target (slower: the
  /// precomputation casts one ray per candidate and target in view).
  double oracle_target_spacing_m = 0.1;
  int oracle_headings = 8;  ///< candidate headings per free robot position (evenly spaced)
  /// The greedy cover stops once its views see this fraction of the coverable samples left.
  double oracle_cover_fraction = 0.99;
  int oracle_max_views = 200;  ///< at most this many views per cover (a tour)
  /// Seconds a goal costs beyond its travel time in the cover's rate (gain / (travel time +
  /// this)): the navigator's slow approach and final alignment; a small constant makes the cover
  /// choose hops of a few decimetres (docs/exploration.md, the oracle).
  double oracle_goal_overhead_s = 20.0;
  /// Seconds each goal adds to the arrival times by which the tour through the chosen views is
  /// ordered (the navigator's approach and alignment: 2-5 s a goal in the oracle's runs).
  double oracle_tour_overhead_s = 4.0;
  /// A view counts a target only up to this depth (m; 0 = the coverage's max_range_m): the map
  /// covers a sample only within 2 cm of a stable surfel, which a far, oblique view at a low
  /// resolution often does not give.
  double oracle_max_range_m = 0.0;
  /// A view is chosen (and kept in the tour) only while it sees at least this many samples not
  /// yet covered by the map (200 samples at the 3 cm sampling: ~0.2 m2; fewer makes a tour of
  /// many views that each add little).
  int oracle_min_view_samples = 200;

  /// Throws InputError naming [section] key for a value out of range or a min above its max.
  void validate(const std::string& section = "exploration") const;
  void loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s) override;
  void saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const override;
};

/// The accepted values of [exploration] planner, in the order of the docs.
std::vector<std::string> plannerNames();

}  // namespace rasm::exploration
