// Runs that never lie (issue 15, docs/io.md): atomic outputs, one run per folder, report.json
// always, sources without a frame, a full disk (a file size limit), SIGINT in the frame loop.
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <zlib.h>

#include <algorithm>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "rasm/core/Error.h"
#include "rasm/pipeline/Interrupts.h"
#include "rasm/pipeline/OutputFiles.h"
#include "rasm/run/MappingRun.h"
#include "run/RunTestFiles.h"

namespace fs = std::filesystem;
using namespace rasm;
using namespace rasm::pipeline;
using namespace rasm::autonomy;
using namespace rasm::run;
using namespace rasm::run::testing;

namespace {
RunConfig rawlogConfig(const std::string& path, const std::string& out) {
  RunConfig cfg = RunConfig::fromString("[source]\ntype = rawlog\npath = " + path + "\n", "test");
  cfg.set("output", "dir", out);
  return cfg;
}

/// Files an earlier run into the same folder would have left with its marker listing them (a
/// temporary of a killed run among them), and one of the user's: runs into it need --force
/// ([output] overwrite = true).
void fillWithEarlierRun(const std::string& dir) {
  fs::create_directories(dir);
  for (const char* f : {"map.ply", "groundtruth.txt", "annotated.rawlog", "map.surfelmap.part",
                        "report.json", "exploration.png"})
    writeBytes(dir + "/" + f, "from an earlier run");
  writeBytes(dir + "/" + kRunMarkerName,
             R"({"files": ["map.ply", "groundtruth.txt", "annotated.rawlog", "map.surfelmap",)"
             R"( "report.json", "exploration.png"]})");
  writeBytes(dir + "/notes.txt", "the user's");
}
}  // namespace

// ---- OutputFiles ----------------------------------------------------------------------------
TEST(OutputFiles, FailingWriterLeavesNeitherFinalNorTemporaryAndNamesTheFile) {
  const std::string dir = tempDir("atomic");
  fs::create_directories(dir);
  writeBytes(dir + "/map.ply", "complete old file");
  try {
    writeAtomically(dir + "/map.ply", [](const std::string& part) {
      writeBytes(part, std::string(1000, 'x'));  // half written, then the disk is full
      throw std::runtime_error("write failed");
    });
    FAIL() << "no error";
  } catch (const OutputError& e) {
    EXPECT_NE(std::string(e.what()).find(dir + "/map.ply"), std::string::npos) << e.what();
  }
  EXPECT_EQ(filesIn(dir), std::vector<std::string>{"map.ply"});
  EXPECT_EQ(readText(dir + "/map.ply"), "complete old file");  // the old one, untouched
  writeFileAtomically(dir + "/map.ply", "new");
  EXPECT_EQ(readText(dir + "/map.ply"), "new");
  fs::remove_all(dir);
}

TEST(OutputFiles, DevFullIsAWriteErrorNamingTheFile) {
  // /dev/full: every write fails with ENOSPC, as on a full disk (the writer writes there: a link
  // planted at the temporary would not be followed).
  const std::string dir = tempDir("devfull");
  fs::create_directories(dir);
  try {
    writeAtomically(dir + "/frames.csv", [](const std::string&) {
      std::FILE* f = std::fopen("/dev/full", "wb");
      ASSERT_NE(f, nullptr);
      const std::string bytes(100000, 'x');
      const bool written = std::fwrite(bytes.data(), 1, bytes.size(), f) == bytes.size();
      const bool closed = std::fclose(f) == 0;
      if (!written || !closed) throw std::runtime_error("write failed");
    });
    FAIL() << "a write to /dev/full succeeded";
  } catch (const OutputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find(dir + "/frames.csv"), std::string::npos) << m;
    EXPECT_NE(m.find("No space left on device"), std::string::npos) << m;
  }
  EXPECT_FALSE(fs::exists(dir + "/frames.csv"));
  EXPECT_TRUE(filesIn(dir).empty());
  fs::remove_all(dir);
}

