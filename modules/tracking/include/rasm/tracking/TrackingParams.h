#pragma once
// Options of the camera tracker of section II-C, INI section [tracking].
// Per-level values have one key per level, level 0 = full resolution: `iterations_level2 = 4`,
// `iterations_level1 = 5`, `iterations_level0 = 10` run 4 iterations at quarter, 5 at half and 10
// at full resolution, in that order (coarse to fine, as KinectFusion).

#include <mrpt/config/CLoadableOptions.h>

#include <array>
#include <string>

namespace rasm::tracking {

/// How the initial guess of IcpTracker::track() is predicted from the last good poses.
enum class MotionModel {
  ConstantVelocity,  ///< T_pred = T_{t-1} * (T_{t-2}^-1 * T_{t-1})
  PreviousPose       ///< T_pred = T_{t-1}
};

struct TTrackingParams : public mrpt::config::CLoadableOptions {
  // ---- coarse-to-fine ICP (II-C) ----
  static constexpr int kMaxLevels = 3;
  /// Pyramid levels used (1..3): ICP runs from level num_levels-1 down to level 0.
  int num_levels = 3;
  /// ICP iterations per level (index = level; keys iterations_level<i>).
  std::array<int, kMaxLevels> iterations{10, 5, 4};
  /// Max distance (m) between a transformed frame vertex and its projectively associated model
  /// vertex, per level (keys max_dist_m_level<i>). Looser at coarse levels, where the guess is
  /// worst: on the test room, from 20 cm / 10 deg offsets 0.3 / 0.15 / 0.05 m converged 20 times
  /// out of 20, KinectFusion-like 0.1 / 0.075 / 0.05 m 15 out of 20 (0.01 mm convergence limits).
  std::array<double, kMaxLevels> max_dist_m{0.05, 0.15, 0.3};
  /// Max angle (deg) between the transformed frame normal and the model normal, per level (keys
  /// max_normal_angle_deg_level<i>). Looser at level 0, whose normals come from raw depth: on
  /// TUM fr1/xyz and 7-Scenes 30 deg rejected half of the correctly aligned pixels (sensor noise),
  /// 45 deg a quarter, with the same pose accuracy; the smoother coarse levels keep 30 deg.
  std::array<double, kMaxLevels> max_normal_angle_deg{45.0, 30.0, 30.0};
  /// Process every n-th pixel in x and y at level 0 only (1 = all). The level-0 vertex map of a
  /// 640x480 frame has ~300k pixels; a stride of 2 keeps ~75k, plenty to constrain 6 DoF.
  int level0_pixel_stride = 2;
  /// Huber threshold (m) on the point-to-plane residual for IRLS weights; 0 = plain least squares.
  /// With depth_noise_weighting it applies to the residual scaled to the noise at 1 m.
  double huber_delta_m = 0.0;
  /// Weight each point-to-plane residual by (sigma(1 m) / sigma(z))^2, sigma(z) the axial noise
  /// of Kinect-type depth (Nguyen et al. 2012, kernels::depthNoiseSigma): far, noisy points
  /// count less. On by default, with model_min_confidence = 3: see there for what it measured.
  bool depth_noise_weighting = true;
  /// With depth_noise_weighting, sigma_z at each point's incidence angle too (the angle between
  /// its normal and the viewing ray; Nguyen et al.'s angle term): grazing points, such as a far
  /// floor seen by a robot, count less than points at the same depth seen head-on. Off: on the
  /// exploring default it let the pose slide 16 cm along a view the model agreed with
  /// (docs/slam-eval.md "The simulated floor's bias").
  bool depth_noise_incidence = false;
  /// Weight each residual by min(1, c / confidence_full), c = confidence of the associated model
  /// surfel, when the caller passes the model's confidence map; 0 = off.
  double confidence_full = 0.0;

