// `rasm eval exploration`: runs grouped by world and planner (seeds averaged), with coverage and
// objects correctly classified at fixed simulated times, time to 90% coverage, path length and
// why each run stopped; a Markdown table, JSON, and a PNG of coverage against simulated time.
#include <mrpt/config/CConfigFile.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

#include "Command.h"
#include "RunObjects.h"
#include "rasm/core/AtomicFile.h"
#include "rasm/core/Error.h"
#include "rasm/pipeline/OutputFiles.h"
#include "rasm/run/LinePlot.h"

namespace fs = std::filesystem;

namespace rasm::app {
namespace {

const CommandDecl kDecl{
    "eval exploration",
    "exploring runs grouped by world and planner: coverage and objects correct over time",
    {{"run folder", "an exploring `rasm run` ([exploration] enabled)", true, true}},
    {{"times", "60,120,180", "the simulated times (s) of the coverage and objects columns"},
     {"json", "out.json", "also write the groups as JSON"},
     {"markdown", "out.md", "also write the table as Markdown"},
     {"plot", "out.png", "plot coverage against simulated time, one panel per world"}},
    "Each run folder is an exploring `rasm run` ([exploration] enabled): its report.json,\n"
    "exploration.json and config.ini ([sim] world and seed). Runs are grouped by world and\n"
    "planner; values are means over the seeds (min-max in brackets). A run that stopped before\n"
    "a time keeps its final values.\n"};

struct Series {
  std::vector<double> t, coverage, objects;
  /// The value at time T: the last sample at or before T (a stopped run keeps its last value).
  static double at(const std::vector<double>& ts, const std::vector<double>& v, double T) {
    double out = v.empty() ? 0.0 : v.front();
    for (std::size_t i = 0; i < ts.size() && ts[i] <= T + 1e-9; ++i) out = v[i];
    return out;
  }
};

struct RunRow {
  std::string dir, world, planner, poses, stop_reason;
  long long seed = 0;
  double coverage = 0, objects = 0, path_m = 0, sim_s = 0, t90 = -1, wall_s = 0;
  double lost_fraction = 0, ate_m = -1;  ///< tracking: frames lost / frames, ATE RMSE (-1: none)
  Series series;
};

nlohmann::json readJson(const fs::path& p) {
  return readRunJson(p.string(), "expected the file an exploring `rasm run` writes");
}

RunRow readRun(const std::string& dir) {
  RunRow r;
  r.dir = dir;
  const nlohmann::json rep = readJson(fs::path(dir) / "report.json");
  if (!rep.contains("exploration"))
    throwInputError(dir + "/report.json",
                    "has no exploration block ([exploration] enabled = false?)");
  const nlohmann::json ex = readJson(fs::path(dir) / "exploration.json");
  const fs::path ini = fs::path(dir) / "config.ini";
  if (!fs::is_regular_file(ini)) throwInputError(ini.string(), "missing; `rasm run` writes it");
  const mrpt::config::CConfigFile cfg(ini.string());
  r.world = fs::path(cfg.read_string("sim", "world", "?")).stem().string();
  r.seed = cfg.read_int("sim", "seed", 0);
  r.poses = cfg.read_string("mapper", "poses", "tracked");
  const double frames = rep.value("frames", 0.0);
  r.lost_fraction = frames > 0 ? rep.value("frames_lost", 0.0) / frames : 0.0;
  if (rep.contains("ate") && rep["ate"].contains("translation_m"))
    r.ate_m = rep["ate"]["translation_m"].value("rmse", -1.0);
  r.planner = rep["exploration"].value("planner", "?");
  r.stop_reason = rep.value("stop_reason", "");
  r.coverage = rep.value("coverage_fraction", 0.0);
  r.objects = rep.value("objects_correct_fraction", 0.0);
  r.path_m = rep.value("path_length_m", 0.0);
  r.sim_s = rep.value("sim_time_s", 0.0);
  r.wall_s = rep.value("seconds", 0.0);
  const auto& t90 = rep["exploration"]["time_to_90_coverage_s"];
  r.t90 = t90.is_number() ? t90.get<double>() : -1.0;
  for (const auto& m : ex["metrics"]) {
    r.series.t.push_back(m.value("t", 0.0));
    r.series.coverage.push_back(m.value("coverage", 0.0));
    r.series.objects.push_back(m.value("objects_correct_fraction", 0.0));
  }
  return r;
}

struct Stat {
  double mean = 0, lo = 0, hi = 0;
  int n = 0;
};
Stat stat(const std::vector<double>& v) {
  Stat s;
  if (v.empty()) return s;
  s.n = int(v.size());
  s.lo = *std::min_element(v.begin(), v.end());
  s.hi = *std::max_element(v.begin(), v.end());
  for (double x : v) s.mean += x / double(v.size());
  return s;
}
std::string fmt(const Stat& s, int decimals) {
  char b[96];
  if (s.n == 0) return "-";
  if (s.n == 1 || s.lo == s.hi)
    std::snprintf(b, sizeof b, "%.*f", decimals, s.mean);
  else
    std::snprintf(b, sizeof b, "%.*f [%.*f-%.*f]", decimals, s.mean, decimals, s.lo, decimals,
                  s.hi);
  return b;
}

void plot(const std::string& path, const std::map<std::string, std::vector<RunRow>>& by_group,
          double tmax) {
  // One panel per world, one line per planner: mean coverage over the seeds against time.
  std::map<std::string, std::map<std::string, std::vector<const RunRow*>>> worlds;
  for (const auto& [key, runs] : by_group)
    for (const RunRow& r : runs)
      worlds[r.world][r.planner + (r.poses == "groundtruth" ? " (gt poses)" : " (tracked)")]
          .push_back(&r);
  const int W = 520, H = 340;
  cv::Mat img(H, W * int(std::max<std::size_t>(1, worlds.size())), CV_8UC3,
              cv::Scalar(255, 255, 255));
  const cv::Scalar colours[] = {{200, 80, 0},  {0, 0, 200},   {0, 150, 0},
                                {150, 0, 150}, {0, 140, 255}, {90, 90, 90}};
  int panel = 0;
  for (const auto& [world, planners] : worlds) {
    std::vector<rasm::run::PlotSeries> series;
    for (const auto& [planner, runs] : planners) {
      // One colour per planner in every panel; runs on tracked poses drawn thin.
      const std::string base = planner.substr(0, planner.find(' '));
      const int ci = base == "ig"          ? 1
                     : base == "frontier"  ? 0
                     : base == "random"    ? 3
                     : base == "lawnmower" ? 2
                     : base == "ig_greedy" ? 4
                                           : 5;
      rasm::run::PlotSeries s{
          planner, {}, {}, colours[ci], planner.find("gt poses") != std::string::npos ? 2 : 1};
      for (int i = 0; i <= 100; ++i) {
        const double t = tmax * i / 100.0;
        double v = 0;
        for (const RunRow* r : runs) v += Series::at(r->series.t, r->series.coverage, t);
        s.x.push_back(t);
        s.y.push_back(v / double(runs.size()));
      }
      series.push_back(std::move(s));
    }
    rasm::run::PlotAxes axes;
    axes.title = world + ": coverage vs simulated time (s)";
    axes.x_min = 0.0;
    axes.x_max = tmax;
    axes.y_min = 0.0;
    axes.y_max = 1.0;
    axes.y_guides = {0.25, 0.5, 0.75, 0.9};
    rasm::run::drawLinePlot(img, cv::Rect(panel++ * W, 0, W, H), axes, series);
  }
  try {
    rasm::pipeline::writeImageAtomically(path, img);
  } catch (const std::exception& e) {
    throwInputError("--plot " + path, std::string("cannot be written: ") + e.what());
  }
  std::printf("wrote %s\n", path.c_str());
}

/// --times: non-negative seconds, comma-separated.
std::vector<double> parseTimes(const std::string& text) {
  std::vector<double> times;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ',')) {
    char* end = nullptr;
    const double t = std::strtod(item.c_str(), &end);
    if (end == item.c_str() || *end != 0 || !(t >= 0))
      throwInputError("--times", "'" + item + "' is not a non-negative number of seconds");
    times.push_back(t);
  }
  return times;
}

