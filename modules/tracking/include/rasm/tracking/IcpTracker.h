#pragma once
// Camera tracking of section II-C: coarse-to-fine point-to-plane ICP with projective data
// association (KinectFusion [30], as in ElasticFusion) of the current frame against the model
// rendered from the previous pose (reliable surfels only: TTrackingParams::model_min_confidence).
// Plain point-to-plane least squares by default; optional: residuals weighted by the depth
// noise model (depth_noise_weighting), an ElasticFusion-style photometric term
// (photometric_weight, needs both colour images), surfel-confidence weights (confidence_full,
// needs the rendered confidence), a half-resolution model (model_level). TrackingParams.h and
// docs/slam-eval.md have the measurements behind the defaults.
//
// How the Mapper uses it (one call per frame):
//
//   tracker.reset(T_world_cam0);                      // first frame: map initialised there
//   for each later frame:
//     buildFramePyramid(frame.depth_m, K, params.numLevels(), pyr);  // core, camera frame
//     ModelMaps m;                                    // render at tracker.lastGoodPose()
//     m.vertex_world = ...; m.normal_world = ...; m.K = K; m.T_world_model = lastGoodPose();
//     m.colour = ...;                                 // optional (photometric term)
//     TrackingResult r = tracker.track(pyr, m, frame.colour);  // motion-model guess, updates state
//     if (r.ok) fuse(frame, r.T_world_cam);           // and render the next model from it
//     else      skip fusion; keep rendering from tracker.lastGoodPose()
//
// Model maps: vertex and normal maps in the WORLD frame at the resolution of frame level
// TTrackingParams::model_level (0 = full), invalid pixels with
// x = NaN (as core's kernels), rendered with intrinsics `K` from the pose `T_world_model`. The
// tracker projects the frame's vertices into that camera to associate them. Its coarse levels
// are built inside each call (kernels::ModelDownsampleKernel: the 2x2 block's foreground samples
// averaged, the rule of core's depth pyramid, so both pyramids sample the same pixel centres).
// Empty (0x0) or all-invalid maps are allowed: the frame is then reported TooFewInliers.
// The optional colour and confidence maps follow the same pyramid rule.
//
// Lost track and recovery: a frame that fails a quality rule (TrackingResult::status) leaves the
// state untouched except that the velocity is reset to zero, so the next guess is the last good
// pose. As long as the Mapper keeps rendering the model from lastGoodPose(), tracking recovers by
// itself once the camera returns near that view. Frames after a loss are checked with the same
// rules; nothing else is needed from the caller.

#include <Eigen/Geometry>
#include <deque>
#include <functional>
#include <memory>
#include <optional>
#include <vector>

#include "rasm/compute/ImageView.h"
#include "rasm/compute/Types.h"
#include "rasm/core/CameraIntrinsics.h"
#include "rasm/core/FrameProcessing.h"
#include "rasm/core/Image.h"
#include "rasm/tracking/MotionPrior.h"
#include "rasm/tracking/TrackingParams.h"
#include "rasm/tracking/TrackingResult.h"
#include "rasm/tracking/kernels/IcpKernels.h"

namespace rasm::tracking {

namespace cuda {
class IcpCudaReducer;
}

/// The model the frame is aligned to: the map rendered from T_world_model.
struct ModelMaps {
  ImageView<const Vec3f> vertex_world;  ///< frame level model_level, world frame, invalid = NaN x
  ImageView<const Vec3f> normal_world;  ///< unit normals, world frame, invalid = NaN x
  CameraIntrinsics K;                   ///< intrinsics of the render (size = map size)
  Eigen::Isometry3d T_world_model = Eigen::Isometry3d::Identity();
  /// Optional rendered colour (same size) for the photometric term; empty = geometry only.
  ImageView<const Bgr8> colour;
  /// Optional rendered surfel confidence (same size), for TTrackingParams::confidence_full.
  ImageView<const float> confidence;
};

/// How far `T_world_cam` is from the prior's pose in the standard deviations of its odometry
/// (MotionPrior::odometry_information, or odometry_information_degenerate when `degenerate` and
/// the prior has one; 0 for a prior that holds no odometry): the rule of
/// TTrackingParams::max_odometry_sigmas, for tracked frames and for relocalised poses alike.
double odometrySigmas(const Eigen::Isometry3d& T_world_cam, const MotionPrior& prior,
                      bool degenerate = false);

/// The pose `r` moved the camera to from `T_from`, with the move kept only along the
/// eigen-directions of r's system that the data hold with at least `min_eigenvalue`
/// (TrackingResult::eigenvalues' scale); along the others the camera stays at T_from. The
/// tracker's own solve does the same at TTrackingParams::min_eigenvalue; loop closure asks more
/// of a registration before it moves the map.
Eigen::Isometry3d moveAlongHeldDirections(const TrackingResult& r, const Eigen::Isometry3d& T_from,
                                          double min_eigenvalue);

class IcpTracker {
 public:
  /// Throws InputError when params are out of range (TTrackingParams::validate).
  explicit IcpTracker(const TTrackingParams& params = TTrackingParams());
  ~IcpTracker();
  IcpTracker(IcpTracker&&) noexcept;
  IcpTracker& operator=(IcpTracker&&) noexcept;

