// Whose files a run folder holds (RunFolder.h; docs/io.md "What rasm writes, what it never
// touches, what it refuses"): a folder holding files rasm did not write is refused and left
// byte-identical; --force ([output] overwrite = true) writes beside them and replaces only rasm's
// names; a folder of an earlier run is reused and only the files its marker lists are removed; a
// second run into a folder in use fails at once and deletes nothing.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <map>

#include "rasm/core/Error.h"
#include "rasm/pipeline/OutputFiles.h"
#include "rasm/pipeline/RunFolder.h"
#include "rasm/run/MappingRun.h"
#include "run/RunTestFiles.h"

namespace fs = std::filesystem;
using namespace rasm;
using namespace rasm::pipeline;
using namespace rasm::autonomy;
using namespace rasm::run;
using namespace rasm::run::testing;

namespace {

/// Every entry of `dir` (hidden ones included) with its bytes, or "-> target" for a link.
std::map<std::string, std::string> snapshot(const std::string& dir) {
  std::map<std::string, std::string> s;
  for (const auto& e : fs::directory_iterator(dir)) {
    const std::string name = e.path().filename().string();
    s[name] = e.is_symlink() ? "-> " + fs::read_symlink(e.path()).string() : readText(e.path());
  }
  return s;
}

/// The probe's victim: a user's folder with no rasm run in it, two names rasm also writes.
const std::map<std::string, std::string> kUserFiles = {
    {"notes.txt", "my notes\n"},
    {"important.ply", "ply\nformat ascii 1.0\nelement vertex 0\nend_header\n"},
    {"ubuntu.iso.part", std::string(4096, 'u')},
    {"thesis.tex.part", "\\documentclass{book}\n"},
    {"config.ini", "[user]\nkey = value\n"},
    {"map.ply", "the user's own map\n"}};

std::string userFolder(const std::string& name) {
  const std::string dir = tempDir(name);
  fs::create_directories(dir);
  for (const auto& [f, bytes] : kUserFiles) writeBytes(dir + "/" + f, bytes);
  return dir;
}

RunConfig twoFrameRun(const std::string& out) {
  RunConfig cfg =
      RunConfig::fromString("[source]\ntype = rawlog\npath = " + kSimRawlog + "\n", "test");
  cfg.set("source", "max_frames", "2");
  cfg.set("output", "dir", out);
  return cfg;
}

std::vector<std::string> markerFiles(const std::string& dir) {
  return readJson(dir + "/" + kRunMarkerName)["files"].get<std::vector<std::string>>();
}

bool contains(const std::vector<std::string>& v, const std::string& s) {
  return std::find(v.begin(), v.end(), s) != v.end();
}
}  // namespace

TEST(RunFolder, UserFolderIsRefusedAndLeftByteIdentical) {
  const std::string dir = userFolder("victim");
  const auto before = snapshot(dir);
  MappingRun run(twoFrameRun(dir));
  try {
    run.run();
    FAIL() << "a run into the user's folder succeeded";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("'" + dir + "'"), std::string::npos) << m;
    for (const auto& [f, bytes] : kUserFiles) EXPECT_NE(m.find("'" + f + "'"), std::string::npos);
    EXPECT_NE(m.find("--force"), std::string::npos) << m;
  }
  EXPECT_EQ(snapshot(dir), before);  // no lock, no marker, nothing removed or replaced
  fs::remove_all(dir);
}

TEST(RunFolder, ForceWritesBesideUserFilesAndReplacesOnlyRasmNames) {
  const std::string dir = userFolder("forced");
  RunConfig cfg = twoFrameRun(dir);
  cfg.set("output", "overwrite", "true");
  MappingRun(cfg).run();
  for (const auto& [f, bytes] : kUserFiles) {
    SCOPED_TRACE(f);
    if (f == "config.ini" || f == "map.ply") {  // rasm's names: replaced by rasm's files
      EXPECT_NE(readText(dir + "/" + f), bytes);
    } else {
      EXPECT_EQ(readText(dir + "/" + f), bytes);
    }
  }
  EXPECT_NE(readText(dir + "/config.ini").find("[output]"), std::string::npos);
  EXPECT_EQ(maps::readSurfelPly(dir + "/map.ply").size(),
            readJson(dir + "/report.json")["surfels"]);
  // The marker lists rasm's files only.
  const std::vector<std::string> marked = markerFiles(dir);
  for (const char* f : {"notes.txt", "important.ply", "ubuntu.iso.part", "thesis.tex.part"})
    EXPECT_FALSE(contains(marked, f)) << f;
  for (const auto& f : readJson(dir + "/report.json")["files"])
    EXPECT_TRUE(contains(marked, f.get<std::string>())) << f;
  // The next run: refused again for the user's files (not for rasm's), nothing changed.
  const auto after_first = snapshot(dir);
  try {
    MappingRun(twoFrameRun(dir)).run();
    FAIL() << "the user's files were not noticed";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("'notes.txt'"), std::string::npos) << m;
    EXPECT_EQ(m.find("'map.ply'"), std::string::npos) << m;
  }
  EXPECT_EQ(snapshot(dir), after_first);
  fs::remove_all(dir);
}

