#include "rasm/run/MappingRun.h"

#include <mrpt/img/TCamera.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/obs/CObservationComment.h>
#include <mrpt/obs/CObservationImage.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/opengl/COpenGLScene.h>
#include <mrpt/serialization/CArchive.h>

#include <unistd.h>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>

#include <optional>
#include "rasm/autonomy/ExplorationLoop.h"
#include "rasm/autonomy/RobotFrameSource.h"
#include "rasm/autonomy/SimObjectScore.h"
#include "rasm/autonomy/SimSource.h"
#include "rasm/core/Error.h"
#include "rasm/core/Log.h"
#include "rasm/core/Params.h"
#include "rasm/core/Printable.h"
#include "rasm/core/SE3.h"
#include "rasm/core/Timing.h"
#include "rasm/io/EvaluationJson.h"
#include "rasm/io/GroundTruthFrameSource.h"
#include "rasm/io/PrefetchingFrameSource.h"
#include "rasm/io/PreloadedFrameSource.h"
#include "rasm/io/RawlogFrameSource.h"
#include "rasm/io/RawlogWriter.h"
#include "rasm/io/RgbdObservation.h"
#include "rasm/io/TrajectoryEvaluator.h"
#include "rasm/pipeline/BuildInfo.h"
#include "rasm/pipeline/Interrupts.h"
#include "rasm/pipeline/stages/ClassificationStage.h"
#include "rasm/pipeline/stages/ExplorationStage.h"
#include "rasm/pipeline/stages/TrackingStage.h"
#include "rasm/run/FloorPlan.h"
#include "rasm/run/OutputsDoc.h"
#include "rasm/run/Progress.h"
#include "rasm/run/RunPlots.h"
#include "rasm/run/RunScene.h"
#include "rasm/surfel_map/MapExport.h"
#ifdef RASM_HAVE_SIM
#include "rasm/sim/SimFrameSource.h"
#endif

namespace fs = std::filesystem;

