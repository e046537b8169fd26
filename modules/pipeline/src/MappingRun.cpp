#include "rasm/pipeline/MappingRun.h"

#include <mrpt/img/TCamera.h>
#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/obs/CObservationImage.h>
#include <mrpt/serialization/CArchive.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <opencv2/imgcodecs.hpp>
#include <sstream>

#include "rasm/core/Error.h"
#include "rasm/core/Params.h"
#include "rasm/core/SE3.h"
#include "rasm/io/EvaluationJson.h"
#include "rasm/io/PrefetchingFrameSource.h"
#include "rasm/io/PreloadedFrameSource.h"
#include "rasm/io/RawlogWriter.h"
#include "rasm/io/RgbdObservation.h"
#include "rasm/io/TrajectoryEvaluator.h"
#include "rasm/pipeline/ExplorationLoop.h"
#include "rasm/pipeline/Progress.h"
#include "rasm/pipeline/SimSource.h"
#include "rasm/pipeline/stages/ClassificationStage.h"
#include "rasm/pipeline/stages/ExplorationStage.h"
#include "rasm/surfel_map/MapExport.h"
#ifdef RASM_HAVE_SIM
#include "rasm/sim/SimFrameSource.h"
#endif

namespace fs = std::filesystem;

namespace rasm::pipeline {

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
  known.insert(known.end(), {"navigation", "output", "sim"});
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
  loadParamsStrict(ini, "navigation", m_navigation, src);
  (void)m_camera.intrinsics();  // validates
  // [sim] belongs to the simulator; it is parsed strictly when the sim source is opened.
  std::vector<std::string> keys;
  ini.getAllKeys("sim", keys);
  m_sim_ini = "[sim]\n";
  for (const auto& k : keys) m_sim_ini += k + " = " + ini.read_string("sim", k, "") + "\n";
  decideExploring(src);
}

/// [explore] enabled: true (a robot the run can drive, or an InputError), false, or auto (explore
/// a simulated robot spec, map anything else).
void MappingRun::decideExploring(const std::string& src) {
  const std::string& mode = m_mapper->stage<ExplorationStage>().exploreParams().enabled;
  if (mode == "true" && m_source.type != "sim")
    throwInputError(src + " [explore] enabled = true",
                    "needs a robot the run can drive: [source] type = sim with a robot "
                    "trajectory spec (got [source] type = " +
                        m_source.type + ")");
  m_exploring = mode == "true" ||
                (mode == "auto" && m_source.type == "sim" && simTrajectoryIsRobot(m_sim_ini, src));
  m_mapper->stage<ExplorationStage>().setExploring(m_exploring);
}

MappingRun::~MappingRun() = default;

std::string MappingRun::effectiveConfig() const {
  mrpt::config::CConfigFileMemory mem;
  m_source.saveToConfigFile(mem, "source");
  m_camera.saveToConfigFile(mem, "camera");
  m_mapper->saveParams(mem);
  m_navigation.saveToConfigFile(mem, "navigation");
  m_output.saveToConfigFile(mem, "output");
  std::string text;
  mem.getContent(text);
  return "; effective configuration of a rasm run (every key, defaults included), from " +
         m_config.source() + "\n" + text + "\n" + m_sim_ini;
}

std::unique_ptr<io::FrameSource> MappingRun::openSource() const {
  if (m_source.type == "sim")
    return openSimSource(m_sim_ini, m_config.source(), m_camera.intrinsics(), m_exploring,
                         m_mapper->stage<ExplorationStage>().exploreParams().camera_rate_hz);
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
  return io::openFrameSource(m_source.path, opt);
}

