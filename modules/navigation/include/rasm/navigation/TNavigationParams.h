#pragma once
// Parameters of the navigator (INI section [navigation]). Defaults suit the simulated office robot
// (0.25 m disc, 0.6 m/s and 90 deg/s limits): see docs/navigation.md for the reasons.

#include <mrpt/config/CLoadableOptions.h>

#include <string>

namespace rasm::navigation {

struct TNavigationParams : public mrpt::config::CLoadableOptions {
  double period_s = 0.1;  ///< navigation step period (the robot's simulated time)
  double max_v_mps = 0.35;
  double max_w_degps = 60.0;
  double goal_tolerance_m = 0.15;
  double heading_tolerance_deg = 8.0;
  double align_w_degps = 40.0;   ///< rotate-in-place speed for the final heading
  double goal_timeout_s = 90.0;  ///< give up on a goal after this long: reason "timeout"
  /// No progress: the distance to the goal did not shrink by stuck_distance_m within
  /// stuck_timeout_s: reason "stuck".
  double stuck_timeout_s = 10.0;
  double stuck_distance_m = 0.15;
  /// Before failing "stuck", up to escape_attempts escapes: turn toward the most open direction
  /// of the scan and drive up to escape_distance_m along it (a robot wedged between a chair and
  /// a desk gets no motion from the reactive navigator, whose PTGs all start in collision with
  /// the margin-grown footprint; seen in the office with object views at 1 m standoff).
  int escape_attempts = 1;
  /// Also the length of the retreat after a collision: the next goal first backs the robot up
  /// this far along the path it came by (the obstacle it hit was not in its obstacle sensing).
  double escape_distance_m = 0.4;
  /// Targets nearer than this are driven to by the own controller: MRPT's PTGs fail on targets
  /// closer than their reach (MRPT-NOTES trap).
  double direct_range_m = 0.5;
  /// A waypoint of a route (Navigator::setGoal's `via`) counts as passed within this distance;
  /// the robot then steers at the next one.
  double via_reach_m = 0.3;
  /// Drive a route's legs (toward a waypoint, and from the last one to the goal) with the own
  /// corridor controller while the straight corridor of the footprint's width to the target is
  /// free in the obstacle scan; the reactive navigator only where it is not. The route's corners
  /// lie on the planning grid's free cells, one footprint radius from the walls, where the
  /// margin-grown PTG footprint touches them: the reactive navigator stood still there in a
  /// 1.7 m hallway (docs/navigation.md "Route").
  bool follow_route = true;
  /// With follow_route, a waypoint counts as passed within this distance (at most via_reach_m):
  /// the corner is driven to, turned at in place, and the next leg starts on the route's line.
  double follow_reach_m = 0.1;
  /// Turn in place toward the goal first when it lies more than this off the heading (the
  /// forward-only PTGs otherwise take a wide loop).
  double face_goal_deg = 45.0;
  // MRPT reactive navigator (CReactiveNavigationSystem) settings.
  double ptg_ref_distance_m = 3.0;   ///< PTG reach: obstacles further than this are ignored
  double ptg_resolution_m = 0.05;    ///< PTG look-up-table cell size
  int ptg_num_paths = 121;           ///< trajectories per PTG
  bool allow_reverse = false;        ///< adds a backward circular-arc PTG
  double footprint_margin_m = 0.05;  ///< the footprint polygon is grown by this for the PTGs
  /// CHolonomicND: CHolonomicFullEval with the example weights stalls in front of a block and
  /// grazes its corner (apparent collision) in the 3 m test; ND goes around (docs/navigation.md).
  std::string holonomic_method = "CHolonomicND";  ///< or CHolonomicFullEval, CHolonomicVFF
  /// Folder of MRPT's PTG cache files (ReacNavGrid_*.dat.gz); empty = $XDG_CACHE_HOME/rasm/ptg,
  /// else $HOME/.cache/rasm/ptg, else <temp dir>/rasm_ptg_cache_<uid> (never a fixed name in a
  /// shared folder: another user's link planted there would receive the files).
  /// MRPT writes them into the current directory by default (MRPT-NOTES trap).
  std::string ptg_cache_dir;

  /// The PTG cache folder in effect (ptg_cache_dir or the per-user default above).
  std::string effectiveCacheDir() const;

  /// Throws InputError "[section] key: ..." naming the key and the expected range.
  void validate(const std::string& section = "navigation") const;
  void loadFromConfigFile(const mrpt::config::CConfigFileBase& cfg,
                          const std::string& section) override;
  /// Writes every key (the strict loader's list of known keys).
  void saveToConfigFile(mrpt::config::CConfigFileBase& cfg,
                        const std::string& section) const override;
};

/// Creates `dir` (and its parents) and checks it is a folder, not a link, owned by this user and
/// writable by no one else; InputError "[navigation] ptg_cache_dir <dir>: ..." otherwise.
void ensurePrivateCacheDir(const std::string& dir);

}  // namespace rasm::navigation