  const TTrackingParams& params() const { return m_params; }

  /// Starts (or restarts) tracking at a known pose with zero velocity.
  void reset(const Eigen::Isometry3d& T_world_cam);
  bool initialized() const { return m_initialized; }

  /// Replaces the last good pose (e.g. by its projection onto a motion constraint) without
  /// touching the pose before it, so the velocity follows the corrected pose.
  void correctLastPose(const Eigen::Isometry3d& T_world_cam) { m_T_last = T_world_cam; }
  /// Moves the whole motion state by a correction of the world frame (a loop closure): the last
  /// poses and the guess become C * T, so the velocity in the camera frame is kept.
  void applyWorldCorrection(const Eigen::Isometry3d& C) {
    m_T_last = C * m_T_last;
    m_T_prev = C * m_T_prev;
    m_last_guess = C * m_last_guess;
  }

  /// Motion-model prediction for the next frame (constant velocity or previous pose). With
  /// constant velocity after k lost frames (k <= lost_velocity_frames) the last velocity applied
  /// k + 1 times; beyond that the last good pose.
  Eigen::Isometry3d predictPose() const;
  /// Consecutive frames lost since the last good one.
  int lostFrames() const { return m_lost_frames; }
  /// Whether predictPose() extrapolates through lost frames (then the caller renders the model
  /// at the previous frame's guess rather than at the last good pose).
  bool extrapolatingThroughLoss() const {
    return m_lost_frames > 0 && m_lost_frames <= m_params.lost_velocity_frames &&
           m_params.motion_model == MotionModel::ConstantVelocity;
  }
  /// Last pose of a frame tracked with ok = true (or of reset()).
  const Eigen::Isometry3d& lastGoodPose() const { return m_T_last; }

  /// Tracks one frame from the motion-model guess. `frame` is core's pyramid (level 0 full
  /// resolution, camera frame) with at least params().numLevels() levels. On ok the pose becomes
  /// the last good pose and the velocity is updated; otherwise only the velocity is reset.
  /// Returns NotInitialized (ok = false) before reset(). Throws InputError on malformed input.
  /// `frame_colour` (optional, registered to the depth, size of level 0) enables the photometric
  /// term when params().photometric_weight > 0 and the model has a colour map, and, without a
  /// prior, the photometric retry of a degenerate frame (photometric_weight_degenerate).
  /// `prior` (optional): the pose predicted from odometry (or another source) with its
  /// uncertainty; it replaces the motion-model guess and enters the solve (MotionPrior.h).
  /// `denser_model` (optional): called when the frame fails against `model` for lack of
  /// support only (Degenerate not accepted, or TooFewInliers), it returns a model with more of
  /// the map (the stage's all-surfel render; nullopt = none) and the frame is aligned again
  /// from the same guess; the second result stands if it is ok and, without a prior, not
  /// degenerate (a degenerate retry has the inliers but not the directions). The stable-surfel
  /// model lags the map by the frames a surfel needs to become stable: at the start of a run and
  /// where a pan has just fused new space it covers too little of the view (docs/tracking.md).
  /// `coloured_model` (optional): the same model as `model` with its colour rendered, called
  /// only when the photometric retry of a degenerate frame needs it and `model` has no colour.
  using DenserModel = std::function<std::optional<ModelMaps>()>;
  TrackingResult track(const std::vector<FrameLevel>& frame, const ModelMaps& model,
                       ImageView<const Bgr8> frame_colour = {}, const MotionPrior* prior = nullptr,
                       const DenserModel& denser_model = {},
                       const DenserModel& coloured_model = {});

  /// Aligns `frame` to `model` starting from an explicit guess; does not touch the motion state.
  /// The quality rules (including the jump vs. the guess) are applied as in track().
  /// `photometric_weight` (>= 0) replaces params().photometricWeight() for this call.
  TrackingResult align(const std::vector<FrameLevel>& frame, const ModelMaps& model,
                       const Eigen::Isometry3d& T_world_cam_guess,
                       ImageView<const Bgr8> frame_colour = {}, const MotionPrior* prior = nullptr,
                       std::optional<double> photometric_weight = std::nullopt);