  // ---- photometric term (joint ICP + RGB as ElasticFusion; kernels::PhotometricReduceKernel) ----
  /// Weight of the photometric cost relative to the point-to-plane one, in m^2 per squared
  /// intensity unit (intensity = luma in [0, 1]): an intensity residual of 1 costs as much as a
  /// point-to-plane residual of sqrt(photometric_weight) m. 0 = geometry only. Used only when
  /// the caller passes both the frame's colour and the model's rendered colour.
  double photometric_weight = 0.0;
  /// The photometric weight for frames with a motion prior (odometry): there the prior holds the
  /// directions the geometry leaves free, and the texture of a floor or a far wall constrains the
  /// yaw and the in-plane translation the prior alone lets drift with the wheels' noise (a robot
  /// turning in place in a room whose walls are beyond the depth range). Measured on exploring
  /// robot runs (docs/slam-eval.md, "Exploring robot"); hand-held frames (no prior) keep
  /// photometric_weight, which made real hand-held sequences worse.
  double photometric_weight_with_prior = 0.003;
  /// The photometric weight for frames without a prior whose geometry leaves a direction
  /// unconstrained (a plain wall, a wall and the floor), while tracking (the previous frame
  /// tracked: from a stale pose, after a loss, a robot without odometry was accepted 2.7 m off,
  /// docs/slam-eval.md): such a frame is aligned once more with
  /// the photometric term at this weight, and that result stands if the joint system constrains
  /// every direction (status ok); otherwise the geometric one does, degenerate. The colour of a
  /// textured wall then holds the slide along it that the geometry cannot see, and frames whose
  /// geometry is well constrained (real hand-held sequences, which the photometric term made
  /// worse) are not touched. 0 = off. docs/slam-eval.md "A pan along a plain textured wall".
  double photometric_weight_degenerate = 0.003;
  /// The photometric weight align() uses: photometric_weight_with_prior with a prior.
  double photometricWeight(bool with_prior) const {
    return with_prior ? photometric_weight_with_prior : photometric_weight;
  }
  /// Huber threshold on the intensity residual (intensity units); 0 = least squares.
  double photometric_huber = 0.0;
  /// Samples whose frame intensity gradient is below this (intensity per pixel of the level)
  /// carry little information and are skipped.
  double photometric_min_gradient = 0.0;
  /// A level stops early once the increment is below both limits. On TUM fr1/xyz and 7-Scenes,
  /// 0.1 mm / 0.01 deg took 8 and 11.5 iterations per frame instead of 13 and 16 at 0.01 mm /
  /// 0.001 deg, with the ATE within 0.4 mm.
  double convergence_translation_m = 1e-4;
  double convergence_rotation_deg = 0.01;

  // ---- model (prepared by the caller, pipeline::Mapper) ----
  /// The model ICP aligns to is rendered from the surfels with at least this confidence; 0 =
  /// those fusion flags stable (confidence >= [fusion] stable_confidence, 10; II-C renders "only
  /// stable points (those with high confidence weights)"). Default 3 with depth_noise_weighting:
  /// with the 50 deg fusion normal gate (TFusionParams.h) that pair is the only setting measured
  /// to meet all three accuracy targets (rasm run + rasm eval ate, docs/slam-eval.md):
  ///                               redkitchen_first300   TUM fr1_xyz_first37   sim 60 s / 30 s
  ///   stable (10), no weighting     2.48 cm               0.29 cm               0.63 / 0.61 cm
  ///   stable (10), weighting        2.27                    -                     -
  ///   >= 5, weighting               2.05                    -                     -
  ///   >= 3, weighting (default)     1.95                  0.27                  0.84 / 0.68
  ///   >= 2, weighting               1.92                  0.27                  1.13 (> 1 cm
  ///   target)
  ///   >= 3, no weighting            2.64                    -                     -
  /// It costs CPU: a min_confidence model visits every member of the blocks in view, not only
  /// their stable prefix (VoxelBlockIndex), ~5-12% more CPU per frame on redkitchen.
  /// Earlier, with the 30 deg gate, off / on:
  ///                        redkitchen_first300   TUM fr1_xyz_first37   sim office_handheld_long
  ///   stable (10)            2.60 / 2.63 cm        0.30 / 0.28 cm        0.67 cm (60 s) / 195 of
  ///                                                                      1010 frames lost
  ///   >= 5                     -  / 2.20             -                     -
  ///   >= 3                   2.51 / 2.07             -                     -
  ///   >= 2                     -  / 2.00           0.27 (on)             3.05 cm (1010 frames) /
  ///                                                                      diverged at 32.7 s
  ///   >= 1                     -  / 2.14             -                     -
  ///   all surfels            6.58 /  -               -                     -
  /// With the 30 deg gate the denser, weighted models drifted or lost track on the simulated
  /// office (its large far planes constrain ICP there, and the weighting discounts them); the
  /// 50 deg gate's cleaner map (fewer duplicate surfels) removed that.
  double model_min_confidence = 3.0;
  /// Pyramid level the caller renders the model at (0 = full resolution, 1 = half). Frame level l
  /// is associated with model level max(0, l - model_level), so at 1 the full-resolution frame
  /// points of level 0 meet the half-resolution model: point-to-plane residuals tolerate the
  /// coarser association along the surface, and the render, the costliest step of tracking,
  /// touches a quarter of the pixels. docs/slam-eval.md has the measurements behind the default.
  int model_level = 0;

