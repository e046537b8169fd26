#pragma once
// The mapping front end of one frame (section II): preprocess (II-A), track against the map
// rendered at the last good pose, stable surfels only (II-C), fuse and clean up (II-B, II-D).
// Later stages (segmentation, classification) hook in between tracking and fusion.
//
//   Mapper mapper(params);
//   for (frame : source) { FrameResult r = mapper.processFrame(frame); ... }
//   mapper.map().saveToPly("map.ply");
//
// Motion prior: a frame with odometry (RgbdFrame::odometry_xyyaw, the robot's wheels) is tracked
// from the odometry's prediction through the camera mount, and ICP weighs the data against it
// (OdometryPrior.h, [robot]); without odometry the tracker's motion model gives the guess.
//
// Lost track: a frame whose TrackingResult is not ok is not fused. It still gets a pose, flagged
// by FrameResult::pose_source: the odometry's prediction when there is one (the model is then
// rendered from that propagated pose, so tracking resumes as soon as the view agrees again), the
// motion model's guess otherwise (the model stays rendered from the last good pose, so tracking
// resumes when the camera comes back near it, IcpTracker.h).

#include <Eigen/Geometry>
#include <array>
#include <memory>
#include <string>
#include <vector>

#include "rasm/core/FrameProcessing.h"
#include "rasm/core/RgbdFrame.h"
#include "rasm/fusion/SurfelFusion.h"
#include "rasm/pipeline/OdometryPrior.h"
#include "rasm/pipeline/RunParams.h"
#include "rasm/surfel_map/CSurfelMap.h"
#include "rasm/surfel_map/SurfelRenderer.h"
#include "rasm/tracking/IcpTracker.h"
#include "rasm/tracking/Relocaliser.h"

namespace rasm::pipeline {

/// Stages timed per frame (milliseconds), in pipeline order.
enum class Stage : int { Preprocess = 0, RenderModel, Track, Relocalise, Fuse, Total, Count };
const char* toString(Stage s);

/// Where a frame's pose comes from.
enum class PoseSource : int {
  Tracked,      ///< ICP against the map (with the odometry prior when there is one)
  Odometry,     ///< lost: the odometry's prediction from the previous frame's pose
  MotionModel,  ///< lost: the tracker's motion-model guess (no odometry)
  Relocalised,  ///< found again against the map's keyframes and verified by ICP (not fused)
};
const char* toString(PoseSource s);

struct MapperParams {
  TMapperParams mapper;
  tracking::TTrackingParams tracking;
  fusion::TFusionParams fusion;
  maps::CSurfelMap::TCreationOptions map;
  TRobotParams robot;
  tracking::TRelocalisationParams relocalisation;
  /// Start at the source's ground-truth pose when the first frame has one (keeps the map in the
  /// ground-truth/world frame; ATE aligns anyway). Otherwise the identity.
  bool init_from_groundtruth = true;
};

struct FrameResult {
  std::size_t index = 0;
  double timestamp_s = 0.0;
  Eigen::Isometry3d T_world_cam = Eigen::Isometry3d::Identity();
  bool tracked = false;  ///< false while lost (the pose is then propagated: pose_source)
  PoseSource pose_source = PoseSource::Tracked;
  bool fused = false;
  bool first = false;
  tracking::TrackingResult tracking;
  fusion::FusionStats fusion;
  bool relocalised = false;    ///< pose_source == Relocalised
  /// While lost: why relocalisation found nothing this frame (Relocaliser's reason, or
  /// "rejected by ICP: <status>"); empty when it was not tried or succeeded.
  std::string relocalisation_failure;
  int model_valid_pixels = 0;  ///< valid pixels of the rendered model ICP aligned to
  bool model_all_surfels = false;  ///< the stable-only model was too sparse: all surfels used
  std::array<double, int(Stage::Count)> ms{};
};

class Mapper {
 public:
  explicit Mapper(const MapperParams& params);
  FrameResult processFrame(const RgbdFrame& frame);

  maps::CSurfelMap& map() { return *m_map; }
  const maps::CSurfelMap& map() const { return *m_map; }
  const tracking::IcpTracker& tracker() const { return m_tracker; }
  const MapperParams& params() const { return m_params; }
  std::size_t framesProcessed() const { return m_frames; }
  std::size_t framesLost() const { return m_lost; }
  std::size_t relocalisations() const { return m_relocalisations; }
  /// Replaces the map with one loaded from a .surfelmap file (a previous run's): the camera is
  /// then localised in it by relocalisation against its keyframes before anything is fused.
  /// Call before the first frame. Throws InputError when the file cannot be read.
  void loadMap(const std::string& path);
  /// Last good camera pose.
  const Eigen::Isometry3d& pose() const { return m_tracker.lastGoodPose(); }
  /// Pose of the last frame processed (tracked or propagated while lost).
  const Eigen::Isometry3d& lastFramePose() const { return m_T_prev_frame; }
  /// Renders the map's colour / segment view at a pose (previews, annotated rawlogs).
  void renderView(const Eigen::Isometry3d& T_world_cam, const CameraIntrinsics& K, maps::RenderedMaps& out);

 private:
  void preprocess(const RgbdFrame& frame);
  /// II-C: renders the tracking model at T_model (reliable surfels, all of them while too few)
  /// and returns the tracker's view of it (valid until the next render).
  tracking::ModelMaps renderModel(const RgbdFrame& frame, const Eigen::Isometry3d& T_model, FrameResult& r);
  /// Issue 14 (5): while lost, the pose from the map's keyframes, verified by ICP against the map
  /// rendered there; on success the tracker restarts from it (r becomes Relocalised).
  void relocalise(const RgbdFrame& frame, FrameResult& r);

  MapperParams m_params;
  std::unique_ptr<maps::CSurfelMap> m_map;
  tracking::IcpTracker m_tracker;
  fusion::SurfelFusion m_fusion;
  maps::SurfelRenderer m_renderer;
  maps::RenderedMaps m_model;
  OdometryPrior m_odometry;
  tracking::Relocaliser m_reloc;
  bool m_localise_in_map = false;  ///< loadMap(): the first pose comes from relocalisation
  Eigen::Isometry3d m_T_prev_frame = Eigen::Isometry3d::Identity();
  Image<float> m_depth_filtered;
  std::vector<FrameLevel> m_pyramid;
  std::size_t m_frames = 0, m_lost = 0, m_relocalisations = 0;
  double m_t0 = 0.0;  ///< timestamp of the first frame: surfel times are relative to it
};

}  // namespace rasm::pipeline