TEST(OutputFiles, ValidUtf8ReplacesOnlyInvalidBytes) {
  EXPECT_EQ(validUtf8("plain"), "plain");
  EXPECT_EQ(validUtf8("caf\xC3\xA9 \xE2\x82\xAC \xF0\x9F\x98\x80"),
            "caf\xC3\xA9 \xE2\x82\xAC \xF0\x9F\x98\x80");
  // PNG's signature byte, a lone continuation byte, an overlong '/', a surrogate, a cut sequence.
  EXPECT_EQ(validUtf8("\x89PNG"), "\xEF\xBF\xBDPNG");
  EXPECT_EQ(validUtf8("a\x80z"), "a\xEF\xBF\xBDz");
  EXPECT_EQ(validUtf8("\xC0\xAF"), "\xEF\xBF\xBD\xEF\xBF\xBD");
  EXPECT_EQ(validUtf8("\xED\xA0\x80"), "\xEF\xBF\xBD\xEF\xBF\xBD\xEF\xBF\xBD");
  EXPECT_EQ(validUtf8("ab\xE2\x82"), "ab\xEF\xBF\xBD\xEF\xBF\xBD");
  EXPECT_NO_THROW((void)nlohmann::json(validUtf8("\xFF\xFE bad")).dump());
}

TEST(OutputFiles, FolderWritesOnlyKnownNamesAndClearsAnEarlierRun) {
  const std::string dir = tempDir("folder");
  fillWithEarlierRun(dir);
  std::vector<std::string> removed;
  // The user's notes.txt: refused unless forced.
  EXPECT_THROW(OutputFolder::claim(dir, OverwritePolicy::EarlierRun, removed), InputError);
  OutputFolder out = OutputFolder::claim(dir, OverwritePolicy::BesideOthers, removed);
  EXPECT_THROW(out.writeText("surprise.txt", "x"), std::logic_error);
  EXPECT_EQ(removed,
            (std::vector<std::string>{"annotated.rawlog", "exploration.png", "groundtruth.txt",
                                      "map.ply", "map.surfelmap.part", "report.json"}));
  EXPECT_EQ(filesIn(dir), std::vector<std::string>{"notes.txt"});  // the user's stays
  out.writeText("frames.csv", "a\n");
  EXPECT_EQ(out.written(), std::vector<std::string>{"frames.csv"});
  fs::remove_all(dir);
}

// ---- sources without a frame ----------------------------------------------------------------
struct NoFrameCase {
  std::string name;
  std::string path;     ///< made by the test when `bytes` is set
  std::string bytes;    ///< content of the file, when the test makes it
  std::string expect;   ///< in the error
  long long start = 0;  ///< [source] start_frame
};

class NoFrameSource : public ::testing::TestWithParam<NoFrameCase> {};

TEST_P(NoFrameSource, FailsWithTheReasonWritesReportAndNoMap) {
  const NoFrameCase& c = GetParam();
  const std::string out = tempDir("noframe_" + c.name);
  fillWithEarlierRun(out);
  std::string path = c.path;
  if (path.empty()) {
    path = out + "_input.rawlog";
    writeBytes(path, c.bytes);
  }
  if (!fs::exists(path)) GTEST_SKIP() << "absent: " << path;
  RunConfig cfg = rawlogConfig(path, out);
  cfg.set("output", "overwrite", "true");  // beside the user's notes.txt
  cfg.set("source", "start_frame", std::to_string(c.start));
  MappingRun run(cfg);
  try {
    run.run();
    FAIL() << "a run without a frame succeeded";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(c.expect), std::string::npos) << e.what();
  }
  // Only this run's config.ini, report.json and run.log, and the user's file (--force).
  EXPECT_EQ(filesIn(out),
            (std::vector<std::string>{"config.ini", "notes.txt", "report.json", "run.log"}));
  // run.log says where the run read from and why it failed.
  std::ifstream log_file(out + "/run.log");
  const std::string log_text((std::istreambuf_iterator<char>(log_file)),
                             std::istreambuf_iterator<char>());
  EXPECT_NE(log_text.find(" info rasm run: "), std::string::npos) << log_text;
  EXPECT_NE(log_text.find(" debug rasm run: failed after 0 frames"), std::string::npos) << log_text;
  EXPECT_NE(log_text.find(c.expect), std::string::npos) << log_text;
  fs::remove(out + "/notes.txt");
  const nlohmann::json rep = expectCompleteRunFolder(out);
  EXPECT_EQ(rep["status"], "failed");
  EXPECT_EQ(rep["frames"], 0);
  EXPECT_NE(rep["error"].get<std::string>().find(c.expect), std::string::npos) << rep["error"];
  fs::remove_all(out);
  fs::remove(out + "_input.rawlog");
}

