// `rasm eval ate|rpe`: TUM benchmark trajectory metrics (rasm::io::TrajectoryEvaluator).
// `rasm eval segmentation`: a run's segmented map against the simulator's ground truth
// (rasm::segmentation::computeSegmentationMetrics, rasm::sim::SurfaceInstanceQuery;
// docs/segmentation.md "Evaluation").
#include <mrpt/config/CConfigFile.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <optional>

#include "Command.h"
#include "RunObjects.h"
#include "rasm/core/AtomicFile.h"
#include "rasm/core/Error.h"
#include "rasm/io/EvaluationJson.h"
#include "rasm/io/TrajectoryEvaluator.h"
#if defined(RASM_HAVE_MODULE_SIM) && defined(RASM_HAVE_MODULE_SEGMENTATION) && \
    defined(RASM_HAVE_MODULE_SURFEL_MAP)
#define RASM_EVAL_SEGMENTATION 1
#include "rasm/segmentation/SegmentationMetrics.h"
#include "rasm/sim/RayScene.h"
#include "rasm/sim/SurfaceInstance.h"
#include "rasm/sim/World.h"
#include "rasm/surfel_map/MapExport.h"
#endif
#if defined(RASM_EVAL_SEGMENTATION) && defined(RASM_HAVE_MODULE_CLASSIFICATION)
#define RASM_EVAL_CLASSIFICATION 1
#include "rasm/classification/ClassificationMetrics.h"
#include "rasm/models/ClassVocabulary.h"
#endif

