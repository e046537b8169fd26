// `rasm eval memory <run folder>`: does a run's memory plateau? Reads
// the run's frames.csv (timestamp_s, surfels, rss_mb, map_memory_bytes: one row per frame) and
// reports, for surfels, RSS and the map store, the value at the run's half time and at its end
// and the growth over the second half (max over the second half against the max over the
// quarter before half time, see secondHalf; the criterion is < 5%), plus bytes per surfel (map
// store / surfels; RSS / surfels). --plot draws the three curves against time.

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "Command.h"
#include "rasm/core/AtomicFile.h"
#include "rasm/core/Error.h"
#include "rasm/pipeline/OutputFiles.h"
#include "rasm/run/LinePlot.h"

namespace rasm::app {
namespace {

const CommandDecl kDecl{
    "eval memory",
    "a run's memory against time and whether it plateaus",
    {{"run folder", "the output folder of a `rasm run` (its frames.csv)"}},
    {{"json", "out.json", "also write the result as JSON"},
     {"plot", "out.png", "plot surfels, RSS and the map store against time"},
     {"max-growth", "0.05", "the largest growth over the second half that still plateaus"}},
    "Memory of a run against time from its frames.csv (surfels, rss_mb, map_memory_bytes): value\n"
    "at half time, at the end, growth over the second half; exit 1 when surfels or RSS grow\n"
    "more than --max-growth over the second half.\n"};

/// The columns of frames.csv this command reads, one value per frame.
struct MemoryCurves {
  std::vector<double> t, surfels, rss_mb, map_mb;
};

MemoryCurves readFramesCsv(const std::string& path) {
  std::ifstream f(path);
  if (!f) throwInputError(path, "cannot be opened (expected the frames.csv of a `rasm run`)");
  std::string line;
  if (!std::getline(f, line)) throwInputError(path, "is empty (expected a header line)");
  std::map<std::string, std::size_t> col;
  {
    std::stringstream ss(line);
    std::string name;
    for (std::size_t i = 0; std::getline(ss, name, ','); ++i) col[name] = i;
  }
  for (const char* c : {"timestamp_s", "surfels", "rss_mb", "map_memory_bytes"})
    if (!col.count(c))
      throwInputError(
          path, std::string("has no column '") + c + "' (a run folder of an older rasm: rerun it)");
  MemoryCurves m;
  for (long long row = 2; std::getline(f, line); ++row) {
    std::vector<std::string> v;
    std::stringstream ss(line);
    for (std::string x; std::getline(ss, x, ',');) v.push_back(x);
    auto num = [&](const char* c) {
      const std::size_t i = col[c];
      char* end = nullptr;
      const double x = i < v.size() ? std::strtod(v[i].c_str(), &end) : NAN;
      if (i >= v.size() || end == v[i].c_str() || !std::isfinite(x))
        throwInputError(path + ":" + std::to_string(row),
                        std::string("column ") + c + " is not a number");
      return x;
    };
    m.t.push_back(num("timestamp_s"));
    m.surfels.push_back(num("surfels"));
    m.rss_mb.push_back(num("rss_mb"));
    m.map_mb.push_back(num("map_memory_bytes") / (1024.0 * 1024.0));
  }
  if (m.t.size() < 2) throwInputError(path, "has fewer than 2 frames: no curve");
  return m;
}

/// Index of the last sample at or before time T.
std::size_t indexAt(const std::vector<double>& t, double T) {
  std::size_t h = 0;
  while (h + 1 < t.size() && t[h + 1] <= T) ++h;
  return h;
}

/// Growth over the second half of the run. The surfel count swings within every pass over a
/// room (unstable surfels come and go), so the level the run had reached at half time is the
/// maximum over the quarter before it ([T/4, T/2]), compared with the maximum over the second
/// half: a curve that only swings gives 0, one that keeps rising gives its rise.
nlohmann::json secondHalf(const std::vector<double>& t, const std::vector<double>& v) {
  const double t0 = t.front(), t1 = t.back();
  const std::size_t q = indexAt(t, t0 + 0.25 * (t1 - t0)), h = indexAt(t, 0.5 * (t0 + t1));
  const double level = *std::max_element(v.begin() + long(q), v.begin() + long(h) + 1);
  const double peak = *std::max_element(v.begin() + long(h), v.end());
  return {{"at_half_time", v[h]},
          {"at_end", v.back()},
          {"max_quarter_before_half_time", level},
          {"max_second_half", peak},
          {"growth_second_half", level > 0 ? (peak - level) / level : 0.0}};
}

void plotCurves(const std::string& path, const MemoryCurves& m, const std::string& title) {
  // Each curve scaled to its own maximum (0 at the bottom); the legend gives the maximum.
  struct Curve {
    const std::vector<double>* v;
    const char* name;
    cv::Scalar colour;
  };
  const Curve curves[] = {{&m.surfels, "surfels", {200, 80, 0}},
                          {&m.rss_mb, "RSS (MB)", {0, 0, 200}},
                          {&m.map_mb, "map store (MB)", {0, 150, 0}}};
  std::vector<rasm::run::PlotSeries> series;
  for (const Curve& c : curves) {
    const double top = std::max(1e-9, *std::max_element(c.v->begin(), c.v->end()));
    char label[96];
    std::snprintf(label, sizeof label, "%s, max %.4g", c.name, top);
    rasm::run::PlotSeries s{label, m.t, {}, c.colour, 1};
    for (double v : *c.v) s.y.push_back(v / top);
    series.push_back(std::move(s));
  }
  rasm::run::PlotAxes axes;
  axes.title = title;
  axes.x_label = "time (s); each curve scaled to its own maximum";
  axes.x_min = m.t.front();
  axes.x_max = std::max(m.t.back(), m.t.front() + 1e-6);
  axes.y_min = 0.0;
  axes.y_max = 1.0;
  axes.y_guides = {0.5};
  axes.x_guides = {0.5 * (axes.x_min + axes.x_max)};  // the halves the growth compares
  const cv::Mat img = rasm::run::linePlot(axes, series, 760, 400);
  try {
    rasm::pipeline::writeImageAtomically(path, img);
  } catch (const std::exception& e) {
    throwInputError("--plot " + path, std::string("cannot be written: ") + e.what());
  }
}

/// --max-growth: a non-negative fraction.
double parseMaxGrowth(const std::string& v) {
  char* end = nullptr;
  const double g = std::strtod(v.c_str(), &end);
  if (end == v.c_str() || *end != 0 || !(g >= 0) || !std::isfinite(g))
    throwInputError("--max-growth", "'" + v + "' is not a non-negative fraction");
  return g;
}

int evalMemory(const ParsedArgs& args) {
  const std::string dir = args.positional("run folder");
  const std::string json_path = args.value("json"), plot_path = args.value("plot");
  const double max_growth =
      args.has("max-growth") ? parseMaxGrowth(args.value("max-growth")) : 0.05;
  const MemoryCurves m = readFramesCsv(dir + "/frames.csv");
  nlohmann::json out;
  out["run"] = dir;
  out["frames"] = m.t.size();
  out["seconds"] = m.t.back() - m.t.front();
  out["surfels"] = secondHalf(m.t, m.surfels);
  out["rss_mb"] = secondHalf(m.t, m.rss_mb);
  out["map_memory_mb"] = secondHalf(m.t, m.map_mb);
  const double n = std::max(1.0, m.surfels.back());
  out["map_bytes_per_surfel"] = m.map_mb.back() * 1024.0 * 1024.0 / n;
  out["rss_bytes_per_surfel"] = m.rss_mb.back() * 1024.0 * 1024.0 / n;
  const bool plateau = out["surfels"]["growth_second_half"].get<double>() <= max_growth &&
                       out["rss_mb"]["growth_second_half"].get<double>() <= max_growth;
  out["plateau"] = plateau;
  out["max_growth"] = max_growth;
  std::printf(
      "memory over %zu frames (%.0f s): surfels peak %.0f -> %.0f (+%.1f%% over the second half), "
      "RSS %.0f -> %.0f MB (+%.1f%%), map store %.0f MB = %.0f bytes/surfel (RSS %.0f "
      "bytes/surfel): %s\n",
      m.t.size(), out["seconds"].get<double>(),
      out["surfels"]["max_quarter_before_half_time"].get<double>(),
      out["surfels"]["max_second_half"].get<double>(),
      100 * out["surfels"]["growth_second_half"].get<double>(),
      out["rss_mb"]["max_quarter_before_half_time"].get<double>(),
      out["rss_mb"]["max_second_half"].get<double>(),
      100 * out["rss_mb"]["growth_second_half"].get<double>(), m.map_mb.back(),
      out["map_bytes_per_surfel"].get<double>(), out["rss_bytes_per_surfel"].get<double>(),
      plateau ? "plateau" : "STILL GROWING");
  if (!json_path.empty()) {
    try {
      writeFileAtomic(json_path, out.dump(2) + "\n");
    } catch (const std::runtime_error& e) {
      throwInputError("--json " + json_path, e.what());
    }
  }
  if (!plot_path.empty()) plotCurves(plot_path, m, "memory of " + dir);
  return plateau ? 0 : 1;
}

const Registrar reg{kDecl, &evalMemory};

}  // namespace
}  // namespace rasm::app
