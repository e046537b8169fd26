#include "rasm/tracking/LoopCloser.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

#include "rasm/core/Log.h"
#include "rasm/core/SE3.h"

namespace rasm::tracking {

void LoopCloser::configure(const TLoopClosureParams& loop, const TTrackingParams& tracking) {
  m_params = loop;
  m_tracking = tracking;
  m_loop = LoopClosure(loop);
  TTrackingParams icp = tracking;
  icp.min_inlier_fraction *= loop.min_inactive_fraction;
  icp.max_jump_translation_m =
      std::max(icp.max_jump_translation_m, 2.0 * loop.max_correction_m + 0.2);
  // A registration that moves the map must be held by the data in every direction: never a
  // degenerate one. (Raising min_eigenvalue to prior_min_eigenvalue left no registration at all
  // on the world-frame panel: the features confirm instead.)
  icp.degenerate_min_inlier_fraction = 2.0;
  m_tracker = IcpTracker(icp);
}

void LoopCloser::start(const Eigen::Vector3d* up) {
  m_loop.reset();
  if (up) m_loop.setUpAxis(*up);
}

void LoopCloser::frameDone(bool weak) {
  ++m_frames_since_node;
  if (weak) ++m_weak_frames_since_node;
}

LoopCheck LoopCloser::check(const RgbdFrame& frame, const std::vector<FrameLevel>& pyramid,
                            const Eigen::Isometry3d& T_track, int frame_valid_pixels,
                            const maps::CSurfelMap& map, MapPartSource& parts, Relocaliser& reloc) {
  LoopCheck out;
  const double t_now = frame.timestamp_s;
  const double t_inactive = t_now - m_params.inactive_after_s;
  if (m_loop.numNodes() < 2 || t_inactive <= m_loop.firstNodeTime()) return out;
  if (++m_frames_since_check < m_params.check_every_frames) return out;
  m_frames_since_check = 0;
  const int frame_valid = std::max(1, frame_valid_pixels);
  // The inactive map: what an earlier pass made and nothing fused since inactive_after_s.
  maps::RenderOptions filter;
  filter.created_before_s = t_inactive;
  const MapPart inactive = parts.render(T_track, false, filter);
  out.rendered = true;
  if (inactive.valid_pixels < m_params.min_inactive_fraction * frame_valid) return out;
  ++m_checks;
  const double t_old = parts.medianInitTimeOfLastRender();
  const TrackingResult v_in = registerAgainst(pyramid, inactive.model, T_track);
  if (!v_in.ok || v_in.check_overlap < m_tracking.check_min_overlap) {
    out.verdict = std::string("unregistered: ") + (v_in.ok ? "overlap" : toString(v_in.status));
    m_candidate_checks = 0;  // confirmations are consecutive checks
    return out;
  }
  const Eigen::Isometry3d T_inactive =
      moveAlongHeldDirections(v_in, T_track, m_params.min_eigenvalue);
  // The active map: the trajectory's own continuation (the tracked pose when it covers too
  // little of the view to register against).
  filter = maps::RenderOptions();
  filter.created_after_s = t_inactive;
  const MapPart active = parts.render(T_track, false, filter);
  Eigen::Isometry3d T_active = T_track;
  if (active.valid_pixels >= m_params.min_inactive_fraction * frame_valid) {
    const TrackingResult v_act = registerAgainst(pyramid, active.model, T_track);
    if (v_act.ok) T_active = moveAlongHeldDirections(v_act, T_track, m_params.min_eigenvalue);
  }
  confirm(frame, pyramid, parts, T_track, v_in, T_inactive, T_active, t_old, t_inactive, map, reloc,
          out);
  return out;
}

void LoopCloser::confirm(const RgbdFrame& frame, const std::vector<FrameLevel>& pyramid,
                         MapPartSource& parts, const Eigen::Isometry3d& T_track,
                         const TrackingResult& v_in, const Eigen::Isometry3d& T_inactive,
                         const Eigen::Isometry3d& T_active, double t_old, double t_inactive,
                         const maps::CSurfelMap& map, Relocaliser& reloc, LoopCheck& out) {
  const double t_now = frame.timestamp_s;
  const LoopVerdict verdict = m_loop.judge(T_active, T_inactive, t_old, t_now);
  if (verdict.accepted()) logPoses(frame.index, T_track, v_in, T_inactive, T_active, verdict);
  out.verdict = verdict.name();
  out.correction_m = verdict.correction_m;
  out.correction_deg = verdict.correction_deg;
  std::string unconfirmed;
  if (verdict.accepted() && m_params.confirmation == "features" &&
      !featuresConfirm(frame, map, T_inactive, t_inactive, verdict, reloc, unconfirmed)) {
    out.verdict = "unconfirmed: " + unconfirmed;
    m_candidate_checks = 0;
  } else if (verdict.accepted() && m_params.confirmation == "colour" &&
             !colourConfirms(frame, pyramid, parts, T_track, T_inactive, t_inactive, verdict,
                             unconfirmed)) {
    out.verdict = "unconfirmed: " + unconfirmed;
    m_candidate_checks = 0;
  } else if (verdict.accepted()) {
    // Closed when confirmations consecutive checks ask for the same correction.
    const bool same =
        m_candidate && m_candidate_checks > 0 &&
        frame.index <= m_candidate->frame + 2 * std::size_t(m_params.check_every_frames) &&
        m_loop.sameCorrection(m_candidate->verdict, verdict, T_track);
    m_candidate_checks = same ? m_candidate_checks + 1 : 1;
    m_candidate = Candidate{verdict, frame.index};
    if (m_candidate_checks >= m_params.confirmations) {
      m_pending = Pending{verdict, T_active, t_old, t_now};
      m_candidate_checks = 0;
    } else {
      out.verdict = "candidate";
    }
  } else {
    m_candidate_checks = 0;
    if (verdict.kind == LoopVerdict::Kind::Refused) ++m_refused;
  }
}

void LoopCloser::logPoses(std::size_t frame_index, const Eigen::Isometry3d& T_track,
                          const TrackingResult& v_in, const Eigen::Isometry3d& T_inactive,
                          const Eigen::Isometry3d& T_active, const LoopVerdict& verdict) const {
  const auto positionAndAxis = [](const Eigen::Isometry3d& T) {
    const Eigen::Vector3d p = T.translation();
    const Eigen::Vector3d z = T.linear().col(2);  // the optical axis in the world
    char text[96];
    std::snprintf(text, sizeof text, "(%.4f %.4f %.4f; axis %.4f %.4f %.4f)", p.x(), p.y(), p.z(),
                  z.x(), z.y(), z.z());
    return std::string(text);
  };
  log::debug("loop check frame " + std::to_string(frame_index) + ": tracked " +
             positionAndAxis(T_track) + ", against the inactive map " +
             positionAndAxis(v_in.T_world_cam) + " (kept along held directions: " +
             positionAndAxis(T_inactive) + "), against the active map " +
             positionAndAxis(T_active) + ", the loop asks for " + positionAndAxis(verdict.T_loop));
  // Where the registration against the inactive map moved the camera from the tracked pose,
  // along the eigenvectors of its system (translation part; eigenvalue: how well the data hold
  // that direction).
  const Eigen::Vector3d d = v_in.T_world_cam.translation() - T_track.translation();
  std::string along;
  for (int k = 0; k < 6; ++k) {
    char text[96];
    std::snprintf(text, sizeof text, " [lambda %.2e: t %.4f %.4f %.4f, moved %.4f]",
                  v_in.eigenvalues(k), v_in.eigenvectors(0, k), v_in.eigenvectors(1, k),
                  v_in.eigenvectors(2, k), d.dot(v_in.eigenvectors.col(k).head<3>()));
    along += text;
  }
  log::debug("  inactive registration: inliers " + std::to_string(v_in.inliers) + ", rms " +
             std::to_string(v_in.rms_m) + " m," + along);
}

bool LoopCloser::colourConfirms(const RgbdFrame& frame, const std::vector<FrameLevel>& pyramid,
                                MapPartSource& parts, const Eigen::Isometry3d& T_track,
                                const Eigen::Isometry3d& T_inactive, double t_inactive,
                                const LoopVerdict& verdict, std::string& why) {
  if (frame.colour.empty() || m_tracking.photometric_weight_degenerate <= 0) {
    why = "no colour";
    return false;
  }
  // The inactive part rendered again, with its colour: the render check() registered against
  // was replaced by the active part's (a MapPart is valid until the next render).
  maps::RenderOptions filter;
  filter.created_before_s = t_inactive;
  const MapPart inactive = parts.render(T_track, true, filter);
  if (inactive.model.colour.empty()) {
    why = "no colour";
    return false;
  }
  m_tracker.reset(T_track);
  const TrackingResult v = m_tracker.align(pyramid, inactive.model, T_track, frame.colour.cview(),
                                           nullptr, m_tracking.photometric_weight_degenerate);
  if (!v.ok) {
    why = std::string("colour: ") + toString(v.status);
    return false;
  }
  return posesAgree(v.T_world_cam, T_inactive, verdict, "colour", why);
}

bool LoopCloser::posesAgree(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b,
                            const LoopVerdict& verdict, const char* what, std::string& why) const {
  const double d_m = translationDistance(a, b);
  const double d_deg = rotationAngle(a, b) * 180.0 / M_PI;
  if (d_m <= std::max(m_params.feature_agreement_m, 0.3 * verdict.correction_m) &&
      d_deg <= std::max(m_params.feature_agreement_deg, 0.3 * verdict.correction_deg))
    return true;
  char text[112];
  std::snprintf(text, sizeof text, "%s puts the camera %.3f m / %.2f deg away", what, d_m, d_deg);
  why = text;
  return false;
}

bool LoopCloser::featuresConfirm(const RgbdFrame& frame, const maps::CSurfelMap& map,
                                 const Eigen::Isometry3d& T_inactive, double t_inactive,
                                 const LoopVerdict& verdict, Relocaliser& reloc, std::string& why) {
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
  const std::optional<RelocalisationResult> pnp = reloc.relocalise(frame, old);
  if (!pnp) {
    why = "features: " + reloc.lastStats().reason;
    return false;
  }
  return posesAgree(pnp->T_world_cam, T_inactive, verdict, "features", why);
}

TrackingResult LoopCloser::registerAgainst(const std::vector<FrameLevel>& pyramid,
                                           const ModelMaps& model,
                                           const Eigen::Isometry3d& T_track) {
  // No prior: a direction the part of the map does not constrain is reported (Degenerate) and
  // the frame is not registered, rather than held where the drifted estimate put it.
  m_tracker.reset(T_track);
  return m_tracker.align(pyramid, model, T_track);
}

TrajectoryCorrection LoopCloser::closeIfDue(std::size_t frame_index, double t_s,
                                            const Eigen::Isometry3d& T_world_cam,
                                            maps::CSurfelMap& map) {
  const double weak = m_frames_since_node > 0
                          ? double(m_weak_frames_since_node) / double(m_frames_since_node)
                          : 0.0;
  if (!m_pending) {
    if (m_loop.addNode(t_s, T_world_cam, false, weak))
      m_frames_since_node = m_weak_frames_since_node = 0;
    return {};
  }
  m_frames_since_node = m_weak_frames_since_node = 0;
  const Pending p = *m_pending;
  m_pending.reset();
  TrajectoryCorrection c = m_loop.close(p.t_now_s, p.T_active, p.verdict.T_loop, p.t_old_s, weak);
  if (c.empty()) return c;
  ClosedLoop closed;
  closed.frame = frame_index;
  closed.timestamp_s = p.t_now_s;
  closed.old_map_time_s = p.t_old_s;
  closed.correction_m = p.verdict.correction_m;
  closed.correction_deg = p.verdict.correction_deg;
  closed.path_m = p.verdict.path_m;
  closed.surfels_moved = deformSurfels(map.store(), c);
  correctKeyframes(map.keyframes(), c);
  m_closed.push_back(closed);
  return c;
}

}  // namespace rasm::tracking