TEST(RunFolder, EarlierRunIsReusedAndOnlyItsListedFilesRemoved) {
  const std::string dir = tempDir("reused");
  {
    RunConfig cfg = twoFrameRun(dir);
    cfg.set("output", "write_rawlog", "true");
    MappingRun(cfg).run();
  }
  ASSERT_TRUE(fs::exists(dir + "/annotated.rawlog"));
  ASSERT_TRUE(fs::exists(dir + "/map.3Dscene"));
  EXPECT_TRUE(contains(markerFiles(dir), "annotated.rawlog"));
  // Temporaries a killed run would have left of its listed files.
  writeBytes(dir + "/map.ply.part", "half");
  writeBytes(dir + "/map.surfelmap.0123abcd.part", "half");
  RunConfig cfg = twoFrameRun(dir);
  cfg.set("output", "write_3dscene", "false");
  MappingRun(cfg).run();
  EXPECT_FALSE(fs::exists(dir + "/annotated.rawlog"));
  EXPECT_FALSE(fs::exists(dir + "/map.3Dscene"));
  const nlohmann::json rep = expectCompleteRunFolder(dir);  // no temporary, files = report's list
  EXPECT_EQ(rep["status"], "ok");
  EXPECT_FALSE(contains(markerFiles(dir), "annotated.rawlog"));
  fs::remove_all(dir);
}

TEST(RunFolder, AMarkerRemovesOnlyNamesARunCanWrite) {
  const std::string base = tempDir("forged");
  const std::string dir = base + "/run";
  fs::create_directories(dir);
  writeBytes(base + "/outside.txt", "outside");
  writeBytes(dir + "/notes.txt", "notes");
  writeBytes(dir + "/map.ply", "rasm's");
  writeBytes(dir + "/" + kRunMarkerName,
             R"({"files": ["notes.txt", "../outside.txt", "map.ply", "/etc/hostname", "."]})");
  std::vector<std::string> removed;
  EXPECT_THROW(OutputFolder::claim(dir, OverwritePolicy::EarlierRun, removed), InputError);
  {
    const OutputFolder out = OutputFolder::claim(dir, OverwritePolicy::BesideOthers, removed);
    EXPECT_EQ(removed, std::vector<std::string>{"map.ply"});
  }
  EXPECT_EQ(readText(dir + "/notes.txt"), "notes");
  EXPECT_EQ(readText(base + "/outside.txt"), "outside");
  EXPECT_EQ(filesIn(dir), std::vector<std::string>{"notes.txt"});
  fs::remove_all(base);
}

TEST(RunFolder, FolderOfAnOlderRasmCountsByItsReportJson) {
  const std::string dir = tempDir("older");
  fs::create_directories(dir);
  writeBytes(dir + "/report.json", R"({"report_schema": 5, "files": ["config.ini", "map.ply"]})");
  writeBytes(dir + "/config.ini", "[source]\n");
  writeBytes(dir + "/map.ply", "ply\n");
  std::vector<std::string> removed;
  { const OutputFolder out = OutputFolder::claim(dir, OverwritePolicy::EarlierRun, removed); }
  EXPECT_EQ(removed, (std::vector<std::string>{"config.ini", "map.ply", "report.json"}));
  EXPECT_TRUE(filesIn(dir).empty());
  // A report.json that is not a rasm run's marks nothing.
  fs::remove_all(dir);
  fs::create_directories(dir);
  writeBytes(dir + "/report.json", R"({"files": ["map.ply"]})");
  writeBytes(dir + "/map.ply", "the user's");
  const auto before = snapshot(dir);
  EXPECT_THROW(OutputFolder::claim(dir, OverwritePolicy::EarlierRun, removed), InputError);
  EXPECT_EQ(snapshot(dir), before);
  fs::remove_all(dir);
}

