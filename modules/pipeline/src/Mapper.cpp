#include "rasm/pipeline/Mapper.h"

#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/serialization/CArchive.h>

#include <chrono>

#include "rasm/compute/Parallel.h"
#include "rasm/core/Error.h"
#include "rasm/core/kernels/FrameKernels.h"

namespace rasm::pipeline {

namespace {
using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); }

int countValid(const Image<Vec3f>& v) {
  const int w = v.width();
  return compute::reduce1D<int>(v.height(), [&](int y, int& n) {
    const Vec3f* r = v.row(y);
    for (int x = 0; x < w; ++x) n += kernels::validVec(r[x]) ? 1 : 0;
  });
}
}  // namespace

const char* toString(Stage s) {
  switch (s) {
    case Stage::Preprocess: return "preprocess";
    case Stage::RenderModel: return "render_model";
    case Stage::Track: return "track";
    case Stage::Relocalise: return "relocalise";
    case Stage::Fuse: return "fuse";
    case Stage::Total: return "total";
    default: return "?";
  }
}

const char* toString(PoseSource s) {
  switch (s) {
    case PoseSource::Tracked: return "tracked";
    case PoseSource::Odometry: return "odometry";
    case PoseSource::MotionModel: return "motion_model";
    case PoseSource::Relocalised: return "relocalised";
  }
  return "?";
}

Mapper::Mapper(const MapperParams& params)
    : m_params(params),
      m_map(std::make_unique<maps::CSurfelMap>(params.map)),
      m_tracker(params.tracking),
      m_fusion(params.fusion),
      m_odometry(params.robot),
      m_reloc(params.relocalisation) {
  if (m_params.tracking.numLevels() > m_params.mapper.pyramid_levels)
    throwInputError("[mapper] pyramid_levels",
                    "must be >= the number of [tracking] levels (" + std::to_string(m_params.tracking.numLevels()) + ")");
}

void Mapper::preprocess(const RgbdFrame& frame) {
  const TMapperParams& p = m_params.mapper;
  const Image<float>* depth = &frame.depth_m;
  if (p.bilateral_filter) {
    bilateralFilterDepth(frame.depth_m, m_depth_filtered, 2, float(p.bilateral_sigma_space_px),
                         float(p.bilateral_sigma_depth_m));
    depth = &m_depth_filtered;
  }
  VertexMapOptions vo;
  vo.min_depth_m = float(p.min_depth_m);
  vo.max_depth_m = float(p.max_depth_m);
  m_pyramid.resize(p.pyramid_levels);
  for (int l = 0; l < p.pyramid_levels; ++l) {
    FrameLevel& L = m_pyramid[l];
    L.K = frame.intrinsics.level(l);
    if (l == 0)
      L.depth_m = *depth;
    else
      downsampleDepth(m_pyramid[l - 1].depth_m, L.depth_m);
    computeVertexMap(L.depth_m, L.K, L.vertex, vo);
    computeNormalMap(L.vertex, L.normal, float(p.normal_max_jump_rel));
  }
}

FrameResult Mapper::processFrame(const RgbdFrame& frame) {
  const auto t_start = Clock::now();
  FrameResult r;
  r.index = frame.index;
  r.timestamp_s = frame.timestamp_s;
  if (m_frames == 0) m_t0 = frame.timestamp_s;
  const double t_rel = frame.timestamp_s - m_t0;

  auto t = Clock::now();
  preprocess(frame);
  r.ms[int(Stage::Preprocess)] = msSince(t);

  if (!m_tracker.initialized() && m_localise_in_map) {
    // A loaded map: nothing is fused until the camera is found in it.
    r.tracked = false;
    r.pose_source = PoseSource::MotionModel;
    r.tracking.status = tracking::TrackingStatus::NotInitialized;
    relocalise(frame, r);
    if (r.relocalised) m_odometry.start(r.T_world_cam, frame.odometry_xyyaw);
  } else if (!m_tracker.initialized()) {
    const Eigen::Isometry3d T0 = (m_params.init_from_groundtruth && frame.gt_T_world_cam) ? *frame.gt_T_world_cam
                                                                                          : Eigen::Isometry3d::Identity();
    m_tracker.reset(T0);
    m_odometry.start(T0, frame.odometry_xyyaw);
    r.first = true;
    r.tracked = true;
    r.T_world_cam = T0;
    r.tracking.ok = true;
    r.tracking.status = tracking::TrackingStatus::Ok;
    r.tracking.T_world_cam = T0;
  } else {
    const std::optional<tracking::MotionPrior> prior = m_odometry.predict(frame.odometry_xyyaw, m_T_prev_frame);
    // The model is rendered where the guess starts from: the previous frame's pose when odometry
    // carries the estimate on (also through lost frames), else the last good pose.
    t = Clock::now();
    const tracking::ModelMaps model = renderModel(frame, prior ? m_T_prev_frame : m_tracker.lastGoodPose(), r);
    r.ms[int(Stage::RenderModel)] = msSince(t);

    t = Clock::now();
    const bool photometric = m_params.tracking.photometric_weight > 0 && !frame.colour.empty();
    r.tracking = m_tracker.track(m_pyramid, model, photometric ? frame.colour.cview() : ImageView<const Bgr8>(),
                                 prior ? &*prior : nullptr);
    r.ms[int(Stage::Track)] = msSince(t);
    r.tracked = r.tracking.ok;
    if (r.tracked) {
      r.T_world_cam = r.tracking.T_world_cam;
      if (m_params.robot.planar_motion) {
        r.T_world_cam = m_odometry.projectToFloor(r.T_world_cam);
        m_tracker.correctLastPose(r.T_world_cam);
      }
    } else {
      r.pose_source = prior ? PoseSource::Odometry : PoseSource::MotionModel;
      r.T_world_cam = prior ? prior->T_world_cam : r.tracking.T_world_cam_guess;
      relocalise(frame, r);
    }
  }
  m_T_prev_frame = r.T_world_cam;

  if (r.tracked && !r.relocalised) {
    t = Clock::now();
    fusion::FusionInput in = fusion::makeFusionInput(frame, m_pyramid[0].vertex, m_pyramid[0].normal, r.T_world_cam);
    in.timestamp_s = t_rel;
    r.fusion = m_fusion.fuse(m_map->store(), in);
    r.fused = true;
    m_reloc.maybeAddKeyframe(frame, r.T_world_cam, m_map->keyframes());
    r.ms[int(Stage::Fuse)] = msSince(t);
  } else if (!r.tracked) {
    ++m_lost;
  }
  ++m_frames;
  r.ms[int(Stage::Total)] = msSince(t_start);
  return r;
}

