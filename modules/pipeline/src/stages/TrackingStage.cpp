#include "rasm/pipeline/stages/TrackingStage.h"

#include <algorithm>
#include <chrono>
#include <cstdio>

#include "rasm/compute/Parallel.h"
#include "rasm/core/Error.h"
#include "rasm/core/Log.h"
#include "rasm/core/SE3.h"
#include "rasm/core/Timing.h"
#include "rasm/core/kernels/FrameKernels.h"
#include "rasm/io/TrajectoryEvaluator.h"

namespace rasm::pipeline {

namespace {

int countValid(const Image<Vec3f>& v) {
  const int w = v.width();
  return compute::reduce1D<int>(v.height(), [&](int y, int& n) {
    const Vec3f* r = v.row(y);
    for (int x = 0; x < w; ++x) n += kernels::validVec(r[x]) ? 1 : 0;
  });
}
}  // namespace

TrackingStage::TrackingStage()
    : MapperStage("tracking", {"render_model", "icp", "relocalise", "loop_closure"}),
      m_odometry(m_robot) {}

TrackingStage::~TrackingStage() = default;

std::vector<ParamsSection> TrackingStage::sections() {
  return {{"tracking", &m_tracking},
          {"robot", &m_robot},
          {"relocalisation", &m_relocalisation},
          {"loop_closure", &m_loop_params}};
}

void TrackingStage::configure(const TMapperParams& mapper) {
  m_tracking.validate("tracking");
  if (m_tracking.numLevels() > mapper.pyramid_levels)
    throwInputError("[mapper] pyramid_levels", "must be >= the number of [tracking] levels (" +
                                                   std::to_string(m_tracking.numLevels()) + ")");
  m_mapper = mapper;
  m_tracker = tracking::IcpTracker(m_tracking);
  m_odometry = tracking::OdometryPrior(m_robot);
  m_reloc = tracking::Relocaliser(m_relocalisation);
  m_reloc_last_fused = tracking::Relocaliser(m_relocalisation.forLastFusedFrame());
  m_loop = tracking::LoopClosure(m_loop_params);
  tracking::TTrackingParams loop_icp = m_tracking;
  loop_icp.min_inlier_fraction *= m_loop_params.min_inactive_fraction;
  loop_icp.max_jump_translation_m =
      std::max(loop_icp.max_jump_translation_m, 2.0 * m_loop_params.max_correction_m + 0.2);
  // A registration that moves the map must be held by the data in every direction: never a
  // degenerate one. (Raising min_eigenvalue to prior_min_eigenvalue left no registration at all
  // on the world-frame panel: the features confirm instead, checkLoop.)
  loop_icp.degenerate_min_inlier_fraction = 2.0;
  m_loop_tracker = tracking::IcpTracker(loop_icp);
}

void TrackingStage::resolveOdometryHeading(bool odometry_from_gyro) {
  m_robot.resolveHeading(odometry_from_gyro);
  m_odometry = tracking::OdometryPrior(m_robot);
}

void TrackingStage::process(FrameContext& ctx, maps::CSurfelMap& map) {
  FrameResult& r = ctx.result;
  if (m_mapper.poses == "groundtruth") {
    if (!ctx.frame->gt_T_world_cam)
      throwInputError(
          "frame " + std::to_string(ctx.frame->index),
          "has no ground-truth pose ([mapper] poses = groundtruth needs one for every frame)");
    if (!m_tracker.initialized()) r.first = true;
    m_tracker.reset(*ctx.frame->gt_T_world_cam);
    r.tracked = true;
    r.T_world_cam = *ctx.frame->gt_T_world_cam;
    r.tracking.ok = true;
    r.tracking.status = tracking::TrackingStatus::Ok;
    r.tracking.T_world_cam = r.T_world_cam;
  } else if (!m_tracker.initialized() && m_localise_in_map) {
    // A loaded map: nothing is fused until the camera is found in it.
    r.tracked = false;
    r.pose_source = PoseSource::MotionModel;
    r.tracking.status = tracking::TrackingStatus::NotInitialized;
    relocalise(ctx, map);
    if (r.relocalised) m_odometry.start(r.T_world_cam, ctx.frame->odometry_xyyaw);
  } else if (!m_tracker.initialized()) {
    initialise(ctx);
  } else {
    track(ctx, map);
    if (m_loop_params.enabled && r.fusable()) checkLoop(ctx, map);
  }
  m_odometry.frameDone(r.tracked);
  ++m_frames_since_node;
  if (r.tracking.status != tracking::TrackingStatus::Ok || !r.tracked) ++m_weak_frames_since_node;
  m_T_prev_frame = r.T_world_cam;
  if (r.tracked)
    m_lost_since_s.reset();
  else if (!m_lost_since_s)
    m_lost_since_s = ctx.frame->timestamp_s;
}

void TrackingStage::initialise(FrameContext& ctx) {
  const RgbdFrame& frame = *ctx.frame;
  FrameResult& r = ctx.result;
  // The map starts in the source's ground-truth frame when the first frame has a pose (ATE
  // aligns anyway), else at the identity.
  const Eigen::Isometry3d T0 =
      frame.gt_T_world_cam ? *frame.gt_T_world_cam : Eigen::Isometry3d::Identity();
  // It starts on the first frame with enough valid depth for the next frame to be tracked
  // against (II-C's min_inliers, at most a tenth of the pixels): a blank frame (no depth, all
  // below min_depth_m) would start an empty map and every later frame would be lost.
  if (!ctx.pyramid.empty()) {
    const Image<Vec3f>& v = ctx.pyramid[0].vertex;
    const int needed = std::max(1, std::min(m_tracking.min_inliers, v.width() * v.height() / 10));
    const int valid = countValid(v);
    if (valid < needed) {
      ++m_frames_before_map;
      r.tracked = false;
      r.pose_source = PoseSource::MotionModel;
      r.T_world_cam = T0;
      r.tracking.status = tracking::TrackingStatus::NotInitialized;
      r.tracking.T_world_cam = T0;
      return;
    }
    if (m_frames_before_map > 0)
      log::warning("the map starts at frame " + std::to_string(frame.index) + ": the " +
                   std::to_string(m_frames_before_map) +
                   " frame(s) before it had too little valid depth (fewer than " +
                   std::to_string(needed) +
                   " valid pixels) and were skipped (report.json frames_before_map)");
  }
  m_tracker.reset(T0);
  m_odometry.start(T0, frame.odometry_xyyaw);
  m_loop.reset();
  if (frame.odometry_xyyaw) m_loop.setUpAxis(m_odometry.up());
  r.first = true;
  r.tracked = true;
  r.T_world_cam = T0;
  r.tracking.ok = true;
  r.tracking.status = tracking::TrackingStatus::Ok;
  r.tracking.T_world_cam = T0;
}

void TrackingStage::track(FrameContext& ctx, const maps::CSurfelMap& map) {
  const RgbdFrame& frame = *ctx.frame;
  FrameResult& r = ctx.result;
  const std::optional<tracking::MotionPrior> prior =
      m_odometry.predict(frame.odometry_xyyaw, m_T_prev_frame);
  const double lost_after = m_relocalisation.relocalise_only_after_lost_s;
  if (!prior && lost_after > 0 && m_lost_since_s &&
      frame.timestamp_s - *m_lost_since_s > lost_after) {
    // Lost too long without odometry: no ICP from the stale pose, relocalisation only.
    r.tracked = false;
    r.tracking.status = tracking::TrackingStatus::NotInitialized;
    r.pose_source = PoseSource::MotionModel;
    r.T_world_cam = m_tracker.lastGoodPose();
    relocalise(ctx, map);
    return;
  }
  // The model is rendered where the guess starts from: the previous frame's pose when odometry
  // or the extrapolated constant velocity carries the estimate on through lost frames, else the
  // last good pose.
  auto t = Clock::now();
  const bool photometric =
      m_tracking.photometricWeight(prior.has_value()) > 0 && !frame.colour.empty();
  // Without a prior, a degenerate frame is retried with the photometric term (IcpTracker::track):
  // the model's colour is rendered only for that retry.
  const bool colour_retry =
      !prior && m_tracking.photometric_weight_degenerate > 0 && !frame.colour.empty();
  const tracking::ModelMaps model = renderModel(
      ctx, map,
      prior || m_tracker.extrapolatingThroughLoss() ? m_T_prev_frame : m_tracker.lastGoodPose(),
      photometric, r);
  recordMs(ctx, kRenderModel, msSince(t));

  t = Clock::now();
  // A frame the stable surfels cannot support is tried once more against all surfels.
  double ms_denser_render = 0.0;
  const tracking::IcpTracker::DenserModel denser = [&]() -> std::optional<tracking::ModelMaps> {
    if (r.model_all_surfels) return std::nullopt;
    const auto tr = Clock::now();
    FrameResult probe;
    tracking::ModelMaps m =
        renderModel(ctx, map, model.T_world_model, photometric || colour_retry, probe, true);
    ms_denser_render += msSince(tr);
    return m;
  };
  const tracking::IcpTracker::DenserModel coloured = [&]() -> std::optional<tracking::ModelMaps> {
    if (!colour_retry) return std::nullopt;
    const auto tr = Clock::now();
    FrameResult probe;
    tracking::ModelMaps m =
        renderModel(ctx, map, model.T_world_model, true, probe, r.model_all_surfels);
    ms_denser_render += msSince(tr);
    return m;
  };
  r.tracking =
      m_tracker.track(ctx.pyramid, model,
                      photometric || colour_retry ? frame.colour.cview() : ImageView<const Bgr8>(),
                      prior ? &*prior : nullptr, denser, coloured);
  if (r.tracking.denser_model) r.model_all_surfels = true;
  recordMs(ctx, kIcp, msSince(t) - ms_denser_render);
  recordMs(ctx, kRenderModel, ms_denser_render);
  r.tracked = r.tracking.ok;
  if (r.tracked && prior) {
    double correction = 0.0;
    r.heading_drift_sigmas =
        m_odometry.addHeadingResidual(*prior, r.tracking.T_world_cam, correction);
    if (m_robot.heading_drift_max_sigmas > 0 &&
        r.heading_drift_sigmas > m_robot.heading_drift_max_sigmas) {
      // Each frame agreed with the odometry within its noise, their sum does not: the heading
      // drifted (an under-rotated turn). Not fused; the pose takes the odometry's heading.
      r.tracked = r.tracking.ok = false;
      r.tracking.status = tracking::TrackingStatus::PriorConflict;
      r.pose_source = PoseSource::Odometry;
      const Eigen::AngleAxisd undo(-correction, m_odometry.up());
      r.T_world_cam = r.tracking.T_world_cam;
      r.T_world_cam.linear() = undo.toRotationMatrix() * r.T_world_cam.linear();
      m_tracker.correctLastPose(r.T_world_cam);
      m_odometry.resetHeadingWindow();
      return;
    }
  } else if (!r.tracked) {
    m_odometry.resetHeadingWindow();
  }
  if (r.tracked) {
    r.T_world_cam = r.tracking.T_world_cam;
    if (m_robot.planar_motion) {
      r.T_world_cam = m_odometry.projectToFloor(r.T_world_cam);
      m_tracker.correctLastPose(r.T_world_cam);
    }
    if (prior) reportFloorDeviation(r);
  } else {
    r.pose_source = prior ? PoseSource::Odometry : PoseSource::MotionModel;
    r.T_world_cam = prior ? prior->T_world_cam : r.tracking.T_world_cam_guess;
    relocalise(ctx, map);
  }
}

void TrackingStage::reportFloorDeviation(FrameResult& r) {
  const auto [height, tilt] = m_odometry.floorDeviation(r.T_world_cam);
  r.floor_height_m = height;
  r.floor_tilt_deg = tilt * 180.0 / M_PI;
  const bool high = m_robot.floor_max_height_m > 0 && std::abs(height) > m_robot.floor_max_height_m;
  const bool tilted =
      m_robot.floor_max_tilt_deg > 0 && r.floor_tilt_deg > m_robot.floor_max_tilt_deg;
  if (high || tilted) ++m_frames_off_floor;
  m_floor_height_abs_m.push_back(std::abs(height));
  m_floor_tilt_deg.push_back(r.floor_tilt_deg);
}

nlohmann::json TrackingStage::floorDriftJson() const {
  const std::size_t n = m_floor_height_abs_m.size();
  std::size_t beyond = 0;
  for (std::size_t i = 0; i < n; ++i)
    if (m_floor_height_abs_m[i] > m_robot.floor_target_height_m ||
        m_floor_tilt_deg[i] > m_robot.floor_target_tilt_deg)
      ++beyond;
  const io::ErrorStats h = io::ErrorStats::of(m_floor_height_abs_m);
  const io::ErrorStats t = io::ErrorStats::of(m_floor_tilt_deg);
  const double fraction = double(beyond) / double(n);
  return {{"comment",
           "the tracked frames' camera against the first frame's floor and the mount (no ground "
           "truth needed): height error |floor_height_m| and tilt floor_tilt_deg; drifted when "
           "more than max_fraction of them are beyond the target height or tilt"},
          {"frames", n},
          {"height_error_m", {{"median", h.median}, {"max", h.max}}},
          {"tilt_deg", {{"median", t.median}, {"max", t.max}}},
          {"target_height_m", m_robot.floor_target_height_m},
          {"target_tilt_deg", m_robot.floor_target_tilt_deg},
          {"max_fraction", m_robot.floor_target_max_fraction},
          {"frames_beyond_target", beyond},
          {"fraction_beyond_target", fraction},
          {"drifted", fraction > m_robot.floor_target_max_fraction}};
}

tracking::ModelMaps TrackingStage::renderModel(FrameContext& ctx, const maps::CSurfelMap& map,
                                               const Eigen::Isometry3d& T_model, bool with_colour,
                                               FrameResult& r, bool all_surfels,
                                               const maps::RenderOptions* time_filter) {
  // II-C: model = the map rendered at the previous pose from its reliable surfels: those with
  // confidence >= [tracking] model_min_confidence, or the ones fusion flagged stable when that is
  // 0. Until enough of them exist (the first frames of a run, or a newly seen area), that model
  // is too sparse to constrain ICP; then all surfels are used.
  const RgbdFrame& frame = *ctx.frame;
  const tracking::TTrackingParams& tp = m_tracking;
  maps::RenderOptions ro;
  ro.min_depth_m = float(m_mapper.min_depth_m);
  ro.max_depth_m = float(m_mapper.max_depth_m) * 1.5f;
  ro.stable_only = !all_surfels && tp.model_min_confidence <= 0;
  ro.min_confidence = all_surfels ? 0.0f : float(tp.model_min_confidence);
  ro.outputs = maps::kRenderVertex | maps::kRenderNormal;
  if (time_filter) {
    ro.time_window_s = time_filter->time_window_s;
    ro.now_s = time_filter->now_s;
    ro.created_after_s = time_filter->created_after_s;
    ro.created_before_s = time_filter->created_before_s;
  }
  // Optional inputs of the tracker: colour for its photometric term, surfel confidence weights.
  if (with_colour) ro.outputs |= maps::kRenderColour;
  if (tp.confidence_full > 0) ro.outputs |= maps::kRenderConfidence;
  // Rendered at pyramid level [tracking] model_level (intrinsics of that level); a pixel a
  // surfel won has that surfel's normal: the render counts the valid model pixels.
  const CameraIntrinsics K_model = frame.intrinsics.level(tp.model_level);
  maps::RenderStats rs;
  m_renderer.render(map.store(), T_model, K_model, ro, m_model, &rs);
  r.model_valid_pixels = int(rs.pixels_drawn);
  r.model_all_surfels = all_surfels;
  const int frame_valid = countValid(ctx.pyramid[tp.model_level].normal);
  if (!all_surfels && r.model_valid_pixels < 0.3 * frame_valid) {
    ro.stable_only = false;
    ro.min_confidence = 0.0f;
    m_renderer.render(map.store(), T_model, K_model, ro, m_model, &rs);
    r.model_valid_pixels = int(rs.pixels_drawn);
    r.model_all_surfels = true;
  }
  tracking::ModelMaps model;
  model.vertex_world = m_model.vertex_world.cview();
  model.normal_world = m_model.normal_world.cview();
  model.K = K_model;
  model.T_world_model = T_model;
  if (ro.outputs & maps::kRenderColour) model.colour = m_model.colour.cview();
  if (ro.outputs & maps::kRenderConfidence) model.confidence = m_model.confidence.cview();
  return model;
}

void TrackingStage::relocalise(FrameContext& ctx, const maps::CSurfelMap& map) {
  const bool reference = m_relocalisation.use_last_fused_frame && m_last_fused.valid;
  if (map.keyframes().empty() && !reference) return;
  const auto t = Clock::now();
  const bool by_reference = reference && !lastFusedKeyframe().empty() &&
                            relocaliseAgainst(ctx, map, lastFusedKeyframe(), m_reloc_last_fused);
  if (!by_reference && !map.keyframes().empty())
    relocaliseAgainst(ctx, map, map.keyframes(), m_reloc);
  recordMs(ctx, kRelocalise, msSince(t));
}

bool TrackingStage::relocaliseAgainst(FrameContext& ctx, const maps::CSurfelMap& map,
                                      const std::vector<maps::Keyframe>& db,
                                      tracking::Relocaliser& reloc) {
  FrameResult& r = ctx.result;
  const std::optional<tracking::RelocalisationResult> cand = reloc.relocalise(*ctx.frame, db);
  if (!cand) {
    r.relocalisation_failure = reloc.lastStats().reason;
    return false;
  }
  // Verify: ICP from the candidate against the map rendered there, every quality rule and the
  // pose check applied (no prior: the candidate is independent of the lost estimate).
  FrameResult probe;
  const tracking::ModelMaps model =
      renderModel(ctx, map, cand->T_world_cam, m_tracking.photometricWeight(false) > 0, probe);
  const tracking::TrackingResult v = m_tracker.align(ctx.pyramid, model, cand->T_world_cam);
  if (!v.ok || v.check_overlap < m_tracking.check_min_overlap) {
    r.relocalisation_failure = std::string("rejected by ICP: ") + tracking::toString(v.status);
    return false;
  }
  m_tracker.reset(v.T_world_cam);
  r.tracking = v;
  r.tracked = true;
  r.relocalised = true;
  r.relocalisation_failure.clear();
  r.pose_source = PoseSource::Relocalised;
  r.T_world_cam = v.T_world_cam;
  r.model_valid_pixels = probe.model_valid_pixels;
  ++m_relocalisations;
  return true;
}

const std::vector<maps::Keyframe>& TrackingStage::lastFusedKeyframe() {
  LastFused& lf = m_last_fused;
  if (!lf.attempted) {
    lf.attempted = true;
    lf.keyframe.clear();
    if (auto kf = m_reloc.makeKeyframe(lf.frame, lf.T_world_cam)) lf.keyframe.push_back(*kf);
  }
  return lf.keyframe;
}

void TrackingStage::finishFrame(FrameContext& ctx, maps::CSurfelMap& map) {
  if (!ctx.result.fused) {
    m_pending_loop.reset();
    return;
  }
  if (m_loop_params.enabled && m_mapper.poses != "groundtruth") closeLoop(ctx, map);
  m_reloc.maybeAddKeyframe(*ctx.frame, ctx.result.T_world_cam, map.keyframes());
  const RgbdFrame& f = *ctx.frame;
  if (!m_relocalisation.use_last_fused_frame || f.colour.empty()) return;
  LastFused& lf = m_last_fused;  // copies into buffers of the same size: no allocation
  lf.frame.index = f.index;
  lf.frame.timestamp_s = f.timestamp_s;
  lf.frame.intrinsics = f.intrinsics;
  lf.frame.depth_m = f.depth_m;
  lf.frame.colour = f.colour;
  lf.T_world_cam = ctx.result.T_world_cam;
  lf.valid = true;
  lf.attempted = false;
}

void TrackingStage::checkLoop(FrameContext& ctx, const maps::CSurfelMap& map) {
  const tracking::TLoopClosureParams& lp = m_loop_params;
  const double t_now = ctx.frame->timestamp_s;
  const double t_inactive = t_now - lp.inactive_after_s;
  if (m_loop.numNodes() < 2 || t_inactive <= m_loop.firstNodeTime()) return;
  if (++m_frames_since_loop_check < lp.check_every_frames) return;
  m_frames_since_loop_check = 0;
  const auto t = Clock::now();
  FrameResult& r = ctx.result;
  const Eigen::Isometry3d T_track = r.T_world_cam;
  const int frame_valid =
      std::max(1, countValid(ctx.pyramid[std::size_t(m_tracking.model_level)].normal));
  // The inactive map: what an earlier pass made and nothing fused since inactive_after_s.
  maps::RenderOptions filter;
  filter.created_before_s = t_inactive;
  FrameResult probe;
  const bool by_colour = lp.confirmation == "colour" && !ctx.frame->colour.empty() &&
                         m_tracking.photometric_weight_degenerate > 0;
  const tracking::ModelMaps inactive =
      renderModel(ctx, map, T_track, by_colour, probe, false, &filter);
  if (probe.model_valid_pixels < lp.min_inactive_fraction * frame_valid) {
    recordMs(ctx, kLoopClosure, msSince(t));
    return;
  }
  ++m_loop_checks;
  const double t_old = medianInitTime(map.store());
  const tracking::TrackingResult v_in = registerForLoop(ctx, inactive, T_track);
  if (!v_in.ok || v_in.check_overlap < m_tracking.check_min_overlap) {
    r.loop_closure =
        std::string("unregistered: ") + (v_in.ok ? "overlap" : tracking::toString(v_in.status));
    m_loop_candidate_checks = 0;  // confirmations are consecutive checks
    recordMs(ctx, kLoopClosure, msSince(t));
    return;
  }
  // The active map: the trajectory's own continuation (the tracked pose when it covers too
  // little of the view to register against).
  filter = maps::RenderOptions();
  filter.created_after_s = t_inactive;
  const tracking::ModelMaps active = renderModel(ctx, map, T_track, false, probe, false, &filter);
  Eigen::Isometry3d T_active = T_track;
  if (probe.model_valid_pixels >= lp.min_inactive_fraction * frame_valid) {
    const tracking::TrackingResult v_act = registerForLoop(ctx, active, T_track);
    if (v_act.ok) T_active = v_act.T_world_cam;
  }
  const tracking::LoopVerdict verdict = m_loop.judge(T_active, v_in.T_world_cam, t_old, t_now);
  r.loop_closure = verdict.name();
  r.loop_correction_m = verdict.correction_m;
  r.loop_correction_deg = verdict.correction_deg;
  std::string unconfirmed;
  if (verdict.accepted() && lp.confirmation == "features" &&
      !featuresConfirm(ctx, map, v_in.T_world_cam, t_inactive, verdict, unconfirmed)) {
    r.loop_closure = "unconfirmed: " + unconfirmed;
    m_loop_candidate_checks = 0;
  } else if (verdict.accepted() && lp.confirmation == "colour" &&
             !colourConfirms(ctx, inactive, T_track, v_in.T_world_cam, verdict, unconfirmed)) {
    r.loop_closure = "unconfirmed: " + unconfirmed;
    m_loop_candidate_checks = 0;
  } else if (verdict.accepted()) {
    // Closed when confirmations consecutive checks ask for the same correction.
    const bool same =
        m_loop_candidate && m_loop_candidate_checks > 0 &&
        ctx.frame->index <= m_loop_candidate->frame + 2 * std::size_t(lp.check_every_frames) &&
        m_loop.sameCorrection(m_loop_candidate->verdict, verdict, T_track);
    m_loop_candidate_checks = same ? m_loop_candidate_checks + 1 : 1;
    m_loop_candidate = LoopCandidate{verdict, ctx.frame->index};
    if (m_loop_candidate_checks >= lp.confirmations) {
      m_pending_loop = PendingLoop{verdict, T_active, t_old, t_now};
      m_loop_candidate_checks = 0;
    } else {
      r.loop_closure = "candidate";
    }
  } else {
    m_loop_candidate_checks = 0;
    if (verdict.kind == tracking::LoopVerdict::Kind::Refused) ++m_loops_refused;
  }
  recordMs(ctx, kLoopClosure, msSince(t));
}

bool TrackingStage::colourConfirms(FrameContext& ctx, const tracking::ModelMaps& inactive,
                                   const Eigen::Isometry3d& T_track,
                                   const Eigen::Isometry3d& T_inactive,
                                   const tracking::LoopVerdict& verdict, std::string& why) {
  if (ctx.frame->colour.empty() || inactive.colour.empty() ||
      m_tracking.photometric_weight_degenerate <= 0) {
    why = "no colour";
    return false;
  }
  m_loop_tracker.reset(T_track);
  const tracking::TrackingResult v =
      m_loop_tracker.align(ctx.pyramid, inactive, T_track, ctx.frame->colour.cview(), nullptr,
                           m_tracking.photometric_weight_degenerate);
  if (!v.ok) {
    why = std::string("colour: ") + tracking::toString(v.status);
    return false;
  }
  return posesAgree(v.T_world_cam, T_inactive, verdict, "colour", why);
}

bool TrackingStage::posesAgree(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b,
                               const tracking::LoopVerdict& verdict, const char* what,
                               std::string& why) const {
  const tracking::TLoopClosureParams& lp = m_loop_params;
  const double d_m = translationDistance(a, b);
  const double d_deg = rotationAngle(a, b) * 180.0 / M_PI;
  if (d_m <= std::max(lp.feature_agreement_m, 0.3 * verdict.correction_m) &&
      d_deg <= std::max(lp.feature_agreement_deg, 0.3 * verdict.correction_deg))
    return true;
  char text[112];
  std::snprintf(text, sizeof text, "%s puts the camera %.3f m / %.2f deg away", what, d_m, d_deg);
  why = text;
  return false;
}

bool TrackingStage::featuresConfirm(FrameContext& ctx, const maps::CSurfelMap& map,
                                    const Eigen::Isometry3d& T_inactive, double t_inactive,
                                    const tracking::LoopVerdict& verdict, std::string& why) {
  // The frame's ORB features against the keyframes of the old map (RANSAC PnP, checked against
  // the frame's depth: Relocaliser.h) give a pose the geometry did not: a registration that slid
  // along a corridor's weak direction is not where the texture puts the camera.
  std::vector<maps::Keyframe> old;
  for (const maps::Keyframe& kf : map.keyframes())
    if (kf.timestamp_s < t_inactive) old.push_back(kf);
  if (old.empty()) {
    why = "no keyframe of the old map";
    return false;
  }
  const std::optional<tracking::RelocalisationResult> pnp = m_reloc.relocalise(*ctx.frame, old);
  if (!pnp) {
    why = "features: " + m_reloc.lastStats().reason;
    return false;
  }
  return posesAgree(pnp->T_world_cam, T_inactive, verdict, "features", why);
}

tracking::TrackingResult TrackingStage::registerForLoop(FrameContext& ctx,
                                                        const tracking::ModelMaps& model,
                                                        const Eigen::Isometry3d& T_track) {
  // No prior: a direction the part of the map does not constrain is reported (Degenerate) and
  // the frame is not registered, rather than held where the drifted estimate put it.
  m_loop_tracker.reset(T_track);
  return m_loop_tracker.align(ctx.pyramid, model, T_track);
}

double TrackingStage::medianInitTime(const maps::SurfelStore& store) const {
  const maps::SurfelArrays a = store.arrays();
  std::vector<float> t_init;
  const Image<std::int32_t>& index = m_model.index;
  for (int y = 0; y < index.height(); y += 4)
    for (int x = 0; x < index.width(); x += 4)
      if (const std::int32_t i = index(x, y); i >= 0 && i < a.size) t_init.push_back(a.t_init[i]);
  if (t_init.empty()) return store.fromMapTime(0.0f);
  auto mid = t_init.begin() + std::ptrdiff_t(t_init.size() / 2);
  std::nth_element(t_init.begin(), mid, t_init.end());
  return store.fromMapTime(*mid);
}

void TrackingStage::closeLoop(FrameContext& ctx, maps::CSurfelMap& map) {
  const FrameResult& r = ctx.result;
  const double weak = m_frames_since_node > 0
                          ? double(m_weak_frames_since_node) / double(m_frames_since_node)
                          : 0.0;
  if (!m_pending_loop) {
    if (m_loop.addNode(ctx.frame->timestamp_s, r.T_world_cam, false, weak))
      m_frames_since_node = m_weak_frames_since_node = 0;
    return;
  }
  m_frames_since_node = m_weak_frames_since_node = 0;
  const auto t = Clock::now();
  const PendingLoop p = *m_pending_loop;
  m_pending_loop.reset();
  const tracking::TrajectoryCorrection c =
      m_loop.close(p.t_now_s, p.T_active, p.verdict.T_loop, p.t_old_s, weak);
  if (c.empty()) return;
  const int moved = tracking::deformSurfels(map.store(), c);
  tracking::correctKeyframes(map.keyframes(), c);
  const Eigen::Isometry3d C_now = c.at(p.t_now_s);
  m_tracker.applyWorldCorrection(C_now);
  m_T_prev_frame = C_now * m_T_prev_frame;
  if (m_last_fused.valid) {
    m_last_fused.T_world_cam = c.at(m_last_fused.frame.timestamp_s) * m_last_fused.T_world_cam;
    m_last_fused.attempted = false;
  }
  m_odometry.resetHeadingWindow();
  const double ms = msSince(t);
  recordMs(ctx, kLoopClosure, ms);
  m_loop_log.push_back({{"frame", r.index},
                        {"timestamp_s", p.t_now_s},
                        {"old_map_time_s", p.t_old_s},
                        {"correction_m", p.verdict.correction_m},
                        {"correction_deg", p.verdict.correction_deg},
                        {"path_m", p.verdict.path_m},
                        {"surfels_moved", moved},
                        {"ms", ms}});
}

void TrackingStage::csvColumns(std::vector<std::string>& c) const {
  c.insert(c.end(), {"status",
                     "inliers",
                     "inlier_fraction",
                     "rms_m",
                     "model_pixels",
                     "model_all_surfels",
                     "icp_iterations",
                     "icp_iterations_level0",
                     "pose_source",
                     "check_overlap",
                     "check_agreement",
                     "check_behind",
                     "used_prior",
                     "on_motion_model",
                     "prior_sigmas",
                     "odometry_sigmas",
                     "heading_drift_sigmas",
                     "floor_height_m",
                     "floor_tilt_deg",
                     "relocalisation_failure",
                     "loop_closure",
                     "loop_correction_m",
                     "loop_correction_deg"});
}

void TrackingStage::csvValues(const FrameContext& ctx, CsvRow& row) const {
  const FrameResult& r = ctx.result;
  const tracking::TrackingResult& t = r.tracking;
  row.add(tracking::toString(t.status)).add(t.inliers).add(t.inlier_fraction, 6).add(t.rms_m, 6);
  row.add(r.model_valid_pixels).add(r.model_all_surfels).add(t.iterations);
  row.add(t.levels.empty() ? 0 : t.levels.back().iterations).add(toString(r.pose_source));
  row.add(t.check_overlap, 4).add(t.check_agreement, 4).add(t.check_behind, 4).add(t.used_prior);
  row.add(t.on_motion_model)
      .add(t.prior_sigmas, 4)
      .add(t.odometry_sigmas, 4)
      .add(r.heading_drift_sigmas, 3)
      .add(r.floor_height_m, 4);
  row.add(r.floor_tilt_deg, 3).add(r.relocalisation_failure).add(r.loop_closure);
  row.add(r.loop_correction_m, 4).add(r.loop_correction_deg, 3);
}

void TrackingStage::report(nlohmann::json& rep) const {
  rep["relocalisations"] = m_relocalisations;
  // Tracked frames with odometry whose camera left the first frame's floor ([robot]
  // floor_max_*): the map drifted, though each frame agreed with it.
  rep["frames_off_floor"] = m_frames_off_floor;
  rep["frames_before_map"] = m_frames_before_map;
  rep["loop_closure"] = {
      {"comment",
       "frames registered against the inactive map (surfels not fused for inactive_after_s), "
       "loops refused as beyond the drift bound, and each loop closed (the map moved with it)"},
      {"enabled", m_loop_params.enabled},
      {"checks", m_loop_checks},
      {"refused", m_loops_refused},
      {"closed", m_loop_log.size()},
      {"loops", m_loop_log}};
  if (m_frames_before_map > 0 && m_tracker.initialized())
    rep["warnings"].push_back("the map started after " + std::to_string(m_frames_before_map) +
                              " frame(s) without enough valid depth; they were skipped (not "
                              "fused, counted in frames_lost)");
  if (!m_floor_height_abs_m.empty()) rep["floor_drift"] = floorDriftJson();
}

}  // namespace rasm::pipeline