TEST(RunFolder, OverwriteFalseTakesOnlyAnEmptyFolder) {
  const std::string dir = tempDir("never");
  std::vector<std::string> removed;
  {
    OutputFolder out = OutputFolder::claim(dir, OverwritePolicy::Never, removed);  // new folder
    out.writeText("frames.csv", "a\n");
  }
  const auto before = snapshot(dir);
  EXPECT_THROW(OutputFolder::claim(dir, OverwritePolicy::Never, removed), InputError);
  EXPECT_EQ(snapshot(dir), before);
  fs::remove(dir + "/frames.csv");  // only the marker and the lock left: empty for a run
  EXPECT_NO_THROW(OutputFolder::claim(dir, OverwritePolicy::Never, removed));
  EXPECT_THROW(overwritePolicy("yes"), InputError);
  RunConfig cfg = twoFrameRun(dir);
  cfg.set("output", "overwrite", "maybe");
  EXPECT_THROW(MappingRun{cfg}, InputError);
  fs::remove_all(dir);
}

TEST(RunFolder, SecondLockFailsAtOnceNamingThePid) {
  const std::string dir = tempDir("lock");
  fs::create_directories(dir);
  {
    const RunFolderLock first(dir);
    try {
      const RunFolderLock second(dir);
      FAIL() << "the folder was locked twice";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(dir + " is in use by another rasm run (pid " +
                                           std::to_string(::getpid()) + ")"),
                std::string::npos)
          << e.what();
    }
  }
  EXPECT_NO_THROW(RunFolderLock{dir});  // released with the first
  fs::remove_all(dir);
}

TEST(RunFolder, RunIntoAFolderInUseFailsAndDeletesNothing) {
  const std::string dir = tempDir("inuse");
  MappingRun(twoFrameRun(dir)).run();
  const auto before = snapshot(dir);
  const RunFolderLock live_run(dir);  // as another rasm run holds it
  MappingRun second(twoFrameRun(dir));
  try {
    second.run();
    FAIL() << "a second run into a folder in use started";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(dir + " is in use by another rasm run (pid "),
              std::string::npos)
        << e.what();
  }
  auto after = snapshot(dir);
  after.erase(kRunLockName);  // holds the pid of its holder
  auto expected = before;
  expected.erase(kRunLockName);
  EXPECT_EQ(after, expected);
  fs::remove_all(dir);
}

TEST(RunFolder, FolderWriterNeverFollowsALinkAtItsTemporary) {
  const std::string dir = tempDir("link");
  fs::create_directories(dir);
  writeBytes(dir + "/victim.ini", "the victim's");
  fs::create_symlink(dir + "/victim.ini", dir + "/config.ini.part");
  std::vector<std::string> removed;
  {
    OutputFolder out = OutputFolder::claim(dir, OverwritePolicy::BesideOthers, removed);
    out.writeText("config.ini", "[rasm]\n");
  }
  EXPECT_EQ(readText(dir + "/victim.ini"), "the victim's");
  EXPECT_TRUE(fs::is_symlink(dir + "/config.ini.part"));
  EXPECT_FALSE(fs::is_symlink(dir + "/config.ini"));
  EXPECT_EQ(readText(dir + "/config.ini"), "[rasm]\n");
  fs::remove_all(dir);
}

TEST(RunFolder, WritePlyFalseWritesNoPlyAtAll) {
  // rasm bench's outputs: no map file of any kind.
  const std::string dir = tempDir("noply");
  RunConfig cfg = twoFrameRun(dir);
  for (const char* k : {"write_ply", "write_3dscene", "save_map", "preview_png"})
    cfg.set("output", k, "false");
  MappingRun(cfg).run();
  for (const std::string& f : filesIn(dir)) {
    const std::string ext = fs::path(f).extension().string();
    EXPECT_TRUE(ext != ".ply" && ext != ".3Dscene" && ext != ".surfelmap") << f;
  }
  EXPECT_TRUE(fs::exists(dir + "/segments.json"));  // the stages' tables are still written
  fs::remove_all(dir);
}
