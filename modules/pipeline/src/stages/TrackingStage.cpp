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
  m_relocaliser.configure(m_relocalisation, m_tracking);
  m_loop.configure(m_loop_params, m_tracking);
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
  m_loop.frameDone(r.tracking.status != tracking::TrackingStatus::Ok || !r.tracked);
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
  const Eigen::Vector3d up = m_odometry.up();
  m_loop.start(frame.odometry_xyyaw ? &up : nullptr);
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
    relocalise(ctx, map, prior ? &*prior : nullptr);
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

class TrackingStage::MapParts : public tracking::MapPartSource {
 public:
  MapParts(TrackingStage& stage, FrameContext& ctx, const maps::CSurfelMap& map)
      : m_stage(stage), m_ctx(ctx), m_map(map) {}
  tracking::MapPart render(const Eigen::Isometry3d& T_world_cam, bool with_colour,
                           const maps::RenderOptions& time_filter) override {
    FrameResult probe;
    tracking::MapPart part;
    part.model =
        m_stage.renderModel(m_ctx, m_map, T_world_cam, with_colour, probe, false, &time_filter);
    part.valid_pixels = probe.model_valid_pixels;
    return part;
  }
  double medianInitTimeOfLastRender() const override {
    const maps::SurfelArrays a = m_map.store().arrays();
    std::vector<float> t_init;
    const Image<std::int32_t>& index = m_stage.m_model.index;
    for (int y = 0; y < index.height(); y += 4)
      for (int x = 0; x < index.width(); x += 4)
        if (const std::int32_t i = index(x, y); i >= 0 && i < a.size) t_init.push_back(a.t_init[i]);
    if (t_init.empty()) return m_map.store().fromMapTime(0.0f);
    auto mid = t_init.begin() + std::ptrdiff_t(t_init.size() / 2);
    std::nth_element(t_init.begin(), mid, t_init.end());
    return m_map.store().fromMapTime(*mid);
  }

 private:
  TrackingStage& m_stage;
  FrameContext& m_ctx;
  const maps::CSurfelMap& m_map;
};

void TrackingStage::relocalise(FrameContext& ctx, const maps::CSurfelMap& map,
                               const tracking::MotionPrior* odometry) {
  const auto t = Clock::now();
  MapParts parts(*this, ctx, map);
  tracking::RelocalisationPolicy::Found f =
      m_relocaliser.relocalise(*ctx.frame, ctx.pyramid, map.keyframes(), parts, m_tracker);
  if (!f.tried) return;
  if (f.found && odometry) {
    // The robot's odometry knows where the camera is within its sigmas (their variance grows
    // over the lost frames): a verified candidate beyond them is a look-alike or a slide.
    const double sigmas = tracking::odometrySigmas(f.verified.T_world_cam, *odometry);
    if (sigmas > m_tracking.max_odometry_sigmas) {
      f.found = false;
      char text[96];
      std::snprintf(text, sizeof text, "odometry puts the camera %.1f sigmas away", sigmas);
      f.failure = text;
    }
  }
  FrameResult& r = ctx.result;
  r.relocalisation_failure = f.failure;
  if (f.found) {
    m_tracker.reset(f.verified.T_world_cam);
    r.tracking = f.verified;
    r.tracked = true;
    r.relocalised = true;
    r.pose_source = PoseSource::Relocalised;
    r.T_world_cam = f.verified.T_world_cam;
    r.model_valid_pixels = f.model_valid_pixels;
    ++m_relocalisations;
  }
  recordMs(ctx, kRelocalise, msSince(t));
}

void TrackingStage::finishFrame(FrameContext& ctx, maps::CSurfelMap& map) {
  if (!ctx.result.fused) {
    m_loop.frameNotFused();
    return;
  }
  if (m_loop_params.enabled && m_mapper.poses != "groundtruth") closeLoop(ctx, map);
  m_relocaliser.frameFused(*ctx.frame, ctx.result.T_world_cam, map.keyframes());
}

void TrackingStage::checkLoop(FrameContext& ctx, const maps::CSurfelMap& map) {
  const auto t = Clock::now();
  FrameResult& r = ctx.result;
  MapParts parts(*this, ctx, map);
  const int frame_valid = countValid(ctx.pyramid[std::size_t(m_tracking.model_level)].normal);
  const tracking::LoopCheck c = m_loop.check(*ctx.frame, ctx.pyramid, r.T_world_cam, frame_valid,
                                             map, parts, m_relocaliser.keyframeRelocaliser());
  if (!c.rendered) return;  // not due
  r.loop_closure = c.verdict;
  r.loop_correction_m = c.correction_m;
  r.loop_correction_deg = c.correction_deg;
  recordMs(ctx, kLoopClosure, msSince(t));
}

void TrackingStage::closeLoop(FrameContext& ctx, maps::CSurfelMap& map) {
  const FrameResult& r = ctx.result;
  const auto t = Clock::now();
  const tracking::TrajectoryCorrection c =
      m_loop.closeIfDue(r.index, ctx.frame->timestamp_s, r.T_world_cam, map);
  if (c.empty()) return;
  const Eigen::Isometry3d C_now = c.at(ctx.frame->timestamp_s);
  m_tracker.applyWorldCorrection(C_now);
  m_T_prev_frame = C_now * m_T_prev_frame;
  m_relocaliser.correct(c);
  m_odometry.resetHeadingWindow();
  const double ms = msSince(t);
  recordMs(ctx, kLoopClosure, ms);
  m_loop_close_ms.push_back(ms);
}

nlohmann::json TrackingStage::loopLogJson() const {
  nlohmann::json log = nlohmann::json::array();
  const std::vector<tracking::ClosedLoop>& closed = m_loop.closed();
  for (std::size_t k = 0; k < closed.size(); ++k)
    log.push_back({{"frame", closed[k].frame},
                   {"timestamp_s", closed[k].timestamp_s},
                   {"old_map_time_s", closed[k].old_map_time_s},
                   {"correction_m", closed[k].correction_m},
                   {"correction_deg", closed[k].correction_deg},
                   {"path_m", closed[k].path_m},
                   {"surfels_moved", closed[k].surfels_moved},
                   {"ms", k < m_loop_close_ms.size() ? m_loop_close_ms[k] : 0.0}});
  return log;
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
       "frames registered against the inactive map (surfels created inactive_after_s or more ago), "
       "loops refused as beyond the drift bound, and each loop closed (the map moved with it)"},
      {"enabled", m_loop_params.enabled},
      {"checks", m_loop.checks()},
      {"refused", m_loop.refused()},
      {"closed", m_loop.closed().size()},
      {"loops", loopLogJson()}};
  if (m_frames_before_map > 0 && m_tracker.initialized())
    rep["warnings"].push_back("the map started after " + std::to_string(m_frames_before_map) +
                              " frame(s) without enough valid depth; they were skipped (not "
                              "fused, counted in frames_lost)");
  if (!m_floor_height_abs_m.empty()) rep["floor_drift"] = floorDriftJson();
}

}  // namespace rasm::pipeline