  /// The pose check of align() on its own (kernels::PoseCheckKernel at params().check_level):
  /// how the frame seen from T_world_cam agrees with the model. For verifying a pose found
  /// elsewhere (relocalisation) before tracking resumes from it.
  struct PoseCheck {
    double overlap = 0.0;    ///< fraction of the frame's valid pixels landing on the model
    double agreement = 0.0;  ///< of those, fraction agreeing with the model's surface
    double behind = 0.0;     ///< of those, fraction behind it (seeing through mapped space)
    /// Disagreement allowed by the relative rule (recent accepted frames), 1 = no history yet.
    double max_disagreement = 1.0;
    bool passed = false;  ///< conclusive (overlap >= check_min_overlap) and within the limits
  };
  /// The relative rule's limit from the recent accepted frames (1 without history).
  double maxDisagreement() const;
  PoseCheck checkPose(const std::vector<FrameLevel>& frame, const ModelMaps& model,
                      const Eigen::Isometry3d& T_world_cam);

 private:
  /// align(), and for a degenerate frame without a prior that follows a tracked frame, align()
  /// again with the photometric term at photometric_weight_degenerate: that result when it is
  /// ok (every direction constrained by geometry and colour together), else the first.
  /// `coloured_model` gives `model` with its colour when `model` has none.
  TrackingResult alignWithColourRetry(const std::vector<FrameLevel>& frame, const ModelMaps& model,
                                      const Eigen::Isometry3d& guess,
                                      ImageView<const Bgr8> frame_colour, const MotionPrior* prior,
                                      const DenserModel& coloured_model = {});
  /// `r` when it is not a prior conflict of a degenerate frame or the prior has no
  /// odometry_information_degenerate; else align() again with the odometry's x, y and yaw held
  /// at that precision: that result when it is ok (held_by_odometry), else `r`.
  TrackingResult retryHeldByOdometry(const std::vector<FrameLevel>& frame, const ModelMaps& model,
                                     const Eigen::Isometry3d& guess,
                                     ImageView<const Bgr8> frame_colour, const MotionPrior& prior,
                                     TrackingResult r);
  PoseCheck checkPoseBuilt(const std::vector<FrameLevel>& frame, const ModelMaps& model,
                           const Eigen::Isometry3d& T_world_cam) const;
  /// The point-to-plane and photometric kernels of frame level l against its model level (the
  /// pose fields are set per iteration).
  void levelKernels(int l, const std::vector<FrameLevel>& frame, const ModelMaps& model,
                    bool photometric, bool confidence, kernels::IcpReduceKernel& k,
                    kernels::PhotometricReduceKernel& pk) const;
  /// One point-to-plane reduction of level l at k's pose (CPU or CUDA); with no model, only the
  /// valid frame pixels are counted.
  kernels::IcpAccumulator reduceLevel(int l, const kernels::IcpReduceKernel& k, bool model_empty);
  /// The CUDA reducer, created on first use; InputError when CUDA is not usable.
  void ensureCudaReducer();
  /// Fills res's pose-check fields; whether the check failed and neither the prior nor the
  /// odometry confirms the pose under the relative rule alone.
  bool poseCheckFailed(const std::vector<FrameLevel>& frame, const ModelMaps& model,
                       const MotionPrior* prior, TrackingResult& res) const;
  void buildModelPyramid(const ModelMaps& model, bool intensity, bool confidence);
  void buildFrameIntensity(const std::vector<FrameLevel>& frame, ImageView<const Bgr8> colour);

  TTrackingParams m_params;
  bool m_initialized = false;
  Eigen::Isometry3d m_T_last = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d m_T_prev = Eigen::Isometry3d::Identity();  ///< good pose before m_T_last
  int m_lost_frames = 0;
  int m_degenerate_run = 0;  ///< degenerate frames accepted on the velocity since the last Ok one
  Eigen::Isometry3d m_last_guess = Eigen::Isometry3d::Identity();  ///< of the previous frame
  /// Scratch: model maps at levels >= 1 (level 0 is the caller's view).
  std::vector<Image<Vec3f>> m_model_vertex, m_model_normal;
  /// Scratch of the photometric term, all levels: model intensity, frame (I, dI/du, dI/dv).
  std::vector<Image<float>> m_model_intensity, m_frame_intensity;
  std::vector<Image<float>> m_model_confidence;  ///< levels >= 1 (level 0 is the caller's view)
  std::vector<Image<Vec3f>> m_frame_igrad;
  std::deque<double> m_recent_disagreement;      ///< of the last accepted frames (relative rule)
  std::unique_ptr<cuda::IcpCudaReducer> m_cuda;  ///< created on first use when use_cuda
};

}  // namespace rasm::tracking