namespace {

using rasm::app::CommandDecl;
using rasm::app::OptionDecl;
using rasm::app::ParsedArgs;

const char* kTrajectoryNotes =
    "Trajectories in TUM format (timestamp tx ty tz qx qy qz qw). ATE aligns the estimate to the\n"
    "ground truth (Horn/Umeyama, SE(3); --scale: Sim(3)); RPE uses intervals of D s (default 1)\n"
    "or D frames (--frames).\n";
const char* kSegmentationNotes =
    "Segmentation: <run folder>/map.ply of `rasm run` against the simulator world of its\n"
    "config.ini ([sim] world; --world for runs of a rawlog recorded in the simulator): each\n"
    "surfel takes the instance of the nearest world surface (none beyond --max-dist-m);\n"
    "docs/segmentation.md.\n";

const CommandDecl kEvalDecl{
    "eval",
    "trajectory metrics: ate | rpe <groundtruth.txt> <estimate.txt>; segmentation | classification "
    "<run folder>",
    {},
    {},
    std::string(kTrajectoryNotes) + kSegmentationNotes};

const OptionDecl kJson{"json", "out.json", "also write the result as JSON"};
const OptionDecl kOffset{"offset", "S", "added to the estimate's timestamps, s (default 0)"};

const CommandDecl kAteDecl{
    "eval ate",
    "absolute trajectory error of an estimate against the ground truth",
    {{"groundtruth.txt", "the ground-truth trajectory (TUM format)"},
     {"estimate.txt", "the estimated trajectory (TUM format)"}},
    {{"no-align", "", "no alignment: both trajectories in the same world frame"},
     {"scale", "", "Sim(3) alignment (scale too) instead of SE(3)"},
     {"max-dt", "S", "largest time difference of an associated pose pair, s (default 0.02)"},
     kOffset,
     kJson},
    kTrajectoryNotes};

const CommandDecl kRpeDecl{
    "eval rpe",
    "relative pose error of an estimate against the ground truth",
    {{"groundtruth.txt", "the ground-truth trajectory (TUM format)"},
     {"estimate.txt", "the estimated trajectory (TUM format)"}},
    {{"delta", "D", "the interval: D s, or D frames with --frames (default 1)"},
     {"frames", "", "--delta counts frames, not seconds"},
     kOffset,
     kJson},
    kTrajectoryNotes};

#ifdef RASM_EVAL_SEGMENTATION
/// The options `rasm eval segmentation` and `rasm eval classification` share.
std::vector<OptionDecl> runEvalOptions() {
  return {
      {"world", "NAME|YAML", "the ground-truth world (default: [sim] world of its config.ini)"},
      kJson,
      {"max-dist-m", "D", "a surfel farther from every world surface has none (default 0.05)"},
      {"min-size-m", "S", "objects smaller than this are not evaluated (default 0.10)"},
      {"min-surfels", "N", "objects with fewer surfels in the map are not evaluated (default 50)"}};
}

CommandDecl segmentationDecl() {
  CommandDecl d{"eval segmentation",
                "a run's segmented map against the simulator's ground truth",
                {{"run folder", "the output folder of `rasm run` (map.ply, config.ini)"}},
                runEvalOptions(),
                kSegmentationNotes};
  d.options.push_back({"stable-only", "", "only the surfels marked stable"});
  return d;
}

#endif
#ifdef RASM_EVAL_CLASSIFICATION
CommandDecl classificationDecl() {
  return {"eval classification",
          "a run's classified objects against the simulator's ground truth",
          {{"run folder", "the output folder of `rasm run` (map.ply, objects.json, config.ini)"}},
          runEvalOptions(),
          kSegmentationNotes};
}
#endif

double parseNumber(const std::string& opt, const std::string& text) {
  try {
    std::size_t n = 0;
    const double v = std::stod(text, &n);
    if (n == text.size() && std::isfinite(v)) return v;
  } catch (const std::exception&) {
  }
  rasm::throwInputError(opt, "'" + text + "' is not a finite number");
}

/// A number > 0 (seconds, frames).
double parsePositive(const std::string& opt, const std::string& text, const char* unit) {
  const double v = parseNumber(opt, text);
  if (!(v > 0))
    rasm::throwInputError(opt + " " + text, std::string("expected a value > 0 ") + unit);
  return v;
}

/// A TUM trajectory file with at least one pose (a folder, an empty or comment-only file are
/// errors naming it).
rasm::io::Trajectory readTrajectoryFile(const std::string& path, const char* role) {
  auto t = rasm::io::readTumTrajectory(path);
  if (t.empty())
    rasm::throwInputError(std::string(role) + " " + path,
                          "holds no pose (expected TUM lines 'timestamp tx ty tz qx qy qz qw')");
  return t;
}

void printStats(const char* name, const char* unit, const rasm::io::ErrorStats& s) {
  std::printf(
      "  %-12s %-5s rmse %10.6f  mean %10.6f  median %10.6f  std %10.6f  min %10.6f  max %10.6f\n",
      name, unit, s.rmse, s.mean, s.median, s.std, s.min, s.max);
}

void writeJson(const std::string& path, const nlohmann::json& j) {
  try {
    rasm::writeFileAtomic(path, j.dump(2) + "\n");
  } catch (const std::runtime_error& e) {
    rasm::throwInputError("--json " + path, e.what());
  }
  std::cout << "wrote " << path << "\n";
}

#ifdef RASM_EVAL_SEGMENTATION

namespace fs = std::filesystem;

/// Finite numbers as numbers, NaN (undefined) as null.
nlohmann::json num(double v) {
  return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json();
}

std::string fmt(double v, const char* f = "%.3f") {
  if (!std::isfinite(v)) return "n/a";
  char b[64];
  std::snprintf(b, sizeof b, f, v);
  return b;
}

void writeJsonAtomically(const std::string& out, const nlohmann::json& j) {
  try {
    rasm::writeFileAtomic(out, j.dump(2) + "\n");
  } catch (const std::runtime_error& e) {
    rasm::throwInputError("--json " + out, e.what());
  }
  std::cout << "wrote " << out << "\n";
}

/// The world a run was made in: --world, else [sim] world of <run>/config.ini when [source]
/// type = sim. A relative world path that does not resolve from here is tried from the run folder.
std::string runWorld(const std::string& run, const std::string& world_opt) {
  const auto resolve = [&](const std::string& w, const std::string& what) {
    try {
      return rasm::sim::resolveWorldPath(w);
    } catch (const rasm::InputError& e) {
      const fs::path rel = fs::path(run) / w;
      if (fs::path(w).is_relative() && fs::is_regular_file(rel)) return rel.string();
      rasm::throwInputError(what, e.what());
    }
  };
  if (!world_opt.empty()) return resolve(world_opt, "--world " + world_opt);
  const std::string ini = (fs::path(run) / "config.ini").string();
  if (!fs::is_regular_file(ini))
    rasm::throwInputError(ini,
                          "missing; expected the config.ini that `rasm run` writes (its [sim] "
                          "world names the world), or pass --world <name or yaml>");
  const mrpt::config::CConfigFile cfg(ini);
  const std::string type = cfg.read_string("source", "type", "sim");
  if (type != "sim") {
    const std::string path = cfg.read_string("source", "path", "");
    rasm::throwInputError(
        ini, "[source] type = " + type + (path.empty() ? "" : " (path " + path + ")") +
                 ": the run did not render a simulator world, so config.ini does not say which "
                 "world is the ground truth; pass --world <name or yaml> (the world the rawlog "
                 "was recorded in with `rasm sim record`)");
  }
  const std::string w = cfg.read_string("sim", "world", "");
  if (w.empty())
    rasm::throwInputError(ini,
                          "[sim] world is missing or empty; expected a world name or YAML "
                          "file, or pass --world");
  return resolve(w, ini + " [sim] world = " + w);
}

struct Target {
  double recovered, pq;
};
/// The targets for the shipped worlds that have them.
std::optional<Target> targetsOf(const std::string& world) {
  if (world == "office") return Target{0.85, 0.6};
  if (world == "cluttered_lab") return Target{0.70, 0.5};
  return std::nullopt;
}

/// Label-stability counters of <run>/report.json "segmentation" (absent: nullopt).
std::optional<std::pair<std::uint64_t, std::uint64_t>> labelCounters(const std::string& run) {
  const std::string path = (fs::path(run) / "report.json").string();
  if (!fs::is_regular_file(path)) return std::nullopt;
  std::ifstream f(path);
  nlohmann::json j;
  try {
    f >> j;
  } catch (const std::exception& e) {
    rasm::throwInputError(path, std::string("not valid JSON (") + e.what() + ")");
  }
  if (!j.is_object() || !j.contains("segmentation") || !j["segmentation"].is_object())
    return std::nullopt;
  const nlohmann::json& s = j["segmentation"];
  const auto count = [&](const char* key) -> std::optional<std::uint64_t> {
    if (!s.contains(key)) return std::nullopt;
    if (!s[key].is_number_integer() || s[key].get<long long>() < 0)
      rasm::throwInputError(
          path, std::string("segmentation.") + key + ": expected a non-negative integer");
    return s[key].get<std::uint64_t>();
  };
  const auto changes = count("label_changes_stable"), stable = count("stable_surfels");
  if (!changes || !stable) return std::nullopt;
  return std::make_pair(*changes, *stable);
}

/// Options shared by `rasm eval segmentation` and `rasm eval classification`.
struct RunEvalOptions {
  std::string run, json, world;
  double max_dist_m = 0.05;
  double min_size_m = 0.10;
  std::size_t min_surfels = 50;
  bool stable_only = false;
};

/// The options of `rasm eval segmentation` and `rasm eval classification`, checked.
RunEvalOptions runEvalOptionsOf(const ParsedArgs& args) {
  RunEvalOptions o;
  o.run = args.positional("run folder");
  o.json = args.value("json");
  o.world = args.value("world");
  if (args.has("max-dist-m")) o.max_dist_m = parseNumber("--max-dist-m", args.value("max-dist-m"));
  if (args.has("min-size-m")) o.min_size_m = parseNumber("--min-size-m", args.value("min-size-m"));
  if (args.has("min-surfels")) {
    const double v = parseNumber("--min-surfels", args.value("min-surfels"));
    if (!(v >= 0.0) || v != std::floor(v))
      rasm::throwInputError("--min-surfels", "expected a non-negative integer");
    o.min_surfels = std::size_t(v);
  }
  o.stable_only = args.has("stable-only");
  if (!(o.max_dist_m > 0.0) || !std::isfinite(o.max_dist_m))
    rasm::throwInputError("--max-dist-m", "expected a distance > 0");
  if (!(o.min_size_m >= 0.0) || !std::isfinite(o.min_size_m))
    rasm::throwInputError("--min-size-m", "expected a size >= 0");
  return o;
}

/// What `rasm eval segmentation` measured on one run, for the summary and the JSON.
struct SegmentationEvaluation {
  std::string run, ply;
  std::string world_name, world_source;
  std::size_t surfels_in_file = 0, unassigned = 0, structure = 0, instances_in_world = 0;
  double max_dist = 0;
  rasm::segmentation::SegmentationMetricsParams mp;
  rasm::segmentation::SegmentationMetrics m;
  std::optional<std::pair<std::uint64_t, std::uint64_t>> counters;  ///< label changes, stable
  double lcps = 0;
  std::optional<Target> target;
};

bool passes(double v, double t) {
  return std::isfinite(v) && v >= t;
}

void printSegmentationSummary(const SegmentationEvaluation& e) {
  const auto& m = e.m;
  const auto& mp = e.mp;
  const auto& counters = e.counters;
  const auto& target = e.target;
  const auto pass = passes;
  std::printf("segmentation of %s against world %s (%s)\n", e.ply.c_str(), e.world_name.c_str(),
              e.world_source.c_str());
  std::printf(
      "  covers: %zu %ssurfels, %zu objects > %.2f m evaluated, %zu surfels unassigned "
      "(> %.3g m from any surface)\n",
      m.surfels, mp.stable_only ? "stable " : "", m.objects_evaluated, mp.min_object_size_m,
      e.unassigned, e.max_dist);
  std::printf(
      "  world: %zu instances: %zu structure (floor/wall/ceiling/door), %zu objects, %zu of "
      "them > %.2f m, %zu of those with < %zu surfels in the map (not evaluated)\n",
      e.instances_in_world, e.structure, m.objects_listed, m.objects_over_size,
      mp.min_object_size_m, m.objects_unseen, mp.min_object_surfels);
  std::printf("  map: %zu segments, %zu surfels with a segment (%.1f %%)\n", m.segments,
              m.segmented_surfels, 100.0 * double(m.segmented_surfels) / double(m.surfels));
  std::printf("  objects recovered (IoU > %.2f)   %zu / %zu = %s\n", mp.iou_threshold, m.recovered,
              m.objects_evaluated, fmt(m.objects_recovered_fraction).c_str());
  std::printf("  PQ %s = SQ %s x RQ %s   (TP %zu, FP %zu, FN %zu)\n", fmt(m.pq).c_str(),
              fmt(m.sq).c_str(), fmt(m.rq).c_str(), m.tp, m.fp, m.fn);
  std::printf("  segments per object              %s   (%zu objects own no segment)\n",
              fmt(m.segments_per_object, "%.2f").c_str(), m.objects_without_segment);
  std::printf("  under-segmented objects          %zu / %zu\n", m.undersegmented_objects,
              m.objects_evaluated);
  if (counters)
    std::printf("  label changes per stable surfel  %s   (%llu changes, %llu stable surfels)\n",
                fmt(e.lcps, "%.4f").c_str(), (unsigned long long)counters->first,
                (unsigned long long)counters->second);
  else
    std::printf(
        "  label changes per stable surfel  n/a (%s/report.json has no segmentation "
        "counters)\n",
        e.run.c_str());
  if (target) {
    std::printf("  targets (%s): recovered >= %.2f %s (%s), PQ >= %.2f %s (%s)\n",
                e.world_name.c_str(), target->recovered,
                pass(m.objects_recovered_fraction, target->recovered) ? "PASS" : "MISS",
                fmt(m.objects_recovered_fraction).c_str(), target->pq,
                pass(m.pq, target->pq) ? "PASS" : "MISS", fmt(m.pq).c_str());
  } else {
    std::printf("  targets: none for world %s (office, cluttered_lab have them)\n",
                e.world_name.c_str());
  }
  std::printf("  %8s %-18s %-16s %8s %7s %6s %5s %5s %s\n", "instance", "class", "name", "surfels",
              "best", "IoU", "segs", "under", "");
  for (const rasm::segmentation::ObjectResult& r : m.per_object) {
    if (!r.evaluated) continue;
    std::string note = r.recovered ? "recovered" : "";
    if (r.undersegmented)
      note += std::string(note.empty() ? "" : ", ") + "with " + std::to_string(r.merged_with);
    std::printf("  %8u %-18s %-16s %8zu %7u %6.3f %5zu %5s %s\n", r.object.instance_id,
                r.object.class_name.c_str(), r.object.name.c_str(), r.surfels, r.best_segment,
                r.iou, r.owned_segments, r.undersegmented ? "yes" : "no", note.c_str());
  }
}

nlohmann::json segmentationJson(const SegmentationEvaluation& e) {
  const auto& m = e.m;
  const auto& mp = e.mp;
  const auto& counters = e.counters;
  const auto& target = e.target;
  const auto pass = passes;
  nlohmann::json j;
  j["run"] = e.run;
  j["map"] = e.ply;
  j["world"] = e.world_name;
  j["world_source"] = e.world_source;
  j["surfels_in_file"] = e.surfels_in_file;
  j["surfels"] = m.surfels;
  j["stable_only"] = mp.stable_only;
  j["surfels_unassigned"] = e.unassigned;
  j["max_dist_m"] = e.max_dist;
  j["segments"] = m.segments;
  j["segmented_surfels"] = m.segmented_surfels;
  j["iou_threshold"] = mp.iou_threshold;
  j["min_object_size_m"] = mp.min_object_size_m;
  j["min_object_surfels"] = mp.min_object_surfels;
  j["instances_in_world"] = e.instances_in_world;
  j["structure_instances"] = e.structure;
  j["objects_in_world"] = m.objects_listed;
  j["objects_over_min_size"] = m.objects_over_size;
  j["objects_not_evaluated"] = m.objects_unseen;
  j["objects_evaluated"] = m.objects_evaluated;
  j["objects_recovered"] = m.recovered;
  j["objects_recovered_fraction"] = num(m.objects_recovered_fraction);
  j["pq"] = num(m.pq);
  j["sq"] = num(m.sq);
  j["rq"] = num(m.rq);
  j["tp"] = m.tp;
  j["fp"] = m.fp;
  j["fn"] = m.fn;
  j["segments_per_object"] = num(m.segments_per_object);
  j["objects_without_segment"] = m.objects_without_segment;
  j["undersegmented_objects"] = m.undersegmented_objects;
  j["undersegmented_fraction"] = num(m.undersegmented_fraction);
  j["label_changes_stable"] = counters ? nlohmann::json(counters->first) : nlohmann::json();
  j["stable_surfels"] = counters ? nlohmann::json(counters->second) : nlohmann::json();
  j["label_changes_per_stable_surfel"] = num(e.lcps);
  if (target) {
    j["targets"] = {
        {"objects_recovered_fraction",
         {{"target", target->recovered},
          {"value", num(m.objects_recovered_fraction)},
          {"pass", pass(m.objects_recovered_fraction, target->recovered)}}},
        {"pq", {{"target", target->pq}, {"value", num(m.pq)}, {"pass", pass(m.pq, target->pq)}}}};
  } else {
    j["targets"] = nullptr;
  }
  nlohmann::json rows = nlohmann::json::array();
  for (const rasm::segmentation::ObjectResult& r : m.per_object) {
    rows.push_back({{"instance", r.object.instance_id},
                    {"class_id", r.object.class_id},
                    {"class", r.object.class_name},
                    {"name", r.object.name},
                    {"static", r.object.is_static},
                    {"size_m", r.object.size_m},
                    {"surfels", r.surfels},
                    {"unsegmented_surfels", r.unsegmented},
                    {"evaluated", r.evaluated},
                    {"best_segment", r.best_segment},
                    {"iou", r.iou},
                    {"recovered", r.recovered},
                    {"dominant_segment", r.dominant_segment},
                    {"segments", r.owned_segments},
                    {"undersegmented", r.undersegmented},
                    {"merged_with", r.merged_with}});
  }
  j["objects"] = std::move(rows);
  return j;
}

int evalSegmentation(const ParsedArgs& args) {
  const RunEvalOptions o = runEvalOptionsOf(args);
  const std::string json = o.json, world_opt = o.world;
  const double max_dist = o.max_dist_m;
  rasm::segmentation::SegmentationMetricsParams mp;
  mp.min_object_size_m = o.min_size_m;
  mp.min_object_surfels = o.min_surfels;
  mp.stable_only = o.stable_only;
  const std::string& run = o.run;
  if (!fs::is_directory(run))
    rasm::throwInputError(run,
                          "no such folder; expected the output folder of `rasm run` (with "
                          "map.ply and config.ini)");
  const std::string ply = (fs::path(run) / "map.ply").string();
  if (!fs::is_regular_file(ply))
    rasm::throwInputError(ply, "missing; expected the surfel PLY that `rasm run` writes");
  const std::string world_path = runWorld(run, world_opt);

  const rasm::maps::PlySurfels map = rasm::maps::readSurfelPly(ply);
  if (map.size() == 0) rasm::throwInputError(ply, "no surfels; nothing to evaluate");
  if (mp.stable_only &&
      std::none_of(map.stable.begin(), map.stable.end(), [](std::uint8_t s) { return s != 0; }))
    rasm::throwInputError(ply, "no stable surfels (--stable-only)");
  const rasm::sim::RayScene scene(rasm::sim::loadWorld(world_path));
  const rasm::sim::World& world = scene.world();
  const rasm::sim::SurfaceInstanceQuery query(scene);

  std::vector<Eigen::Vector3f> positions(map.size());
  for (std::size_t i = 0; i < map.size(); ++i) positions[i] = map.position[i];
  const std::vector<rasm::sim::NearestSurface> nearest = query.nearest(positions, float(max_dist));
  std::vector<std::uint32_t> instance(map.size());
  std::size_t unassigned = 0;
  for (std::size_t i = 0; i < map.size(); ++i) {
    instance[i] = nearest[i].instance_id;
    if (instance[i] == 0 && (!mp.stable_only || map.stable[i])) ++unassigned;
  }

  std::vector<rasm::segmentation::GtObject> objects;
  std::size_t structure = 0;
  for (const rasm::sim::WorldInstanceInfo& w : rasm::sim::worldInstances(world)) {
    if (w.is_structure) {
      ++structure;
      continue;
    }
    rasm::segmentation::GtObject o;
    o.instance_id = w.instance_id;
    o.class_id = w.class_id;
    o.class_name = w.class_name;
    o.name = w.name;
    o.size_m = w.size_m;
    o.is_static = w.is_static;
    objects.push_back(std::move(o));
  }
  const rasm::segmentation::SegmentationMetrics m = rasm::segmentation::computeSegmentationMetrics(
      map.segment, instance, map.stable, objects, mp);
  const auto counters = labelCounters(run);
  const double lcps =
      counters ? rasm::segmentation::labelChangesPerStableSurfel(counters->first, counters->second)
               : std::nan("");

  SegmentationEvaluation e;
  e.run = run;
  e.ply = ply;
  e.world_name = world.name;
  e.world_source = world.source;
  e.surfels_in_file = map.size();
  e.unassigned = unassigned;
  e.structure = structure;
  e.instances_in_world = world.objects.size();
  e.max_dist = max_dist;
  e.mp = mp;
  e.m = m;
  e.counters = counters;
  e.lcps = lcps;
  e.target = targetsOf(world.name);
  printSegmentationSummary(e);
  if (!json.empty()) writeJsonAtomically(json, segmentationJson(e));
  return 0;
}

#endif  // RASM_EVAL_SEGMENTATION

#ifdef RASM_EVAL_CLASSIFICATION

/// Segment -> class name of <run>/objects.json (aliases mapped to the simulator's names): every
/// segment of an object carries the object's class; and segment -> the detections fused into its
/// object.
std::map<std::uint32_t, std::string> readSegmentClasses(const std::string& run,
                                                        std::map<std::uint32_t, int>& detections) {
  const nlohmann::json objects = rasm::app::readRunObjects(run);
  const std::string path = (fs::path(run) / "objects.json").string();
  std::map<std::uint32_t, std::string> out;
  for (const auto& o : objects) {
    if (!o.contains("class") || !o["class"].is_string())
      rasm::throwInputError(path, "an object without \"class\"");
    std::string name = o["class"].get<std::string>();
    const int id = rasm::models::classIdFromName(name);
    if (id > 0) name = rasm::models::className(id);
    for (const std::uint32_t s : rasm::app::objectSegments(o, path)) {
      if (out.count(s) != 0)
        rasm::throwInputError(path, "segment " + std::to_string(s) + " is in two objects");
      out[s] = name;
      detections[s] = o.value("detections_fused", 0);
    }
  }
  return out;
}

/// The objects of <run>/objects.json with their classes (aliases mapped to the simulator's
/// names) and segments, for the object-level metrics.
std::vector<rasm::classification::ReportedObject> readReportedObjects(const std::string& run) {
  const std::string path = (fs::path(run) / "objects.json").string();
  std::vector<rasm::classification::ReportedObject> out;
  for (const auto& o : rasm::app::readRunObjects(run)) {
    rasm::classification::ReportedObject r;
    r.id = o.value("id", std::uint32_t(out.size()));
    r.class_name = o.at("class").get<std::string>();
    const int id = rasm::models::classIdFromName(r.class_name);
    if (id > 0) r.class_name = rasm::models::className(id);
    r.segments = rasm::app::objectSegments(o, path);
    out.push_back(std::move(r));
  }
  return out;
}

/// The object-level part of `rasm eval classification`'s --json document.
nlohmann::json objectLevelJson(const rasm::classification::ObjectLevelMetrics& m) {
  nlohmann::json rows = nlohmann::json::array();
  for (const auto& r : m.per_reported)
    rows.push_back({{"id", r.object.id},
                    {"class", r.object.class_name},
                    {"surfels", r.surfels},
                    {"best_object", r.best_name},
                    {"best_object_class", r.best_class},
                    {"iou", r.iou},
                    {"correct", r.correct}});
  return {{"reported", m.reported},
          {"reported_correct", m.reported_correct},
          {"precision", num(m.precision)},
          {"objects", m.objects},
          {"objects_found", m.objects_found},
          {"recall", num(m.recall)},
          {"missed", m.missed},
          {"per_reported", rows}};
}

/// The --json document of `rasm eval classification`.
nlohmann::json classificationJson(const rasm::classification::ClassificationMetrics& m,
                                  const std::string& run, const std::string& world) {
  nlohmann::json j, per_class = nlohmann::json::object(), confusion = nlohmann::json::object();
  for (const auto& [c, st] : m.per_class)
    per_class[c] = {{"objects", st.objects},
                    {"correct", st.objects_correct},
                    {"recall", num(st.recall())},
                    {"segments_predicted", st.segments_predicted},
                    {"segments_true", st.segments_true},
                    {"precision", num(st.precision())}};
  for (const auto& [t, row] : m.confusion)
    for (const auto& [p, n] : row) confusion[t][p] = n;
  nlohmann::json objs = nlohmann::json::array();
  for (const auto& r : m.per_object)
    objs.push_back({{"name", r.object.name},
                    {"class", r.object.class_name},
                    {"evaluated", r.evaluated},
                    {"surfels", r.surfels},
                    {"segment", r.segment},
                    {"segment_share", r.segment_share},
                    {"segmented", r.segmented},
                    {"predicted", r.predicted},
                    {"views", r.views},
                    {"correct", r.correct}});
  j["run"] = run;
  j["world"] = world;
  j["objects_evaluated"] = m.evaluated;
  j["object_accuracy"] = num(m.object_accuracy);
  j["segmented_coco_objects"] = m.segmented_detectable;
  j["segmented_coco_accuracy"] = num(m.segmented_accuracy);
  j["per_class"] = per_class;
  j["confusion"] = confusion;
  j["objects"] = objs;
  nlohmann::json views = nlohmann::json::array();
  for (const auto& b : m.by_views)
    views.push_back(
        {{"min_views", b.min_views},
         {"max_views", b.max_views < 0 ? nlohmann::json() : nlohmann::json(b.max_views)},
         {"objects", b.objects},
         {"accuracy", num(b.objects ? double(b.correct) / double(b.objects) : std::nan(""))}});
  j["accuracy_by_views"] = views;
  return j;
}

int evalClassification(const ParsedArgs& args) {
  const RunEvalOptions o = runEvalOptionsOf(args);
  const std::string json = o.json, world_opt = o.world;
  const double max_dist = o.max_dist_m;
  rasm::classification::ClassificationMetricsParams mp;
  mp.min_object_size_m = o.min_size_m;
  mp.min_object_surfels = o.min_surfels;
  const std::string& run = o.run;
  const std::string ply = (fs::path(run) / "map.ply").string();
  if (!fs::is_regular_file(ply))
    rasm::throwInputError(ply, "missing; expected the surfel PLY that `rasm run` writes");
  std::map<std::uint32_t, int> segment_detections;
  const auto segment_class = readSegmentClasses(run, segment_detections);
  const std::string world_path = runWorld(run, world_opt);
  const rasm::maps::PlySurfels map = rasm::maps::readSurfelPly(ply);
  if (map.size() == 0) rasm::throwInputError(ply, "no surfels; nothing to evaluate");
  const rasm::sim::RayScene scene(rasm::sim::loadWorld(world_path));
  const rasm::sim::SurfaceInstanceQuery query(scene);
  std::vector<Eigen::Vector3f> positions(map.size());
  for (std::size_t i = 0; i < map.size(); ++i) positions[i] = map.position[i];
  const auto nearest = query.nearest(positions, float(max_dist));
  std::vector<std::uint32_t> instance(map.size());
  for (std::size_t i = 0; i < map.size(); ++i) instance[i] = nearest[i].instance_id;
  std::vector<rasm::classification::GtClassObject> objects;
  for (const rasm::sim::WorldInstanceInfo& w : rasm::sim::worldInstances(scene.world()))
    objects.push_back(
        {w.instance_id, w.class_name, w.name, w.size_m, w.is_structure || w.class_id == 0});
  for (int id = 1; id <= rasm::models::kNumCocoClasses; ++id)
    mp.detectable_classes.insert(rasm::models::className(id));
  const auto m = rasm::classification::computeClassificationMetrics(
      map.segment, instance, segment_class, objects, mp, segment_detections);
  std::printf("classification of %s against world %s\n", run.c_str(), scene.world().name.c_str());
  std::printf("  objects evaluated (> %.2f m, >= %zu surfels)  %zu\n", mp.min_object_size_m,
              mp.min_object_surfels, m.evaluated);
  std::printf("  object_accuracy                 %s  (%zu of %zu carry their class)\n",
              fmt(m.object_accuracy).c_str(), m.correct, m.evaluated);
  std::printf("  segmented COCO-class accuracy   %s  (%zu of %zu segmented COCO-class objects)\n",
              fmt(m.segmented_accuracy).c_str(), m.segmented_detectable_correct,
              m.segmented_detectable);
  std::printf("  %-18s %8s %8s %10s %10s\n", "class", "objects", "recall", "predicted",
              "precision");
  for (const auto& [c, st] : m.per_class)
    std::printf("  %-18s %8zu %8s %10zu %10s\n", c.c_str(), st.objects, fmt(st.recall()).c_str(),
                st.segments_predicted, fmt(st.precision()).c_str());
  std::printf("  accuracy by detections fused into the object's segment (views):");
  for (const auto& b : m.by_views)
    std::printf("  %d%s%s: %s (%zu)", b.min_views,
                b.max_views < 0 ? "+" : (b.max_views == b.min_views ? "" : "-"),
                b.max_views > b.min_views ? std::to_string(b.max_views).c_str() : "",
                fmt(b.objects ? double(b.correct) / double(b.objects) : std::nan("")).c_str(),
                b.objects);
  std::printf("\n  per object (evaluated): name class -> predicted [segment share]\n");
  for (const auto& r : m.per_object)
    if (r.evaluated)
      std::printf("    %-22s %-14s -> %-14s %s%s  share %.2f\n", r.object.name.c_str(),
                  r.object.class_name.c_str(), r.predicted.c_str(), r.correct ? "ok" : "WRONG",
                  r.segmented ? "" : " (not segmented)", r.segment_share);
  const auto ol = rasm::classification::computeObjectLevelMetrics(
      map.segment, instance, readReportedObjects(run), objects, mp);
  std::printf("  object level (IoU > %.2f with an object of its class):\n", mp.min_object_iou);
  std::printf("    precision   %s  (%zu of %zu reported objects)\n", fmt(ol.precision).c_str(),
              ol.reported_correct, ol.reported);
  std::printf("    recall      %s  (%zu of %zu evaluated COCO-class objects)\n",
              fmt(ol.recall).c_str(), ol.objects_found, ol.objects);
  std::printf("    per reported object: id class -> best object (class) IoU\n");
  for (const auto& r : ol.per_reported)
    std::printf("      %-4u %-14s -> %-22s (%s) %.2f %s\n", r.object.id,
                r.object.class_name.c_str(), r.best_name.empty() ? "-" : r.best_name.c_str(),
                r.best_class.c_str(), r.iou, r.correct ? "ok" : "WRONG");
  if (!json.empty()) {
    nlohmann::json j = classificationJson(m, run, scene.world().name);
    j["object_level"] = objectLevelJson(ol);
    writeJsonAtomically(json, j);
  }
  return 0;
}

#endif  // RASM_EVAL_CLASSIFICATION

/// The two trajectories of `rasm eval ate|rpe`.
std::pair<rasm::io::Trajectory, rasm::io::Trajectory> readTrajectories(const ParsedArgs& args) {
  return {readTrajectoryFile(args.positional("groundtruth.txt"), "ground truth"),
          readTrajectoryFile(args.positional("estimate.txt"), "estimate")};
}

int evalAte(const ParsedArgs& args) {
  rasm::io::AteOptions ate;
  ate.align = !args.has("no-align");
  ate.scale = args.has("scale");
  if (args.has("max-dt")) ate.max_dt_s = parsePositive("--max-dt", args.value("max-dt"), "s");
  if (args.has("offset")) ate.offset_s = parseNumber("--offset", args.value("offset"));
  if (!ate.align && ate.scale) throw rasm::InputError("--scale needs alignment (drop --no-align)");
  const auto [gt, est] = readTrajectories(args);
  const auto r = rasm::io::TrajectoryEvaluator::computeAte(gt, est, ate);
  std::printf(
      "ATE  %s  %zu pose pairs (|dt| < %.3f s)  ground truth %zu poses, estimate %zu poses\n",
      !ate.align  ? "no alignment"
      : ate.scale ? "Sim(3) alignment"
                  : "SE(3) alignment",
      r.translation_m.count, ate.max_dt_s, gt.size(), est.size());
  printStats("translation", "[m]", r.translation_m);
  if (ate.scale) std::printf("  scale %.6f\n", r.scale);
  if (args.has("json")) writeJson(args.value("json"), rasm::io::toJson(r, ate));
  return 0;
}

int evalRpe(const ParsedArgs& args) {
  rasm::io::RpeOptions rpe;
  if (args.has("delta"))
    rpe.delta = parsePositive("--delta", args.value("delta"), "(s, or frames with --frames)");
  rpe.delta_in_frames = args.has("frames");
  if (args.has("offset")) rpe.offset_s = parseNumber("--offset", args.value("offset"));
  if (rpe.delta_in_frames && (rpe.delta < 1 || rpe.delta != std::floor(rpe.delta)))
    rasm::throwInputError("--delta " + std::to_string(rpe.delta),
                          "expected a whole number of frames >= 1 with --frames");
  const auto [gt, est] = readTrajectories(args);
  const auto r = rasm::io::TrajectoryEvaluator::computeRpe(gt, est, rpe);
  std::printf("RPE  delta %g %s  %zu pose pairs\n", rpe.delta, rpe.delta_in_frames ? "frames" : "s",
              r.pairs);
  printStats("translation", "[m]", r.translation_m);
  printStats("rotation", "[deg]", r.rotation_deg);
  if (args.has("json")) writeJson(args.value("json"), rasm::io::toJson(r, rpe));
  return 0;
}

const rasm::app::Registrar reg{kEvalDecl};
const rasm::app::Registrar reg_ate{kAteDecl, &evalAte};
const rasm::app::Registrar reg_rpe{kRpeDecl, &evalRpe};
#ifdef RASM_EVAL_SEGMENTATION
const rasm::app::Registrar reg_segmentation{segmentationDecl(), &evalSegmentation};
#endif
#ifdef RASM_EVAL_CLASSIFICATION
const rasm::app::Registrar reg_classification{classificationDecl(), &evalClassification};
#endif

}  // namespace
