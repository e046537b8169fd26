#pragma once
// rasm::tracking::LoopCloser: the loop-closure policy of a tracked run ([loop_closure]) around
// LoopClosure's graph: when to check, how a check registers the frame against the inactive and
// the active map, what confirms a loop (consecutive checks asking for the same correction; the
// frame's features or its colour agreeing with the geometry), and closing a confirmed loop once
// the frame is fused. The map parts come from the caller (MapPartSource: the tracking stage
// renders them as it renders its tracking model), so the policy is here and the stage wires it.
//
//   LoopCloser lc;  lc.configure(loop_params, tracking_params);
//   first frame:               lc.start(up_axis_or_null);
//   every frame:               lc.frameDone(weak);
//   tracked, fusable frame:    LoopCheck c = lc.check(frame, pyramid, T_track, map, parts, reloc);
//   fused frame (map locked):  TrajectoryCorrection corr = lc.closeIfDue(t, T, map); apply corr
//   frame not fused:           lc.frameNotFused();

#include <Eigen/Geometry>
#include <optional>
#include <string>
#include <vector>

#include "rasm/core/FrameProcessing.h"
#include "rasm/core/RgbdFrame.h"
#include "rasm/surfel_map/CSurfelMap.h"
#include "rasm/tracking/IcpTracker.h"
#include "rasm/tracking/LoopClosure.h"
#include "rasm/tracking/MapPartSource.h"
#include "rasm/tracking/Relocaliser.h"
#include "rasm/tracking/TrackingParams.h"

namespace rasm::tracking {

/// What one check found (frames.csv loop_closure, loop_correction_*): "agrees", "candidate",
/// "refused", "closed" (confirmed: closed when the frame is fused), "unconfirmed: <why>",
/// "unregistered: <why>"; empty when the frame was not checked.
struct LoopCheck {
  bool rendered = false;  ///< the check was due and rendered the inactive map
  std::string verdict;
  double correction_m = 0.0, correction_deg = 0.0;
};

/// One loop closed (report.json loop_closure.loops).
struct ClosedLoop {
  std::size_t frame = 0;
  double timestamp_s = 0.0, old_map_time_s = 0.0;
  double correction_m = 0.0, correction_deg = 0.0, path_m = 0.0;
  int surfels_moved = 0;
};

class LoopCloser {
 public:
  /// The loop registration's ICP is `tracking` with the inlier fraction scaled by
  /// min_inactive_fraction (the part covers part of the view), the jump bound raised to the
  /// loop's, and never a degenerate registration.
  void configure(const TLoopClosureParams& loop, const TTrackingParams& tracking);
  const TLoopClosureParams& params() const { return m_params; }

  /// A new trajectory starts (the map's first frame); `up`: a ground robot's up axis (corrections
  /// about it only), or null.
  void start(const Eigen::Vector3d* up);
  /// Every frame: the graph's chain edge weakens with frames not tracked Ok since its last node.
  void frameDone(bool weak);
  /// Read phase of a tracked, fusable frame: every check_every_frames, once the map has an
  /// inactive part, the frame registered against the inactive and the active map and judged.
  /// `frame_valid_pixels`: valid normals at the model level (the parts' coverage is against it).
  LoopCheck check(const RgbdFrame& frame, const std::vector<FrameLevel>& pyramid,
                  const Eigen::Isometry3d& T_track, int frame_valid_pixels,
                  const maps::CSurfelMap& map, MapPartSource& parts, Relocaliser& reloc);
  /// Write phase of a fused frame at T_world_cam: a graph node, or the confirmed loop closed and
  /// the surfels and keyframes moved with their time's correction. Returns the correction (empty
  /// when nothing was closed); the caller moves its own poses with it (correction.at(t)).
  TrajectoryCorrection closeIfDue(std::size_t frame_index, double t_s,
                                  const Eigen::Isometry3d& T_world_cam, maps::CSurfelMap& map);
  /// A frame that was not fused drops a confirmed loop (it would be closed on the next one).
  void frameNotFused() { m_pending.reset(); }

  std::size_t checks() const { return m_checks; }
  std::size_t refused() const { return m_refused; }
  const std::vector<ClosedLoop>& closed() const { return m_closed; }

 private:
  /// The frame against a part of the map from T_track, without a prior.
  TrackingResult registerAgainst(const std::vector<FrameLevel>& pyramid, const ModelMaps& model,
                                 const Eigen::Isometry3d& T_track);
  /// Whether the frame's features against the keyframes made before t_inactive (PnP) put the
  /// camera where the registration against the inactive map did; `why` says why not.
  bool featuresConfirm(const RgbdFrame& frame, const maps::CSurfelMap& map,
                       const Eigen::Isometry3d& T_inactive, double t_inactive,
                       const LoopVerdict& verdict, Relocaliser& reloc, std::string& why);
  /// The poses of an accepted verdict, to run.log (debug): the tracked one, the registration
  /// against the inactive map (as registered, kept along held directions, and its move along
  /// each eigen-direction), against the active map, and the one the loop asks for.
  void logPoses(std::size_t frame_index, const Eigen::Isometry3d& T_track,
                const TrackingResult& v_in, const Eigen::Isometry3d& T_inactive,
                const Eigen::Isometry3d& T_active, const LoopVerdict& verdict) const;
  /// Whether the registration against the inactive map (surfels made before t_inactive, rendered
  /// with their colour) by joint ICP + RGB agrees with the geometric one, T_inactive.
  bool colourConfirms(const RgbdFrame& frame, const std::vector<FrameLevel>& pyramid,
                      MapPartSource& parts, const Eigen::Isometry3d& T_track,
                      const Eigen::Isometry3d& T_inactive, double t_inactive,
                      const LoopVerdict& verdict, std::string& why);
  /// Within feature_agreement_* or 30% of the verdict's correction; `why` names `what` if not.
  bool posesAgree(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b,
                  const LoopVerdict& verdict, const char* what, std::string& why) const;
  /// A judged registration: confirmed, counted as a candidate, or dropped.
  void confirm(const RgbdFrame& frame, const std::vector<FrameLevel>& pyramid, MapPartSource& parts,
               const Eigen::Isometry3d& T_track, const TrackingResult& v_in,
               const Eigen::Isometry3d& T_inactive, const Eigen::Isometry3d& T_active, double t_old,
               double t_inactive, const maps::CSurfelMap& map, Relocaliser& reloc, LoopCheck& out);

  TLoopClosureParams m_params;
  TTrackingParams m_tracking;
  LoopClosure m_loop;
  IcpTracker m_tracker;  ///< registers frames against the inactive / active map
  int m_frames_since_check = 0;
  /// Frames since the last graph node, and those of them not tracked Ok (degenerate or lost).
  int m_frames_since_node = 0, m_weak_frames_since_node = 0;
  struct Pending {
    LoopVerdict verdict;
    Eigen::Isometry3d T_active;
    double t_old_s = 0, t_now_s = 0;
  };
  std::optional<Pending> m_pending;  ///< confirmed, closed when the frame is fused
  struct Candidate {
    LoopVerdict verdict;
    std::size_t frame = 0;
  };
  std::optional<Candidate> m_candidate;  ///< the last accepted check
  int m_candidate_checks = 0;            ///< consecutive checks that agree with it
  std::size_t m_refused = 0, m_checks = 0;
  std::vector<ClosedLoop> m_closed;
};

}  // namespace rasm::tracking