  // ---- initial guess ----
  MotionModel motion_model = MotionModel::ConstantVelocity;
  /// Constant velocity through lost frames: for this many consecutive lost frames (without a
  /// motion prior) the guess keeps extrapolating the last velocity, then it falls back to the last
  /// good pose (0 = zero velocity from the first lost frame, the default). A hand-held pan at
  /// 150 deg/s turns 5 deg per frame: two lost frames with zero velocity leave the guess 15 deg
  /// behind, beyond max_jump_rotation_deg. Measured at 5 on one generated fast pan (no change:
  /// its frames were refused as degenerate, not for the guess) and on the kidnapped
  /// office_handheld_long together with degenerate_max_run_frames 8 (relocalised 19 frames after
  /// the cut instead of 1; which of the two did it is not established), so it stays off.
  /// Either way a frame tracked again after a loss restarts from zero velocity (the motion over
  /// the gap is not applied again to the next frame).
  int lost_velocity_frames = 0;

  // ---- tracking-quality rules (a frame failing any of them is lost: ok = false) ----
  /// Minimum inliers at level 0 (after the stride) and minimum inliers / valid frame pixels.
  int min_inliers = 1000;
  double min_inlier_fraction = 0.15;
  /// Maximum RMS point-to-plane residual (m) of the level-0 inliers.
  double max_rms_m = 0.025;
  /// Maximum deviation of the result from the initial guess (motion-model prediction): a bigger
  /// correction means ICP slid into a wrong minimum.
  double max_jump_translation_m = 0.15;
  double max_jump_rotation_deg = 10.0;
  /// Degeneracy: smallest eigenvalue of the normalised, scale-balanced J^T J (see
  /// TrackingResult::min_eigenvalue). Directions below it are not updated (kept from the guess).
  /// Seen: a room with boxes 0.012-0.015, TUM / 7-Scenes frames 0.013-0.022, a single wall 1e-11
  /// (noise-free), ICP stuck in a wrong minimum typically 1e-5..1e-3.
  double min_eigenvalue = 1e-3;
  /// A degenerate frame (e.g. a single wall) is accepted (ok, fused with the unconstrained
  /// directions taken from the guess) only if at least this fraction of its valid pixels are
  /// inliers: with directions the geometry cannot check, near-total agreement with the model is
  /// the remaining evidence. ICP that slid into a wrong minimum along a partially constrained
  /// direction also looks degenerate but agrees with far fewer pixels. > 1 = never accept.
  double degenerate_min_inlier_fraction = 0.7;
  /// Without a prior, a degenerate frame that fails that fraction is still accepted (its weak
  /// directions from the constant-velocity guess, every other rule and the pose check passed) for
  /// at most this many consecutive frames after a well-constrained one (0 = never, the default).
  /// A hand-held pan from mapped into new space sees less and less of the model (inliers 0.59 ->
  /// 0.30 over 6 frames on a generated room, each pose within 1.2 deg) and, refused, never fuses
  /// the new space it turned to: at 8 that run was tracked throughout (855 / 855, 0.22 cm). But
  /// the velocity then feeds itself along the unconstrained directions: office_robot_loop without
  /// odometry went from 5 / 743 tracked (honestly lost) to 743 / 743 "tracked" with a silent
  /// 3.9 m jump along the room (docs/slam-eval.md). Off until the run is bounded by something
  /// the data check.
  int degenerate_max_run_frames = 0;