namespace rasm::run {

using namespace rasm::pipeline;
using namespace rasm::autonomy;

// ---------------------------------------------------------------------------------------------
std::optional<CameraIntrinsics> TCameraParams::intrinsics() const {
  if (fx > 0) {
    CameraIntrinsics k(fx, fy > 0 ? fy : fx, cx, cy, width, height);
    if (!preset.empty()) {
      const CameraIntrinsics p = CameraIntrinsics::preset(preset);
      if (width <= 0) k.width = p.width;
      if (height <= 0) k.height = p.height;
    }
    if (k.width <= 0 || k.height <= 0)
      throwInputError("[camera]", "fx given without width/height or preset");
    return k;
  }
  if (!preset.empty()) return CameraIntrinsics::preset(preset);
  return std::nullopt;
}

void TCameraParams::loadFromConfigFile(const mrpt::config::CConfigFileBase& c,
                                       const std::string& s) {
  MRPT_LOAD_CONFIG_VAR(preset, string, c, s);
  MRPT_LOAD_CONFIG_VAR(fx, double, c, s);
  MRPT_LOAD_CONFIG_VAR(fy, double, c, s);
  MRPT_LOAD_CONFIG_VAR(cx, double, c, s);
  MRPT_LOAD_CONFIG_VAR(cy, double, c, s);
  MRPT_LOAD_CONFIG_VAR(width, int, c, s);
  MRPT_LOAD_CONFIG_VAR(height, int, c, s);
  if (!preset.empty()) (void)CameraIntrinsics::preset(preset);  // validates the name
}

void TCameraParams::saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const {
  MRPT_SAVE_CONFIG_VAR(preset, c, s);
  MRPT_SAVE_CONFIG_VAR(fx, c, s);
  MRPT_SAVE_CONFIG_VAR(fy, c, s);
  MRPT_SAVE_CONFIG_VAR(cx, c, s);
  MRPT_SAVE_CONFIG_VAR(cy, c, s);
  MRPT_SAVE_CONFIG_VAR(width, c, s);
  MRPT_SAVE_CONFIG_VAR(height, c, s);
}

// ---------------------------------------------------------------------------------------------
std::vector<std::string> MappingRun::knownSections() const {
  std::vector<std::string> known = {"source", "camera"};
  for (const std::string& s : m_mapper->sectionNames()) known.push_back(s);
  known.insert(known.end(),
               {"navigation", "output", "view", "mesh", "sim", "openni2", "segway_rmp"});
  return known;
}

MappingRun::MappingRun(const RunConfig& config) : m_config(config) {
  const auto& ini = m_config.ini();
  const std::string& src = m_config.source();
  // The Mapper loads its own sections and its stages' (strictly); unknown sections are checked
  // against the list it derives.
  m_mapper = std::make_unique<Mapper>(ini, src);
  m_config.checkSections(knownSections());
  loadParamsStrict(ini, "source", m_source, src);
  loadParamsStrict(ini, "camera", m_camera, src);
  loadParamsStrict(ini, "output", m_output, src);
  loadParamsStrict(ini, "view", m_view, src);
  loadParamsStrict(ini, "mesh", m_mesh, src);
  if (m_view.enabled) LiveView::requireDisplay();
  loadParamsStrict(ini, "navigation", m_navigation, src);
  loadParamsStrict(ini, "openni2", m_openni2, src);
  loadParamsStrict(ini, "segway_rmp", m_segway, src);
  (void)m_camera.intrinsics();  // validates
  // [sim] belongs to the simulator; it is parsed strictly when the sim source is opened.
  std::vector<std::string> keys;
  ini.getAllKeys("sim", keys);
  m_sim_ini = "[sim]\n";
  for (const auto& k : keys) m_sim_ini += k + " = " + ini.read_string("sim", k, "") + "\n";
  decideExploring(src);
}

/// [exploration] enabled: true (a robot the run can drive, or an InputError), false, or auto
/// (explore a simulated robot spec, map anything else). [robot] type must fit the source.
void MappingRun::decideExploring(const std::string& src) {
  const std::string& mode = m_mapper->stage<ExplorationStage>().loopParams().enabled;
  const std::string& robot = m_mapper->stage<TrackingStage>().robotParams().type;
#ifndef RASM_HAVE_SIM
  if (m_source.type == "sim")
    throwInputError(src + " [source] type = sim",
                    "this rasm was built without the simulator (-DRASM_WITH_SIM=OFF): give a real "
                    "source, e.g. rasm run FOLDER");
#endif
  if (robot == "sim" && m_source.type != "sim")
    throwInputError(src + " [robot] type = sim",
                    "needs [source] type = sim (got " + m_source.type + ")");
  if (robot == "segway_rmp" && m_source.type != "openni2")
    throwInputError(
        src + " [robot] type = segway_rmp",
        "needs a live camera on the robot: [source] type = openni2 (got " + m_source.type + ")");
  m_explore_real = mode == "true" && robot == "segway_rmp";
  if (mode == "true" && !m_explore_real && (m_source.type != "sim" || robot == "none"))
    throwInputError(src + " [exploration] enabled = true",
                    "needs a robot the run can drive: [source] type = sim with a robot "
                    "trajectory spec, or [robot] type = segway_rmp (got [source] type = " +
                        m_source.type + ", [robot] type = " + robot + ")");
  m_exploring = !m_explore_real && robot != "none" &&
                (mode == "true" || (mode == "auto" && m_source.type == "sim" &&
                                    simTrajectoryIsRobot(m_sim_ini, src)));
  // The octree (V-A) for either loop: the simulated robot's or the real one's (wrapLive).
  m_mapper->stage<ExplorationStage>().setExploring(m_exploring || m_explore_real);
}

MappingRun::~MappingRun() = default;

std::string MappingRun::effectiveConfig() const {
  mrpt::config::CConfigFileMemory mem;
  m_source.saveToConfigFile(mem, "source");
  m_camera.saveToConfigFile(mem, "camera");
  m_mapper->saveParams(mem);
  m_navigation.saveToConfigFile(mem, "navigation");
  m_openni2.saveToConfigFile(mem, "openni2");
  m_segway.saveToConfigFile(mem, "segway_rmp");
  m_output.saveToConfigFile(mem, "output");
  m_view.saveToConfigFile(mem, "view");
  m_mesh.saveToConfigFile(mem, "mesh");
  std::string text;
  mem.getContent(text);
  return "; effective configuration of a rasm run (every key, defaults included), from " +
         m_config.source() + "\n" + text + "\n" + m_sim_ini;
}

std::unique_ptr<io::FrameSource> MappingRun::openSource() const {
  if (m_source.type == "sim")
    return openSimSource(m_sim_ini, m_config.source(), m_camera.intrinsics(), m_exploring,
                         m_mapper->stage<ExplorationStage>().loopParams().camera_rate_hz);
  if (m_source.type == "openni2" && m_live_camera) return m_live_camera();
  if (m_source.type == "openni2")  // opens at its first frame (a missing camera: report.json)
    return std::make_unique<io::OpenNI2FrameSource>(m_openni2, m_camera.intrinsics());
  io::FrameSourceOptions opt;
  opt.intrinsics_override = m_camera.intrinsics();
  if (!fs::exists(m_source.path))
    throwInputError("[source] path '" + m_source.path + "'",
                    "does not exist (expected a rawlog file or a dataset folder)");
  const bool is_dir = fs::is_directory(m_source.path);
  if (m_source.type == "rawlog" && is_dir)
    throwInputError("[source] path '" + m_source.path + "'",
                    "is a folder, expected a .rawlog file for type = rawlog");
  if ((m_source.type == "tum" || m_source.type == "7scenes") && !is_dir)
    throwInputError("[source] path '" + m_source.path + "'",
                    "is a file, expected a dataset folder for type = " + m_source.type);
  std::unique_ptr<io::FrameSource> source = io::openFrameSource(m_source.path, opt);
  if (m_source.groundtruth.empty()) return source;
  // Frames without a pose of their own take the file's (a replayed run's annotated.rawlog with
  // its groundtruth.txt): the map starts at the true pose, the world-frame error is reported.
  io::Trajectory groundtruth;
  try {
    groundtruth = io::readTumTrajectory(m_source.groundtruth);
  } catch (const std::exception& e) {
    throwInputError("[source] groundtruth '" + m_source.groundtruth + "'", e.what());
  }
  return std::make_unique<io::GroundTruthFrameSource>(std::move(source), std::move(groundtruth));
}

namespace {
/// Whether any alive surfel's best class is above the 0.5 prior (the class scenes and mesh).
bool anySurfelClassified(const maps::SurfelArrays& a) {
  for (int i = 0; i < a.size && a.n_classes > 0; ++i)
    if (a.alive(i) && maps::bestClass(a, i).id != 0) return true;
  return false;
}

/// CPU time of this process, all threads (s).
double processCpuSeconds() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

/// Peak resident set size of this process (VmHWM), MB; 0 when unknown.
double peakRssMb() {
  std::ifstream f("/proc/self/status");
  std::string line;
  while (std::getline(f, line))
    if (line.rfind("VmHWM:", 0) == 0) return std::atof(line.c_str() + 6) / 1024.0;
  return 0.0;
}

/// Resident set size of this process now (/proc/self/statm), MB; 0 when unknown. Read once per
/// frame for frames.csv rss_mb (a few microseconds): the memory curve of long runs.
double currentRssMb() {
  std::ifstream f("/proc/self/statm");
  unsigned long long size_pages = 0, resident_pages = 0;
  if (!(f >> size_pages >> resident_pages)) return 0.0;
  return double(resident_pages) * double(sysconf(_SC_PAGESIZE)) / (1024.0 * 1024.0);
}

/// Runs of consecutive lost frames (honest loss reporting).
struct LossIntervals {
  std::size_t intervals = 0, longest = 0, current = 0;
  void add(bool tracked) {
    if (tracked) {
      current = 0;
      return;
    }
    if (current++ == 0) ++intervals;
    longest = std::max(longest, current);
  }
};

/// Now as ISO 8601 UTC, "2025-01-31T14:05:09Z" (report.json started_utc / finished_utc).
std::string utcNow() {
  const std::time_t t = std::time(nullptr);
  std::tm tm{};
  gmtime_r(&t, &tm);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return buf;
}

nlohmann::json poseJson(const Eigen::Isometry3d& T) {
  const Eigen::Quaterniond q(T.linear());
  return {{"t", {T.translation().x(), T.translation().y(), T.translation().z()}},
          {"q_xyzw", {q.x(), q.y(), q.z(), q.w()}}};
}

/// Why a run that mapped frames gave no usable map, or "": an empty map (no frame had valid
/// depth for II-B to fuse: all zero, below the minimum depth, a wrong depth scale or focal
/// length) or every frame lost by tracking (against a loaded map of another scene).
std::string nothingFusedReason(std::size_t processed, std::size_t lost, int surfels,
                               const std::string& load_map) {
  const std::string n = std::to_string(processed);
  if (surfels == 0)
    return "nothing was fused: the map is empty after " + n + " frames (tracking lost " +
           std::to_string(lost) +
           "); check that the depth images hold valid depth within [mapper] min_depth_m / "
           "max_depth_m, at the right scale (a rawlog's rangeUnits; TUM: 5000 per metre), and "
           "the camera intrinsics (report.json \"intrinsics\")";
  if (lost >= processed)
    return "tracking lost all " + n + " frames: nothing was fused" +
           (load_map.empty() ? std::string()
                             : " into the map loaded from " + load_map +
                                   " ([mapper] load_map); is it a map of this scene?");
  return "";
}
}  // namespace

bool MappingRun::classMapView(const maps::RenderedMaps& view, cv::Mat& out) const {
  // The class map of IV (the paper's Fig. 5 bottom): each pixel's surfel in its best class's
  // colour, faded to grey as the class's probability falls to the 0.5 prior; black = no surfel.
  const maps::SurfelArrays a = m_mapper->map().store().arrays();
  out = cv::Mat(view.colour.height(), view.colour.width(), CV_8UC3, cv::Scalar(0, 0, 0));
  if (a.n_classes == 0 || !m_mapper->stage<ClassificationStage>().fusedAnyEvidence()) return false;
  for (int y = 0; y < out.rows; ++y)
    for (int x = 0; x < out.cols; ++x) {
      const int i = view.index(x, y);
      if (i < 0 || i >= a.size) continue;
      const Bgr8 c = maps::classColour(maps::bestClass(a, i));
      out.at<cv::Vec3b>(y, x) = cv::Vec3b(c.b, c.g, c.r);
    }
  return true;
}

void MappingRun::writeAnnotated(io::RawlogWriter& w, const RgbdFrame& frame, const FrameResult& r) {
  // MRPT's robot convention, which RawLogViewer draws a path from ("Maps & Paths", its travelled
  // distance): the estimated robot base on the floor (T_world_cam T_base_cam^-1: x, y, yaw) as a
  // CObservationOdometry before the frame, labelled with the tracking status, and the camera's
  // pose on that base as the scan's sensorPose; odometry + sensorPose = the estimated T_world_cam.
  const Eigen::Isometry3d T_base =
      r.T_world_cam * m_mapper->stage<TrackingStage>().robotParams().T_base_cam().inverse();
  const Eigen::Matrix3d R = T_base.linear();
  const mrpt::poses::CPose2D base(T_base.translation().x(), T_base.translation().y(),
                                  std::atan2(R(1, 0), R(0, 0)));
  mrpt::obs::CObservationOdometry odo;
  odo.sensorLabel = !r.tracked                                 ? "POSE_LOST"
                    : r.pose_source == PoseSource::Relocalised ? "POSE_RELOCALISED"
                                                               : "POSE_TRACKED";
  odo.timestamp = mrpt::Clock::fromDouble(frame.timestamp_s);
  odo.odometry = base;
  if (!r.tracked && m_annotated_lost.size() < 200)  // why: in the closing comment
    m_annotated_lost.push_back("frame " + std::to_string(r.index) + ": " +
                               tracking::toString(r.tracking.status) + ", pose from " +
                               toString(r.pose_source));
  w.writeObject(odo);
  mrpt::obs::CObservation3DRangeScan obs;
  io::FrameToObservationOptions fo;
  fo.sensor_pose_from_ground_truth = false;
  io::observationFromFrame(frame, obs, fo);
  obs.sensorPose = mrptSensorPoseFromOptical(r.T_world_cam) - mrpt::poses::CPose3D(base);
  w.writeObject(obs);
  maps::RenderedMaps view;
  m_mapper->renderView(r.T_world_cam, frame.intrinsics, view);
  const cv::Mat img(view.colour.height(), view.colour.width(), CV_8UC3, view.colour.data(),
                    view.colour.pitchBytes());
  mrpt::obs::CObservationImage im;
  im.sensorLabel = "MAP_VIEW";
  im.timestamp = obs.timestamp;
  im.cameraPose = obs.sensorPose;
  frame.intrinsics.toTCamera(im.cameraParams);
  im.image = mrpt::img::CImage(img, mrpt::img::DEEP_COPY);
  w.writeObject(im);
  cv::Mat classes;
  if (classMapView(view, classes)) {  // the class map (IV) once the map carries classes
    im.sensorLabel = "CLASS_VIEW";
    im.image = mrpt::img::CImage(classes, mrpt::img::DEEP_COPY);
    w.writeObject(im);
  }
}

/// What the frame loop gathers for the outputs.
struct MappingRun::Accumulated {
  io::Trajectory estimate, estimate_tracked, groundtruth;
  LossIntervals loss;
  std::vector<double> ms_sum, ms_max;  ///< per Mapper timer
  std::string frames_csv;              ///< frames.csv: one row per processed frame
  std::string error;         ///< what ended the run early (bad input), empty = the source ended
  std::string output_error;  ///< an output file that could not be written (full disk, ...)
  long long read = 0;        ///< frames the source yielded (before start / step / drop)
  std::size_t processed = 0;
  int interrupted_by = 0;  ///< the stopping signal, 0 = none
  bool interrupted_in_frames = false;
  CameraIntrinsics last_K;
  bool have_K = false;
  std::chrono::steady_clock::time_point t_start;
  std::string started_utc = utcNow();  ///< report.json started_utc
  double cpu_start_s = 0.0, preload_s = 0.0;
  double cpu_s = 0.0;                      ///< CPU seconds of the frame loop
  double objects_scored_t = std::nan("");  ///< timestamp of the last m_object_score measurement
  bool last_row_scored = false;            ///< frames.csv's last row has objects_correct
  /// m_object_score's measurement after finishRun: (correct, detectable).
  std::optional<std::pair<std::size_t, std::size_t>> final_objects;
};

OutputFolder MappingRun::prepareOutputFolder() const {
  // One run per folder: the files the earlier run listed go before this one writes any; files
  // rasm did not write are never removed (RunFolder.h).
  std::vector<std::string> removed;
  OutputFolder out =
      OutputFolder::claim(m_output.dir, overwritePolicy(m_output.overwrite), removed);
  if (!removed.empty())
    log::info("rasm run: removed the " + std::to_string(removed.size()) +
              " files the earlier run listed in " + m_output.dir + "/" + kRunMarkerName);
  if (!m_output.write_ply) out.leaveOut({"map.ply", "map_segments.ply", "map_classes.ply"});
  out.announce("report.json");  // an aborting signal may write it from here on
  setAbortReport(out.path("report.json"));
  setFramesDone(0);
  return out;
}

void MappingRun::resolveAutoSettings(const io::FrameSource& source) {
  bool simulated = false;
  bool gyro = false;  // a rawlog, a dataset or a live robot: the wheels' heading
#ifdef RASM_HAVE_SIM
  if (const auto* sim_source = dynamic_cast<const sim::SimFrameSource*>(&source)) {
    simulated = true;
    gyro = sim_source->sequence().robot() &&
           sim_source->sequence().robot()->params().odometry_heading == "gyro";
  }
#else
  (void)source;
#endif
  m_mapper->stage<TrackingStage>().resolveOdometryHeading(gyro);
  m_mapper->stage<ClassificationStage>().resolveAuto(simulated);
}

std::unique_ptr<io::FrameSource> MappingRun::wrapSource(std::unique_ptr<io::FrameSource> source,
                                                        double& preload_s) {
#ifdef RASM_HAVE_SIM
  // The simulated detector's occlusion test casts rays into the scene the frames come from.
  if (const auto* sim_source = dynamic_cast<const sim::SimFrameSource*>(source.get())) {
    m_mapper->stage<ClassificationStage>().setSimScene(&sim_source->sequence().scene());
    if (!m_exploring && m_output.objects_score_period_s > 0)  // (the loop measures its own)
      m_object_score = std::make_shared<SimObjectScore>(sim_source->sequence().scene());
  }
#endif
  preload_s = 0.0;
#ifdef RASM_HAVE_SIM
  // Exploring: the run drives the robot, so each frame must be rendered after the commands the
  // previous one led to (no read-ahead).
  if (m_exploring) {
    auto* sim_source = dynamic_cast<sim::SimFrameSource*>(source.get());
    m_loop = std::make_unique<ExplorationLoop>(*m_mapper, sim_source->sequence(), m_navigation);
    return source;
  }
#endif
  if (m_source.type == "openni2" || m_source.real_time) return wrapLive(std::move(source));
  if (m_source.preload) {
    const auto t0 = std::chrono::steady_clock::now();
    long long limit = 0;
    if (m_source.max_frames > 0)
      limit = m_source.start_frame + (long long)m_source.max_frames * m_source.frame_step;
    Progress reading("frames read", limit > 0 ? limit : source->sizeHint());
    source = std::make_unique<io::PreloadedFrameSource>(
        std::move(source), limit, [&](long long n) { reading.update(n); },
        std::size_t(m_source.preload_max_mib) << 20);
    reading.finish(source->sizeHint(), "in memory");
    preload_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  } else if (m_source.prefetch_frames > 0) {
    source =
        std::make_unique<io::PrefetchingFrameSource>(std::move(source), m_source.prefetch_frames);
  }
  return source;
}

std::unique_ptr<io::FrameSource> MappingRun::wrapLive(std::unique_ptr<io::FrameSource> source) {
  if (m_mapper->stage<TrackingStage>().robotParams().type == "segway_rmp") {
    const Eigen::Isometry3d T_base_cam =
        m_mapper->stage<TrackingStage>().robotParams().T_base_cam();
    auto robot = std::make_unique<robot::SegwayRmpRobot>(m_segway, T_base_cam);
    auto on_robot = std::make_unique<RobotFrameSource>(std::move(source), std::move(robot));
    m_robot_source = on_robot.get();
    if (m_explore_real) startRealExploration(on_robot->robot(), T_base_cam);
    source = std::move(on_robot);
  }
  // A camera paces itself (pace = false); a replay is paced by its timestamps.
  auto rt =
      std::make_unique<io::RealTimeFrameSource>(std::move(source), m_source.type != "openni2");
  m_realtime = rt.get();
  return rt;
}

/// [exploration] enabled = true on the Segway (VI): the navigator steps in a thread of its own at
/// [navigation] period_s of wall time and senses obstacles in the camera's depth (the RMP has no
/// laser); the planner runs on map snapshots ([exploration] planner_thread); the workspace is
/// [exploration] workspace_*; no ground truth.
void MappingRun::startRealExploration(robot::SegwayRmpRobot& robot,
                                      const Eigen::Isometry3d& T_base_cam) {
  auto driver = std::make_unique<WallClockRobotDriver>(robot, m_navigation.period_s);
  driver->enableDepthScan(T_base_cam, m_segway.depthScanParams());
  m_loop = std::make_unique<ExplorationLoop>(*m_mapper, std::move(driver),
                                             m_segway.footprintPolygon(), m_navigation);
}

/// Ranges "a-b,c" of sorted indices.
static std::string indexRanges(const std::vector<long long>& v) {
  std::string out;
  for (std::size_t i = 0; i < v.size();) {
    std::size_t j = i;
    while (j + 1 < v.size() && v[j + 1] == v[j] + 1) ++j;
    out += (out.empty() ? "" : ",") + std::to_string(v[i]) +
           (j > i ? "-" + std::to_string(v[j]) : std::string());
    i = j + 1;
  }
  return out;
}

void MappingRun::liveReport(nlohmann::json& rep, std::size_t processed, double seconds) const {
  if (m_realtime) {
    const io::RealTimeStats s = m_realtime->stats();
    nlohmann::json rt;
    rt["paced_by"] = m_source.type == "openni2" ? "camera" : "timestamps";
    rt["frames_offered"] = s.offered;
    rt["frames_dropped"] = s.dropped;
    rt["frames_processed"] = processed;
    rt["offered_fps"] = s.offered_span_s > 0 ? double(s.offered - 1) / s.offered_span_s : 0.0;
    rt["processed_fps"] = seconds > 0 ? double(processed) / seconds : 0.0;
    rt["dropped_frames"] = indexRanges(s.dropped_indices);  // RgbdFrame::index (frames.csv)
    rep["real_time"] = rt;
  }
  if (m_robot_source) {
    const robot::SegwayRmpRobot::Status st = m_robot_source->robot().status();
    const Eigen::Vector3d odo = m_robot_source->robot().odometry();
    rep["robot"] = {{"type", "segway_rmp"},
                    {"address", m_robot_source->robot().describe()},
                    {"link_ok", st.link_ok},
                    {"commands_sent", st.commands_sent},
                    {"responses", st.responses},
                    {"bad_responses", st.bad_responses},
                    {"watchdog_stops", st.watchdog_stops},
                    {"operational_state", st.operational_state},
                    {"fault_status", st.fault_status},
                    {"battery_soc_pct", st.battery_soc_pct},
                    {"odometry_xyyaw", {odo.x(), odo.y(), odo.z()}}};
  }
}

long long MappingRun::expectedFrames(const io::FrameSource& source) const {
  long long total = source.sizeHint();
  if (total > 0) {
    total = std::max<long long>(0, total - m_source.start_frame);
    total = (total + m_source.frame_step - 1) / m_source.frame_step;
    if (m_source.max_frames > 0) total = std::min<long long>(total, m_source.max_frames);
  } else if (m_source.max_frames > 0) {
    total = m_source.max_frames;
  }
#ifdef RASM_HAVE_SIM
  if (m_loop && total <= 0) {
    const double budget = m_mapper->stage<ExplorationStage>().loopParams().time_budget_s;
    const auto* sim_source = dynamic_cast<const sim::SimFrameSource*>(&source);
    if (budget > 0 && sim_source)
      total = (long long)(budget / sim_source->sequence().frameInterval()) + 1;
  }
#endif
  return total;
}

void MappingRun::recordFrame(Accumulated& acc, const RgbdFrame& f, const FrameResult& r) {
  ++acc.processed;
  setFramesDone((long long)acc.processed);
  acc.last_K = f.intrinsics;
  acc.have_K = true;
  // Every frame has a pose (propagated while lost: pose_source in frames.csv).
  acc.estimate.push_back({r.timestamp_s, r.T_world_cam});
  if (r.tracked) acc.estimate_tracked.push_back({r.timestamp_s, r.T_world_cam});
  acc.loss.add(r.tracked);
  if (f.gt_T_world_cam) acc.groundtruth.push_back({f.timestamp_s, *f.gt_T_world_cam});
  for (std::size_t s = 0; s < acc.ms_sum.size(); ++s) {
    acc.ms_sum[s] += r.ms[s];
    acc.ms_max[s] = std::max(acc.ms_max[s], r.ms[s]);
  }
  acc.frames_csv += m_mapper->csvRow();
  char memory[64];  // runCsvColumns() after the stages': memory now (rasm eval memory)
  std::snprintf(memory, sizeof memory, ",%.1f,%zu", currentRssMb(),
                m_mapper->map().store().memoryBytes());
  acc.frames_csv += memory + objectsScoreCells(acc, f) + "\n";
}

std::string MappingRun::objectsScoreCells(Accumulated& acc, const RgbdFrame& f) {
  std::optional<std::pair<std::size_t, std::size_t>> measured;
#ifdef RASM_HAVE_SIM
  if (m_loop) {
    measured = m_loop->objectsMeasuredThisFrame();
  } else if (m_object_score && !(f.timestamp_s - acc.objects_scored_t <
                                 m_output.objects_score_period_s)) {  // (NaN: the first frame)
    acc.objects_scored_t = f.timestamp_s;
    const SimObjectScore::Score s =
        m_object_score->score(m_mapper->map(), m_mapper->stage<ClassificationStage>());
    measured = std::make_pair(s.correct, s.detectable);
  }
#else
  (void)f;
#endif
  acc.last_row_scored = measured.has_value();
  if (!measured) return ",,";
  return "," + std::to_string(measured->first) + "," + std::to_string(measured->second);
}

void MappingRun::frameLoop(io::FrameSource& source, Accumulated& acc, OutputFolder& out,
                           const std::function<void(const FrameResult&)>& on_frame) {
  Progress progress("frames", expectedFrames(source));
  if (m_loop)  // (a wall-clock budget ends the frames before the simulated one)
    progress.setTimeLimit(m_mapper->stage<ExplorationStage>().loopParams().wall_budget_s);
  // annotated.rawlog: each input observation with the ESTIMATED pose (writeAnnotated), followed
  // by a CObservationImage "MAP_VIEW" of the map rendered from that pose.
  // Its writer renames its temporary at close() and removes it when destroyed open.
  std::unique_ptr<io::RawlogWriter> annotated;
  std::optional<ScopedTemporary> annotated_part;
  const std::size_t n_timers = m_mapper->timerNames().size();
  acc.ms_sum.assign(n_timers, 0.0);
  acc.ms_max.assign(n_timers, 0.0);
  acc.frames_csv = m_mapper->csvHeader();
  for (const std::string& c : runCsvColumns()) acc.frames_csv += "," + c;  // recordFrame's
  acc.frames_csv += "\n";
  try {
    while (m_source.max_frames == 0 || acc.processed < std::size_t(m_source.max_frames)) {
      if (stopSignal() != 0) break;  // SIGINT / SIGTERM: no further frame
      // The exploration stopped by its rule (a live camera does not end by itself).
      if (m_loop && m_loop->finished()) break;
      std::optional<RgbdFrame> f = source.next();
      if (!f) break;
      const long long idx = acc.read++;
      if (idx < m_source.start_frame || (idx - m_source.start_frame) % m_source.frame_step != 0)
        continue;
      if (m_source.dropped(idx)) continue;
      if (m_source.blanked(idx)) {
        f->depth_m.setTo(0.0f);
        if (!f->colour.empty()) f->colour.setTo(Bgr8{});
      }
      const FrameResult r = m_mapper->processFrame(*f);
      if (m_loop) m_loop->afterFrame(*f, r);
      recordFrame(acc, *f, r);
      if (on_frame) on_frame(r);
      if (m_output.write_rawlog) {
        try {
          if (!annotated) {
            annotated = openAnnotated(out);
            annotated_part.emplace(annotated->temporaryPath());
          }
          writeAnnotated(*annotated, *f, r);
        } catch (const std::exception& e) {
          annotated_part.reset();
          annotated.reset();  // removes its temporary
          acc.output_error = validUtf8(e.what());
          break;
        }
      }
      char extra[160];
      std::snprintf(extra, sizeof extra, "surfels %d lost %zu %s", m_mapper->map().size(),
                    m_mapper->framesLost(), r.tracked ? "" : tracking::toString(r.tracking.status));
      progress.update(static_cast<long long>(acc.processed),
                      m_loop ? std::string(extra) + " | " + m_loop->progressText() : extra);
    }
  } catch (const std::exception& e) {
    acc.error = validUtf8(e.what());
  }
  acc.interrupted_in_frames = stopSignal() != 0;
  progress.finish(static_cast<long long>(acc.processed), "done");
  if (annotated) try {
      annotated->writeObject(annotatedComment(true));
      annotated->close();
      out.recordWritten("annotated.rawlog");
    } catch (const std::exception& e) {
      if (acc.output_error.empty()) acc.output_error = validUtf8(e.what());
    }
}

std::unique_ptr<io::RawlogWriter> MappingRun::openAnnotated(OutputFolder& out) const {
  out.announce("annotated.rawlog");
  io::RawlogWriterOptions wo;
  wo.sensor_label = "RGBD";
  wo.sensor_pose_from_ground_truth = false;
  auto w = std::make_unique<io::RawlogWriter>(out.path("annotated.rawlog"), wo);
  w->writeObject(annotatedComment(false));  // rasm's reader takes no sensorPose as ground truth
  return w;
}

mrpt::obs::CObservationComment MappingRun::annotatedComment(bool closing) const {
  mrpt::obs::CObservationComment c;
  c.sensorLabel = "rasm";
  c.text = std::string(io::kRawlogNoGroundTruthMarker) +
           ".\nrasm annotated rawlog: per frame a CObservationOdometry (label POSE_TRACKED, "
           "POSE_LOST or POSE_RELOCALISED) with the estimated robot base pose (x, y, yaw; "
           "RawLogViewer: \"Raw-map\" > \"Map from odometry\" draws the path), then the "
           "observation with the camera's pose on that base as sensorPose (odometry + sensorPose "
           "= the estimated camera pose, trajectory.txt), then the map rendered from that pose "
           "(MAP_VIEW) and, once the map has classes, the class map (CLASS_VIEW).\n";
  if (closing) {  // RawLogViewer shows the last comment: the frames tracking lost, and why
    c.text += "Frames tracking lost: " + std::to_string(m_mapper->framesLost()) + "\n";
    for (const std::string& l : m_annotated_lost) c.text += l + "\n";
  }
  return c;
}

std::string MappingRun::noFrameReason(const Accumulated& acc) const {
  std::string why = "the source (" + m_source.type + ") yielded no frame to map: it ended after " +
                    std::to_string(acc.read) + " frames";
  if (acc.read > 0 && acc.read <= m_source.start_frame)
    why += ", before [source] start_frame = " + std::to_string(m_source.start_frame);
  else if (acc.read > 0)
    why += ", all of them skipped by [source] frame_step / drop_frames";
  return why;
}

namespace {
/// A JSON file this run wrote into `out` (null when it wrote none: the drawings go without).
nlohmann::json writtenJson(const OutputFolder& out, const std::string& name) {
  const auto& w = out.written();
  if (std::find(w.begin(), w.end(), name) == w.end()) return {};
  std::ifstream f(out.path(name));
  return nlohmann::json::parse(f, nullptr, false);
}
}  // namespace

void MappingRun::writeOutputs(const Accumulated& acc, OutputFolder& out) {
  out.writeText("frames.csv", acc.frames_csv);
  out.writeText("trajectory.txt",
                io::tumTrajectoryText(acc.estimate, "rasm estimate (T_world_cam, optical frame)"));
  if (!acc.groundtruth.empty())
    out.writeText("groundtruth.txt",
                  io::tumTrajectoryText(acc.groundtruth, "ground truth of the source"));
  // The stages' files first: the scenes and the floor plan draw objects.json's objects.
  m_mapper->writeOutputs(out);
  if (m_loop) {
    m_loop->writeOutputs(out);
    if (m_loop->groundTruth()) {  // exploration.png (RunPlots.h)
      const cv::Mat plot = explorationPlot(m_loop->metrics());
      if (!plot.empty()) out.writeImage("exploration.png", plot);
    }
  }
  const std::vector<ObjectBox> objects = objectBoxes(writtenJson(out, "objects.json"));
  writeMapFiles(acc, objects, out);
  if (m_output.preview_png && acc.have_K && acc.processed > 0) writePreviews(acc, out);
  if (m_output.preview_png) writePlots(acc, out);
  if (m_output.floorplan) writeFloorPlan(acc, objects, out);
}

void MappingRun::writeFloorPlan(const Accumulated& acc, const std::vector<ObjectBox>& objects,
                                OutputFolder& out) const {
  FloorPlanInput in;
  const maps::SurfelArrays a = m_mapper->map().store().arrays();
  for (int i = 0; i < a.size; ++i)
    if (a.alive(i) && a.stable(i)) {
      in.points_world.push_back(a.position(i));
      in.normals_world.push_back(a.normal(i));
      in.radii_m.push_back(a.radius(i));
    }
  for (const io::StampedPose& p : acc.estimate) in.T_world_cam.push_back(p.T_world_cam);
  // The simulator's worlds are z up (the map starts at the first frame's true pose in them);
  // anything else (a rawlog, TUM, 7-Scenes, a live camera) says nothing about gravity, and the
  // cameras' up axis decides (FloorPlan.h).
  in.world_z_up = m_source.type == "sim";
  in.title = "rasm " + m_output.dir;
  in.objects = objects;
  in.goals = floorPlanGoals(writtenJson(out, "exploration.json"));
  const FloorPlan plan = drawFloorPlan(in);
  if (plan.image.empty()) return;
  out.writeImage("floorplan.png", plan.image);
  out.writeText("floorplan.svg", plan.svg);
}

void MappingRun::writePlots(const Accumulated& acc, OutputFolder& out) const {
  const CsvColumns frames = parseCsvColumns(acc.frames_csv);
  if (!acc.estimate.empty())
    out.writeImage("plot_trajectory.png", trajectoryPlot(acc.estimate, acc.groundtruth, frames));
  const cv::Mat tracking = trackingPlot(frames, acc.estimate, acc.groundtruth);
  if (!tracking.empty()) out.writeImage("plot_tracking.png", tracking);
  const cv::Mat objects_plot = objectsPlot(frames);
  if (!objects_plot.empty()) out.writeImage("plot_objects.png", objects_plot);
  const cv::Mat timing = timingPlot(frames, m_mapper->stageTimerNames());
  if (!timing.empty()) out.writeImage("plot_timing.png", timing);
}

void MappingRun::writeMapFiles(const Accumulated& acc, const std::vector<ObjectBox>& objects,
                               OutputFolder& out) const {
  const maps::CSurfelMap& map = m_mapper->map();
  const bool classified =
      (m_output.write_3dscene || m_output.write_mesh) && anySurfelClassified(map.store().arrays());
  if (m_output.write_ply) out.write("map.ply", [&](const std::string& p) { map.saveToPly(p); });
  if (m_output.write_3dscene) {
    const maps::SurfelArrays a = map.store().arrays();
    // The map with the paths, the last camera and the exploration's views (RunScene.h).
    RunOverlay overlay;
    overlay.estimate = acc.estimate;
    overlay.groundtruth = acc.groundtruth;
    if (acc.have_K) overlay.K = acc.last_K;
    if (m_loop) overlay.views = m_loop->sceneViews();
    overlay.objects = objects;
    auto scene = [&](const char* name, maps::SurfelColouring colouring) {
      maps::SurfelVisualOptions vis = map.renderingOptions.visual;
      if (colouring != maps::SurfelColouring::Rgb) vis.colouring = colouring;
      out.write(name, [&](const std::string& p) {
        writeGzArchive(p, *runScene(map.store(), vis, overlay));
      });
    };
    scene("map.3Dscene", maps::SurfelColouring::Rgb);
    // The same scene coloured by segment (III) when the map has segments: SceneViewer3D shows
    // the objects the segmentation found.
    bool segmented = false;
    for (int i = 0; i < a.size && !segmented; ++i) segmented = a.alive(i) && a.segment[i] != 0;
    if (segmented) scene("map_segments.3Dscene", maps::SurfelColouring::Segment);
    // And coloured by class (IV) when any surfel carries one.
    if (classified) scene("map_classes.3Dscene", maps::SurfelColouring::Class);
  }
  if (m_output.save_map)
    out.write("map.surfelmap", [&](const std::string& p) { writeGzArchive(p, map); });
  if (m_output.write_mesh) writeMesh(acc, classified, out);
}

/// mesh.ply (and mesh_classes.ply when `classified`: a surfel carries a class): the map fused
/// along the estimated path (SurfelMesh.h).
void MappingRun::writeMesh(const Accumulated& acc, bool classified, OutputFolder& out) const {
  if (!acc.have_K || acc.estimate.empty()) return;
  if (const std::string why = meshing::SurfelMesh::unavailable(); !why.empty()) {
    log::warning(why + "; mesh.ply not written ([output] write_mesh = false skips it)");
    return;
  }
  const auto t0 = Clock::now();
  std::vector<Eigen::Isometry3d> poses;
  for (const auto& p : acc.estimate) poses.push_back(p.T_world_cam);
  const maps::SurfelStore& store = m_mapper->map().store();
  meshing::SurfelMesh mesh = meshing::SurfelMesh::build(store, poses, acc.last_K, m_mesh);
  if (mesh.triangles() == 0) {  // no stable surface seen from the path (a few frames)
    log::debug("mesh: no surface to mesh, mesh.ply not written");
    return;
  }
  out.write("mesh.ply", [&](const std::string& p) { mesh.writePly(p); });
  if (classified) {
    mesh.colourByClass(store);
    out.write("mesh_classes.ply", [&](const std::string& p) { mesh.writePly(p); });
  }
  log::debug("mesh: " + std::to_string(mesh.triangles()) + " triangles, " +
             std::to_string(mesh.vertices()) + " vertices from " + std::to_string(mesh.views()) +
             " views in " + std::to_string(int(msSince(t0))) + " ms");
}

void MappingRun::writePreviews(const Accumulated& acc, OutputFolder& out) const {
  maps::RenderedMaps view;
  m_mapper->renderView(m_mapper->pose(), acc.last_K, view);
  cv::Mat img(view.colour.height(), view.colour.width(), CV_8UC3, view.colour.data(),
              view.colour.pitchBytes());
  out.writeImage("preview.png", img);
  // The same view coloured by segment (III), when the map has segments.
  bool any = false;
  cv::Mat seg(img.rows, img.cols, CV_8UC3, cv::Scalar(0, 0, 0));
  for (int y = 0; y < view.segment.height(); ++y)
    for (int x = 0; x < view.segment.width(); ++x) {
      if (view.index(x, y) < 0) continue;
      const std::uint32_t l = view.segment(x, y);
      any = any || l != 0;
      const Bgr8 c = maps::labelColour(l);
      seg.at<cv::Vec3b>(y, x) = cv::Vec3b(c.b, c.g, c.r);
    }
  if (any) out.writeImage("preview_segments.png", seg);
  cv::Mat classes;
  if (classMapView(view, classes)) out.writeImage("preview_classes.png", classes);
}

nlohmann::json MappingRun::reportJson(const std::string& source, const Accumulated& acc,
                                      RunSummary& sum) const {
  const std::size_t processed = acc.processed;
  nlohmann::json rep;
  // What wrote this report and when (docs/outputs.md "Schema versions").
  rep["report_schema"] = kReportSchema;
  rep["frames_schema"] = kFramesSchema;
  const BuildInfo& build = buildInfo();
  rep["rasm"] = {{"version", build.version}, {"commit", build.commit}, {"build_date", build.date}};
  rep["started_utc"] = acc.started_utc;
  rep["finished_utc"] = utcNow();
  rep["status"] = sum.status;
  const std::string& error = !acc.error.empty() ? acc.error : acc.output_error;
  if (!error.empty()) rep["error"] = error;
  if (acc.interrupted_by != 0) {
    rep["interrupted_by"] = signalName(acc.interrupted_by);
    rep["interrupted_during"] = acc.interrupted_in_frames ? "frames" : "outputs";
  }
  rep["config_source"] = m_config.source();
  rep["source"] = source;
  // The intrinsics the frames were mapped with (the source's own, [camera], or a guess that
  // `source` then says), whatever their origin.
  if (acc.have_K)
    rep["intrinsics"] = {{"fx", acc.last_K.fx},       {"fy", acc.last_K.fy},
                         {"cx", acc.last_K.cx},       {"cy", acc.last_K.cy},
                         {"width", acc.last_K.width}, {"height", acc.last_K.height}};
  rep["frames"] = processed;
  rep["frames_read"] = acc.read;
  rep["frames_lost"] = sum.lost;
  rep["seconds"] = sum.seconds;
  // With [source] preload the frames were decoded before the clock started (preload_seconds).
  rep["preloaded"] = m_source.preload;
  if (m_source.preload) rep["preload_seconds"] = acc.preload_s;
  rep["fps"] = sum.fps;
  // CPU time of the whole process (all threads, the reader included) per frame: on a shared
  // machine a steadier measure of the work than frames/s.
  rep["cpu_ms_per_frame"] = processed > 0 ? 1e3 * acc.cpu_s / double(processed) : 0.0;
  rep["surfels"] = sum.surfels;
  rep["map_memory_bytes"] = m_mapper->map().store().memoryBytes();
  rep["peak_rss_mb"] = peakRssMb();
  nlohmann::json st;
  const std::vector<std::string>& timers = m_mapper->timerNames();
  for (std::size_t s = 0; s < timers.size() && s < acc.ms_sum.size(); ++s)
    st[timers[s]] = {{"mean_ms", processed ? acc.ms_sum[s] / double(processed) : 0.0},
                     {"max_ms", acc.ms_max[s]}};
  rep["stages"] = st;
  rep["stage_order"] = m_mapper->stageTimerNames();
  if (processed > 0) rep["final_pose"] = poseJson(m_mapper->pose());
  rep["frames_tracked"] = processed - sum.lost;
  rep["tracked_fraction"] = processed > 0 ? double(processed - sum.lost) / double(processed) : 0.0;
  rep["lost_intervals"] = acc.loss.intervals;
  rep["longest_lost_interval_frames"] = acc.loss.longest;
  m_mapper->report(rep);  // the stages' fields (relocalisations, keyframes, ...)
  if (m_loop) m_loop->report(rep);
  if (const auto& o = acc.final_objects) {
    rep["objects_correct_fraction"] = o->second > 0 ? double(o->first) / double(o->second) : 0.0;
    if (rep.contains("classification")) {
      rep["classification"]["objects_correct"] = o->first;
      rep["classification"]["objects_detectable"] = o->second;
    }
  }
  liveReport(rep, processed, sum.seconds);
  addAte(acc, rep, sum);
  return rep;
}

void MappingRun::addAte(const Accumulated& acc, nlohmann::json& rep, RunSummary& sum) const {
  io::Trajectory groundtruth = acc.groundtruth;
  if (!m_source.groundtruth.empty()) {
    try {
      groundtruth = io::readTumTrajectory(m_source.groundtruth);
    } catch (const std::exception& e) {
      rep["ate_error"] = e.what();
      groundtruth.clear();
    }
  }
  // ATE over every frame (lost ones at their propagated pose) and over the tracked ones alone;
  // each states how many frames it covers.
  const io::AteOptions ao;
  auto ate = [&](const io::Trajectory& est, const char* key) -> std::optional<double> {
    if (groundtruth.size() < 3 || est.size() < 3) return std::nullopt;
    try {
      const io::AteResult a = io::TrajectoryEvaluator::computeAte(groundtruth, est, ao);
      rep[key] = io::toJson(a, ao);
      return a.translation_m.rmse;
    } catch (const std::exception& e) {
      rep[std::string(key) + "_error"] = e.what();
      return std::nullopt;
    }
  };
  sum.ate_rmse_m = ate(acc.estimate, "ate");
  sum.ate_tracked_rmse_m = ate(acc.estimate_tracked, "ate_tracked");
  addWorldFrameError(acc, groundtruth, rep, sum);
}

void MappingRun::addWorldFrameError(const Accumulated& acc, const io::Trajectory& groundtruth,
                                    nlohmann::json& rep, RunSummary& sum) const {
  if (groundtruth.size() < 2 || acc.estimate.size() < 2) return;
  const io::WorldFrameOptions wo;
  sum.truth = !m_source.groundtruth.empty() ? "the ground-truth file"
              : m_source.type == "sim"      ? "the simulator's truth"
                                            : "the source's ground truth";
  nlohmann::json j;
  j["comment"] =
      "estimate against " + sum.truth +
      " in the world frame, without alignment (the run started at the true pose: its first "
      "estimate within 1 mm and 0.05 deg of the ground truth there); errors: position, height "
      "(vertical, along up_world), horizontal, tilt (angle between the estimated and the true "
      "camera's up direction: roll and pitch, not heading), heading (rotation about up_world)";
  auto summary = [](const io::WorldFrameError& w) {
    WorldFrameSummary s;
    s.frames = w.position_m.count;
    s.rms_m = w.position_m.rmse;
    s.max_m = w.position_m.max;
    s.vertical_max_m = w.vertical_m.max;
    s.tilt_max_deg = w.tilt_deg.max;
    s.heading_max_deg = w.heading_deg.max;
    return s;
  };
  try {
    const io::WorldFrameError all =
        io::TrajectoryEvaluator::computeWorldFrameError(groundtruth, acc.estimate, wo);
    j["started_at_ground_truth"] = all.startsAtGroundTruth();
    if (!all.startsAtGroundTruth()) {
      j["comment"] =
          "not computed: the first estimate is not the ground truth's pose (start_error), so the "
          "two world frames differ; only the aligned ate compares them";
      j["start_error"] = {{"position_m", all.start_position_error_m},
                          {"rotation_deg", all.start_rotation_error_deg}};
      rep["world_frame_error"] = j;
      return;
    }
    j["all"] = io::toJson(all, wo);
    sum.world_error = summary(all);
    if (acc.estimate_tracked.size() >= 2) {
      const io::WorldFrameError tracked =
          io::TrajectoryEvaluator::computeWorldFrameError(groundtruth, acc.estimate_tracked, wo);
      j["tracked"] = io::toJson(tracked, wo);
      sum.world_error_tracked = summary(tracked);
    }
  } catch (const std::exception& e) {
    j["error"] = e.what();
  }
  rep["world_frame_error"] = j;
}

void MappingRun::finishFrames(Accumulated& acc) {
  try {
    m_mapper->finishRun();
  } catch (const std::exception& e) {
    if (acc.error.empty()) acc.error = validUtf8(e.what());
  }
  // The exploration loop lets go of the source's robot here, while the source still lives.
  if (m_loop) try {
      m_loop->finish(!acc.error.empty()  ? "error"
                     : stopSignal() != 0 ? "interrupted"
                                         : "source_end");
    } catch (const std::exception& e) {
      if (acc.error.empty()) acc.error = validUtf8(e.what());
    }
#ifdef RASM_HAVE_SIM
  // The objects as the final regrouping left them: report.json and frames.csv's last row.
  if (m_object_score && acc.processed > 0) try {
      const SimObjectScore::Score s =
          m_object_score->score(m_mapper->map(), m_mapper->stage<ClassificationStage>());
      acc.final_objects = std::make_pair(s.correct, s.detectable);
      const std::string empty = ",,\n", cells = "," + std::to_string(s.correct) + "," +
                                                std::to_string(s.detectable) + "\n";
      if (!acc.last_row_scored && acc.frames_csv.size() >= empty.size() &&
          acc.frames_csv.compare(acc.frames_csv.size() - empty.size(), empty.size(), empty) == 0)
        acc.frames_csv.replace(acc.frames_csv.size() - empty.size(), empty.size(), cells);
    } catch (const std::exception& e) {
      if (acc.error.empty()) acc.error = validUtf8(e.what());
    }
#endif
  if (acc.processed == 0 && acc.error.empty() && acc.output_error.empty() && stopSignal() == 0)
    acc.error = noFrameReason(acc);
  if (acc.processed > 0 && acc.error.empty() && acc.output_error.empty() && stopSignal() == 0)
    acc.error = nothingFusedReason(acc.processed, m_mapper->framesLost(), m_mapper->map().size(),
                                   m_mapper->mapperParams().load_map);
  acc.cpu_s = processCpuSeconds() - acc.cpu_start_s;
}

RunSummary MappingRun::summarise(const Accumulated& acc) const {
  RunSummary sum;
  sum.out_dir = m_output.dir;
  sum.seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - acc.t_start).count();
  sum.frames = acc.processed;
  sum.fps = acc.processed > 0 ? double(acc.processed) / sum.seconds : 0.0;
  sum.lost = m_mapper->framesLost();
  sum.lost_intervals = acc.loss.intervals;
  sum.relocalisations = m_mapper->relocalisations();
  sum.surfels = std::size_t(m_mapper->map().size());
  sum.explored = m_loop != nullptr;
  return sum;
}