/// The first `bytes` bytes of the simulated rawlog as stored (gzip), or of its content (plain: a
/// gzip stream cut short is refused before the run starts, RunRejectedBeforeAnyFrame... below).
std::string truncatedSimRawlog(std::size_t bytes, bool plain) {
  std::string head;
  if (plain) {
    gzFile f = gzopen(kSimRawlog.c_str(), "rb");
    head.resize(bytes);
    head.resize(std::size_t(std::max(0, gzread(f, head.data(), unsigned(bytes)))));
    gzclose(f);
    return head;
  }
  std::ifstream f(kSimRawlog, std::ios::binary);
  head.resize(bytes);
  f.read(head.data(), std::streamsize(bytes));
  return head;
}

INSTANTIATE_TEST_SUITE_P(
    Cases, NoFrameSource,
    ::testing::Values(
        NoFrameCase{"empty", "", "", "no CObservation3DRangeScan in 0 rawlog entries"},
        NoFrameCase{"text", "", "hello, I am not a rawlog\n", "corrupt or truncated rawlog"},
        NoFrameCase{"png", "", std::string("\x89PNG\r\n\x1a\n\0\0\0\rIHDR", 16),
                    "corrupt or truncated rawlog"},
        NoFrameCase{"truncated", "", truncatedSimRawlog(100, true),
                    "frame 0 (rawlog entry 1): corrupt or truncated rawlog"},
        NoFrameCase{"laser_only", "/usr/share/mrpt/datasets/rot_scan_2d.rawlog", "",
                    "no CObservation3DRangeScan in 1 rawlog entries"},
        NoFrameCase{"start_beyond_end", kSimRawlog, "",
                    "yielded no frame to map: it ended after 20 frames, before [source] "
                    "start_frame = 1000",
                    1000}),
    [](const auto& info) { return info.param.name; });

TEST(RunOutputs, OneFrameWorks) {
  const std::string out = tempDir("oneframe");
  RunConfig cfg = rawlogConfig(kSimRawlog, out);
  cfg.set("source", "start_frame", "19");  // the last of 20
  MappingRun run(cfg);
  const RunSummary s = run.run();
  EXPECT_EQ(s.frames, 1u);
  EXPECT_GT(s.surfels, 10000u);
  const nlohmann::json rep = expectCompleteRunFolder(out);
  EXPECT_EQ(rep["status"], "ok");
  EXPECT_EQ(rep["frames"], 1);
  EXPECT_EQ(rep["frames_read"], 20);
  EXPECT_EQ(maps::readSurfelPly(out + "/map.ply").size(), s.surfels);
  fs::remove_all(out);
}

