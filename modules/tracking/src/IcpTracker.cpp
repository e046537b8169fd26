#include "rasm/tracking/IcpTracker.h"
#include "rasm/core/Angles.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <string>

#include "rasm/compute/Device.h"
#include "rasm/compute/Parallel.h"
#include "rasm/core/Error.h"
#include "rasm/core/SE3.h"
#include "rasm/tracking/IcpCuda.h"
#include "rasm/tracking/kernels/IcpKernels.h"
#include "rasm/tracking/kernels/PoseCheckKernels.h"

namespace rasm::tracking {

const char* toString(TrackingStatus s) {
  switch (s) {
    case TrackingStatus::Ok:
      return "ok";
    case TrackingStatus::Degenerate:
      return "degenerate";
    case TrackingStatus::TooFewInliers:
      return "too_few_inliers";
    case TrackingStatus::HighResidual:
      return "high_residual";
    case TrackingStatus::ExcessiveMotion:
      return "excessive_motion";
    case TrackingStatus::Inconsistent:
      return "inconsistent";
    case TrackingStatus::PriorConflict:
      return "prior_conflict";
    case TrackingStatus::Diverged:
      return "diverged";
    case TrackingStatus::NotInitialized:
      return "not_initialized";
  }
  return "?";
}

namespace {

/// Below this many inliers a level's system is not solved (6 unknowns; margin for noise).
constexpr double kMinSolveInliers = 20;

RigidF toRigidF(const Eigen::Isometry3d& T) {
  return RigidF::fromMatrix(T.matrix().cast<float>());
}

/// The normal equations of one linearisation, normalised and analysed: the point-to-plane
/// sums plus, optionally, the photometric ones scaled by kappa (m^2 per squared intensity unit,
/// TTrackingParams::photometric_weight), so the joint cost is in the units of the geometric one.
struct IcpSystem {
  Eigen::Matrix<double, 6, 6> H;  ///< J^T W J
  Vector6d g;                     ///< J^T W r
  double inliers = 0, valid = 0, rms_m = 0, mean_depth_m = 1;
  double weight = 0;  ///< sum of the point-to-plane weights (the count without IRLS weights)
  /// Eigen-decomposition of D^-1 H D^-1 / weight, D = diag(1,1,1,d,d,d), d = mean depth: the
  /// rotation columns become (p - c) x n / d, of the same order as the unit normals, so the
  /// eigenvalues compare translation and rotation constraints on one dimensionless scale.
  Vector6d eigenvalues = Vector6d::Zero();
  Eigen::Matrix<double, 6, 6> eigenvectors = Eigen::Matrix<double, 6, 6>::Identity();

  explicit IcpSystem(const kernels::IcpAccumulator& a,
                     const kernels::IcpAccumulator* photo = nullptr, double kappa = 0.0) {
    using A = kernels::IcpAccumulator;
    int k = A::kJtJ;
    for (int i = 0; i < 6; ++i)
      for (int j = i; j < 6; ++j) {
        H(i, j) = H(j, i) = a.s[k] + (photo ? kappa * photo->s[k] : 0.0);
        ++k;
      }
    for (int i = 0; i < 6; ++i)
      g(i) = a.s[A::kJtr + i] + (photo ? kappa * photo->s[A::kJtr + i] : 0.0);
    inliers = a.inliers();
    valid = a.valid();
    weight = a.s[A::kW];
    if (inliers > 0 && weight > 0) {
      rms_m = std::sqrt(a.s[A::kR2] / inliers);
      mean_depth_m = std::max(1e-3, a.s[A::kDepth] / inliers);
      const Vector6d dinv = scaleInv();
      const Eigen::Matrix<double, 6, 6> Hs = dinv.asDiagonal() * H * dinv.asDiagonal() / weight;
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 6, 6>> es(Hs);
      eigenvalues = es.eigenvalues();
      eigenvectors = es.eigenvectors();
    }
  }
  Vector6d scaleInv() const {
    Vector6d d;
    d << 1, 1, 1, 1 / mean_depth_m, 1 / mean_depth_m, 1 / mean_depth_m;
    return d;
  }

  /// Gauss-Newton step H xi = -g. Well-conditioned systems are solved with LDLT; otherwise the
  /// step is restricted to the eigen-directions above `min_eig` (the others stay at the current
  /// estimate, i.e. at the motion-model guess). Measured on the room scene of the tests, this
  /// truncation also widens the basin of convergence (fewer slides along weakly constrained
  /// directions while the overlap is still partial). Returns the number of unconstrained
  /// directions.
  int solve(double min_eig, Vector6d& xi) const {
    int unconstrained = 0;
    for (int i = 0; i < 6; ++i)
      if (eigenvalues(i) < min_eig) ++unconstrained;
    if (unconstrained == 0) {
      xi = H.ldlt().solve(-g);
      return 0;
    }
    // In scaled coordinates xs = D xi: Hs xs = -gs with Hs = D^-1 H D^-1 / W, gs = D^-1 g / W.
    const Vector6d dinv = scaleInv();
    const Vector6d gs = dinv.cwiseProduct(g) / weight;
    Vector6d xs = Vector6d::Zero();
    for (int i = 0; i < 6; ++i)
      if (eigenvalues(i) >= min_eig)
        xs -= eigenvectors.col(i) * (eigenvectors.col(i).dot(gs) / eigenvalues(i));
    xi = dinv.cwiseProduct(xs);
    return unconstrained;
  }

