#include "rasm/tracking/RelocalisationPolicy.h"

#include <optional>

namespace rasm::tracking {

void RelocalisationPolicy::configure(const TRelocalisationParams& reloc,
                                     const TTrackingParams& tracking) {
  m_params = reloc;
  m_tracking = tracking;
  m_reloc = Relocaliser(reloc);
  m_reloc_last_fused = Relocaliser(reloc.forLastFusedFrame());
}

RelocalisationPolicy::Found RelocalisationPolicy::relocalise(
    const RgbdFrame& frame, const std::vector<FrameLevel>& pyramid,
    const std::vector<maps::Keyframe>& map_keyframes, MapPartSource& parts, IcpTracker& tracker) {
  Found out;
  const bool reference = m_params.use_last_fused_frame && m_last_fused.valid;
  if (map_keyframes.empty() && !reference) return out;
  out.tried = true;
  const bool by_reference =
      reference && !lastFusedKeyframe().empty() &&
      tryDatabase(frame, pyramid, lastFusedKeyframe(), m_reloc_last_fused, parts, tracker, out);
  if (!by_reference && !map_keyframes.empty())
    tryDatabase(frame, pyramid, map_keyframes, m_reloc, parts, tracker, out);
  return out;
}

bool RelocalisationPolicy::tryDatabase(const RgbdFrame& frame,
                                       const std::vector<FrameLevel>& pyramid,
                                       const std::vector<maps::Keyframe>& db, Relocaliser& reloc,
                                       MapPartSource& parts, IcpTracker& tracker, Found& out) {
  const std::optional<RelocalisationResult> cand = reloc.relocalise(frame, db);
  if (!cand) {
    out.failure = reloc.lastStats().reason;
    return false;
  }
  // Verify: ICP from the candidate against the map rendered there, every quality rule and the
  // pose check applied (no prior: the candidate is independent of the lost estimate).
  const MapPart model = parts.render(cand->T_world_cam, m_tracking.photometricWeight(false) > 0,
                                     maps::RenderOptions());
  const TrackingResult v = tracker.align(pyramid, model.model, cand->T_world_cam);
  // A degenerate verification is refused: along the directions the map does not hold there the
  // pose would be the features' alone, and a look-alike place passes every other rule
  // (docs/slam-eval.md "Relocalisation at 320x240").
  if (!v.ok || v.status == TrackingStatus::Degenerate ||
      v.check_overlap < m_tracking.check_min_overlap) {
    out.failure = std::string("rejected by ICP: ") + toString(v.status);
    return false;
  }
  out.found = true;
  out.verified = v;
  out.model_valid_pixels = model.valid_pixels;
  out.failure.clear();
  return true;
}

const std::vector<maps::Keyframe>& RelocalisationPolicy::lastFusedKeyframe() {
  LastFused& lf = m_last_fused;
  if (!lf.attempted) {
    lf.attempted = true;
    lf.keyframe.clear();
    if (auto kf = m_reloc.makeKeyframe(lf.frame, lf.T_world_cam)) lf.keyframe.push_back(*kf);
  }
  return lf.keyframe;
}

void RelocalisationPolicy::frameFused(const RgbdFrame& frame, const Eigen::Isometry3d& T_world_cam,
                                      std::vector<maps::Keyframe>& map_keyframes) {
  m_reloc.maybeAddKeyframe(frame, T_world_cam, map_keyframes);
  if (!m_params.use_last_fused_frame || frame.colour.empty()) return;
  LastFused& lf = m_last_fused;  // copies into buffers of the same size: no allocation
  lf.frame.index = frame.index;
  lf.frame.timestamp_s = frame.timestamp_s;
  lf.frame.intrinsics = frame.intrinsics;
  lf.frame.depth_m = frame.depth_m;
  lf.frame.colour = frame.colour;
  lf.T_world_cam = T_world_cam;
  lf.valid = true;
  lf.attempted = false;
}

void RelocalisationPolicy::correct(const TrajectoryCorrection& c) {
  if (!m_last_fused.valid) return;
  m_last_fused.T_world_cam = c.at(m_last_fused.frame.timestamp_s) * m_last_fused.T_world_cam;
  m_last_fused.attempted = false;
}

}  // namespace rasm::tracking
