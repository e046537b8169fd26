#pragma once
// rasm::tracking::RelocalisationPolicy: how a lost camera is found again ([relocalisation]), and
// the keyframes that makes possible. A lost frame is matched first against the last fused frame
// (ORB-SLAM's reference keyframe: use_last_fused_frame, with its own acceptance,
// TRelocalisationParams::forLastFusedFrame), then against the map's keyframes (Relocaliser:
// ORB, PnP); a candidate pose is verified by ICP against the map rendered there (every tracking
// rule and the pose check, check_min_overlap; a degenerate verification is refused) before
// tracking may restart from it. A robot's relocalised pose must also agree with its odometry
// (TrackingStage::relocalise). Fused frames
// become the map's keyframes by the spacing rules, and the last of them is kept (its keyframe is
// made only when a lost frame needs it). The map is rendered by the caller (MapPartSource, as for
// loop closure), so the policy is here and the tracking stage wires it.
//
//   RelocalisationPolicy rp;  rp.configure(reloc_params, tracking_params);
//   fused frame:   rp.frameFused(frame, T_world_cam, map.keyframes());
//   lost frame:    Found f = rp.relocalise(frame, pyramid, map.keyframes(), parts, tracker);
//                  if (f.found) tracker.reset(f.verified.T_world_cam);
//   loop closed:   rp.correct(correction);

#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "rasm/core/FrameProcessing.h"
#include "rasm/core/RgbdFrame.h"
#include "rasm/surfel_map/Keyframe.h"
#include "rasm/tracking/IcpTracker.h"
#include "rasm/tracking/LoopClosure.h"
#include "rasm/tracking/MapPartSource.h"
#include "rasm/tracking/RelocalisationParams.h"
#include "rasm/tracking/Relocaliser.h"
#include "rasm/tracking/TrackingParams.h"

namespace rasm::tracking {

class RelocalisationPolicy {
 public:
  /// What one lost frame's relocalisation found.
  struct Found {
    bool tried = false;          ///< there was a database to try (the last fused frame, keyframes)
    bool found = false;          ///< a candidate passed the ICP verification
    TrackingResult verified;     ///< that verification (found)
    int model_valid_pixels = 0;  ///< pixels of the map rendered at the candidate (found)
    /// Why nothing was found: the Relocaliser's reason, or "rejected by ICP: <status>"; empty
    /// when found or when no candidate was looked for.
    std::string failure;
  };

  void configure(const TRelocalisationParams& reloc, const TTrackingParams& tracking);
  const TRelocalisationParams& params() const { return m_params; }

  /// A lost frame against the last fused frame, then the map's keyframes; `tracker` verifies a
  /// candidate (align from it, no prior); the caller restarts tracking from a found pose.
  Found relocalise(const RgbdFrame& frame, const std::vector<FrameLevel>& pyramid,
                   const std::vector<maps::Keyframe>& map_keyframes, MapPartSource& parts,
                   IcpTracker& tracker);
  /// A fused frame at T_world_cam: a keyframe of the map when the spacing rules say so, and the
  /// last fused frame (with colour) kept for relocalise().
  void frameFused(const RgbdFrame& frame, const Eigen::Isometry3d& T_world_cam,
                  std::vector<maps::Keyframe>& map_keyframes);
  /// A closed loop moved the world: the last fused frame's pose moves with it.
  void correct(const TrajectoryCorrection& c);
  /// The relocaliser of the map's keyframes (loop closure's feature confirmation uses it).
  Relocaliser& keyframeRelocaliser() { return m_reloc; }

 private:
  /// One database tried; true when its candidate passed the verification.
  bool tryDatabase(const RgbdFrame& frame, const std::vector<FrameLevel>& pyramid,
                   const std::vector<maps::Keyframe>& db, Relocaliser& reloc, MapPartSource& parts,
                   IcpTracker& tracker, Found& out);
  /// The last fused frame as a one-keyframe database (its features detected on first use);
  /// empty when there is none or it has too few features.
  const std::vector<maps::Keyframe>& lastFusedKeyframe();

  TRelocalisationParams m_params;
  TTrackingParams m_tracking;
  Relocaliser m_reloc;
  Relocaliser m_reloc_last_fused;  ///< with [relocalisation] last_fused_* acceptance
  struct LastFused {
    RgbdFrame frame;
    Eigen::Isometry3d T_world_cam = Eigen::Isometry3d::Identity();
    bool valid = false, attempted = false;
    std::vector<maps::Keyframe> keyframe;  ///< 0 or 1
  } m_last_fused;
};

}  // namespace rasm::tracking