  /// Gauss-Newton step with a Gaussian prior on the increment: minimises the ICP cost / sigma^2
  /// plus (xi - delta)^T Lambda (xi - delta), delta the increment that would move the estimate
  /// onto the prior's pose. Degeneracy per direction: the data enter only along the
  /// eigen-directions above `min_eig` (scaled coordinates, as solve()); along the others
  /// (a floor's in-plane directions, where noisy normals add spurious, biased constraints) the
  /// prior alone decides. So (H_s + sigma^2 Lambda) xi = -g_s + sigma^2 Lambda delta with H_s,
  /// g_s the normal equations restricted to the constrained subspace.
  void solveWithPrior(const Eigen::Matrix<double, 6, 6>& information, const Vector6d& delta,
                      double pixel_sigma2, double min_eig, Vector6d& xi) const {
    Eigen::Matrix<double, 6, 6> Hs =
        Eigen::Matrix<double, 6, 6>::Zero();  // scaled, constrained part
    Eigen::Matrix<double, 6, 6> Ps = Eigen::Matrix<double, 6, 6>::Zero();  // projector onto it
    for (int i = 0; i < 6; ++i)
      if (eigenvalues(i) >= min_eig) {
        Hs += eigenvalues(i) * eigenvectors.col(i) * eigenvectors.col(i).transpose();
        Ps += eigenvectors.col(i) * eigenvectors.col(i).transpose();
      }
    const Vector6d dinv = scaleInv();
    const Vector6d dsc = dinv.cwiseInverse();
    const Eigen::Matrix<double, 6, 6> H_c = weight * dsc.asDiagonal() * Hs * dsc.asDiagonal();
    const Vector6d g_c = dsc.asDiagonal() * (Ps * dinv.cwiseProduct(g));
    const Eigen::Matrix<double, 6, 6> Hp = H_c + pixel_sigma2 * information;
    xi = Hp.ldlt().solve(-g_c + pixel_sigma2 * (information * delta));
  }
};

/// The increment delta (IcpKernels.h coordinates: world axes about the camera centre c of T) with
/// P exp(delta) P^-1 T = T_target.
Vector6d incrementTo(const Eigen::Isometry3d& T, const Eigen::Isometry3d& T_target) {
  Eigen::Isometry3d Pc = Eigen::Isometry3d::Identity();
  Pc.translation() = T.translation();
  return se3Log(Pc.inverse() * T_target * T.inverse() * Pc);
}

/// Counts of kernels::PoseCheckKernel for the pose T at frame level `level`.
kernels::PoseCheckCounts checkPoseCounts(const FrameLevel& F,
                                         const ImageView<const Vec3f>& model_vertex,
                                         const ImageView<const Vec3f>& model_normal,
                                         const CameraIntrinsics& K_model,
                                         const Eigen::Isometry3d& T_world_model,
                                         const Eigen::Isometry3d& T, const TTrackingParams& P) {
  kernels::PoseCheckKernel k;
  k.frame_vertex = F.vertex.view();
  k.frame_normal = F.normal.view();
  k.model_vertex = model_vertex;
  k.model_normal = model_normal;
  k.K_model = K_model.plain();
  k.T_world_cam = toRigidF(T);
  k.T_model_cam = toRigidF(T_world_model.inverse() * T);
  k.T_model_world = toRigidF(T_world_model.inverse());
  k.base_gate_m = float(P.check_gate_m);
  k.noise_sigmas = float(P.check_noise_sigmas);
  k.min_normal_cos = float(std::cos(P.check_max_normal_angle_deg * kRadPerDeg));
  k.occluder_margin_m = float(P.check_occluder_margin_m);
  return compute::reduce1D<kernels::PoseCheckCounts>(k.rows(), k);
}

void checkMap(const ImageView<const Vec3f>& v, const ImageView<const Vec3f>& n,
              const std::string& what) {
  if (v.width != n.width || v.height != n.height)
    throwInputError("tracking: " + what, "vertex map " + std::to_string(v.width) + "x" +
                                             std::to_string(v.height) + " and normal map " +
                                             std::to_string(n.width) + "x" +
                                             std::to_string(n.height) + " differ in size");
}

/// InputError naming what does not fit: the frame pyramid against [tracking] num_levels, the
/// maps' validity, the model maps against their intrinsics and the model level, and the colour
/// and confidence images used.
void checkAlignInputs(const TTrackingParams& P, const std::vector<FrameLevel>& frame,
                      const ModelMaps& model, ImageView<const Bgr8> frame_colour, bool photometric,
                      bool confidence) {
  const int L = P.num_levels;
  if (static_cast<int>(frame.size()) < L)
    throwInputError("tracking: frame pyramid",
                    "has " + std::to_string(frame.size()) +
                        " levels, [tracking] num_levels = " + std::to_string(L));
  for (int l = 0; l < L; ++l) {
    const FrameLevel& F = frame[l];
    checkMap(F.vertex.view(), F.normal.view(), "frame level " + std::to_string(l));
    if (F.vertex.empty())
      throwInputError("tracking: frame level " + std::to_string(l),
                      "empty vertex map (build it with buildFramePyramid)");
  }
  checkMap(model.vertex_world, model.normal_world, "model maps");
  if (model.vertex_world.empty()) return;
  const auto size = [](int w, int h) { return std::to_string(w) + "x" + std::to_string(h); };
  if (model.K.width != model.vertex_world.width || model.K.height != model.vertex_world.height)
    throwInputError("tracking: model maps",
                    "size " + size(model.vertex_world.width, model.vertex_world.height) +
                        " differs from the model intrinsics " + model.K.toString());
  const FrameLevel& model_frame_level = frame[P.model_level];
  if (model.K.width != model_frame_level.depth_m.width() ||
      model.K.height != model_frame_level.depth_m.height())
    throwInputError(
        "tracking: model maps",
        "size " + size(model.K.width, model.K.height) + " differs from frame level " +
            std::to_string(P.model_level) + " ([tracking] model_level), " +
            size(model_frame_level.depth_m.width(), model_frame_level.depth_m.height()));
  if (photometric) {
    if (model.colour.width != model.vertex_world.width ||
        model.colour.height != model.vertex_world.height)
      throwInputError(
          "tracking: model colour",
          "size " + size(model.colour.width, model.colour.height) + " differs from the vertex map");
    if (frame_colour.width != frame[0].depth_m.width() ||
        frame_colour.height != frame[0].depth_m.height())
      throwInputError("tracking: frame colour", "size " +
                                                    size(frame_colour.width, frame_colour.height) +
                                                    " differs from the level-0 depth image");
  }
  if (confidence && (model.confidence.width != model.vertex_world.width ||
                     model.confidence.height != model.vertex_world.height))
    throwInputError("tracking: model confidence",
                    "size " + size(model.confidence.width, model.confidence.height) +
                        " differs from the vertex map");
}

/// T <- P exp(xi) P^-1 T (left-multiplicative about the pivot c, see IcpKernels.h), the step's
/// size in `st`; false when the step or the pose is not finite (diverged).
bool applyStep(const Vector6d& xi, Eigen::Isometry3d& T, TrackingLevelStats& st) {
  if (!xi.allFinite()) return false;
  Eigen::Isometry3d Pc = Eigen::Isometry3d::Identity();
  Pc.translation() = T.translation();
  T = Pc * se3Exp(xi) * Pc.inverse() * T;
  st.last_step_translation_m = xi.head<3>().norm();
  st.last_step_rotation_rad = xi.tail<3>().norm();
  return T.matrix().allFinite();
}

/// The result's fit: inliers and residual from level 0's last system, the eigen-analysis and
/// unconstrained directions from the weakest level's (have_weakest false: no level had enough
/// inliers, all six directions unconstrained), the correction from the guess, and the distances
/// to the prior in its sigmas.
void summariseFit(const TTrackingParams& P, const IcpSystem& last, const IcpSystem& weakest,
                  bool have_weakest, const MotionPrior* prior, TrackingResult& res) {
  res.inliers = int(last.inliers);
  res.inlier_fraction = last.valid > 0 ? last.inliers / last.valid : 0.0;
  res.rms_m = last.rms_m;
  res.eigenvalues = weakest.eigenvalues;
  res.eigenvectors = weakest.eigenvectors;
  res.eigen_mean_depth_m = weakest.mean_depth_m;
  res.min_eigenvalue = weakest.eigenvalues(0);
  res.unconstrained_directions = have_weakest ? 0 : 6;
  for (int i = 0; i < 6 && have_weakest; ++i)
    if (weakest.eigenvalues(i) < P.min_eigenvalue) ++res.unconstrained_directions;
  res.correction_translation_m = translationDistance(res.T_world_cam_guess, res.T_world_cam);
  res.correction_rotation_rad = rotationAngle(res.T_world_cam_guess, res.T_world_cam);
  if (prior && res.T_world_cam.matrix().allFinite()) {
    const Vector6d d = incrementTo(res.T_world_cam, prior->T_world_cam);
    res.prior_sigmas = std::sqrt(std::max(0.0, d.dot(prior->information * d)));
    res.odometry_sigmas = odometrySigmas(res.T_world_cam, *prior, res.unconstrained_directions > 0);
  }
}

/// The quality rules (most severe first) and whether the frame is accepted.
void judgeQuality(const TTrackingParams& P, bool diverged, bool check_failed, bool with_prior,
                  TrackingResult& res) {
  if (diverged || !res.T_world_cam.matrix().allFinite())
    res.status = TrackingStatus::Diverged;
  else if (res.inliers < P.min_inliers || res.inlier_fraction < P.min_inlier_fraction)
    res.status = TrackingStatus::TooFewInliers;
  else if (res.rms_m > P.max_rms_m)
    res.status = TrackingStatus::HighResidual;
  else if (res.correction_translation_m > P.max_jump_translation_m ||
           res.correction_rotation_rad > P.max_jump_rotation_deg * kRadPerDeg)
    res.status = TrackingStatus::ExcessiveMotion;
  else if (check_failed)
    res.status = TrackingStatus::Inconsistent;
  else if ((P.max_prior_sigmas > 0 && res.prior_sigmas > P.max_prior_sigmas) ||
           (P.max_odometry_sigmas > 0 && res.odometry_sigmas > P.max_odometry_sigmas))
    res.status = TrackingStatus::PriorConflict;
  else if (res.unconstrained_directions > 0)
    res.status = TrackingStatus::Degenerate;
  else
    res.status = TrackingStatus::Ok;
  // A degenerate frame: with a prior its weak directions come from the prior (per direction,
  // not a reason to drop the frame); without one, only near-total agreement with the model
  // supports the directions the geometry cannot check.
  res.ok = res.status == TrackingStatus::Ok ||
           (res.status == TrackingStatus::Degenerate &&
            (with_prior || res.inlier_fraction >= P.degenerate_min_inlier_fraction));
}

}  // namespace

IcpTracker::IcpTracker(const TTrackingParams& params) : m_params(params) {
  m_params.validate();
}
IcpTracker::~IcpTracker() = default;
IcpTracker::IcpTracker(IcpTracker&&) noexcept = default;
IcpTracker& IcpTracker::operator=(IcpTracker&&) noexcept = default;

void IcpTracker::reset(const Eigen::Isometry3d& T_world_cam) {
  m_T_last = m_T_prev = m_last_guess = T_world_cam;
  m_lost_frames = 0;
  m_degenerate_run = 0;
  m_initialized = true;
}

Eigen::Isometry3d IcpTracker::predictPose() const {
  if (m_params.motion_model == MotionModel::PreviousPose) return m_T_last;
  if (m_lost_frames > m_params.lost_velocity_frames) return m_T_last;
  // Constant velocity: apply the last inter-frame motion (in the camera frame) once more, and
  // once per frame lost since.
  const Eigen::Isometry3d step = m_T_prev.inverse() * m_T_last;
  Eigen::Isometry3d T = m_T_last;
  for (int k = 0; k <= m_lost_frames; ++k) T = T * step;
  return orthonormalize(T);
}

TrackingResult IcpTracker::track(const std::vector<FrameLevel>& frame, const ModelMaps& model,
                                 ImageView<const Bgr8> frame_colour, const MotionPrior* prior,
                                 const DenserModel& denser_model,
                                 const DenserModel& coloured_model) {
  if (!m_initialized) {
    TrackingResult r;
    r.status = TrackingStatus::NotInitialized;
    return r;
  }
  const Eigen::Isometry3d guess = prior ? prior->T_world_cam : predictPose();
  TrackingResult r = alignWithColourRetry(frame, model, guess, frame_colour, prior, coloured_model);
  if (prior) r = retryHeldByOdometry(frame, model, guess, frame_colour, *prior, std::move(r));
  const bool unsupported = r.status == TrackingStatus::TooFewInliers ||
                           (r.status == TrackingStatus::Degenerate && !r.ok);
  if (unsupported && denser_model) {
    if (const std::optional<ModelMaps> denser = denser_model()) {
      TrackingResult r2 = alignWithColourRetry(frame, *denser, guess, frame_colour, prior);
      r2.denser_model = true;
      // Without a prior, a retry that is still degenerate is not taken: the denser model gives
      // it the inliers a degenerate frame needs, but not the directions it lacks, and a robot
      // camera facing a floor slid 0.6 m in 75 such frames, each agreeing (slam-eval.md).
      if (r2.ok && (r2.status == TrackingStatus::Ok || prior)) r = std::move(r2);
    }
  }
  // A short run of degenerate frames after well-constrained ones rides on the velocity.
  if (r.status == TrackingStatus::Ok) {
    m_degenerate_run = 0;
  } else if (r.status == TrackingStatus::Degenerate && !r.ok && !prior && m_lost_frames == 0 &&
             m_params.motion_model == MotionModel::ConstantVelocity &&
             m_degenerate_run < m_params.degenerate_max_run_frames) {
    r.ok = true;
    r.on_motion_model = true;
    ++m_degenerate_run;
  } else if (!r.ok) {
    m_degenerate_run = m_params.degenerate_max_run_frames;  // no more until an Ok frame
  }
  if (r.ok && r.check_overlap >= m_params.check_min_overlap) {
    m_recent_disagreement.push_back(1.0 - r.check_agreement);
    while (int(m_recent_disagreement.size()) > m_params.check_history)
      m_recent_disagreement.pop_front();
  }
  if (r.ok) {
    // The velocity is the last frame-to-frame motion: after lost frames bridged by the
    // extrapolation, from the previous frame's guess; after a longer loss, zero.
    if (m_lost_frames == 0 || prior)
      m_T_prev = m_T_last;
    else if (extrapolatingThroughLoss())
      m_T_prev = m_last_guess;
    else
      m_T_prev = r.T_world_cam;
    m_T_last = r.T_world_cam;
    m_lost_frames = 0;
  } else {
    ++m_lost_frames;
    // Zero velocity once the extrapolation ends (or with a prior, which carries the motion).
    if (prior || m_lost_frames > m_params.lost_velocity_frames) m_T_prev = m_T_last;
  }
  m_last_guess = guess;
  return r;
}

TrackingResult IcpTracker::alignWithColourRetry(const std::vector<FrameLevel>& frame,
                                                const ModelMaps& model,
                                                const Eigen::Isometry3d& guess,
                                                ImageView<const Bgr8> frame_colour,
                                                const MotionPrior* prior,
                                                const DenserModel& coloured_model) {
  TrackingResult r = align(frame, model, guess, frame_colour, prior);
  const double w = m_params.photometric_weight_degenerate;
  if (r.status != TrackingStatus::Degenerate || prior || w <= 0 || frame_colour.empty() ||
      m_lost_frames > 0)
    return r;
  std::optional<ModelMaps> rendered;
  if (model.colour.empty() && coloured_model) rendered = coloured_model();
  const ModelMaps& m = rendered ? *rendered : model;
  if (m.colour.empty()) return r;
  // The geometry leaves a direction free: the colour may hold it. Taken only if it does, and
  // only while tracking: then the guess is within one frame's motion of the camera, inside the
  // photometric term's basin; from a stale pose it can find a wrong minimum that every rule
  // accepts (docs/tracking.md).
  TrackingResult rc = align(frame, m, guess, frame_colour, nullptr, w);
  if (rc.status != TrackingStatus::Ok) return r;
  rc.photometric_retry = true;
  return rc;
}

TrackingResult IcpTracker::retryHeldByOdometry(const std::vector<FrameLevel>& frame,
                                               const ModelMaps& model,
                                               const Eigen::Isometry3d& guess,
                                               ImageView<const Bgr8> frame_colour,
                                               const MotionPrior& prior, TrackingResult r) {
  if (r.status != TrackingStatus::PriorConflict || r.unconstrained_directions == 0 ||
      prior.odometry_information_degenerate.isZero())
    return r;
  // The geometry left a direction free and ICP moved along it further than the odometry allows
  // there: solve again with the odometry's x, y and yaw held at their degenerate-frame precision
  // (a gyro's heading), so that the free direction follows the odometry and the others the data.
  MotionPrior held = prior;
  held.information += prior.odometry_information_degenerate - prior.odometry_information;
  TrackingResult rh = align(frame, model, guess, frame_colour, &held);
  if (!rh.ok) return r;
  rh.held_by_odometry = true;
  return rh;
}

IcpTracker::PoseCheck IcpTracker::checkPose(const std::vector<FrameLevel>& frame,
                                            const ModelMaps& model,
                                            const Eigen::Isometry3d& T_world_cam) {
  if (model.vertex_world.empty()) return {};
  checkMap(model.vertex_world, model.normal_world, "model maps");
  buildModelPyramid(model, false, false);
  return checkPoseBuilt(frame, model, T_world_cam);
}

IcpTracker::PoseCheck IcpTracker::checkPoseBuilt(const std::vector<FrameLevel>& frame,
                                                 const ModelMaps& model,
                                                 const Eigen::Isometry3d& T_world_cam) const {
  const TTrackingParams& P = m_params;
  const int cl = std::min(P.check_level, P.num_levels - 1);
  const int cml = std::max(0, cl - P.model_level);
  if (static_cast<int>(frame.size()) <= cl)
    throwInputError("tracking: frame pyramid", "has " + std::to_string(frame.size()) +
                                                   " levels, the pose check needs " +
                                                   std::to_string(cl + 1));
  const kernels::PoseCheckCounts c = checkPoseCounts(
      frame[cl],
      cml == 0 ? model.vertex_world : ImageView<const Vec3f>(m_model_vertex[cml - 1].view()),
      cml == 0 ? model.normal_world : ImageView<const Vec3f>(m_model_normal[cml - 1].view()),
      model.K.level(cml), model.T_world_model, T_world_cam, P);
  PoseCheck r;
  const double overlap = double(c.overlap());
  r.overlap = c.valid > 0 ? overlap / double(c.valid) : 0.0;
  r.agreement = overlap > 0 ? double(c.agree) / overlap : 0.0;
  r.behind = overlap > 0 ? double(c.behind) / overlap : 0.0;
  r.max_disagreement = maxDisagreement();
  r.passed = r.overlap >= P.check_min_overlap && r.agreement >= P.check_min_agreement &&
             r.behind <= P.check_max_behind && 1.0 - r.agreement <= r.max_disagreement;
  return r;
}

double IcpTracker::maxDisagreement() const {
  const TTrackingParams& P = m_params;
  if (P.check_max_disagreement_ratio <= 0 || m_recent_disagreement.size() < 5) return 1.0;
  std::vector<double> v(m_recent_disagreement.begin(), m_recent_disagreement.end());
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return std::max(P.check_min_disagreement, P.check_max_disagreement_ratio * v[v.size() / 2]);
}

void IcpTracker::buildModelPyramid(const ModelMaps& model, bool intensity, bool confidence) {
  const int L = m_params.num_levels - m_params.model_level;  // model levels the frame levels use
  m_model_vertex.resize(std::max(0, L - 1));
  m_model_normal.resize(std::max(0, L - 1));
  if (confidence) m_model_confidence.resize(std::max(0, L - 1));
  if (intensity) {
    m_model_intensity.resize(L);
    m_model_intensity[0].resize(model.vertex_world.width, model.vertex_world.height);
    compute::forEach2D(
        model.vertex_world.width, model.vertex_world.height,
        kernels::IntensityKernel{model.colour, model.vertex_world, m_model_intensity[0].view()});
  }
  const RigidF T_model_world = toRigidF(model.T_world_model.inverse());
  ImageView<const Vec3f> v = model.vertex_world, n = model.normal_world;
  for (int l = 1; l < L; ++l) {
    Image<Vec3f>& ov = m_model_vertex[l - 1];
    Image<Vec3f>& on = m_model_normal[l - 1];
    ov.resize((v.width + 1) / 2, (v.height + 1) / 2);
    on.resize(ov.width(), ov.height());
    kernels::ModelDownsampleKernel k;
    k.in_vertex = v;
    k.in_normal = n;
    k.out_vertex = ov.view();
    k.out_normal = on.view();
    k.T_model_world = T_model_world;
    k.max_diff_m = 0.03f;
    if (intensity) {
      m_model_intensity[l].resize(ov.width(), ov.height());
      k.in_intensity = m_model_intensity[l - 1].cview();
      k.out_intensity = m_model_intensity[l].view();
    }
    if (confidence) {
      m_model_confidence[l - 1].resize(ov.width(), ov.height());
      k.in_confidence = l == 1 ? model.confidence : m_model_confidence[l - 2].cview();
      k.out_confidence = m_model_confidence[l - 1].view();
    }
    compute::forEach2D(ov.width(), ov.height(), k);
    v = ov.view();
    n = on.view();
  }
}

void IcpTracker::buildFrameIntensity(const std::vector<FrameLevel>& frame,
                                     ImageView<const Bgr8> colour) {
  const int L = m_params.num_levels;
  m_frame_intensity.resize(L);
  m_frame_igrad.resize(L);
  for (int l = 0; l < L; ++l) {
    const int w = frame[l].depth_m.width(), h = frame[l].depth_m.height();
    Image<float>& I = m_frame_intensity[l];
    I.resize(w, h);
    if (l == 0)
      compute::forEach2D(w, h, kernels::IntensityKernel{colour, {}, I.view()});
    else
      compute::forEach2D(
          w, h, kernels::IntensityDownsampleKernel{m_frame_intensity[l - 1].cview(), I.view()});
    m_frame_igrad[l].resize(w, h);
    compute::forEach2D(w, h, kernels::IntensityGradientKernel{I.cview(), m_frame_igrad[l].view()});
  }
}

TrackingResult IcpTracker::align(const std::vector<FrameLevel>& frame, const ModelMaps& model,
                                 const Eigen::Isometry3d& T_world_cam_guess,
                                 ImageView<const Bgr8> frame_colour, const MotionPrior* prior,
                                 std::optional<double> photometric_weight) {
  const TTrackingParams& P = m_params;
  const bool model_empty = model.vertex_world.empty();
  // Photometric term: only with both colour images (and a model to render them from).
  const double kappa = photometric_weight ? std::max(0.0, *photometric_weight)
                                          : P.photometricWeight(prior != nullptr);
  const bool photometric =
      kappa > 0 && !model_empty && !model.colour.empty() && !frame_colour.empty();
  const bool confidence = P.confidence_full > 0 && !model_empty && !model.confidence.empty();
  checkAlignInputs(P, frame, model, frame_colour, photometric, confidence);
  if (P.use_cuda) ensureCudaReducer();

  TrackingResult res;
  res.T_world_cam_guess = T_world_cam_guess;
  Eigen::Isometry3d T = T_world_cam_guess;
  if (!model_empty) buildModelPyramid(model, photometric, confidence);
  if (photometric) buildFrameIntensity(frame, frame_colour);
  const Eigen::Isometry3d T_model_world = model.T_world_model.inverse();
  const double conv_rot_rad = P.convergence_rotation_deg * kRadPerDeg;
  const double prior_sigma2 = P.prior_pixel_sigma_m * P.prior_pixel_sigma_m;
  res.used_prior = prior != nullptr;

  bool diverged = false;
  IcpSystem last(kernels::IcpAccumulator{});  // level 0's last system
  IcpSystem weakest = last;  // the level's last system with the smallest eigenvalue
  bool have_weakest = false;
  for (int l = P.num_levels - 1; l >= 0 && !diverged; --l) {
    TrackingLevelStats st;
    st.level = l;
    kernels::IcpReduceKernel k;
    kernels::PhotometricReduceKernel pk;
    levelKernels(l, frame, model, photometric, confidence, k, pk);
    IcpSystem level_last(kernels::IcpAccumulator{});
    if (P.use_cuda && !model_empty) m_cuda->upload(l, k);

    for (int it = 0; it < P.iterations[l]; ++it) {
      k.T_world_cam = toRigidF(T);
      k.T_model_cam = toRigidF(T_model_world * T);
      k.pivot_world = T.translation().cast<float>();
      kernels::IcpAccumulator acc_photo;
      const kernels::IcpAccumulator acc = reduceLevel(l, k, model_empty);
      if (photometric) {
        pk.T_world_cam = k.T_world_cam;
        pk.T_cam_world = toRigidF(T.inverse());
        pk.pivot_world = k.pivot_world;
        acc_photo = compute::reduce1D<kernels::IcpAccumulator>(pk.items(), pk);
        st.photometric_inliers = int(acc_photo.inliers());
        st.photometric_rms =
            acc_photo.inliers() > 0
                ? std::sqrt(acc_photo.s[kernels::IcpAccumulator::kR2] / acc_photo.inliers())
                : 0.0;
      }
      const IcpSystem sys(acc, photometric ? &acc_photo : nullptr, kappa);
      ++st.iterations;
      ++res.iterations;
      st.inliers = int(sys.inliers);
      st.valid_pixels = int(sys.valid);
      st.rms_m = sys.rms_m;
      st.min_eigenvalue = sys.eigenvalues(0);
      if (l == 0) last = sys;
      level_last = sys;
      if (sys.inliers < kMinSolveInliers) break;  // nothing to solve at this level

      Vector6d xi;
      if (prior)
        sys.solveWithPrior(prior->information, incrementTo(T, prior->T_world_cam), prior_sigma2,
                           P.prior_min_eigenvalue, xi);
      else
        sys.solve(P.min_eigenvalue, xi);
      diverged = !applyStep(xi, T, st);
      if (diverged) break;
      if (st.last_step_translation_m < P.convergence_translation_m &&
          st.last_step_rotation_rad < conv_rot_rad)
        break;
    }
    if (l == 0) {
      res.photometric_inliers = st.photometric_inliers;
      res.photometric_rms = st.photometric_rms;
      res.final_step_translation_m = st.last_step_translation_m;
      res.final_step_rotation_rad = st.last_step_rotation_rad;
    }
    res.levels.push_back(st);
    if (level_last.inliers >= kMinSolveInliers &&
        (!have_weakest || level_last.eigenvalues(0) < weakest.eigenvalues(0))) {
      weakest = level_last;
      have_weakest = true;
    }
  }

  res.T_world_cam = orthonormalize(T);
  summariseFit(P, last, weakest, have_weakest, prior, res);
  const bool check_failed = poseCheckFailed(frame, model, prior, res);
  judgeQuality(P, diverged, check_failed, prior != nullptr, res);
  return res;
}

void IcpTracker::levelKernels(int l, const std::vector<FrameLevel>& frame, const ModelMaps& model,
                              bool photometric, bool confidence, kernels::IcpReduceKernel& k,
                              kernels::PhotometricReduceKernel& pk) const {
  const TTrackingParams& P = m_params;
  k.frame_vertex = frame[l].vertex.view();
  k.frame_normal = frame[l].normal.view();
  const int ml = std::max(0, l - P.model_level);  // model level associated with frame level l
  if (!model.vertex_world.empty()) {
    k.model_vertex =
        ml == 0 ? model.vertex_world : ImageView<const Vec3f>(m_model_vertex[ml - 1].view());
    k.model_normal =
        ml == 0 ? model.normal_world : ImageView<const Vec3f>(m_model_normal[ml - 1].view());
  }
  k.K_model = model.K.level(ml).plain();
  k.max_dist_m = float(P.max_dist_m[l]);
  k.min_normal_cos = float(std::cos(P.max_normal_angle_deg[l] * kRadPerDeg));
  k.huber_delta_m = float(P.huber_delta_m);
  k.depth_noise_weighting = P.depth_noise_weighting;
  k.depth_noise_incidence = P.depth_noise_incidence;
  if (confidence) {
    k.model_confidence =
        ml == 0 ? model.confidence : ImageView<const float>(m_model_confidence[ml - 1].cview());
    k.confidence_full = float(P.confidence_full);
  }
  k.stride = l == 0 ? P.level0_pixel_stride : 1;
  if (photometric) {
    pk.model_vertex = k.model_vertex;
    pk.model_intensity = m_model_intensity[ml].cview();
    pk.frame_igrad = m_frame_igrad[l].cview();
    pk.frame_depth_m = frame[l].depth_m.cview();
    pk.K_frame = frame[l].K.plain();
    pk.max_depth_diff_m = k.max_dist_m;
    pk.min_gradient = float(P.photometric_min_gradient);
    pk.huber_delta = float(P.photometric_huber);
    pk.stride = k.stride;
  }
}

void IcpTracker::ensureCudaReducer() {
  const auto avail = compute::cudaAvailability();
  if (!avail.available)
    throwInputError("[tracking] use_cuda", "CUDA is not usable: " + avail.reason);
  if (!m_cuda) m_cuda = std::make_unique<cuda::IcpCudaReducer>();
}

kernels::IcpAccumulator IcpTracker::reduceLevel(int l, const kernels::IcpReduceKernel& k,
                                                bool model_empty) {
  kernels::IcpAccumulator acc;
  if (model_empty) {
    // Nothing to associate with: only count the valid frame pixels.
    for (int y = 0; y < k.frame_vertex.height; y += k.stride)
      for (int x = 0; x < k.frame_vertex.width; x += k.stride)
        if (k.frame_vertex(x, y).x() == k.frame_vertex(x, y).x() &&
            k.frame_normal(x, y).x() == k.frame_normal(x, y).x())
          acc.s[kernels::IcpAccumulator::kValid] += 1;
  } else if (m_params.use_cuda) {
    acc = m_cuda->reduce(l, k);
  } else {
    acc = compute::reduce1D<kernels::IcpAccumulator>(k.items(), k);
  }
  return acc;
}

bool IcpTracker::poseCheckFailed(const std::vector<FrameLevel>& frame, const ModelMaps& model,
                                 const MotionPrior* prior, TrackingResult& res) const {
  // Pose check: the aligned frame against the model it was aligned to.
  const TTrackingParams& P = m_params;
  if (model.vertex_world.empty() || !res.T_world_cam.matrix().allFinite()) return false;
  const PoseCheck c = checkPoseBuilt(frame, model, res.T_world_cam);
  res.check_overlap = c.overlap;
  res.check_agreement = c.agreement;
  res.check_behind = c.behind;
  const bool failed = c.overlap >= P.check_min_overlap && !c.passed;
  const bool relative_rule_alone = c.agreement >= P.check_min_agreement &&
                                   c.behind <= P.check_max_behind &&
                                   1.0 - c.agreement > c.max_disagreement;
  const bool prior_confirms = prior && P.check_prior_confirms_sigmas > 0 &&
                              res.prior_sigmas <= P.check_prior_confirms_sigmas;
  const bool odometry_confirms = prior && P.check_odometry_confirms_sigmas > 0 &&
                                 !prior->odometry_information.isZero() &&
                                 res.odometry_sigmas <= P.check_odometry_confirms_sigmas;
  return failed && !(relative_rule_alone && (prior_confirms || odometry_confirms));
}

double odometrySigmas(const Eigen::Isometry3d& T_world_cam, const MotionPrior& prior,
                      bool degenerate) {
  const Vector6d d = incrementTo(T_world_cam, prior.T_world_cam);
  const Eigen::Matrix<double, 6, 6>& information =
      degenerate && !prior.odometry_information_degenerate.isZero()
          ? prior.odometry_information_degenerate
          : prior.odometry_information;
  return std::sqrt(std::max(0.0, d.dot(information * d)));
}

Eigen::Isometry3d moveAlongHeldDirections(const TrackingResult& r, const Eigen::Isometry3d& T_from,
                                          double min_eigenvalue) {
  // The move as the analysis parametrises it: the camera centre's translation and a rotation
  // about the centre, both along the world axes; rotation scaled by the mean depth (xs = D xi).
  const double depth = r.eigen_mean_depth_m;
  Vector6d xs;
  xs.head<3>() = r.T_world_cam.translation() - T_from.translation();
  xs.tail<3>() = depth * so3Log(r.T_world_cam.linear() * T_from.linear().transpose());
  Vector6d kept = Vector6d::Zero();
  for (int i = 0; i < 6; ++i)
    if (r.eigenvalues(i) >= min_eigenvalue)
      kept += r.eigenvectors.col(i) * r.eigenvectors.col(i).dot(xs);
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = so3Exp(kept.tail<3>() / depth) * T_from.linear();
  T.translation() = T_from.translation() + kept.head<3>();
  return T;
}

}  // namespace rasm::tracking
