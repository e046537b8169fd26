// Evaluation sweeps that scale out (issue 19, 6): scripts/sweep.sh runs a tiny grid through GNU
// parallel and `rasm sweep gather` makes one row per task; with --slurm it writes an array job
// file (valid bash, one task per SLURM_ARRAY_TASK_ID) and runs nothing.
#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>
#include <sstream>

#include "RasmProcess.h"

namespace fs = std::filesystem;
using namespace rasm::app::testing;

namespace {
const std::string kSweep = std::string(RASM_SOURCE_DIR) + "/scripts/sweep.sh";

std::string sweep(const std::string& args) {
  return "RASM=" + std::string(RASM_BINARY) + " " + kSweep + " " + args;
}

std::vector<std::string> lines(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string l; std::getline(in, l);) out.push_back(l);
  return out;
}
}  // namespace

TEST(Sweep, TwoTasksRunThroughParallelAndGatherIntoOneRowEach) {
  if (shell("command -v parallel").status != 0)
    GTEST_SKIP() << "GNU parallel is not installed (scripts/install-deps.sh installs it)";
  const std::string dir = freshDir("sweep_local");
  const Result r = shell(sweep("--out " + dir +
                               " --worlds office --planners 'ig frontier' "
                               "--seeds 3 --jobs 2 -- " +
                               shortRunArgs(4)));
  ASSERT_EQ(r.status, 0) << r.output;
  // The CSV: a header and one row per task, in task order, both ok.
  const std::vector<std::string> csv = lines(readFile(dir + "/results.csv"));
  ASSERT_EQ(csv.size(), 3u) << readFile(dir + "/results.csv");
  EXPECT_EQ(csv[0].rfind("task,name,world,planner,seed,input,status,frames,", 0), 0u) << csv[0];
  EXPECT_EQ(csv[1].rfind("1,001_office_ig_s3,office,ig,3,,ok,4,", 0), 0u) << csv[1];
  EXPECT_EQ(csv[2].rfind("2,002_office_frontier_s3,office,frontier,3,,ok,4,", 0), 0u) << csv[2];
  const nlohmann::json j = nlohmann::json::parse(readFile(dir + "/results.json"));
  ASSERT_EQ(j["rows"].size(), 2u);
  EXPECT_EQ(j["not_ok"], 0);
  for (const auto& row : j["rows"]) {
    EXPECT_EQ(row["status"], "ok");
    EXPECT_EQ(row["frames"], 4);
    EXPECT_TRUE(row["coverage"].is_number()) << row;  // exploring runs
    EXPECT_TRUE(row["commit"].is_string()) << row;
  }
  EXPECT_EQ(lines(readFile(dir + "/results.md")).size(), 4u);  // header, rule, two rows
  // Each task wrote its own run folder; the parallel joblog has both, exit 0.
  for (const char* run : {"001_office_ig_s3", "002_office_frontier_s3"})
    EXPECT_TRUE(fs::exists(dir + "/runs/" + run + "/report.json")) << run;
  EXPECT_EQ(lines(readFile(dir + "/joblog.tsv")).size(), 3u);
  // Every task explored: the grouped exploration table of rasm eval exploration too.
  const std::string ex = readFile(dir + "/exploration.md");
  EXPECT_NE(ex.find("| office | tracked | frontier | 1 |"), std::string::npos) << ex;
  EXPECT_NE(ex.find("| office | tracked | ig | 1 |"), std::string::npos) << ex;
  fs::remove_all(dir);
}

TEST(Sweep, SlurmArrayFileIsWrittenAndNothingRuns) {
  const std::string dir = freshDir("sweep_slurm");
  const std::string file = dir + "/sweep.sbatch";
  const Result r = shell(sweep("--out " + dir +
                               " --worlds 'office two_rooms' --seeds '1 2' "
                               "--slurm " +
                               file +
                               " --slurm-time 00:20:00 --sbatch "
                               "--partition=cpu -- --set source.max_frames=50"));
  ASSERT_EQ(r.status, 0) << r.output;
  const std::string text = readFile(file);
  for (const char* line : {"#SBATCH --array=1-4\n", "#SBATCH --time=00:20:00\n",
                           "#SBATCH --partition=cpu\n", "\"$SLURM_ARRAY_TASK_ID\""})
    EXPECT_NE(text.find(line), std::string::npos) << line << " in\n" << text;
  EXPECT_EQ(shell("bash -n " + file).status, 0);
  EXPECT_EQ(shell("bash -n " + dir + "/run_task.sh").status, 0);
  const std::vector<std::string> tasks = lines(readFile(dir + "/tasks.tsv"));
  ASSERT_EQ(tasks.size(), 5u);
  EXPECT_NE(tasks[4].find("--set sim.world=two_rooms --set sim.trajectory=two_rooms_robot "
                          "--set sim.seed=2"),
            std::string::npos)
      << tasks[4];
  EXPECT_NE(tasks[4].find("--out runs/004_two_rooms_ig_s2 --set output.overwrite=true --set "
                          "source.max_frames=50"),
            std::string::npos)
      << tasks[4];
  EXPECT_TRUE(fs::is_empty(dir + "/runs"));
  // Gathered before any task ran: one row per task, each missing; not an error.
  const Result g = runRasm("sweep gather " + dir);
  EXPECT_EQ(g.status, 0) << g.output;
  const nlohmann::json j = nlohmann::json::parse(readFile(dir + "/results.json"));
  ASSERT_EQ(j["rows"].size(), 4u);
  EXPECT_EQ(j["not_ok"], 4);
  EXPECT_EQ(j["rows"][3]["status"], "missing");
  EXPECT_EQ(j["rows"][3]["world"], "two_rooms");
  fs::remove_all(dir);
}

TEST(Sweep, BadInputIsNamed) {
  Result r = runRasm("sweep gather /nonexistent/sweep");
  EXPECT_EQ(r.status, 3);
  EXPECT_NE(r.output.find("/nonexistent/sweep: is not a folder"), std::string::npos) << r.output;
  r = shell(sweep("--jobs zero --dry-run --out /tmp/rasm_sweep_bad_" + std::to_string(getpid())));
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.output.find("--jobs 'zero'"), std::string::npos) << r.output;
  r = shell(sweep("--inputs /nonexistent.ini --dry-run --out /tmp/rasm_sweep_bad_" +
                  std::to_string(getpid())));
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.output.find("'/nonexistent.ini' does not exist"), std::string::npos) << r.output;
  fs::remove_all("/tmp/rasm_sweep_bad_" + std::to_string(getpid()));
}
