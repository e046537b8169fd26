#pragma once
// Options of the loop closure (rasm::tracking::LoopClosure, run by the tracking stage), INI
// section [loop_closure]. Keys are the member names. Distances in metres, angles in degrees,
// times in seconds. docs/tracking.md "Loop closure" explains the method and the measurements.

#include <mrpt/config/CLoadableOptions.h>

#include <string>

namespace rasm::tracking {

struct TLoopClosureParams : public mrpt::config::CLoadableOptions {
  /// Whether tracked frames are registered against the inactive map to close loops.
  bool enabled = false;

  // ---- the trajectory graph ----
  /// A tracked frame becomes a node of the pose graph when this much time passed since the last
  /// node (the surfels made between two nodes move with them).
  double node_every_s = 0.5;
  /// Uncertainty of the motion between two consecutive nodes (the edges of the chain): standard
  /// deviation per metre travelled and per degree turned, and its floor per edge. They only
  /// decide how a loop's correction is spread along the chain (more where the motion was larger).
  /// Heading drifts while driving straight too (degenerate views, wheel slip): the rotation's
  /// sigma grows with both, per degree turned and per metre travelled.
  double chain_sigma_m_per_m = 0.02;
  double chain_sigma_deg_per_deg = 0.002;
  double chain_sigma_deg_per_m = 0.5;
  /// The frames between two nodes that the data did not hold in every direction (degenerate:
  /// those directions are the odometry's; lost: propagated) make the edge's sigmas up to this
  /// many times larger (1 + (factor - 1) x their fraction): drift happens there, so a loop's
  /// correction goes there.
  double chain_sigma_weak_factor = 10.0;
  double chain_sigma_min_m = 0.001;
  double chain_sigma_min_deg = 0.05;
  /// Uncertainty of a loop constraint (the frame registered against the inactive map).
  double loop_sigma_m = 0.003;
  double loop_sigma_deg = 0.1;

  // ---- detection (ElasticFusion's local loop closure: active against inactive model) ----
  /// Surfels created this long ago or earlier are the inactive map, those created since the
  /// active map (ElasticFusion's delta_t, on the creation time: rasm tracks against and fuses
  /// into the whole map, so an old surfel seen again is not made new by the fusion).
  double inactive_after_s = 20.0;
  /// A tracked frame is registered against the inactive model every this many frames.
  int check_every_frames = 5;
  /// ... when the inactive model covers at least this fraction of the frame's valid pixels.
  double min_inactive_fraction = 0.3;
  /// A registration moves the camera only along the directions its system holds with at least
  /// this eigenvalue (TrackingResult::eigenvalues; the tracker's own bar, [tracking]
  /// min_eigenvalue, is 1e-3); along the others the tracked pose stands, for the inactive and the
  /// active map alike (moveAlongHeldDirections). On gen3903 two checks 5 frames apart asked for
  /// 3.2-3.4 cm, almost all of it along their weakest direction (eigenvalue 1.6e-3 and 2.1e-3,
  /// every other direction >= 1.1e-2); the loop closed and moved the camera from 2.4 to 4.8 cm
  /// off the truth, while the right closures of the run moved along directions held at 2e-2 to
  /// 8e-2 (docs/results-worldframe.md "A wrong closure, frame by frame"). 0: the registration as
  /// it is.
  double min_eigenvalue = 1e-2;
  /// A loop is closed when this many consecutive checks (check_every_frames apart) ask for the
  /// same correction (within min_correction_* plus a quarter of it): one registration that slid
  /// along a weak direction does not move the map.
  int confirmations = 2;
  /// What must confirm an accepted correction, within feature_agreement_m or 30% of the
  /// correction and feature_agreement_deg or 30% of it (ICP against a corridor slid 7.7 cm along
  /// its weak direction, twice, on generated room 3905; texture does not slide with it):
  ///   colour:   the registration against the inactive map with its colour (joint ICP + RGB at
  ///             [tracking] photometric_weight_degenerate, as ElasticFusion registers its
  ///             models) gives the same pose as the geometric one;
  ///   features: the frame's ORB features against the old map's keyframes (PnP, Relocaliser);
  ///   none.
  std::string confirmation = "colour";
  double feature_agreement_m = 0.03;
  double feature_agreement_deg = 1.5;
  /// Corrections below both of these are agreement: nothing to close.
  double min_correction_m = 0.02;
  double min_correction_deg = 0.5;
  /// Corrections beyond what the drift since the old map can explain are refused (a false loop,
  /// e.g. a similar room): max_correction_m + drift_m_per_m x the path length (m) between the
  /// old map's time and now, and the same for the angle.
  double max_correction_m = 0.05;
  double drift_m_per_m = 0.05;
  double max_correction_deg = 1.0;
  double drift_deg_per_m = 1.0;

  void loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s) override;
  void saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const override;
  /// Throws InputError naming [section] key for an out-of-range value.
  void validate(const std::string& section) const;
};

}  // namespace rasm::tracking
