#pragma once
// Trajectory metrics of the TUM RGB-D benchmark (Sturm et al., IROS 2012, section VI):
//  - ATE (absolute trajectory error, evaluate_ate.py): estimate and ground truth associated by
//    timestamp (associateTimestamps, max 0.02 s), the estimate's positions aligned onto the ground
//    truth's in closed form (Horn / Umeyama: SE(3), or Sim(3) with `scale`), then statistics of the
//    per-pose translation residuals.
//  - RPE (relative pose error, evaluate_rpe.py with --fixed_delta): for every estimate pose i the
//    pose j nearest to `delta` later (seconds: within half the median estimate period, so
//    intervals are not shortened at the end or across gaps; or exactly `delta` frames), E_ij =
//    (Q_i^-1 Q_j)^-1 (P_i^-1 P_j) with Q ground truth and P estimate (the paper's eq. 1), its
//    translation norm (m) and rotation angle (deg); ground-truth poses are the nearest stamps
//    within twice the median ground-truth period. evaluate_rpe.py composes the two relative motions
//    in the opposite order, which changes the translational error only at second order (rotation
//    error x distance).
//  - World-frame error (no alignment): for a run that starts at a known pose (its first estimate
//    is the ground truth there), the estimate is already in the ground truth's world frame, so
//    any alignment would hide the drift it measures (an SE(3) alignment rotates a tilted floor
//    flat and lifts a sunk one). Pairs associated as for the ATE; per pair the position error
//    split along the world's up axis (vertical) and across it (horizontal), and the tilt error:
//    the angle between the up direction as the estimated and as the true camera see it (roll
//    and pitch error; a heading error does not count).

#include <Eigen/Geometry>
#include <cstddef>
#include <vector>

#include "rasm/io/Trajectory.h"

namespace rasm::io {

/// Statistics of a set of errors (as the TUM scripts print them; std is the population std).
struct ErrorStats {
  std::size_t count = 0;
  double rmse = 0, mean = 0, median = 0, std = 0, min = 0, max = 0;
  static ErrorStats of(std::vector<double> values);
};

struct AteOptions {
  double max_dt_s = 0.02;  ///< association tolerance
  double offset_s = 0.0;   ///< added to the estimate's stamps
  bool align = true;       ///< false: compare raw positions (same world frame assumed)
  bool scale = false;      ///< Sim(3) alignment (monocular); needs align
};

struct AteResult {
  ErrorStats translation_m;
  /// Alignment applied to the estimate: p_gt ~ scale * R * p_est + t.
  Eigen::Isometry3d T_gt_est = Eigen::Isometry3d::Identity();
  double scale = 1.0;
  /// Per associated pair: stamps and translation error (m), in time order.
  std::vector<double> gt_stamps, est_stamps, errors_m;
};

struct WorldFrameOptions {
  double max_dt_s = 0.02;  ///< association tolerance, as AteOptions
  /// The world's up direction (against gravity): z, as in the simulator's and MRPT's robot
  /// worlds.
  Eigen::Vector3d up_world = Eigen::Vector3d::UnitZ();
};

/// Errors of an estimate against the ground truth in their common world frame, not aligned.
struct WorldFrameError {
  ErrorStats position_m;    ///< |p_est - p_gt|
  ErrorStats vertical_m;    ///< |(p_est - p_gt) . up_world|
  ErrorStats horizontal_m;  ///< |(p_est - p_gt)| across up_world
  ErrorStats tilt_deg;      ///< angle between R_est^T up_world and R_gt^T up_world
  /// Heading (yaw) error: the rotation R_est R_gt^T about up_world (its twist about up), the
  /// error that turns into horizontal drift as the robot drives (distance x heading error).
  ErrorStats heading_deg;
  /// Of the estimate's first pose (its earliest stamp) against the ground truth it associates
  /// with: position (m) and rotation angle (deg); NaN when it associates with none.
  double start_position_error_m = 0, start_rotation_error_deg = 0;
  /// Whether the first estimated pose is the ground truth's within the tolerances: the run
  /// started at a known pose, so the world-frame error is meaningful without alignment.
  bool startsAtGroundTruth(double max_position_m = 1e-3, double max_rotation_deg = 0.05) const;
};

struct RpeOptions {
  double delta = 1.0;  ///< interval, in seconds (delta_in_frames false) or frames
  bool delta_in_frames = false;
  double offset_s = 0.0;
};

struct RpeResult {
  ErrorStats translation_m;  ///< per interval `delta`
  ErrorStats rotation_deg;
  std::size_t pairs = 0;
};

/// Closed-form least-squares alignment (Umeyama 1991; Horn 1987 for the rotation) of point sets:
/// finds s, R, t minimising sum |dst_i - (s R src_i + t)|^2. With with_scale false s = 1.
/// Needs >= 3 non-collinear points for a unique rotation (fewer: a least-squares solution).
void alignUmeyama(const std::vector<Eigen::Vector3d>& src, const std::vector<Eigen::Vector3d>& dst,
                  bool with_scale, Eigen::Matrix3d& R, Eigen::Vector3d& t, double& s);

class TrajectoryEvaluator {
 public:
  /// Throws InputError when fewer than 3 pairs (alignment) / 1 pair associate.
  static AteResult computeAte(const Trajectory& ground_truth, const Trajectory& estimate,
                              const AteOptions& opt = {});
  /// Throws InputError when fewer than 2 pairs associate.
  static WorldFrameError computeWorldFrameError(const Trajectory& ground_truth,
                                                const Trajectory& estimate,
                                                const WorldFrameOptions& opt = {});
  /// Throws InputError when no interval can be evaluated.
  static RpeResult computeRpe(const Trajectory& ground_truth, const Trajectory& estimate,
                              const RpeOptions& opt = {});
};

}  // namespace rasm::io
