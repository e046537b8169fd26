// `rasm run [file.ini | FOLDER | FILE.rawlog] [options]`: one mapping run
// (rasm::run::MappingRun) and its summary. Its options other than --set stand for INI keys and
// apply in the order given.
#include <cstdio>
#include <filesystem>
#include <initializer_list>
#include <iostream>
#include <nlohmann/json.hpp>
#include <string>

#include "Command.h"
#include "rasm/core/Error.h"
#include "rasm/core/Printable.h"
#include "rasm/pipeline/Interrupts.h"
#include "rasm/run/MappingRun.h"

namespace {

/// " (a, b)": those of `names` the run wrote (report.json "files"), so that the summary names only
/// files that exist ([output] write_ply = false and the like); "" when none.
std::string writtenAmong(const nlohmann::json& report, std::initializer_list<const char*> names) {
  std::string list;
  const auto files = report.find("files");
  if (files == report.end() || !files->is_array()) return list;
  for (const char* n : names)
    for (const auto& f : *files)
      if (f.is_string() && f.get<std::string>() == n)
        list += (list.empty() ? "" : ", ") + std::string(n);
  return list.empty() ? list : " (" + list + ")";
}

/// The run's accuracy against the ground truth: first the world-frame error (no alignment) when
/// the run started at the true pose, then the ATE after its SE(3) alignment; nothing without
/// ground truth.
void printAccuracy(const rasm::run::RunSummary& s) {
  const std::size_t tracked_frames = s.frames - s.lost;
  if (const auto& w = s.world_error) {
    char tracked[128] = "";
    if (s.world_error_tracked && s.lost > 0)
      std::snprintf(tracked, sizeof tracked, " (over the %zu tracked: RMS %.1f cm, max %.1f cm)",
                    s.world_error_tracked->frames, 100.0 * s.world_error_tracked->rms_m,
                    100.0 * s.world_error_tracked->max_m);
    std::printf(
        "world-frame error (no alignment, against %s): RMS %.1f cm, max %.1f cm; height max %.1f "
        "cm; tilt max %.2f deg; heading max %.2f deg over %zu frames%s\n",
        s.truth.c_str(), 100.0 * w->rms_m, 100.0 * w->max_m, 100.0 * w->vertical_max_m,
        w->tilt_max_deg, w->heading_max_deg, w->frames, tracked);
  }
  if (!s.ate_rmse_m) return;
  char tracked[96] = "";
  if (s.ate_tracked_rmse_m && s.lost > 0)
    std::snprintf(tracked, sizeof tracked, ", %.4f m over the %zu tracked", *s.ate_tracked_rmse_m,
                  tracked_frames);
  std::printf(
      "ATE RMSE %.4f m after SE(3) alignment, over all %zu frames (lost ones at their propagated "
      "pose)%s\n",
      *s.ate_rmse_m, s.frames, tracked);
}

/// The warning of report.json floor_drift: only when the map's floor drifted beyond [robot]
/// floor_target_* on more than floor_target_max_fraction of the tracked frames.
void printFloorDrift(const nlohmann::json& report) {
  const auto f = report.find("floor_drift");
  if (f == report.end() || !(*f)["drifted"].get<bool>()) return;
  std::printf(
      "WARNING: the map's floor drifted: camera height off by %.1f cm (median; max %.1f), tilted "
      "%.2f deg (median; max %.2f) over %zu tracked frames, %.0f%% of them beyond %.1f cm / %.2f "
      "deg ([robot] floor_target_*; report.json floor_drift, frames.csv floor_height_m, "
      "floor_tilt_deg)\n",
      100.0 * (*f)["height_error_m"]["median"].get<double>(),
      100.0 * (*f)["height_error_m"]["max"].get<double>(), (*f)["tilt_deg"]["median"].get<double>(),
      (*f)["tilt_deg"]["max"].get<double>(), (*f)["frames"].get<std::size_t>(),
      100.0 * (*f)["fraction_beyond_target"].get<double>(),
      100.0 * (*f)["target_height_m"].get<double>(), (*f)["target_tilt_deg"].get<double>());
}

/// Whether `rasm run`'s file argument names data rather than an INI: a folder (TUM RGB-D,
/// ICL-NUIM or 7-Scenes) or a rawlog. Such data is mapped with the embedded default's settings
/// and [source] type = auto (io::openFrameSource picks the reader, or names what it expected).
bool isDataset(const std::string& path) {
  const auto ends = [&path](const std::string& ext) {
    return path.size() >= ext.size() &&
           path.compare(path.size() - ext.size(), ext.size(), ext) == 0;
  };
  return std::filesystem::is_directory(path) || ends(".rawlog") || ends(".rawlog.gz");
}

const rasm::app::CommandDecl kDecl{
    "run",
    "map a sequence: rasm run [file.ini | FOLDER | FILE.rawlog] [--set s.k=v] [--out DIR]",
    {{"file.ini | FOLDER | FILE.rawlog",
      "the configuration, or data mapped with the embedded default's settings", false}},
    {{"set", "section.key=value", "set one key of the configuration", "", true},
     {"out", "DIR", "the output folder ([output] dir)"},
     {"force", "", "write into a folder holding other files ([output] overwrite = true)"},
     {"max-frames", "N", "stop after N frames ([source] max_frames)"},
     {"map", "map.surfelmap", "start from a saved map ([mapper] load_map)"},
     {"view", "", "open the live 3-D window ([view] enabled = true)"},
     {"quiet", "", "warnings and errors only ([output] log_level = warning)", "q"},
     {"verbose", "", "every message ([output] log_level = debug); errors in full", "v"}},
    "Without a file, runs the embedded default (the simulated office, ini/default.ini).\n"
    "A folder (TUM RGB-D, ICL-NUIM, 7-Scenes sequence) or a rawlog is mapped with the\n"
    "default's settings and its own camera ([source] type = auto, path = it).\n"
    "--out DIR: an empty or new folder (created; its parent folder must exist), or one\n"
    "of an earlier rasm run (only the files it listed in DIR/.rasm-run.json are\n"
    "removed). A folder holding other files is refused; --force ([output] overwrite =\n"
    "true) writes beside them: they are left alone, only rasm's own file names are\n"
    "replaced.\n"
    "--view ([view] enabled) opens a 3-D window that shows the map growing, the path and\n"
    "the camera (keys: 1 colour, 2 segments, 3 classes, p paths); it needs a display.\n"
    "-q / --quiet shows warnings and errors only, -v / --verbose every message\n"
    "([output] log_level); DIR/run.log holds every message of the run, time-stamped.\n"};

/// The configuration overrides the options stand for, in the order given.
std::vector<std::string> overridesOf(const rasm::app::ParsedArgs& args) {
  std::vector<std::string> overrides;
  for (const auto& [option, value] : args.given()) {
    if (option == "set")
      overrides.push_back(value);
    else if (option == "out")
      overrides.push_back("output.dir=" + value);
    else if (option == "force")
      overrides.push_back("output.overwrite=true");
    else if (option == "max-frames")
      overrides.push_back("source.max_frames=" + value);
    else if (option == "map")
      overrides.push_back("mapper.load_map=" + value);
    else if (option == "view")
      overrides.push_back("view.enabled=true");
    else if (option == "quiet")
      overrides.push_back("output.log_level=warning");
    else if (option == "verbose")
      overrides.push_back("output.log_level=debug");
  }
  return overrides;
}

int printSummary(const rasm::run::MappingRun& run, const rasm::run::RunSummary& s);

int runMain(const rasm::app::ParsedArgs& args) {
  using namespace rasm::pipeline;
  using namespace rasm::run;
  const std::string ini_path = args.positional(kDecl.positionals[0].name);
  const std::vector<std::string> overrides = overridesOf(args);
  const bool dataset = !ini_path.empty() && isDataset(ini_path);
  RunConfig cfg =
      ini_path.empty() || dataset ? RunConfig::embeddedDefault() : RunConfig::fromFile(ini_path);
  if (dataset) {  // before the --set overrides, which may still change them
    cfg.applyOverride("source.type=auto");
    cfg.applyOverride("source.path=" + std::filesystem::absolute(ini_path).string());
  }
  for (const auto& o : overrides) cfg.applyOverride(o);
  MappingRun run(cfg);
  // SIGINT / SIGTERM: stop after the current frame and write its outputs; again: abort at once.
  installInterruptHandlers();
  return printSummary(run, run.run());
}

/// What the run did, after it: frames, accuracy, outputs, segments, objects, exploration and
/// warnings; returns the exit code (128 + the signal when interrupted).
int printSummary(const rasm::run::MappingRun& run, const rasm::run::RunSummary& s) {
  using rasm::pipeline::signalName;
  const double lost_pct = s.frames ? 100.0 * double(s.lost) / double(s.frames) : 0.0;
  std::printf(
      "frames %zu (tracked %zu, lost %zu = %.1f%% in %zu intervals, %zu relocalisations) in %.1f s "
      "= %.2f "
      "frames/s, %zu surfels\n",
      s.frames, s.frames - s.lost, s.lost, lost_pct, s.lost_intervals, s.relocalisations, s.seconds,
      s.fps, s.surfels);
  const bool gt_poses = run.mapper().mapperParams().poses == "groundtruth";
  if (gt_poses) {
    std::printf(
        "poses: the source's ground truth ([mapper] poses = groundtruth), not tracked: no ATE\n");
  } else {
    printAccuracy(s);
  }
  const std::string out_dir = rasm::escapeControlChars(s.out_dir);  // echoed: no raw escapes
  std::printf("outputs in %s\n", out_dir.c_str());
  if (const auto seg = s.report.find("segmentation");
      seg != s.report.end() && seg->contains("segments"))
    std::printf("segments: %d%s\n", (*seg)["segments"].get<int>(),
                writtenAmong(s.report, {"segments.json", "map_segments.ply", "map_segments.3Dscene",
                                        "preview_segments.png"})
                    .c_str());
  if (const auto cls = s.report.find("classification");
      cls != s.report.end() && cls->contains("objects")) {
    std::string by_class;
    for (const auto& [name, n] : (*cls)["objects_by_class"].items())
      by_class += (by_class.empty() ? "" : ", ") + name + " " + std::to_string(n.get<int>());
    std::printf("objects: %d named%s%s%s%s; rasm objects %s\n", (*cls)["objects"].get<int>(),
                by_class.empty() ? "" : " (", by_class.c_str(), by_class.empty() ? "" : ")",
                writtenAmong(s.report, {"objects.json", "map_classes.ply", "map_classes.3Dscene",
                                        "preview_classes.png"})
                    .c_str(),
                out_dir.c_str());
    if (cls->contains("objects_correct"))  // a simulated run that did not explore
      std::printf(
          "objects against the simulated world: %d of its %d detectable objects carry their "
          "class (frames.csv objects_correct, plot_objects.png)\n",
          (*cls)["objects_correct"].get<int>(), (*cls)["objects_detectable"].get<int>());
    for (const auto& d : (*cls)["detectors"])
      if (d.contains("disabled"))
        std::printf("WARNING: %s\n", d["disabled"].get<std::string>().c_str());
  }
  if (s.explored) {
    const auto& r = s.report;
    const auto& x = r["exploration"];
    std::printf(
        "exploration (%s planner): stopped by %s after %.0f simulated s, %.1f m driven, %d goals "
        "(%d reached); coverage %.3f of the world's observable surface; %d of %d detectable "
        "objects carry their class (exploration.json, exploration.png)\n",
        x["planner"].get<std::string>().c_str(), r["stop_reason"].get<std::string>().c_str(),
        r["sim_time_s"].get<double>(), r["path_length_m"].get<double>(), x["goals"].get<int>(),
        x["goals_reached"].get<int>(), r["coverage_fraction"].get<double>(),
        x["objects_correct"].get<int>(), x["objects_detectable"].get<int>());
  }
  if (lost_pct > 5.0)
    std::printf(
        "WARNING: tracking lost %.1f%% of the frames (%zu of %zu, frames.csv: tracked = 0); the "
        "map holds only "
        "the tracked ones\n",
        lost_pct, s.lost, s.frames);
  printFloorDrift(s.report);
  if (s.interrupted_by != 0) {
    std::printf(
        "INTERRUPTED by %s: the outputs hold the %zu frames done (report.json: status "
        "interrupted)\n",
        signalName(s.interrupted_by).c_str(), s.frames);
    return 128 + s.interrupted_by;
  }
  return 0;
}

const rasm::app::Registrar reg{kDecl, &runMain};

}  // namespace