namespace {
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

/// Runs of consecutive lost frames (issue 14's honest loss reporting).
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

nlohmann::json poseJson(const Eigen::Isometry3d& T) {
  const Eigen::Quaterniond q(T.linear());
  return {{"t", {T.translation().x(), T.translation().y(), T.translation().z()}},
          {"q_xyzw", {q.x(), q.y(), q.z(), q.w()}}};
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
  mrpt::obs::CObservation3DRangeScan obs;
  io::FrameToObservationOptions fo;
  fo.sensor_pose_from_ground_truth = false;
  io::observationFromFrame(frame, obs, fo);
  obs.sensorPose = mrptSensorPoseFromOptical(r.T_world_cam);
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
  std::string error;                   ///< what ended the loop early, empty = the source ended
  std::size_t processed = 0;
  CameraIntrinsics last_K;
  bool have_K = false;
  std::chrono::steady_clock::time_point t_start;
  double cpu_start_s = 0.0, preload_s = 0.0;
  double cpu_s = 0.0;  ///< CPU seconds of the frame loop
};

void MappingRun::prepareOutputFolder() const {
  std::error_code ec;
  fs::create_directories(m_output.dir, ec);
  if (ec)
    throwInputError("[output] dir '" + m_output.dir + "'", "cannot be created: " + ec.message());
  if (!m_output.overwrite && !fs::is_empty(m_output.dir))
    throwInputError("[output] dir '" + m_output.dir + "'",
                    "is not empty and [output] overwrite = false");
  writeFileAtomically(m_output.dir + "/config.ini", effectiveConfig());
}

std::unique_ptr<io::FrameSource> MappingRun::openWrappedSource(double& preload_s) {
  std::unique_ptr<io::FrameSource> source = openSource();
#ifdef RASM_HAVE_SIM
  // The simulated detector's occlusion test casts rays into the scene the frames come from.
  if (const auto* sim_source = dynamic_cast<const sim::SimFrameSource*>(source.get()))
    m_mapper->stage<ClassificationStage>().setSimScene(&sim_source->sequence().scene());
#endif
  preload_s = 0.0;
#ifdef RASM_HAVE_SIM
  // Exploring: the run drives the robot, so each frame must be rendered after the commands the
  // previous one led to (no read-ahead).
  if (m_exploring) {
    auto* sim_source = dynamic_cast<sim::SimFrameSource*>(source.get());
    m_explore = std::make_unique<ExplorationLoop>(*m_mapper, sim_source->sequence(), m_navigation);
    return source;
  }
#endif
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

void MappingRun::frameLoop(io::FrameSource& source, Accumulated& acc,
                           const std::function<void(const FrameResult&)>& on_frame) {
  long long total = source.sizeHint();
  if (total > 0) {
    total = std::max<long long>(0, total - m_source.start_frame);
    total = (total + m_source.frame_step - 1) / m_source.frame_step;
    if (m_source.max_frames > 0) total = std::min<long long>(total, m_source.max_frames);
  } else if (m_source.max_frames > 0) {
    total = m_source.max_frames;
  }
  if (m_explore && total <= 0) {
    const double budget = m_mapper->stage<ExplorationStage>().exploreParams().time_budget_s;
    const auto* sim_source = dynamic_cast<const sim::SimFrameSource*>(&source);
    if (budget > 0 && sim_source)
      total = (long long)(budget / sim_source->sequence().frameInterval()) + 1;
  }
  Progress progress("frames", total);
  // annotated.rawlog: each input observation with the ESTIMATED camera pose as sensorPose (MRPT
  // sensor frame), followed by a CObservationImage "MAP_VIEW" of the map rendered from that pose.
  std::unique_ptr<io::RawlogWriter> annotated;
  if (m_output.write_rawlog) {
    io::RawlogWriterOptions wo;
    wo.sensor_label = "RGBD";
    wo.sensor_pose_from_ground_truth = false;
    annotated = std::make_unique<io::RawlogWriter>(m_output.dir + "/annotated.rawlog", wo);
  }
  const std::size_t n_timers = m_mapper->timerNames().size();
  acc.ms_sum.assign(n_timers, 0.0);
  acc.ms_max.assign(n_timers, 0.0);
  acc.frames_csv = m_mapper->csvHeader() + "\n";
  long long read = 0;
  try {
    while (m_source.max_frames == 0 || acc.processed < std::size_t(m_source.max_frames)) {
      std::optional<RgbdFrame> f = source.next();
      if (!f) break;
      const long long idx = read++;
      if (idx < m_source.start_frame || (idx - m_source.start_frame) % m_source.frame_step != 0)
        continue;
      if (m_source.dropped(idx)) continue;
      if (m_source.blanked(idx)) {
        f->depth_m.setTo(0.0f);
        if (!f->colour.empty()) f->colour.setTo(Bgr8{});
      }
      const FrameResult r = m_mapper->processFrame(*f);
      if (m_explore) m_explore->afterFrame(*f, r);
      ++acc.processed;
      acc.last_K = f->intrinsics;
      acc.have_K = true;
      // Every frame has a pose (propagated while lost: pose_source in frames.csv).
      acc.estimate.push_back({r.timestamp_s, r.T_world_cam});
      if (r.tracked) acc.estimate_tracked.push_back({r.timestamp_s, r.T_world_cam});
      acc.loss.add(r.tracked);
      if (f->gt_T_world_cam) acc.groundtruth.push_back({f->timestamp_s, *f->gt_T_world_cam});
      for (std::size_t s = 0; s < n_timers; ++s) {
        acc.ms_sum[s] += r.ms[s];
        acc.ms_max[s] = std::max(acc.ms_max[s], r.ms[s]);
      }
      if (on_frame) on_frame(r);
      if (annotated) writeAnnotated(*annotated, *f, r);
      acc.frames_csv += m_mapper->csvRow();
      acc.frames_csv += "\n";
      char extra[160];
      std::snprintf(extra, sizeof extra, "surfels %d lost %zu %s", m_mapper->map().size(),
                    m_mapper->framesLost(), r.tracked ? "" : tracking::toString(r.tracking.status));
      progress.update(static_cast<long long>(acc.processed),
                      m_explore ? std::string(extra) + " | " + m_explore->progressText() : extra);
    }
  } catch (const std::exception& e) {
    acc.error = e.what();
  }
  progress.finish(static_cast<long long>(acc.processed), "done");
  if (annotated) annotated->close();
}

void MappingRun::writeOutputs(const Accumulated& acc) {
  const std::string dir = m_output.dir;
  writeFileAtomically(dir + "/frames.csv", acc.frames_csv);
  io::writeTumTrajectory(dir + "/trajectory.txt", acc.estimate,
                         "rasm estimate (T_world_cam, optical frame)");
  if (!acc.groundtruth.empty())
    io::writeTumTrajectory(dir + "/groundtruth.txt", acc.groundtruth, "ground truth of the source");
  if (m_output.write_ply) m_mapper->map().saveToPly(dir + "/map.ply");
  if (m_output.write_3dscene) {
    m_mapper->map().saveTo3DScene(dir + "/map.3Dscene");
    // The same scene coloured by segment (III) when the map has segments: SceneViewer3D shows
    // the objects the segmentation found.
    const maps::SurfelArrays a = m_mapper->map().store().arrays();
    bool segmented = false;
    for (int i = 0; i < a.size && !segmented; ++i) segmented = a.alive(i) && a.segment[i] != 0;
    if (segmented) {
      maps::SurfelVisualOptions vis = m_mapper->map().renderingOptions.visual;
      vis.colouring = maps::SurfelColouring::Segment;
      maps::writeSurfelScene(m_mapper->map().store(), dir + "/map_segments.3Dscene", vis);
    }
    // And coloured by class (IV) when any surfel carries one.
    bool classified = false;
    for (int i = 0; i < a.size && !classified && a.n_classes > 0; ++i)
      classified = a.alive(i) && maps::bestClass(a, i).id != 0;
    if (classified) {
      maps::SurfelVisualOptions vis = m_mapper->map().renderingOptions.visual;
      vis.colouring = maps::SurfelColouring::Class;
      maps::writeSurfelScene(m_mapper->map().store(), dir + "/map_classes.3Dscene", vis);
    }
  }
  if (m_output.save_map) {
    const std::string p = dir + "/map.surfelmap";
    {
      mrpt::io::CFileGZOutputStream f(p + ".part");
      auto a = mrpt::serialization::archiveFrom(f);
      a << m_mapper->map();
    }
    fs::rename(p + ".part", p);
  }
  m_mapper->writeOutputs(dir);
  if (m_explore) m_explore->writeOutputs(dir);
  if (m_output.preview_png && acc.have_K && acc.processed > 0) {
    maps::RenderedMaps view;
    m_mapper->renderView(m_mapper->pose(), acc.last_K, view);
    cv::Mat img(view.colour.height(), view.colour.width(), CV_8UC3, view.colour.data(),
                view.colour.pitchBytes());
    cv::imwrite(dir + "/preview.png", img);
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
    if (any) cv::imwrite(dir + "/preview_segments.png", seg);
    cv::Mat classes;
    if (classMapView(view, classes)) cv::imwrite(dir + "/preview_classes.png", classes);
  }
}

void MappingRun::writeReport(const io::FrameSource& source, Accumulated& acc, RunSummary& sum) {
  const std::size_t processed = acc.processed;
  nlohmann::json rep;
  rep["status"] = acc.error.empty() ? "ok" : "failed";
  if (!acc.error.empty()) rep["error"] = acc.error;
  rep["config_source"] = m_config.source();
  rep["source"] = source.describe();
  rep["frames"] = processed;
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
  for (std::size_t s = 0; s < timers.size(); ++s)
    st[timers[s]] = {{"mean_ms", processed ? acc.ms_sum[s] / double(processed) : 0.0},
                     {"max_ms", acc.ms_max[s]}};
  rep["stages"] = st;
  if (processed > 0) rep["final_pose"] = poseJson(m_mapper->pose());
  rep["frames_tracked"] = processed - sum.lost;
  rep["tracked_fraction"] = processed > 0 ? double(processed - sum.lost) / double(processed) : 0.0;
  rep["lost_intervals"] = acc.loss.intervals;
  rep["longest_lost_interval_frames"] = acc.loss.longest;
  m_mapper->report(rep);  // the stages' fields (relocalisations, keyframes, ...)

  io::Trajectory groundtruth = acc.groundtruth;
  if (m_explore) m_explore->report(rep);
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
  sum.report = rep;
  writeFileAtomically(m_output.dir + "/report.json", rep.dump(2) + "\n");
}

RunSummary MappingRun::run(const std::function<void(const FrameResult&)>& on_frame) {
  if (m_mapper->framesProcessed() > 0)
    throw std::logic_error("MappingRun::run: once per MappingRun");
  Accumulated acc;
  prepareOutputFolder();
  std::unique_ptr<io::FrameSource> source = openWrappedSource(acc.preload_s);
  // Frame rate and CPU time count the mapping (not a preload before it).
  acc.t_start = std::chrono::steady_clock::now();
  acc.cpu_start_s = processCpuSeconds();
  if (!m_mapper->mapperParams().load_map.empty())
    m_mapper->loadMap(m_mapper->mapperParams().load_map);
  std::fprintf(stderr, "rasm run: %s -> %s\n", source->describe().c_str(), m_output.dir.c_str());

  frameLoop(*source, acc, on_frame);
  try {
    m_mapper->finishRun();
  } catch (const std::exception& e) {
    if (acc.error.empty()) acc.error = e.what();
  }
  // The exploration loop lets go of the source's robot here, while `source` still lives.
  if (m_explore) try {
      m_explore->finish(acc.error.empty() ? "source_end" : "error");
    } catch (const std::exception& e) {
      if (acc.error.empty()) acc.error = e.what();
    }

  acc.cpu_s = processCpuSeconds() - acc.cpu_start_s;
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
  sum.explored = m_explore != nullptr;
  writeOutputs(acc);
  writeReport(*source, acc, sum);
  if (!acc.error.empty())
    throw InputError(acc.error + " (outputs of the " + std::to_string(acc.processed) +
                     " frames before it were written to " + m_output.dir + ")");
  return sum;
}

}  // namespace rasm::pipeline