// ---- one run per folder ---------------------------------------------------------------------
TEST(RunOutputs, SecondRunLeavesNoFileOfTheFirst) {
  const std::string out = tempDir("mixed");
  {  // ground truth and the annotated rawlog
    RunConfig cfg = rawlogConfig(kSimRawlog, out);
    cfg.set("source", "max_frames", "3");
    cfg.set("output", "write_rawlog", "true");
    MappingRun(cfg).run();
    EXPECT_TRUE(fs::exists(out + "/groundtruth.txt"));
    EXPECT_TRUE(fs::exists(out + "/annotated.rawlog"));
    (void)expectCompleteRunFolder(out);
  }
  {  // a frame without ground truth, no rawlog, no 3-D scene
    RunConfig cfg = rawlogConfig(RASM_MRPT_TEST_RAWLOG, out);
    cfg.set("output", "write_3dscene", "false");
    MappingRun(cfg).run();
  }
  EXPECT_FALSE(fs::exists(out + "/annotated.rawlog"));
  EXPECT_FALSE(fs::exists(out + "/map.3Dscene"));
  EXPECT_FALSE(fs::exists(out + "/map_segments.3Dscene"));
  const nlohmann::json rep = expectCompleteRunFolder(out);  // the folder is report's list exactly
  EXPECT_EQ(rep["frames"], 1);
  // The first run's 3 ground-truth poses are gone (this run's frame may carry one of its own).
  if (fs::exists(out + "/groundtruth.txt")) {
    EXPECT_EQ(io::readTumTrajectory(out + "/groundtruth.txt").size(), 1u) << "stale ground truth";
  }
  fs::remove_all(out);
}

TEST(RunOutputs, RunRejectedBeforeAnyFrameLeavesTheEarlierRunAsItWas) {
  const std::string out = tempDir("rejected");
  {
    RunConfig cfg = rawlogConfig(kSimRawlog, out);
    cfg.set("source", "max_frames", "2");
    MappingRun(cfg).run();
  }
  const std::vector<std::string> before = filesIn(out);
  const std::string config = readText(out + "/config.ini"), report = readText(out + "/report.json");
  // A missing rawlog, and a gzip rawlog cut short (its stream is checked before the first frame).
  const std::string cut = out + "_cut.rawlog";
  writeBytes(cut, truncatedSimRawlog(100000, false));
  for (const std::string& source : {std::string("/nonexistent/seq.rawlog"), cut}) {
    SCOPED_TRACE(source);
    RunConfig cfg = rawlogConfig(source, out);
    cfg.set("source", "max_frames", "7");
    MappingRun run(cfg);
    EXPECT_THROW(run.run(), InputError);
    EXPECT_EQ(filesIn(out), before);
    EXPECT_EQ(readText(out + "/config.ini"), config);
    EXPECT_EQ(readText(out + "/report.json"), report);
  }
  fs::remove(cut);
  fs::remove_all(out);
}

// ---- a full disk ----------------------------------------------------------------------------
/// RLIMIT_FSIZE makes every write beyond `bytes` in any file fail (EFBIG, with SIGXFSZ ignored):
/// a full disk reached in whichever file crosses it.
class FileSizeLimit {
 public:
  explicit FileSizeLimit(rlim_t bytes) {
    getrlimit(RLIMIT_FSIZE, &m_old);
    m_old_handler = std::signal(SIGXFSZ, SIG_IGN);
    rlimit l = m_old;
    l.rlim_cur = bytes;
    setrlimit(RLIMIT_FSIZE, &l);
  }
  ~FileSizeLimit() {
    setrlimit(RLIMIT_FSIZE, &m_old);
    std::signal(SIGXFSZ, m_old_handler);
  }

 private:
  rlimit m_old{};
  void (*m_old_handler)(int) = nullptr;
};

class FullDisk : public ::testing::TestWithParam<std::pair<long, std::string>> {};

