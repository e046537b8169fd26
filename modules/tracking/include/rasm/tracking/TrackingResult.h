#pragma once
// Outcome of tracking one frame (II-C) with the quality signals the Mapper needs to decide
// whether to fuse it.

#include <Eigen/Geometry>
#include <vector>

namespace rasm::tracking {

enum class TrackingStatus {
  Ok,               ///< converged, enough inliers, small residual, plausible motion
  Degenerate,       ///< geometry leaves some directions unconstrained (e.g. a single wall); those
                    ///< directions keep the initial guess. ok if inlier_fraction >=
                    ///< degenerate_min_inlier_fraction.
  TooFewInliers,    ///< too little overlap with the model (empty / unrelated model, fast motion)
  HighResidual,     ///< inliers found but the RMS point-to-plane residual is too high
  ExcessiveMotion,  ///< the result is too far from the initial guess (wrong local minimum)
  Inconsistent,     ///< the aligned frame contradicts the model it was aligned to (pose check:
                    ///< too few overlapping pixels agree, or too many see through mapped surfaces)
  PriorConflict,    ///< the result is too many sigmas away from the motion prior (odometry)
  Diverged,         ///< the linear system could not be solved or produced non-finite poses
  NotInitialized    ///< track() before reset(): no pose to predict from
};

const char* toString(TrackingStatus s);

/// Statistics of one pyramid level, taken at the last linearisation point of that level.
struct TrackingLevelStats {
  int level = 0;
  int iterations = 0;  ///< iterations run (<= the configured number)
  int inliers = 0;
  int valid_pixels = 0;          ///< frame pixels with a valid vertex and normal (after the stride)
  double rms_m = 0.0;            ///< RMS point-to-plane residual of the inliers
  int photometric_inliers = 0;   ///< model pixels used by the photometric term (0 = off)
  double photometric_rms = 0.0;  ///< their RMS intensity residual (luma in [0, 1])
  double min_eigenvalue = 0.0;   ///< of the level's last system (see TrackingResult)
  double last_step_translation_m = 0.0;
  double last_step_rotation_rad = 0.0;
};

struct TrackingResult {
  /// Estimated camera pose (optical frame). When !ok it is the best estimate anyway, for
  /// diagnostics; the caller should not use it to fuse.
  Eigen::Isometry3d T_world_cam = Eigen::Isometry3d::Identity();
  /// The initial guess ICP started from (motion-model prediction or the caller's guess).
  Eigen::Isometry3d T_world_cam_guess = Eigen::Isometry3d::Identity();
  bool ok = false;
  TrackingStatus status = TrackingStatus::NotInitialized;
  /// A degenerate frame accepted on the constant-velocity guess alone (IcpTracker::track,
  /// TTrackingParams::degenerate_max_run_frames); frames.csv `on_motion_model`.
  bool on_motion_model = false;
  /// The result is the second alignment, against the denser (all-surfel) model, after the
  /// stable-surfel model gave the frame too little support (IcpTracker::track's denser_model).
  bool denser_model = false;

  // Quality of the final (level 0) alignment.
  int inliers = 0;
  double inlier_fraction = 0.0;  ///< inliers / valid frame pixels at level 0
  double rms_m = 0.0;            ///< RMS point-to-plane residual of the inliers (m)
  int photometric_inliers = 0;   ///< level-0 samples of the photometric term (0 = off)
  double photometric_rms = 0.0;  ///< their RMS intensity residual (luma in [0, 1])
  /// Degeneracy: smallest eigenvalue of J^T J / inliers with the rotation columns scaled by the
  /// mean inlier depth, so translation and rotation share one dimensionless scale (a wall seen
  /// head-on constrains its normal direction with ~1, the directions in the plane with ~0).
  /// Taken over the last system of every level, minimum wins: sensor noise on normals creates
  /// spurious constraints at fine levels, the smoother coarse levels show the true geometry.
  double min_eigenvalue = 0.0;
  /// Eigenvalues (ascending) and unit eigenvectors of that matrix (the level with the minimum),
  /// in coordinates [translation (m); rotation (rad) * mean depth] along the world axes;
  /// directions with eigenvalue < params min_eigenvalue are unconstrained.
  Eigen::Matrix<double, 6, 1> eigenvalues = Eigen::Matrix<double, 6, 1>::Zero();
  Eigen::Matrix<double, 6, 6> eigenvectors = Eigen::Matrix<double, 6, 6>::Identity();
  /// The mean inlier depth (m) the rotation columns of that matrix were scaled by.
  double eigen_mean_depth_m = 1.0;
  int unconstrained_directions = 0;
  /// Last increment at level 0.
  double final_step_translation_m = 0.0;
  double final_step_rotation_rad = 0.0;
  /// Correction ICP applied to the guess: translation (m) and rotation (rad) of guess^-1 * T.
  double correction_translation_m = 0.0;
  double correction_rotation_rad = 0.0;
  int iterations = 0;  ///< all levels together

  // Pose check after alignment (kernels::PoseCheckKernel at TTrackingParams::check_level).
  /// Fraction of the frame's valid pixels that land on the model's surface.
  double check_overlap = 0.0;
  /// Of those: fraction agreeing with the surface, fraction lying behind it.
  double check_agreement = 0.0;
  double check_behind = 0.0;
  /// Motion prior: whether one was used, and the Mahalanobis distance of the result from it.
  bool used_prior = false;
  double prior_sigmas = 0.0;
  /// The same distance in the odometry's directions only (x, y along the floor, yaw;
  /// MotionPrior::odometry_information); 0 without an odometry prior.
  double odometry_sigmas = 0.0;
  /// The geometry alone left a direction unconstrained and this result is the photometric
  /// retry's (TTrackingParams::photometric_weight_degenerate).
  bool photometric_retry = false;
  /// A degenerate frame that conflicted with the odometry, solved again with the odometry's x, y
  /// and yaw at MotionPrior::odometry_information_degenerate (IcpTracker::track).
  bool held_by_odometry = false;
  std::vector<TrackingLevelStats> levels;  ///< in the order run (coarsest first)
};

}  // namespace rasm::tracking
