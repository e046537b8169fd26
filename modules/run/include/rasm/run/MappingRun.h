#pragma once
// One `rasm run`: configuration -> frame source -> Mapper -> output folder (DESIGN.md "Outputs of
// a run"). app/cmd_run.cpp is a thin layer over it, and the end-to-end tests drive it directly.
//
// The output folder holds the files of one run (docs/io.md "Runs that never lie"): nothing in it
// changes until the configuration, the source and a map to continue are checked; then the folder
// is claimed (RunFolder.h: a folder holding files rasm did not write is refused unless [output]
// overwrite = true, a folder in use by another run is refused, only the files the earlier run
// listed are removed), config.ini is written, and every file is written under a temporary name
// and renamed when complete (OutputFiles.h). When a frame fails (corrupt rawlog,
// bad depth), the outputs of the frames before it are still written, report.json says "status":
// "failed" with the error, and the error is rethrown (InputError); a source that yields no frame
// is such an error, and then only config.ini and report.json are written. An output file that
// cannot be written (full disk) ends the writing: report.json names it and OutputError is thrown.
// After a SIGINT / SIGTERM (Interrupts.h) the run reads no further frame and writes the outputs
// of the frames done with "status": "interrupted". report.json is written last, always.

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <mrpt/obs/CObservationComment.h>
#include <nlohmann/json.hpp>
#include <opencv2/core/mat.hpp>

#include "rasm/io/FrameSource.h"
#include "rasm/io/OpenNI2FrameSource.h"
#include "rasm/io/RawlogWriter.h"
#include "rasm/io/RealTimeFrameSource.h"
#include "rasm/io/Trajectory.h"
#include "rasm/meshing/SurfelMesh.h"
#include "rasm/navigation/TNavigationParams.h"
#include "rasm/pipeline/Mapper.h"
#include "rasm/pipeline/OutputFiles.h"
#include "rasm/robot/SegwayRmpRobot.h"
#include "rasm/run/FloorPlan.h"
#include "rasm/run/LiveView.h"
#include "rasm/run/RunConfig.h"

namespace rasm::autonomy {
class ExplorationLoop;
class RobotFrameSource;
class SimObjectScore;
}  // namespace rasm::autonomy

namespace rasm::run {

/// [camera]: intrinsics of the sensor when the source does not carry them (TUM-format folders,
/// the simulator). preset: a rasm::CameraIntrinsics::preset name; fx > 0 overrides all values.
struct TCameraParams : mrpt::config::CLoadableOptions {
  std::string preset;
  double fx = 0, fy = 0, cx = 0, cy = 0;
  int width = 0, height = 0;
  std::optional<CameraIntrinsics> intrinsics() const;  ///< nullopt when nothing is set
  void loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s) override;
  void saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const override;
};

/// World-frame error of a run that started at the ground truth's pose (no alignment; report.json
/// world_frame_error): over `frames` pose pairs, metres and degrees.
struct WorldFrameSummary {
  std::size_t frames = 0;
  double rms_m = 0, max_m = 0;  ///< position
  double vertical_max_m = 0;    ///< height (along the world's up)
  double tilt_max_deg = 0;      ///< angle of the camera's up direction (roll and pitch)
  double heading_max_deg = 0;   ///< rotation about the world's up (yaw)
};

struct RunSummary {
  std::string out_dir;
  std::size_t frames = 0, lost = 0;
  std::size_t lost_intervals = 0;  ///< runs of consecutive lost frames
  std::size_t relocalisations = 0;
  double seconds = 0.0, fps = 0.0;
  std::size_t surfels = 0;
  std::optional<double> ate_rmse_m;  ///< over every frame (lost ones at their propagated pose)
  std::optional<double> ate_tracked_rmse_m;  ///< over the tracked frames alone
  /// Without alignment, when the run started at the ground truth's pose: over every frame and
  /// over the tracked ones; `truth` says against what, in words ("the simulator's truth").
  std::optional<WorldFrameSummary> world_error, world_error_tracked;
  std::string truth;
  nlohmann::json report;   ///< what report.json holds
  bool explored = false;   ///< [exploration] enabled: report holds the exploration's fields
  std::string status;      ///< report.json "status": ok, failed or interrupted
  int interrupted_by = 0;  ///< the signal that stopped the run (SIGINT, SIGTERM), 0 = none
};

