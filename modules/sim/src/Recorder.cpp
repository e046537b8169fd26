#include "rasm/sim/Recorder.h"

#include <mrpt/config/CConfigFileMemory.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>
#include <stdexcept>

#include "rasm/core/Error.h"
#include "rasm/core/Params.h"
#include "rasm/sim/FrameImages.h"
#include "rasm/sim/RayScene.h"
#include "rasm/sim/RgbdSensor.h"
#include "rasm/sim/SimClasses.h"
#include "rasm/sim/SimulatedDiffDriveRobot.h"

#ifdef RASM_SIM_HAVE_IO
#include "rasm/io/RawlogWriter.h"
#include "rasm/io/Trajectory.h"
#endif

namespace fs = std::filesystem;

namespace rasm::sim {

bool recorderCanWriteRawlogs() {
#ifdef RASM_SIM_HAVE_IO
  return true;
#else
  return false;
#endif
}

#ifdef RASM_SIM_HAVE_IO
namespace {

/// Applies key = value overrides to a params struct through the strict INI loader, so unknown
/// keys and bad values fail the same way as in an INI file.
void applyOverrides(mrpt::config::CLoadableOptions& params, const std::string& section,
                    const std::map<std::string, std::string>& kv, const std::string& source) {
  if (kv.empty()) return;
  mrpt::config::CConfigFileMemory mem;
  params.saveToConfigFile(mem, section);  // start from the current values
  for (const auto& [k, v] : kv) mem.write(section, k, v);
  loadParamsStrict(mem, section, params, source);
}

/// Progress line on stderr: frames, rate and ETA, at most once a second.
class Progress {
 public:
  explicit Progress(bool enabled) : m_on(enabled), m_tty(isatty(STDERR_FILENO) != 0) {}
  void update(std::size_t frames, double fraction, bool final = false) {
    if (!m_on) return;
    const auto now = std::chrono::steady_clock::now();
    const double elapsed = std::chrono::duration<double>(now - m_start).count();
    if (!final && elapsed - m_last < 1.0) return;
    m_last = elapsed;
    const double fps = elapsed > 0 ? double(frames) / elapsed : 0.0;
    const double eta = fraction > 1e-6 ? elapsed * (1.0 - fraction) / fraction : 0.0;
    std::fprintf(stderr, "%ssim record: %zu frames (%3.0f%%), %.1f frames/s, ETA %.0f s%s",
                 m_tty ? "\r" : "", frames, 100.0 * std::min(1.0, fraction), fps, final ? 0.0 : eta,
                 (m_tty && !final) ? "" : "\n");
    std::fflush(stderr);
  }