TEST_P(FullDisk, NamesTheFileAndLeavesOnlyCompleteFiles) {
  const auto& [limit, setting] = GetParam();
  const std::string out = tempDir("fulldisk");
  RunConfig cfg = rawlogConfig(kSimRawlog, out);
  cfg.set("source", "max_frames", "10");
  if (!setting.empty()) cfg.set("output", setting, "false");
  MappingRun run(cfg);
  std::string error;
  {
    const FileSizeLimit full(rlim_t(limit) * 1024);
    try {
      run.run();
    } catch (const OutputError& e) {
      error = e.what();
    }
  }
  ASSERT_FALSE(error.empty()) << "no write failed under a " << limit << " KiB limit";
  const nlohmann::json rep = expectCompleteRunFolder(out);
  EXPECT_EQ(rep["status"], "failed");
  // The error names the file, which is absent.
  const std::string prefix = "output file '" + out + "/";
  const std::size_t at = error.find(prefix);
  ASSERT_NE(at, std::string::npos) << error;
  const std::string name =
      error.substr(at + prefix.size(), error.find('\'', at + prefix.size()) - (at + prefix.size()));
  EXPECT_FALSE(fs::exists(out + "/" + name)) << name;
  EXPECT_NE(error.find("File too large"), std::string::npos) << error;
  EXPECT_NE(rep["error"].get<std::string>().find(name), std::string::npos) << rep["error"];
  fs::remove_all(out);
}

// 8 KiB: config.ini (13 KB) fails; 64 KiB: map.ply; 500 KiB without the PLY: map.3Dscene (about
// 0.6 MB at 10 frames), in gzip's last flush or before it; 2 MiB without PLY and scenes:
// map.surfelmap.
INSTANTIATE_TEST_SUITE_P(Limits, FullDisk,
                         ::testing::Values(std::make_pair(8L, std::string()),
                                           std::make_pair(64L, std::string()),
                                           std::make_pair(500L, std::string("write_ply")),
                                           std::make_pair(1000L, std::string("write_ply"))));

// ---- SIGINT in the frame loop (in-process; the binary's tests send them from outside) -------
TEST(RunOutputs, SigintAfterTheThirdFrameWritesTheOutputsOfThreeFrames) {
  const std::string out = tempDir("sigint");
  RunConfig cfg = rawlogConfig(kSimRawlog, out);
  cfg.set("output", "write_rawlog", "true");
  MappingRun run(cfg);
  installInterruptHandlers();
  int seen = 0;
  const RunSummary s = run.run([&](const FrameResult&) {
    if (++seen == 3) std::raise(SIGINT);  // a real signal, while frame 3 finishes
  });
  uninstallInterruptHandlers();
  EXPECT_EQ(s.frames, 3u);
  EXPECT_EQ(s.status, "interrupted");
  EXPECT_EQ(s.interrupted_by, SIGINT);
  const nlohmann::json rep = expectCompleteRunFolder(out);  // 3 poses, 3 rows, 3 rawlog frames
  EXPECT_EQ(rep["status"], "interrupted");
  EXPECT_EQ(rep["interrupted_by"], "SIGINT");
  EXPECT_EQ(rep["interrupted_during"], "frames");
  EXPECT_EQ(rep["frames"], 3);
  EXPECT_TRUE(fs::exists(out + "/map.ply"));
  EXPECT_TRUE(fs::exists(out + "/annotated.rawlog"));
  fs::remove_all(out);
}

TEST(RunOutputs, SignalBeforeTheRunBeganLeavesTheFolderAsItWas) {
  const std::string out = tempDir("sigearly");
  fillWithEarlierRun(out);
  const std::vector<std::string> before = filesIn(out);
  MappingRun run(rawlogConfig(kSimRawlog, out));
  installInterruptHandlers();
  std::raise(SIGTERM);  // e.g. Ctrl-C while the detectors load
  const RunSummary s = run.run();
  uninstallInterruptHandlers();
  EXPECT_EQ(s.status, "interrupted");
  EXPECT_EQ(s.interrupted_by, SIGTERM);
  EXPECT_EQ(s.frames, 0u);
  EXPECT_EQ(filesIn(out), before);
  fs::remove_all(out);
}
