// `rasm sweep gather <sweep folder>`: the evaluation table of a sweep (scripts/sweep.sh: a grid of
// independent `rasm run`s, run by GNU parallel or as a Slurm array job): one row per task of its
// tasks.tsv, the task's parameters and the headline numbers of its report.json, as Markdown, JSON
// and CSV. When every finished task is an exploring run, the grouped exploration table of `rasm
// eval exploration` follows (the same writer). docs/outputs.md "Sweeps".
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "Command.h"
#include "RunObjects.h"
#include "rasm/core/AtomicFile.h"
#include "rasm/core/Error.h"

namespace fs = std::filesystem;

namespace {

const rasm::app::CommandDecl kSweepDecl{
    "sweep",
    "the table of a sweep (scripts/sweep.sh): rasm sweep gather <folder>",
    {},
    {},
    "scripts/sweep.sh runs the sweep (GNU parallel or a Slurm array job); rasm sweep gather\n"
    "tabulates it.\n"};

const rasm::app::CommandDecl kGatherDecl{
    "sweep gather",
    "one row per task of a sweep: its parameters and its report.json's headline numbers",
    {{"sweep folder", "the --out folder of scripts/sweep.sh"}},
    {{"markdown", "out.md", "the Markdown table (default: <sweep folder>/results.md)"},
     {"json", "out.json", "the rows as JSON (default: <sweep folder>/results.json)"},
     {"csv", "out.csv", "the rows as CSV (default: <sweep folder>/results.csv)"}},
    "One row per task of <sweep folder>/tasks.tsv (scripts/sweep.sh writes it; without it, every\n"
    "<sweep folder>/runs/<name> holding a report.json): the task's columns (world, planner, seed,\n"
    "input) and its report.json's status, frames, tracked fraction, ATE, frame rate, segments,\n"
    "objects, coverage, objects correct, path, simulated and wall time, stop reason, commit.\n"
    "Tasks without a report.json are rows with status \"missing\" (see runs/<name>.log).\n"
    "Writes <sweep folder>/results.{md,json,csv} unless given other paths; when every finished\n"
    "task explored, also exploration.{md,json} (rasm eval exploration over them).\n"};

/// One task: its parameters (tasks.tsv columns other than args) and its run folder.
struct Task {
  std::vector<std::pair<std::string, std::string>> params;
  std::string name;
  fs::path dir;
};

std::vector<std::string> splitTabs(const std::string& line) {
  std::vector<std::string> out;
  std::stringstream ss(line);
  std::string f;
  while (std::getline(ss, f, '\t')) out.push_back(f);
  if (!line.empty() && line.back() == '\t') out.emplace_back();
  return out;
}

std::vector<Task> readTasks(const fs::path& sweep) {
  std::vector<Task> tasks;
  const fs::path tsv = sweep / "tasks.tsv";
  if (!fs::exists(tsv)) {  // no task list: every run folder under runs/
    const fs::path runs = sweep / "runs";
    if (!fs::is_directory(runs))
      rasm::throwInputError(sweep.string(),
                            "holds neither tasks.tsv nor a runs/ folder "
                            "(expected the --out folder of scripts/sweep.sh)");
    for (const auto& e : fs::directory_iterator(runs))
      if (e.is_directory() && fs::exists(e.path() / "report.json"))
        tasks.push_back({{}, e.path().filename().string(), e.path()});
    std::sort(tasks.begin(), tasks.end(),
              [](const Task& a, const Task& b) { return a.name < b.name; });
    return tasks;
  }
  std::ifstream f(tsv);
  std::string line;
  if (!std::getline(f, line)) rasm::throwInputError(tsv.string(), "is empty (expected a header)");
  const std::vector<std::string> header = splitTabs(line);
  const auto name_col = std::find(header.begin(), header.end(), "name") - header.begin();
  if (name_col == long(header.size()))
    rasm::throwInputError(tsv.string(), "has no \"name\" column in its header");
  for (int line_no = 2; std::getline(f, line); ++line_no) {
    if (line.empty()) continue;
    const std::vector<std::string> fields = splitTabs(line);
    if (fields.size() != header.size())
      rasm::throwInputError(tsv.string() + ":" + std::to_string(line_no),
                            "has " + std::to_string(fields.size()) + " fields, the header " +
                                std::to_string(header.size()));
    Task t;
    t.name = fields[std::size_t(name_col)];
    t.dir = sweep / "runs" / t.name;
    for (std::size_t i = 0; i < header.size(); ++i)
      if (header[i] != "args") t.params.emplace_back(header[i], fields[i]);
    tasks.push_back(std::move(t));
  }
  return tasks;
}

/// report.json at a JSON pointer ("/ate/translation_m/rmse"), or null.
nlohmann::json at(const nlohmann::json& rep, const char* pointer) {
  const nlohmann::json::json_pointer p(pointer);
  return rep.contains(p) ? rep[p] : nlohmann::json();
}

/// The row of one task: its parameters, then the report's numbers (null where they do not apply).
nlohmann::ordered_json taskRow(const Task& t, bool& explored) {
  nlohmann::ordered_json row;
  for (const auto& [k, v] : t.params) row[k] = v;
  if (t.params.empty()) row["name"] = t.name;
  const fs::path report = t.dir / "report.json";
  explored = false;
  if (!fs::exists(report)) {
    row["status"] = "missing";
    return row;
  }
  const nlohmann::json rep = rasm::app::readRunJson(report.string(), "expected a rasm run report");
  explored = rep.contains("exploration");
  row["status"] = at(rep, "/status");
  row["frames"] = at(rep, "/frames");
  row["tracked_fraction"] = at(rep, "/tracked_fraction");
  const nlohmann::json ate = at(rep, "/ate/translation_m/rmse");
  row["ate_cm"] = ate.is_number() ? nlohmann::json(100.0 * ate.get<double>()) : ate;
  row["fps"] = at(rep, "/fps");
  row["segments"] = at(rep, "/segmentation/segments");
  row["objects"] = at(rep, "/classification/objects");
  row["coverage"] = at(rep, "/coverage_fraction");
  row["objects_correct"] = at(rep, "/objects_correct_fraction");
  row["path_m"] = at(rep, "/path_length_m");
  row["sim_s"] = at(rep, "/sim_time_s");
  row["wall_s"] = at(rep, "/seconds");
  row["stop_reason"] = at(rep, "/stop_reason");
  row["commit"] = at(rep, "/rasm/commit");
  row["error"] = at(rep, "/error");
  return row;
}

std::string cell(const nlohmann::ordered_json& v) {
  if (v.is_null()) return "";
  if (v.is_string()) return v.get<std::string>();
  if (v.is_number_float()) {
    char b[32];
    std::snprintf(b, sizeof b, "%.4g", v.get<double>());
    return b;
  }
  return v.dump();
}

std::string csvField(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string q = "\"";
  for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

/// The rows as a Markdown table and as CSV (columns of the first row with the most fields).
void writeTables(const std::vector<nlohmann::ordered_json>& rows, std::string& md,
                 std::string& csv) {
  std::vector<std::string> cols;
  for (const auto& r : rows)
    if (r.size() > cols.size()) {
      cols.clear();
      for (auto it = r.begin(); it != r.end(); ++it) cols.push_back(it.key());
    }
  std::ostringstream m, c;
  for (std::size_t i = 0; i < cols.size(); ++i) {
    m << "| " << cols[i] << " ";
    c << (i ? "," : "") << csvField(cols[i]);
  }
  m << "|\n";
  c << "\n";
  for (std::size_t i = 0; i < cols.size(); ++i) m << "|---";
  m << "|\n";
  for (const auto& r : rows) {
    for (std::size_t i = 0; i < cols.size(); ++i) {
      const std::string v = r.contains(cols[i]) ? cell(r[cols[i]]) : "";
      std::string escaped;
      for (char ch : v)
        escaped += ch == '|' ? std::string("\\|") : std::string(1, ch == '\n' ? ' ' : ch);
      m << "| " << escaped << " ";
      c << (i ? "," : "") << csvField(v);
    }
    m << "|\n";
    c << "\n";
  }
  md = m.str();
  csv = c.str();
}

void writeFile(const std::string& path, const std::string& text, const char* option) {
  try {
    rasm::writeFileAtomic(path, text);
  } catch (const std::runtime_error& e) {
    rasm::throwInputError(std::string(option) + " " + path, e.what());
  }
  std::fprintf(stderr, "wrote %s\n", path.c_str());
}

int gather(const rasm::app::ParsedArgs& args) {
  const std::string folder = args.positional("sweep folder");
  const std::string md_path = args.value("markdown"), json_path = args.value("json"),
                    csv_path = args.value("csv");
  const fs::path sweep(folder);
  if (!fs::is_directory(sweep)) rasm::throwInputError(folder, "is not a folder");
  const std::vector<Task> tasks = readTasks(sweep);
  if (tasks.empty()) rasm::throwInputError(folder, "holds no task (tasks.tsv empty, no run)");

  std::vector<nlohmann::ordered_json> rows;
  std::vector<std::string> explored_dirs;
  std::size_t not_ok = 0, finished = 0;
  for (const Task& t : tasks) {
    bool explored = false;
    rows.push_back(taskRow(t, explored));
    const bool ok = rows.back()["status"] == "ok";
    not_ok += !ok;
    finished += rows.back()["status"] != "missing";
    if (explored && ok) explored_dirs.push_back(t.dir.string());
  }
  std::string md, csv;
  writeTables(rows, md, csv);
  std::cout << md;
  const nlohmann::ordered_json json = {{"sweep", fs::absolute(sweep).lexically_normal().string()},
                                       {"tasks", rows.size()},
                                       {"not_ok", not_ok},
                                       {"rows", rows}};
  writeFile(md_path.empty() ? (sweep / "results.md").string() : md_path, md, "--markdown");
  writeFile(json_path.empty() ? (sweep / "results.json").string() : json_path, json.dump(2) + "\n",
            "--json");
  writeFile(csv_path.empty() ? (sweep / "results.csv").string() : csv_path, csv, "--csv");
  if (not_ok > 0)
    std::fprintf(stderr,
                 "rasm sweep gather: %zu of %zu tasks not ok (failed, interrupted or "
                 "missing: runs/<name>.log)\n",
                 not_ok, rows.size());
  if (!explored_dirs.empty() && explored_dirs.size() == finished) {
    std::vector<std::string> ex = explored_dirs;
    ex.insert(ex.end(), {"--markdown", (sweep / "exploration.md").string(), "--json",
                         (sweep / "exploration.json").string()});
    return rasm::app::runCommand("eval exploration", ex);
  }
  return 0;
}

const rasm::app::Registrar reg{kSweepDecl};
const rasm::app::Registrar reg_gather{kGatherDecl, &gather};

}  // namespace
