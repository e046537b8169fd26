#pragma once
// II-C: the camera pose of the frame by coarse-to-fine ICP against the map rendered at the
// previous pose (reliable surfels), with the wheel odometry as a prior when the source has it;
// relocalisation against the map's keyframes while lost. Sections [tracking],
// [robot] (camera mount, odometry noise) and [relocalisation].
//
// Motion prior: a frame with odometry (RgbdFrame::odometry_xyyaw) is tracked from the odometry's
// prediction through the camera mount, and ICP weighs the data against it (OdometryPrior.h);
// without odometry the tracker's motion model gives the guess.
//
// Lost track: a frame whose TrackingResult is not ok is not fused. It still gets a pose, flagged
// by FrameResult::pose_source: the odometry's prediction when there is one (the model is then
// rendered from that propagated pose, so tracking resumes as soon as the view agrees again), the
// motion model's guess otherwise (the model stays rendered from the last good pose, so tracking
// resumes when the camera comes back near it, IcpTracker.h). Each lost frame tries to relocalise;
// a candidate is verified by ICP plus the pose check before tracking restarts from it.
//
// Keyframes: fused frames become relocalisation keyframes of the map by the spacing rules of
// [relocalisation] (finishFrame).
//
// Loop closure ([loop_closure], LoopClosure.h): fused frames become nodes of the trajectory graph;
// every check_every_frames a tracked frame is registered against the inactive and the active map
// (process, read phase) and an accepted loop is closed after the frame is fused (finishFrame,
// under the map lock): the graph solved, the surfels and keyframes moved with their time's
// correction, the tracker's pose with the current one. The exploration octree is not moved.

#include <memory>
#include <optional>
#include <vector>

#include "rasm/pipeline/MapperStage.h"
#include "rasm/surfel_map/SurfelRenderer.h"
#include "rasm/tracking/IcpTracker.h"
#include "rasm/tracking/LoopClosure.h"
#include "rasm/tracking/OdometryPrior.h"
#include "rasm/tracking/Relocaliser.h"

namespace rasm::pipeline {

class TrackingStage : public MapperStage {
 public:
  enum Part { kRenderModel = 0, kIcp, kRelocalise, kLoopClosure };
  TrackingStage();
  ~TrackingStage() override;

  std::vector<ParamsSection> sections() override;
  void configure(const TMapperParams& mapper) override;
  void process(FrameContext& ctx, maps::CSurfelMap& map) override;
  void finishFrame(FrameContext& ctx, maps::CSurfelMap& map) override;
  void csvColumns(std::vector<std::string>& columns) const override;
  void csvValues(const FrameContext& ctx, CsvRow& row) const override;
  void report(nlohmann::json& rep) const override;

  /// The map was loaded from a file: the first pose comes from relocalisation in it.
  void localiseInLoadedMap() { m_localise_in_map = true; }

  const tracking::TTrackingParams& params() const { return m_tracking; }
  const tracking::TRobotParams& robotParams() const { return m_robot; }
  /// [robot] odometry_heading = auto made definite before the first frame
  /// (TRobotParams::resolveHeading): whether the frames' odometry heading is a gyro's.
  void resolveOdometryHeading(bool odometry_from_gyro);
  const tracking::TRelocalisationParams& relocalisationParams() const { return m_relocalisation; }
  const tracking::IcpTracker& tracker() const { return m_tracker; }
  std::size_t relocalisations() const { return m_relocalisations; }
  /// Loops closed so far (report.json loop_closure).
  std::size_t loopsClosed() const { return m_loop_log.size(); }
  /// Pose of the last frame processed (tracked or propagated while lost).
  const Eigen::Isometry3d& lastFramePose() const { return m_T_prev_frame; }