  // ---- motion prior (odometry or motion model, IcpTracker::track's `prior`) ----
  /// Standard deviation (m) assumed for one point-to-plane residual when the ICP data are
  /// weighed against a motion prior: the ICP information is J^T W J / sigma^2. Much larger than
  /// the sensor noise (1.9 mm at 1 m) because neighbouring residuals are correlated (the model is
  /// one surface, not independent samples) and camera-fixed depth artefacts bias them; with
  /// tens of thousands of inliers the data still dominate every direction they constrain well.
  /// Measured on simulated robot paths (docs/slam-eval.md, "Robot, fast motion, ..."): 0.01
  /// drifted 4-20 cm along floors and corridors; 0.05 gave 0.9-3.0 cm, 0.1 0.8-1.5 cm (four
  /// paths, one of them in a generated world). 0.05 is kept because at 0.1 an 8 cm wheel slip
  /// in a well-constrained room (prior sigma 3 mm) was followed and accepted, 7.6 cm off
  /// (MotionPrior.DataOverrulesAWrongPriorAndTheConflictIsReported); at 0.05 it is refused.
  double prior_pixel_sigma_m = 0.05;
  /// With a prior, the data enter only along the directions whose eigenvalue (as
  /// min_eigenvalue) is at least this; the prior alone holds the others. Noisy normals of a
  /// floor seen at a grazing angle add spurious, biased constraints around 1e-3..1e-2 that made
  /// ICP slide along a corridor: 1e-2 kept two_rooms_robot at 1.5 cm where 3e-3 gave 2.4 and
  /// 1e-3 2.6. The price: a wheel slip in a room whose weakest directions are just below it
  /// (rooms measure 0.012-0.015) is followed partly, and caught by max_prior_sigmas.
  double prior_min_eigenvalue = 1e-2;
  /// A result further from the prior than this many standard deviations (Mahalanobis distance
  /// of the 6-DoF difference under the prior's covariance) is lost (status prior_conflict):
  /// on the simulated robot paths the largest was 2.5 (99th percentile 1.3); a slip of several
  /// odometry sigmas or a wrong ICP minimum goes beyond. 0 = no check.
  double max_prior_sigmas = 6.0;
  /// The same rule in the odometry's directions only (x, y along the floor, yaw about its
  /// normal; MotionPrior::odometry_information): a result further than this many standard
  /// deviations of the odometry from its x, y and yaw is lost (prior_conflict). With the floor
  /// measurement on, the height, roll and pitch take a large share of prior_sigmas on every frame,
  /// so a slide along the floor of a few odometry sigmas stays below max_prior_sigmas. Measured
  /// on three simulated robot runs at 320x240 (4,152 frames whose step is within 3 mm of the
  /// truth): 99.9th percentile 1.8, max 2.46; a slide of 0.9, 2.2 and 1.5 cm in three frames
  /// measured 2.74, 5.0 and 3.3. At 3 the first slide frame was fused and the run lost 8% of its
  /// frames to the disagreement it left (docs/slam-eval.md "A prior conflict in x, y and yaw").
  /// 0 = no check.
  double max_odometry_sigmas = 2.5;