/// One group's (world, poses, planner) markdown row, appended to `md`, and JSON entry: the
/// statistics of its runs at `times` and at their end, and each run.
nlohmann::json groupRow(const std::vector<RunRow>& runs, const std::vector<double>& times,
                        std::ostringstream& md) {
  std::map<std::string, int> reasons;
  std::vector<double> cov_final, t90, path, sim, wall, lost, ate_cm;
  int reached90 = 0;
  for (const RunRow& r : runs) {
    cov_final.push_back(r.coverage);
    if (r.t90 >= 0) {
      t90.push_back(r.t90);
      ++reached90;
    }
    path.push_back(r.path_m);
    sim.push_back(r.sim_s);
    wall.push_back(r.wall_s);
    lost.push_back(r.lost_fraction);
    if (r.ate_m >= 0) ate_cm.push_back(100.0 * r.ate_m);
    ++reasons[r.stop_reason];
  }
  md << "| " << runs.front().world << " | " << runs.front().poses << " | " << runs.front().planner
     << " | " << runs.size() << " |";
  nlohmann::json j = {{"world", runs.front().world},
                      {"poses", runs.front().poses},
                      {"planner", runs.front().planner},
                      {"runs", runs.size()}};
  for (double t : times) {
    std::vector<double> v;
    for (const RunRow& r : runs) v.push_back(Series::at(r.series.t, r.series.coverage, t));
    md << " " << fmt(stat(v), 3) << " |";
    j["coverage_at"][std::to_string(int(t))] = stat(v).mean;
  }
  md << " " << fmt(stat(cov_final), 3) << " | " << fmt(stat(t90), 0)
     << (reached90 < int(runs.size())
             ? " (" + std::to_string(reached90) + " of " + std::to_string(runs.size()) + " reached)"
             : std::string())
     << " |";
  for (double t : times) {
    std::vector<double> v;
    for (const RunRow& r : runs) v.push_back(Series::at(r.series.t, r.series.objects, t));
    md << " " << fmt(stat(v), 3) << " |";
    j["objects_correct_at"][std::to_string(int(t))] = stat(v).mean;
  }
  std::string why;
  for (const auto& [reason, n] : reasons)
    why += (why.empty() ? "" : ", ") + reason + (n > 1 ? " x" + std::to_string(n) : "");
  md << " " << fmt(stat(path), 1) << " | " << fmt(stat(sim), 0) << " | " << fmt(stat(wall), 0)
     << " | " << fmt(stat(lost), 3) << " | " << fmt(stat(ate_cm), 1) << " | " << why << " |\n";
  j["coverage_final"] = stat(cov_final).mean;
  j["time_to_90_coverage_s"] = t90.empty() ? nlohmann::json() : nlohmann::json(stat(t90).mean);
  j["runs_reaching_90"] = reached90;
  j["path_length_m"] = stat(path).mean;
  j["sim_time_s"] = stat(sim).mean;
  j["frames_lost_fraction"] = stat(lost).mean;
  j["ate_rmse_cm"] = ate_cm.empty() ? nlohmann::json() : nlohmann::json(stat(ate_cm).mean);
  j["stop_reasons"] = reasons;
  nlohmann::json seeds = nlohmann::json::array();
  for (const RunRow& r : runs)
    seeds.push_back(
        {{"dir", r.dir},
         {"seed", r.seed},
         {"coverage", r.coverage},
         {"objects_correct_fraction", r.objects},
         {"path_length_m", r.path_m},
         {"sim_time_s", r.sim_s},
         {"stop_reason", r.stop_reason},
         {"time_to_90_coverage_s", r.t90 < 0 ? nlohmann::json() : nlohmann::json(r.t90)}});
  j["per_run"] = seeds;
  return j;
}