class MappingRun {
 public:
  /// Loads every section strictly (InputError names the file, section and key).
  explicit MappingRun(const RunConfig& config);
  ~MappingRun();

  /// Sections this build understands: the run's own ([source] [camera] [navigation] [output]
  /// [sim]) and the Mapper's and its stages' (Mapper::sectionNames).
  std::vector<std::string> knownSections() const;

  /// Runs to the end of the source (or [source] max_frames, or a SIGINT / SIGTERM when
  /// installInterruptHandlers() was called) and writes the output folder. Once per MappingRun
  /// (the Mapper and its map are the run's). `on_frame` (optional) sees every result, e.g. for
  /// tests. InputError for bad input (no frame at all included), OutputError when an output
  /// cannot be written; report.json is written before either is thrown.
  RunSummary run(const std::function<void(const pipeline::FrameResult&)>& on_frame = {});

  const pipeline::TSourceParams& sourceParams() const { return m_source; }
  const pipeline::TOutputParams& outputParams() const { return m_output; }
  /// The configured Mapper (its stages' params: mapper().stage<FusionStage>().params()); after
  /// run(), with the map of the run.
  const pipeline::Mapper& mapper() const { return *m_mapper; }

  /// Every key of every section with its effective value (defaults included), as INI text.
  std::string effectiveConfig() const;

  /// Opens the configured frame source.
  std::unique_ptr<io::FrameSource> openSource() const;
  /// Replaces the OpenNI2 camera of [source] type = openni2 by `open()`'s live source (stamped
  /// with UNIX time, paced by itself): a synthetic camera in tests, a camera rasm has no driver
  /// for. Everything after it (the robot, real-time dropping, exploration) is as configured.
  void setLiveCamera(std::function<std::unique_ptr<io::FrameSource>()> open) {
    m_live_camera = std::move(open);
  }

