#pragma once
#include <limits>
// What one frame carries through the Mapper's stages (DESIGN.md "Stages, threads and the map they
// share"): the frame, its pyramid (II-A), the pose and how it was obtained (II-C), the 4x index map
// at T_t (II-D), label maps (III) and the per-stage timings. Each stage reads what the stages
// before it wrote and adds its own part; FrameResult is the part that outlives the frame (the
// caller's copy, frames.csv, report.json).

#include <Eigen/Geometry>
#include <cstdint>
#include <string>
#include <vector>

#include "rasm/core/FrameProcessing.h"
#include "rasm/core/Image.h"
#include "rasm/core/RgbdFrame.h"
#include "rasm/fusion/SurfelFusion.h"
#include "rasm/tracking/IcpTracker.h"

namespace rasm::pipeline {

/// Where a frame's pose comes from.
enum class PoseSource : int {
  Tracked,      ///< ICP against the map (with the odometry prior when there is one)
  Odometry,     ///< lost: the odometry's prediction from the previous frame's pose
  MotionModel,  ///< lost: the tracker's motion-model guess (no odometry)
  Relocalised,  ///< found again against the map's keyframes and verified by ICP (not fused)
};
const char* toString(PoseSource s);

/// The outcome of one frame.
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
  bool relocalised = false;  ///< pose_source == Relocalised
  /// While lost: why relocalisation found nothing this frame (Relocaliser's reason, or
  /// "rejected by ICP: <status>"); empty when it was not tried or succeeded.
  std::string relocalisation_failure;
  /// With odometry: the accumulated heading disagreement with it, in sigmas (OdometryPrior).
  double heading_drift_sigmas = 0.0;
  /// A robot's tracked camera against the first frame's floor (OdometryPrior::floorDeviation):
  /// height above the mount's (m) and tilt (deg); NaN without odometry.
  double floor_height_m = std::numeric_limits<double>::quiet_NaN();
  double floor_tilt_deg = std::numeric_limits<double>::quiet_NaN();
  /// Loop closure (LoopClosure.h), on the frames registered against the inactive map: "agrees",
  /// "candidate", "refused" (beyond the drift bound), "closed", "unconfirmed: <why>",
  /// "unregistered: <why>" (ICP against the inactive map
  /// failed); empty when not checked. The correction asked for, where the camera is.
  std::string loop_closure;
  double loop_correction_m = 0.0, loop_correction_deg = 0.0;
  int model_valid_pixels = 0;      ///< valid pixels of the rendered model ICP aligned to
  bool model_all_surfels = false;  ///< model from all surfels: stable-only too sparse, or retried
  /// Milliseconds per timer, in the order of Mapper::timerNames() (stages, their parts, "total").
  std::vector<double> ms;

  /// Tracked at a pose the map may be fused at (a relocalised frame is verified, not fused).
  bool fusable() const { return tracked && !relocalised; }
};

struct FrameContext {
  const RgbdFrame* frame = nullptr;
  double t_rel_s = 0.0;  ///< since the run's first frame (surfel times are relative to it)
  /// II-A: vertex / normal maps in the camera frame per level (0 = full resolution).
  std::vector<FrameLevel> pyramid;
  FrameResult result;
  /// II-D: fusion's 4x index map of the map at T_t (IndexMapStage), before any update of this
  /// frame; valid while result.fusable() until FusionStage changes the map.
  fusion::IndexMapView index_map;
  /// III: propagated segment labels L^p per frame pixel (0 = none), which FusionStage hands to
  /// fusion's segment-weight update; empty = no segmentation stage.
  Image<std::uint32_t> labels;
};

}  // namespace rasm::pipeline