int evalExploration(const ParsedArgs& args) {
  const std::vector<std::string> dirs = args.positionals("run folder");
  const std::vector<double> times =
      args.has("times") ? parseTimes(args.value("times")) : std::vector<double>{60, 120, 180};
  const std::string json = args.value("json"), markdown = args.value("markdown"),
                    plot_path = args.value("plot");
  std::map<std::string, std::vector<RunRow>> groups;  // "world / planner"
  double tmax = 0;
  for (const std::string& d : dirs) {
    RunRow r = readRun(d);
    tmax = std::max(tmax, r.sim_s);
    groups[r.world + " / " + r.poses + " / " + r.planner].push_back(std::move(r));
  }
  std::ostringstream md;
  md << "| world | poses | planner | runs |";
  for (double t : times) md << " coverage @" << t << " s |";
  md << " final coverage | time to 90% (s) |";
  for (double t : times) md << " objects correct @" << t << " s |";
  md << " path (m) | simulated (s) | wall (s) | frames lost | ATE (cm) | stopped by |\n"
     << "|---|---|---|---|";
  for (std::size_t i = 0; i < 2 * times.size() + 8; ++i) md << "---|";
  md << "\n";
  nlohmann::json out = nlohmann::json::array();
  for (const auto& [key, runs] : groups) out.push_back(groupRow(runs, times, md));
  std::printf("%s", md.str().c_str());
  if (!markdown.empty()) {
    try {
      writeFileAtomic(markdown, md.str());
    } catch (const std::runtime_error& e) {
      throwInputError("--markdown " + markdown, e.what());
    }
  }
  if (!json.empty()) {
    try {
      writeFileAtomic(json, nlohmann::json{{"groups", out}}.dump(2) + "\n");
    } catch (const std::runtime_error& e) {
      throwInputError("--json " + json, e.what());
    }
  }
  if (!plot_path.empty()) plot(plot_path, groups, std::max(1.0, tmax));
  return 0;
}

const Registrar reg{kDecl, &evalExploration};

}  // namespace
}  // namespace rasm::app