 private:
  void initialise(FrameContext& ctx);
  void track(FrameContext& ctx, const maps::CSurfelMap& map);
  /// The tracking model: the map rendered at T_model (reliable surfels, all of them while too
  /// few, or with `all_surfels`), as the tracker sees it (valid until the next render); with
  /// its colour when the tracker's photometric term needs it.
  /// `time_filter` (optional): only the active (inactive_before_s NaN, time_window_s finite) or
  /// the inactive part of the map (loop closure).
  tracking::ModelMaps renderModel(FrameContext& ctx, const maps::CSurfelMap& map,
                                  const Eigen::Isometry3d& T_model, bool with_colour,
                                  FrameResult& r, bool all_surfels = false,
                                  const maps::RenderOptions* time_filter = nullptr);
  /// Loop closure, read phase: the frame registered against the inactive and the active map,
  /// judged; an accepted loop waits in m_pending_loop for closeLoop().
  void checkLoop(FrameContext& ctx, const maps::CSurfelMap& map);
  /// Loop closure, write phase (finishFrame of a fused frame): the node, or the pending loop
  /// closed and the map, keyframes and tracker moved.
  void closeLoop(FrameContext& ctx, maps::CSurfelMap& map);
  /// Median creation time (absolute s) of the surfels the last render drew (m_model.index).
  double medianInitTime(const maps::SurfelStore& store) const;
  /// Whether the frame's features against the keyframes made before t_inactive (PnP) put the
  /// camera where the registration against the inactive map did ([loop_closure]
  /// feature_agreement_*); `why` says why not.
  bool featuresConfirm(FrameContext& ctx, const maps::CSurfelMap& map,
                       const Eigen::Isometry3d& T_inactive, double t_inactive,
                       const tracking::LoopVerdict& verdict, std::string& why);
  /// Whether the registration against the inactive map with its colour (joint ICP + RGB)
  /// agrees with the geometric one, T_inactive.
  bool colourConfirms(FrameContext& ctx, const tracking::ModelMaps& inactive,
                      const Eigen::Isometry3d& T_track, const Eigen::Isometry3d& T_inactive,
                      const tracking::LoopVerdict& verdict, std::string& why);
  /// Within feature_agreement_* or 30% of the verdict's correction; `why` names `what` if not.
  bool posesAgree(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b,
                  const tracking::LoopVerdict& verdict, const char* what, std::string& why) const;
  /// The frame against a part of the map from T_track, without a prior.
  tracking::TrackingResult registerForLoop(FrameContext& ctx, const tracking::ModelMaps& model,
                                           const Eigen::Isometry3d& T_track);
  /// While lost: the pose from the last fused frame ([relocalisation] use_last_fused_frame),
  /// then from the map's keyframes, each candidate verified by ICP against the map rendered
  /// there; on success the tracker restarts from it (the frame becomes Relocalised).
  void relocalise(FrameContext& ctx, const maps::CSurfelMap& map);
  /// One keyframe database tried: true when its candidate passed the ICP verification.
  bool relocaliseAgainst(FrameContext& ctx, const maps::CSurfelMap& map,
                         const std::vector<maps::Keyframe>& db, tracking::Relocaliser& reloc);
  /// The last fused frame as a one-keyframe database (its features detected on first use);
  /// empty when there is none or it has too few features.
  const std::vector<maps::Keyframe>& lastFusedKeyframe();
  /// floor_height_m / floor_tilt_deg of a tracked robot frame, counted when beyond [robot]
  /// floor_max_* and kept for floorDriftJson.
  void reportFloorDeviation(FrameResult& r);
  /// report.json floor_drift: the statistics of the tracked frames' floor deviation and whether
  /// they cross [robot] floor_target_*.
  nlohmann::json floorDriftJson() const;

  tracking::TTrackingParams m_tracking;
  tracking::TRobotParams m_robot;
  tracking::TRelocalisationParams m_relocalisation;
  tracking::TLoopClosureParams m_loop_params;
  TMapperParams m_mapper;
  tracking::IcpTracker m_tracker;
  tracking::OdometryPrior m_odometry;
  tracking::Relocaliser m_reloc;
  tracking::Relocaliser m_reloc_last_fused;  ///< with [relocalisation] last_fused_* acceptance
  tracking::LoopClosure m_loop;
  /// Registers frames against the inactive / active map: [tracking] with the inlier fraction
  /// scaled by min_inactive_fraction (the model covers part of the view) and the jump bound
  /// raised to the loop's (judge() bounds the correction).
  tracking::IcpTracker m_loop_tracker;
  int m_frames_since_loop_check = 0;
  /// Frames since the last graph node, and those of them not tracked Ok (degenerate or lost).
  int m_frames_since_node = 0, m_weak_frames_since_node = 0;
  struct PendingLoop {
    tracking::LoopVerdict verdict;
    Eigen::Isometry3d T_active;
    double t_old_s = 0, t_now_s = 0;
  };
  std::optional<PendingLoop> m_pending_loop;
  struct LoopCandidate {
    tracking::LoopVerdict verdict;
    std::size_t frame = 0;
  };
  std::optional<LoopCandidate> m_loop_candidate;  ///< the last accepted check
  int m_loop_candidate_checks = 0;                ///< consecutive checks that agree with it
  std::size_t m_loops_refused = 0, m_loop_checks = 0;
  nlohmann::json m_loop_log = nlohmann::json::array();  ///< one entry per loop closed
  maps::SurfelRenderer m_renderer;
  maps::RenderedMaps m_model;
  bool m_localise_in_map = false;
  /// Timestamp of the first frame of the current lost stretch (none while tracked).
  std::optional<double> m_lost_since_s;
  /// The last fused frame (depth, colour, intrinsics, index) and its pose: ORB-SLAM's reference
  /// keyframe, made into `keyframe` only when a lost frame needs it.
  struct LastFused {
    RgbdFrame frame;
    Eigen::Isometry3d T_world_cam = Eigen::Isometry3d::Identity();
    bool valid = false, attempted = false;
    std::vector<maps::Keyframe> keyframe;  ///< 0 or 1
  } m_last_fused;
  Eigen::Isometry3d m_T_prev_frame = Eigen::Isometry3d::Identity();
  std::size_t m_relocalisations = 0;
  std::size_t m_frames_off_floor = 0;  ///< see report()
  /// Frames before the map started: too little valid depth to start it (initialise()).
  std::size_t m_frames_before_map = 0;
  /// Per tracked frame with odometry: |camera height - mount height| over the first frame's
  /// floor (m) and the camera's tilt from the mount's (deg); report.json floor_drift.
  std::vector<double> m_floor_height_abs_m, m_floor_tilt_deg;
};

}  // namespace rasm::pipeline