 private:
  bool m_on, m_tty;
  std::chrono::steady_clock::time_point m_start = std::chrono::steady_clock::now();
  double m_last = -1e9;
};

void writeClassesJson(const World& world, const std::string& path, std::size_t frames,
                      double rate_hz) {
  nlohmann::json j;
  j["format"] = "rasm sim labels v1";
  j["world"] = world.name;
  j["world_file"] = world.source;
  j["frames"] = frames;
  j["rate_hz"] = rate_hz;
  j["images"] =
      "instance_NNNNNN.png / class_NNNNNN.png: 16-bit PNG, NNNNNN = frame index, 0 = none";
  nlohmann::json classes = nlohmann::json::array();
  for (int i = 0; i < numClasses(); ++i)
    classes.push_back({{"id", i}, {"name", className(i)}, {"coco", isCocoClass(i)}});
  j["classes"] = classes;
  nlohmann::json inst = nlohmann::json::array();
  for (const WorldObject& o : world.objects)
    inst.push_back({{"id", o.instance_id},
                    {"class_id", o.class_id},
                    {"class", className(o.class_id)},
                    {"name", o.name},
                    {"static", o.is_static},
                    {"mesh", fs::path(o.mesh_source).filename().string()}});
  j["instances"] = inst;
  std::ofstream f(path);
  if (!f) throwInputError(path, "cannot write");
  f << j.dump(1) << "\n";
  if (!f) throwInputError(path, "write failed");
}

}  // namespace
#endif

RecordResult recordSequence(const World& world, const TrajectorySpec& spec,
                            const RecordOptions& opt,
                            const std::function<void(const RgbdFrame&)>& on_frame) {
#ifndef RASM_SIM_HAVE_IO
  (void)world, (void)spec, (void)opt, (void)on_frame;
  throw std::runtime_error("rasm sim record: this build has no io module, cannot write rawlogs");
#else
  TSensorParams sp;
  applyOverrides(sp, "sim_sensor", spec.sensor_overrides, spec.source + " sensor:");
  applyOverrides(sp, "sim_sensor", opt.sensor_overrides, "command line");
  TRobotParams rp;
  applyOverrides(rp, "sim_robot", spec.robot_overrides, spec.source + " robot:");
  applyOverrides(rp, "sim_robot", opt.robot_overrides, "command line");

  RecordResult res;
  const fs::path out(opt.out_rawlog);
  const fs::path stem = out.parent_path() / out.stem();
  res.rawlog_path = out.string();
  res.groundtruth_path = stem.string() + "_groundtruth.txt";
  res.labels_dir = opt.write_labels ? stem.string() + "_labels" : std::string();

  io::RawlogWriterOptions wopt;
  wopt.sensor_label = "RGBD_SIM";
  wopt.external_images = opt.external_images;
  io::RawlogWriter writer(out.string(), wopt);
  if (opt.write_labels) {
    fs::create_directories(res.labels_dir);
    for (const auto& e :
         fs::directory_iterator(res.labels_dir)) {  // stale frames of an earlier run
      const std::string n = e.path().filename().string();
      if (n.rfind("instance_", 0) == 0 || n.rfind("class_", 0) == 0) fs::remove(e.path());
    }
  }

  const RayScene scene(world);
  const RgbdSensor sensor(scene, sp);
  const double dt = 1.0 / spec.rate_hz;

  std::unique_ptr<HandheldTrajectory> hand;
  std::unique_ptr<SimulatedDiffDriveRobot> robot;
  std::unique_ptr<PurePursuit> pursuit;
  long long planned = -1;  // frames, when known in advance
  if (spec.kind == TrajectorySpec::Kind::Handheld) {
    hand = std::make_unique<HandheldTrajectory>(spec.keyframes, spec.jitter, opt.seed);
    const double duration = spec.duration_s.value_or(hand->endTime() - hand->startTime());
    planned = (long long)(std::floor(duration * spec.rate_hz + 1e-9)) + 1;
  } else {
    robot = std::make_unique<SimulatedDiffDriveRobot>(scene, rp, spec.start_pose, opt.seed);
    std::vector<Eigen::Vector2d> path{spec.start_pose.head<2>()};
    path.insert(path.end(), spec.waypoints.begin(), spec.waypoints.end());
    pursuit = std::make_unique<PurePursuit>(path, spec.controller, spec.loop, spec.laps);
    if (spec.duration_s)
      planned = (long long)(std::floor(*spec.duration_s * spec.rate_hz + 1e-9)) + 1;
  }
  if (opt.max_frames >= 0 && (planned < 0 || opt.max_frames < planned)) planned = opt.max_frames;
  const long long limit =
      planned >= 0 ? planned
                   : (long long)(std::floor(spec.max_duration_s * spec.rate_hz + 1e-9)) + 1;

  io::Trajectory gt;
  Progress progress(opt.progress);
  RgbdFrame frame;
  double stuck_s = 0.0;
  for (long long i = 0; i < limit; ++i) {
    const double t = double(i) * dt;
    const Eigen::Isometry3d T = hand ? hand->pose(hand->startTime() + t) : robot->cameraPose();
    sensor.render(T, opt.seed, std::size_t(i), frame);
    frame.timestamp_s = t;
    frame.index = std::size_t(i);
    if (robot) frame.odometry_xyyaw = robot->odometry();
    if (on_frame) on_frame(frame);
    writer.write(frame);
    gt.push_back({t, T});
    if (opt.write_labels) {
      char name[64];
      std::snprintf(name, sizeof(name), "/instance_%06lld.png", i);
      saveLabelPng(frame.gt_instance, res.labels_dir + name);
      std::snprintf(name, sizeof(name), "/class_%06lld.png", i);
      saveLabelPng(frame.gt_class, res.labels_dir + name);
    }
    ++res.frames;
    res.duration_s = t;
    double fraction = planned > 0 ? double(i + 1) / double(planned) : 0.0;

    if (robot) {
      if (pursuit->done()) break;
      const int sub = spec.control_substeps;
      for (int k = 0; k < sub; ++k) {
        const Eigen::Vector2d cmd = pursuit->command(robot->pose());
        robot->setVelocityCommand(cmd.x(), cmd.y());
        robot->step(dt / sub);
        stuck_s = robot->collided() ? stuck_s + dt / sub : 0.0;
      }
      if (planned < 0) fraction = pursuit->progress() / pursuit->totalLength();
      if (stuck_s >= 1.0) {
        res.robot_collided = true;
        std::fprintf(stderr,
                     "sim record: warning: the robot has been stuck against an obstacle for 1 s at "
                     "(%.2f, %.2f); "
                     "stopping the recording at frame %lld (check the waypoints of %s)\n",
                     robot->pose().x(), robot->pose().y(), i, spec.source.c_str());
        break;
      }
    }
    progress.update(res.frames, fraction);
  }
  progress.update(res.frames, 1.0, true);
  writer.close();
  io::writeTumTrajectory(res.groundtruth_path, gt,
                         "ground truth T_world_cam (optical frame) of " + out.filename().string() +
                             ", world " + world.name + ", seed " + std::to_string(opt.seed));
  if (opt.write_labels)
    writeClassesJson(world, res.labels_dir + "/classes.json", res.frames, spec.rate_hz);
  return res;
#endif
}

RecordResult recordSequence(const RecordOptions& opt) {
  const World world = loadWorld(opt.world);
  const TrajectorySpec spec = loadTrajectorySpec(opt.trajectory_spec);
  return recordSequence(world, spec, opt);
}

}  // namespace rasm::sim