namespace {
/// run.log in the folder; a folder that refuses it is a warning, not the run's end.
void openRunLog(OutputFolder& out, std::optional<log::FileGuard>& run_log) {
  out.announce("run.log");
  try {
    run_log.emplace(out.path("run.log"));
    out.recordWritten("run.log");
  } catch (const std::exception& e) {
    log::warning(std::string(e.what()) + " (the run goes on without run.log)");
  }
}
}  // namespace

RunSummary MappingRun::run(const std::function<void(const FrameResult&)>& on_frame) {
  if (m_mapper->framesProcessed() > 0)
    throw std::logic_error("MappingRun::run: once per MappingRun");
  Accumulated acc;
  // What can be checked without a frame is checked before the output folder changes: a run that
  // fails here leaves an earlier run's files as they were.
  std::unique_ptr<io::FrameSource> source = openSource();
  resolveAutoSettings(*source);  // before config.ini, which records what the run used
  if (!m_mapper->mapperParams().load_map.empty())
    m_mapper->loadMap(m_mapper->mapperParams().load_map);
  if (stopSignal() != 0) {  // stopped before it began: the folder stays as it was
    RunSummary sum;
    sum.out_dir = m_output.dir;
    sum.status = "interrupted";
    sum.interrupted_by = stopSignal();
    return sum;
  }
  OutputFolder out = prepareOutputFolder();
  // Every message of the run also goes to run.log in the folder; the console shows those from
  // [output] log_level up (set for this run, restored after it).
  struct ConsoleLevel {
    log::Level before = log::consoleLevel();
    ~ConsoleLevel() { log::setConsoleLevel(before); }
  } console_level;
  log::setConsoleLevel(log::parseLevel(m_output.log_level, "[output] log_level"));
  std::optional<log::FileGuard> run_log;
  openRunLog(out, run_log);
  try {
    out.writeText("config.ini", effectiveConfig());
  } catch (const std::exception& e) {
    acc.output_error = validUtf8(e.what());  // then no frame: report.json says why
  }
  const std::string described = source->describe();
  try {
    source = wrapSource(std::move(source), acc.preload_s);
  } catch (const std::exception& e) {
    acc.error = validUtf8(e.what());
    m_loop.reset();  // its navigation thread drives the source's robot: it goes first
    source.reset();
  }
  // Frame rate and CPU time count the mapping (not a preload before it).
  acc.t_start = std::chrono::steady_clock::now();
  acc.cpu_start_s = processCpuSeconds();
  log::info("rasm run: " + escapeControlChars(described) + " -> " +
            escapeControlChars(m_output.dir));

  std::unique_ptr<LiveView> view;
  if (m_view.enabled) try {
      view = std::make_unique<LiveView>(*m_mapper, m_view);
    } catch (const std::exception& e) {  // a window that does not open does not stop the mapping
      log::warning(std::string("the live view did not open: ") + e.what());
    }
  const std::function<void(const FrameResult&)> each_frame = [&](const FrameResult& r) {
    if (view) {
      view->addFrame(r, acc.last_K);  // recordFrame has set it
      if (view->overlayDue())         // what the run does, drawn over the map
        view->setOverlay(m_loop ? m_loop->sceneViews() : std::vector<SceneView>{},
                         objectBoxes(m_mapper->stage<ClassificationStage>().reportedObjects()));
    }
    if (on_frame) on_frame(r);
  };
  if (source && acc.output_error.empty()) frameLoop(*source, acc, out, each_frame);
  view.reset();  // its last snapshot (and screenshot) before the outputs
  finishFrames(acc);
  RunSummary sum = summarise(acc);
  // Outputs of the frames done (none without a frame: no map of nothing), report.json last.
  if (acc.processed > 0 && acc.output_error.empty()) try {
      writeOutputs(acc, out);
    } catch (const std::exception& e) {
      acc.output_error = validUtf8(e.what());
    }
  acc.interrupted_by = stopSignal();
  sum.interrupted_by = acc.interrupted_by;
  sum.status = !acc.error.empty() || !acc.output_error.empty() ? "failed"
               : acc.interrupted_by != 0                       ? "interrupted"
                                                               : "ok";
  log::debug("rasm run: " + sum.status + " after " + std::to_string(acc.processed) + " frames, " +
             std::to_string(sum.lost) + " lost" + (acc.error.empty() ? "" : ": " + acc.error) +
             (acc.output_error.empty() ? "" : "; output: " + acc.output_error));
  nlohmann::json rep = reportJson(described, acc, sum);
  rep["files"] = out.written();
  sum.report = rep;
  const std::string note = " (" + std::to_string(acc.processed) + " frames mapped; " +
                           m_output.dir + "/report.json lists the files written)";
  try {
    out.writeText("report.json",
                  rep.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n");
  } catch (const std::exception& e) {
    const std::string first = acc.output_error.empty() ? acc.error : acc.output_error;
    throw OutputError(std::string(e.what()) + (first.empty() ? "" : "; before it: " + first));
  }
  setAbortReport("");  // from here a second signal must not replace the complete report
  if (!acc.output_error.empty()) throw OutputError(acc.output_error + note);
  if (!acc.error.empty()) throw InputError(acc.error + note);
  return sum;
}

}  // namespace rasm::run
