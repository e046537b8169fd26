#include "rasm/sim/Recorder.h"

#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <regex>
#include <stdexcept>

#include "rasm/core/AtomicFile.h"
#include "rasm/core/Error.h"
#include "rasm/models/ClassVocabulary.h"
#include "rasm/sim/FrameImages.h"
#include "rasm/sim/SimulatedSequence.h"

#ifdef RASM_SIM_HAVE_IO
#include "rasm/io/RawlogWriter.h"
#include "rasm/io/Trajectory.h"
#endif

namespace fs = std::filesystem;

namespace rasm::sim {

#ifdef RASM_SIM_HAVE_IO
namespace {

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

/// A file `rasm sim record` writes into its labels folder: instance_NNNNNN.png, class_NNNNNN.png,
/// classes.json, or a temporary of one of them (AtomicFile's names: what a killed recording
/// leaves).
bool isLabelsFolderFile(const std::string& name) {
  static const std::regex own(
      R"(((instance|class)_[0-9]{6}\.png|classes\.json)((\.[0-9a-f]{8})?\.part(\.png)?)?)");
  return std::regex_match(name, own);
}

/// The labels folder `dir`, made ready for a recording: created when missing (never its parent
/// folders); else refused, unchanged, when it holds anything a recording does not write (the
/// user's files), and the files of an earlier recording removed (stale frames of a longer one).
void prepareLabelsFolder(const std::string& dir) {
  std::error_code ec;
  if (!fs::exists(fs::symlink_status(dir, ec))) {
    requireParentFolder(dir, "labels folder '" + dir + "'");
    fs::create_directory(dir, ec);
    if (ec) throwInputError("labels folder '" + dir + "'", "cannot be created: " + ec.message());
    return;
  }
  if (!fs::is_directory(fs::symlink_status(dir, ec)))
    throwInputError("labels folder '" + dir + "'", "is not a folder");
  std::vector<fs::path> own;
  std::string others;
  for (const auto& e : fs::directory_iterator(dir)) {
    const std::string n = e.path().filename().string();
    if (isLabelsFolderFile(n) && !e.is_directory(ec))
      own.push_back(e.path());
    else
      others += (others.empty() ? "'" : ", '") + n + "'";
  }
  if (!others.empty())
    throwInputError("labels folder '" + dir + "'",
                    "holds files rasm sim record did not write: " + others +
                        ". Nothing was changed: record to another name, or move them away");
  for (const fs::path& p : own) fs::remove(p, ec);  // a link itself, never its target
}

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
  for (int i = 0; i < models::numClasses(); ++i)
    classes.push_back(
        {{"id", i}, {"name", models::className(i)}, {"coco", models::isCocoClass(i)}});
  j["classes"] = classes;
  nlohmann::json inst = nlohmann::json::array();
  for (const WorldObject& o : world.objects)
    inst.push_back({{"id", o.instance_id},
                    {"class_id", o.class_id},
                    {"class", models::className(o.class_id)},
                    {"name", o.name},
                    {"static", o.is_static},
                    {"mesh", fs::path(o.mesh_source).filename().string()}});
  j["instances"] = inst;
  try {
    writeFileAtomic(path, j.dump(1) + "\n");
  } catch (const std::runtime_error& e) {
    throwInputError(path, e.what());
  }
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
  SequenceOptions sopt;
  sopt.seed = opt.seed;
  sopt.sensor_overrides = opt.sensor_overrides;
  sopt.robot_overrides = opt.robot_overrides;
  sopt.max_frames = opt.max_frames;
  SimulatedSequence seq(world, spec, sopt);

  RecordResult res;
  const fs::path out(opt.out_rawlog);
  const fs::path stem = out.parent_path() / out.stem();
  res.rawlog_path = out.string();
  res.groundtruth_path = stem.string() + "_groundtruth.txt";
  res.labels_dir = opt.write_labels ? stem.string() + "_labels" : std::string();

  io::RawlogWriterOptions wopt;
  wopt.sensor_label = "RGBD_SIM";
  wopt.external_images = opt.external_images;
  requireParentFolder(out.string(), "output '" + out.string() + "'");
  if (opt.write_labels) prepareLabelsFolder(res.labels_dir);  // before anything is written
  io::RawlogWriter writer(out.string(), wopt);

  io::Trajectory gt;
  Progress progress(opt.progress);
  RgbdFrame frame;
  while (seq.next(frame)) {
    if (on_frame) on_frame(frame);
    writer.write(frame);
    gt.push_back({frame.timestamp_s, *frame.gt_T_world_cam});
    if (opt.write_labels && !frame.gt_instance.empty()) {  // [sim_sensor] labels = false: none
      char name[64];
      std::snprintf(name, sizeof(name), "/instance_%06zu.png", frame.index);
      saveLabelPng(frame.gt_instance, res.labels_dir + name);
      std::snprintf(name, sizeof(name), "/class_%06zu.png", frame.index);
      saveLabelPng(frame.gt_class, res.labels_dir + name);
    }
    ++res.frames;
    res.duration_s = frame.timestamp_s;
    progress.update(res.frames, seq.progress());
  }
  res.robot_collided = seq.robotStuck();
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