 private:
  struct Accumulated;  // what the frame loop gathers for the outputs
  /// Claims the output folder (OutputFolder::claim; InputError when it cannot be used).
  pipeline::OutputFolder prepareOutputFolder() const;
  void decideExploring(const std::string& src);
  /// The settings that are auto made definite for this source: [robot] odometry_heading
  /// (TRobotParams::resolveHeading: the simulated robot's gyro, else the wheels) and
  /// [classification] detectors / threaded (the simulator's detector on the mapping thread for
  /// the simulator's frames, the DNN detector on a worker thread for every other source).
  void resolveAutoSettings(const io::FrameSource& source);
  /// The opened source with its read-ahead / preload wrapper; `preload_s` = seconds spent
  /// preloading. An exploring run ([exploration] enabled) gets no read-ahead: the source's robot is
  /// driven by the exploration loop created here.
  std::unique_ptr<io::FrameSource> wrapSource(std::unique_ptr<io::FrameSource> source,
                                              double& preload_s);
  /// A live source or a real-time replay: the robot's odometry ([robot] type = segway_rmp, which
  /// connects here) and the real-time offering of frames (docs/hardware.md).
  std::unique_ptr<io::FrameSource> wrapLive(std::unique_ptr<io::FrameSource> source);
  /// [exploration] enabled = true on the Segway: the closed loop on the wall clock (m_loop).
  void startRealExploration(robot::SegwayRmpRobot& robot, const Eigen::Isometry3d& T_base_cam);
  /// report.json "real_time" (frames offered / dropped / processed, rates) and "robot".
  void liveReport(nlohmann::json& rep, std::size_t processed, double seconds) const;
  /// Frames the run expects (progress display), 0 when unknown.
  long long expectedFrames(const io::FrameSource& source) const;
  /// Maps frames until the source or [source] max_frames ends or a signal asks to stop; an
  /// exception of a frame ends the loop and is kept in acc.error.
  void frameLoop(io::FrameSource& source, Accumulated& acc, pipeline::OutputFolder& out,
                 const std::function<void(const pipeline::FrameResult&)>& on_frame);
  void recordFrame(Accumulated& acc, const RgbdFrame& f, const pipeline::FrameResult& r);
  /// frames.csv objects_correct, objects_detectable of the frame just mapped: the exploration
  /// loop's measurement, or m_object_score's every [output] objects_score_period_s; ",," when
  /// none was made at this frame.
  std::string objectsScoreCells(Accumulated& acc, const RgbdFrame& f);
  std::unique_ptr<io::RawlogWriter> openAnnotated(pipeline::OutputFolder& out) const;
  void writeAnnotated(io::RawlogWriter& w, const RgbdFrame& frame, const pipeline::FrameResult& r);
  /// annotated.rawlog's comment: what it holds (first), and at its end the frames lost and why.
  mrpt::obs::CObservationComment annotatedComment(bool closing) const;
  /// The stages' finishRun and the exploration's end; the error of a run without any frame.
  void finishFrames(Accumulated& acc);
  std::string noFrameReason(const Accumulated& acc) const;
  RunSummary summarise(const Accumulated& acc) const;
  /// The class map (IV) of a rendered view (grey where no class rose above 0.5); false when no
  /// class evidence has been fused into the map yet (nothing to show).
  bool classMapView(const maps::RenderedMaps& view, cv::Mat& out) const;
  /// frames.csv, trajectory, ground truth, map files, the stages' files, previews.
  void writeOutputs(const Accumulated& acc, pipeline::OutputFolder& out);
  /// `objects`: objects.json's objects as written (drawn in the scenes).
  void writeMesh(const Accumulated& acc, bool classified, pipeline::OutputFolder& out) const;
  void writeMapFiles(const Accumulated& acc, const std::vector<ObjectBox>& objects,
                     pipeline::OutputFolder& out) const;
  /// plot_trajectory.png and plot_timing.png (RunPlots.h), with [output] preview_png.
  void writePlots(const Accumulated& acc, pipeline::OutputFolder& out) const;
  void writePreviews(const Accumulated& acc, pipeline::OutputFolder& out) const;
  /// floorplan.png / .svg (FloorPlan.h) from the map, the path, `objects` (objects.json's) and
  /// the goals of the exploration.json just written.
  void writeFloorPlan(const Accumulated& acc, const std::vector<ObjectBox>& objects,
                      pipeline::OutputFolder& out) const;
  /// report.json's fields (and the summary's ATE); `source` describes the source.
  nlohmann::json reportJson(const std::string& source, const Accumulated& acc,
                            RunSummary& sum) const;
  void addAte(const Accumulated& acc, nlohmann::json& rep, RunSummary& sum) const;
  /// report.json world_frame_error (and the summary's) when the estimate started at the ground
  /// truth's pose.
  void addWorldFrameError(const Accumulated& acc, const io::Trajectory& groundtruth,
                          nlohmann::json& rep, RunSummary& sum) const;

  RunConfig m_config;
  pipeline::TSourceParams m_source;
  TCameraParams m_camera;
  pipeline::TOutputParams m_output;
  TViewParams m_view;           ///< [view]: the live window (LiveView.h)
  meshing::TMeshParams m_mesh;  ///< [mesh]: mesh.ply (meshing/SurfelMesh.h)
  std::string m_sim_ini;        ///< [sim] section text, handed to the simulator source
  navigation::TNavigationParams m_navigation;  ///< [navigation]: the exploring robot's navigator
  io::TOpenNI2Params m_openni2;                ///< [openni2]: the live camera ([source] openni2)
  robot::TSegwayRmpParams m_segway;            ///< [segway_rmp]: [robot] type = segway_rmp
  bool m_explore_real = false;  ///< [exploration] enabled = true on a real robot (segway_rmp)
  const io::RealTimeFrameSource* m_realtime = nullptr;  ///< in the source chain, when real time
  const autonomy::RobotFrameSource* m_robot_source = nullptr;  ///< in the source chain, segway_rmp
  std::unique_ptr<pipeline::Mapper> m_mapper;
  std::unique_ptr<autonomy::ExplorationLoop> m_loop;  ///< exploring: the closed loop (V, VI)
  /// A simulated source that is not explored: objects correct against its world ([output]
  /// objects_score_period_s). (shared_ptr: an incomplete type without the simulator.)
  std::shared_ptr<autonomy::SimObjectScore> m_object_score;
  bool m_exploring = false;                   ///< [exploration] enabled and the source decide
  std::vector<std::string> m_annotated_lost;  ///< annotated.rawlog: lost frames and why (200)
  std::function<std::unique_ptr<io::FrameSource>()> m_live_camera;  ///< setLiveCamera
};

}  // namespace rasm::run
