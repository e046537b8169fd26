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
// resumes when the camera comes back near it, IcpTracker.h). Each lost frame tries to relocalise
// (tracking/RelocalisationPolicy.h, its policy); a candidate is verified by ICP plus the pose
// check against the map this stage renders there before tracking restarts from it.
//
// Keyframes: fused frames become relocalisation keyframes of the map by the spacing rules of
// [relocalisation] (finishFrame).
//
// Loop closure ([loop_closure], tracking/LoopCloser.h, its policy): fused frames become nodes of
// the trajectory graph; every check_every_frames a tracked frame is registered against the
// inactive and the active map, which this stage renders as it renders its model (process, read
// phase), and a confirmed loop is closed after the frame is fused (finishFrame, under the map
// lock): the graph solved, the surfels and keyframes moved with their time's correction, the
// tracker's pose with the current one. The exploration octree is not moved.

#include <memory>
#include <optional>
#include <vector>

#include "rasm/pipeline/MapperStage.h"
#include "rasm/surfel_map/SurfelRenderer.h"
#include "rasm/tracking/IcpTracker.h"
#include "rasm/tracking/LoopCloser.h"
#include "rasm/tracking/OdometryPrior.h"
#include "rasm/tracking/RelocalisationPolicy.h"

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
  std::size_t loopsClosed() const { return m_loop.closed().size(); }
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
  /// The map (or a part of it) rendered by renderModel for the loop check and the verification
  /// of relocalisation candidates (TrackingStage.cpp).
  class MapParts;
  /// Loop closure, read phase: the frame checked (LoopCloser::check) into result.loop_closure.
  void checkLoop(FrameContext& ctx, const maps::CSurfelMap& map);
  /// Loop closure, write phase (finishFrame of a fused frame): the node, or the confirmed loop
  /// closed (LoopCloser::closeIfDue) and the tracker's poses moved with it.
  void closeLoop(FrameContext& ctx, maps::CSurfelMap& map);
  /// report.json loop_closure.loops: one entry per loop closed.
  nlohmann::json loopLogJson() const;
  /// While lost: RelocalisationPolicy::relocalise; on success the tracker restarts from the
  /// verified pose (the frame becomes Relocalised). With `odometry` (a robot's prior for this
  /// frame) a verified pose more than [tracking] max_odometry_sigmas from it is refused.
  void relocalise(FrameContext& ctx, const maps::CSurfelMap& map,
                  const tracking::MotionPrior* odometry = nullptr);
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
  tracking::RelocalisationPolicy m_relocaliser;
  tracking::LoopCloser m_loop;
  std::vector<double> m_loop_close_ms;  ///< per loop closed: the time its correction took
  maps::SurfelRenderer m_renderer;
  maps::RenderedMaps m_model;
  bool m_localise_in_map = false;
  /// Timestamp of the first frame of the current lost stretch (none while tracked).
  std::optional<double> m_lost_since_s;
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