  // ---- pose check after alignment (kernels::PoseCheckKernel) ----
  /// Pyramid level of the check (frame level; the model level is max(0, level - model_level)).
  int check_level = 1;
  /// Agreement gate: |p - q| <= check_gate_m + check_noise_sigmas * sigma(z) (depth noise model)
  /// and normals within check_max_normal_angle_deg.
  double check_gate_m = 0.01;
  double check_noise_sigmas = 3.0;
  double check_max_normal_angle_deg = 45.0;
  /// Frame points more than this in front of the model's surface are something the map does not
  /// hold yet before a mapped surface (a chair before a wall: the model is rendered from reliable
  /// surfels only), not a pose error, and are left out of the overlap. Counted as disagreement,
  /// exploring robots lost correct frames as inconsistent whenever they turned to such objects,
  /// and those frames, not fused, kept the objects out of the map (docs/slam-eval.md, "Exploring
  /// robot"). Not smaller: a pose 6 cm too high puts the floor 6 cm in front, and at 0 (every
  /// point in front ignored) PoseCheck.TellsTheRightPoseFromWrongOnes passes a wrong pose. Objects
  /// lower than this before a reliable surface (a box on the floor, a book on a desk) still
  /// count against a right pose until they are fused.
  double check_occluder_margin_m = 0.15;
  /// Of the frame pixels that land on the model's surface, at least this fraction must agree
  /// with it, and at most check_max_behind may lie behind it (seeing through mapped space);
  /// otherwise the pose is lost (status inconsistent). The check needs check_min_overlap of the
  /// frame's valid pixels on the model to be conclusive; below that the other rules decide.
  double check_min_agreement = 0.5;
  double check_max_behind = 0.25;
  double check_min_overlap = 0.1;
  /// Relative rule: the disagreement (1 - agreement) may be at most this many times the median
  /// of the last check_history accepted frames' (and at least check_min_disagreement): a pose
  /// sliding away shows as a jump of the disagreement against the frames before it, whatever
  /// the sensor's usual level (a real Kinect's differs from the simulator's). 0 = off.
  double check_max_disagreement_ratio = 3.0;
  double check_min_disagreement = 0.15;
  int check_history = 30;
  /// A frame that fails the relative rule alone (its agreement above check_min_agreement, its
  /// disagreement a jump against the recent frames') is accepted when a motion prior (odometry)
  /// puts its pose within this many of the prior's sigmas: a pose sliding away along a plane
  /// leaves the wheels' estimate, a right pose whose view disagrees with a model fused a few
  /// centimetres off does not. 0 = off (the relative rule alone decides). 2 halved the exploring
  /// default's inconsistent frames (docs/slam-eval.md "The simulated floor's bias").
  double check_prior_confirms_sigmas = 2.0;
  /// The same with the odometry's part of the prior alone (x, y, yaw: what the wheels measure;
  /// MotionPrior::odometry_information), either rule overrules. The floor part of a prior can be
  /// 2-3 sigmas off where the model was fused a little off the floor, the wheels within 1 sigma
  /// (flats 3952 and 3955: docs/results-worldframe.md). 0 = off.
  double check_odometry_confirms_sigmas = 0.0;

  // ---- backend ----
  /// Run the ICP reduction on the GPU (CUDA launcher of the same kernel). Needs a CUDA build
  /// and device; track() throws InputError otherwise. The photometric term has no CUDA launcher
  /// yet: it is reduced on the CPU either way.
  bool use_cuda = false;

  int numLevels() const { return num_levels; }

  void loadFromConfigFile(const mrpt::config::CConfigFileBase& cfg,
                          const std::string& section) override;
  void saveToConfigFile(mrpt::config::CConfigFileBase& cfg,
                        const std::string& section) const override;
  /// Throws InputError naming `section` and the offending key when a value is out of range.
  void validate(const std::string& section = "tracking") const;
};

const char* toString(MotionModel m);

}  // namespace rasm::tracking
