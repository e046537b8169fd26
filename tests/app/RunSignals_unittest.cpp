// `rasm run` under real SIGINT / SIGTERM sent from outside (issue 15, docs/io.md "Runs that never
// lie"): the built binary is started on a simulated hand-held run at 320x240, and signals arrive
// during the frames or while the outputs are written. Whatever the moment, the folder holds only
// complete files and report.json says what happened.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include "run/RunTestFiles.h"

namespace fs = std::filesystem;
using namespace rasm::run::testing;
using Clock = std::chrono::steady_clock;

namespace {
struct Child {
  pid_t pid = -1;
  std::string out;
};

/// Starts `rasm run` on the simulated office (hand-held, 320x240, a few hundred frames) into a
/// fresh folder; its output goes to <out>.log.
/// Forks and execs `args` (args[0] the binary) with stdout and stderr to `log`; `tmpdir`, when
/// not empty, becomes the child's $TMPDIR. Returns the child's pid.
pid_t spawn(std::vector<std::string> args, const std::string& log, const std::string& tmpdir = "") {
  std::fflush(stdout);  // else the child's freopen flushes our buffer a second time
  std::fflush(stderr);
  const pid_t pid = fork();
  if (pid == 0) {
    if (!tmpdir.empty()) ::setenv("TMPDIR", tmpdir.c_str(), 1);
    FILE* f = std::freopen(log.c_str(), "w", stdout);
    if (f) (void)dup2(fileno(stdout), 2);
    std::vector<char*> argv;
    for (std::string& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    execv(argv[0], argv.data());
    _exit(127);
  }
  return pid;
}

Child startRun(const std::string& name, const std::vector<std::string>& extra = {}) {
  Child c;
  c.out = tempDir("signals_" + name);
  std::vector<std::string> args = {RASM_BINARY, "run",
                                   "--out",     c.out,
                                   "--set",     "sim.trajectory=office_handheld",
                                   "--set",     "camera.preset=",
                                   "--set",     "camera.fx=262.5",
                                   "--set",     "camera.fy=262.5",
                                   "--set",     "camera.cx=159.5",
                                   "--set",     "camera.cy=119.5",
                                   "--set",     "camera.width=320",
                                   "--set",     "camera.height=240"};
  args.insert(args.end(), extra.begin(), extra.end());
  c.pid = spawn(args, c.out + ".log");
  return c;
}

/// Waits (at most 60 s) until `path` exists; false on time-out or when the child ended.
bool waitFor(const Child& c, const std::string& path) {
  const auto until = Clock::now() + std::chrono::seconds(60);
  while (Clock::now() < until) {
    if (fs::exists(path)) return true;
    int status = 0;
    if (waitpid(c.pid, &status, WNOHANG) == c.pid) return false;
    std::this_thread::sleep_for(std::chrono::microseconds(200));
  }
  return false;
}

int exitCode(const Child& c) {
  int status = 0;
  waitpid(c.pid, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : 1000 + WTERMSIG(status);
}

void cleanUp(const Child& c) {
  fs::remove_all(c.out);
  fs::remove(c.out + ".log");
}
}  // namespace

TEST(RunSignals, SigintDuringFramesStopsAndWritesTheFramesDone) {
  const Child c = startRun("frames", {"--set", "output.write_rawlog=true"});
  // annotated.rawlog.part appears with the first frame.
  ASSERT_TRUE(waitFor(c, c.out + "/annotated.rawlog.part")) << readText(c.out + ".log");
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  kill(c.pid, SIGINT);
  EXPECT_EQ(exitCode(c), 128 + SIGINT) << readText(c.out + ".log");
  const nlohmann::json rep = expectCompleteRunFolder(c.out);
  EXPECT_EQ(rep["status"], "interrupted");
  EXPECT_EQ(rep["interrupted_by"], "SIGINT");
  EXPECT_EQ(rep["interrupted_during"], "frames");
  EXPECT_GE(rep["frames"].get<int>(), 1);
  EXPECT_LT(rep["frames"].get<int>(), 200);  // the trajectory is far longer
  for (const char* f : {"map.ply", "map.surfelmap", "trajectory.txt", "annotated.rawlog"})
    EXPECT_TRUE(fs::exists(c.out + "/" + f)) << f;
  cleanUp(c);
}

TEST(RunSignals, SigtermWhileWritingEachOutputFinishesTheOutputs) {
  // The signal arrives as each of these files appears: the run writes all outputs anyway.
  int interrupted = 0;
  for (const char* part : {"frames.csv", "map.ply.part", "map.surfelmap.part", "objects.json"}) {
    SCOPED_TRACE(part);
    const Child c = startRun("outputs", {"--max-frames", "30"});
    const bool seen = waitFor(c, c.out + "/" + part);
    kill(c.pid, SIGTERM);
    const int code = exitCode(c);
    if (!seen) {  // the file came and went between two looks: the run may have ended already
      cleanUp(c);
      continue;
    }
    EXPECT_TRUE(code == 128 + SIGTERM || code == 0) << code << readText(c.out + ".log");
    const nlohmann::json rep = expectCompleteRunFolder(c.out);
    EXPECT_EQ(rep["frames"], 30);
    if (code != 0) {
      ++interrupted;
      EXPECT_EQ(rep["status"], "interrupted");
      EXPECT_EQ(rep["interrupted_during"], "outputs");
    }
    for (const char* f : {"map.ply", "map.surfelmap", "trajectory.txt", "objects.json"})
      EXPECT_TRUE(fs::exists(c.out + "/" + f)) << f;
    cleanUp(c);
  }
  std::printf("signal while writing: %d of 4 runs interrupted in their outputs\n", interrupted);
  EXPECT_GE(interrupted, 2);
}

TEST(RunSignals, SecondSignalAbortsAtOnceLeavingOnlyCompleteFiles) {
  // Two signals: during the frames, and at several points of the output writing.
  int aborted = 0;
  for (const char* part : {"annotated.rawlog.part", "map.ply.part", "map.3Dscene.part",
                           "map.surfelmap.part", "segments.json"}) {
    SCOPED_TRACE(part);
    const Child c = startRun("abort", {"--max-frames", "30", "--set", "output.write_rawlog=true"});
    const bool seen = waitFor(c, c.out + "/" + part);
    kill(c.pid, SIGTERM);
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
    kill(c.pid, SIGTERM);
    const int code = exitCode(c);
    EXPECT_TRUE(code == 128 + SIGTERM || (!seen && code == 0)) << code;
    const nlohmann::json rep = expectCompleteRunFolder(c.out);  // no temporary, all whole
    if (code == 128 + SIGTERM) {
      // Aborted, or (when the second signal came after the report) interrupted.
      EXPECT_TRUE(rep["status"] == "aborted" || rep["status"] == "interrupted") << rep["status"];
      aborted += rep["status"] == "aborted";
      if (rep["status"] == "aborted")  // its files: the marker, which lists every file present
        EXPECT_EQ(rep["files_listed_in"], ".rasm-run.json") << rep;
      EXPECT_EQ(rep["report_schema"], 1);  // the short aborted report says what wrote it too
      EXPECT_TRUE(rep["rasm"]["commit"].is_string()) << rep;
      std::printf("%s: %s after %d frames, files %s\n", part,
                  rep["status"].get<std::string>().c_str(), rep["frames"].get<int>(),
                  ::testing::PrintToString(filesIn(c.out)).c_str());
    }
    cleanUp(c);
  }
  EXPECT_GE(aborted, 3);
}

namespace {
/// Starts `rasm bench` on the simulated hand-held office at 320x240 with $TMPDIR = `tmp`.
Child startBench(const std::string& tmp) {
  Child c;
  c.out = tmp;
  std::vector<std::string> args = {RASM_BINARY, "bench",
                                   "--set",     "sim.trajectory=office_handheld",
                                   "--set",     "camera.preset=",
                                   "--set",     "camera.fx=262.5",
                                   "--set",     "camera.fy=262.5",
                                   "--set",     "camera.cx=159.5",
                                   "--set",     "camera.cy=119.5",
                                   "--set",     "camera.width=320",
                                   "--set",     "camera.height=240"};
  c.pid = spawn(args, tmp + ".log", tmp);
  return c;
}

/// The bench's scratch folder in `tmp` once its run has written config.ini (at most 60 s).
std::string waitForBenchScratch(const Child& c) {
  const auto until = Clock::now() + std::chrono::seconds(60);
  while (Clock::now() < until) {
    for (const auto& e : fs::directory_iterator(c.out))
      if (fs::exists(e.path() / "config.ini")) return e.path().string();
    int status = 0;
    if (waitpid(c.pid, &status, WNOHANG) == c.pid) return "";
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  return "";
}
}  // namespace

// `rasm bench` stopped by a signal left its mkdtemp folder behind: the first signal now stops
// the run, which returns and removes it; a second one aborts and the handler removes it.
TEST(RunSignals, BenchStoppedBySignalsRemovesItsScratchFolder) {
  for (const int signals : {1, 2}) {
    SCOPED_TRACE(signals);
    const std::string tmp = tempDir("bench_signal");
    const Child c = startBench(tmp);
    const std::string scratch = waitForBenchScratch(c);
    ASSERT_NE(scratch, "") << readText(tmp + ".log");
    std::this_thread::sleep_for(std::chrono::milliseconds(signals == 1 ? 1000 : 300));
    kill(c.pid, signals == 1 ? SIGINT : SIGTERM);
    if (signals == 2) {
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
      kill(c.pid, SIGTERM);
    }
    EXPECT_EQ(exitCode(c), signals == 1 ? 128 + SIGINT : 128 + SIGTERM) << readText(tmp + ".log");
    EXPECT_FALSE(fs::exists(scratch)) << readText(tmp + ".log");
    EXPECT_TRUE(fs::is_empty(tmp)) << ::testing::PrintToString(filesIn(tmp));
    if (signals == 1)
      EXPECT_NE(readText(tmp + ".log").find("\"status\":\"interrupted\""), std::string::npos)
          << readText(tmp + ".log");
    fs::remove_all(tmp);
    fs::remove(tmp + ".log");
  }
}