tracking::ModelMaps Mapper::renderModel(const RgbdFrame& frame, const Eigen::Isometry3d& T_model, FrameResult& r) {
  // II-C: model = the map rendered at the previous pose from its reliable surfels: those with
  // confidence >= [tracking] model_min_confidence, or the ones fusion flagged stable when that is
  // 0. Until enough of them exist (the first frames of a run, or a newly seen area), that model
  // is too sparse to constrain ICP; then all surfels are used.
  const tracking::TTrackingParams& tp = m_params.tracking;
  maps::RenderOptions ro;
  ro.min_depth_m = float(m_params.mapper.min_depth_m);
  ro.max_depth_m = float(m_params.mapper.max_depth_m) * 1.5f;
  ro.stable_only = tp.model_min_confidence <= 0;
  ro.min_confidence = float(tp.model_min_confidence);
  ro.outputs = maps::kRenderVertex | maps::kRenderNormal;
  // Optional inputs of the tracker: colour for its photometric term, surfel confidence weights.
  if (tp.photometric_weight > 0 && !frame.colour.empty()) ro.outputs |= maps::kRenderColour;
  if (tp.confidence_full > 0) ro.outputs |= maps::kRenderConfidence;
  // Rendered at pyramid level [tracking] model_level (intrinsics of that level); a pixel a
  // surfel won has that surfel's normal: the render counts the valid model pixels.
  const CameraIntrinsics K_model = frame.intrinsics.level(tp.model_level);
  maps::RenderStats rs;
  m_renderer.render(m_map->store(), T_model, K_model, ro, m_model, &rs);
  r.model_valid_pixels = int(rs.pixels_drawn);
  const int frame_valid = countValid(m_pyramid[tp.model_level].normal);
  if (r.model_valid_pixels < 0.3 * frame_valid) {
    ro.stable_only = false;
    ro.min_confidence = 0.0f;
    m_renderer.render(m_map->store(), T_model, K_model, ro, m_model, &rs);
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

void Mapper::relocalise(const RgbdFrame& frame, FrameResult& r) {
  if (m_map->keyframes().empty()) return;
  const auto t = Clock::now();
  const std::optional<tracking::RelocalisationResult> cand = m_reloc.relocalise(frame, m_map->keyframes());
  if (!cand) {
    r.relocalisation_failure = m_reloc.lastStats().reason;
  } else {
    // Verify: ICP from the candidate against the map rendered there, every quality rule and
    // the pose check applied (no prior: the candidate is independent of the lost estimate).
    FrameResult probe;
    const tracking::ModelMaps model = renderModel(frame, cand->T_world_cam, probe);
    const tracking::TrackingResult v = m_tracker.align(m_pyramid, model, cand->T_world_cam);
    if (v.ok && v.check_overlap >= m_params.tracking.check_min_overlap) {
      m_tracker.reset(v.T_world_cam);
      r.tracking = v;
      r.tracked = true;
      r.relocalised = true;
      r.pose_source = PoseSource::Relocalised;
      r.T_world_cam = v.T_world_cam;
      r.model_valid_pixels = probe.model_valid_pixels;
      ++m_relocalisations;
    } else {
      r.relocalisation_failure = std::string("rejected by ICP: ") + tracking::toString(v.status);
    }
  }
  r.ms[int(Stage::Relocalise)] = msSince(t);
}

void Mapper::loadMap(const std::string& path) {
  if (m_frames > 0) throwInputError("map '" + path + "'", "must be loaded before the first frame");
  auto loaded = std::make_unique<maps::CSurfelMap>(m_params.map);
  try {
    mrpt::io::CFileGZInputStream f(path);
    auto a = mrpt::serialization::archiveFrom(f);
    a >> *loaded;
  } catch (const std::exception& e) {
    throwInputError("map '" + path + "'", std::string("cannot be read as a rasm surfel map (.surfelmap): ") + e.what());
  }
  if (loaded->keyframes().empty())
    throwInputError("map '" + path + "'", "has no relocalisation keyframes: the camera cannot be localised in it");
  m_map = std::move(loaded);
  m_localise_in_map = true;
}

void Mapper::renderView(const Eigen::Isometry3d& T_world_cam, const CameraIntrinsics& K, maps::RenderedMaps& out) {
  maps::RenderOptions ro;
  ro.max_depth_m = 20.0f;
  m_renderer.render(m_map->store(), T_world_cam, K, ro, out);
}

}  // namespace rasm::pipeline
