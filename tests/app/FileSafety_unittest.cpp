// The built binary never touches what rasm did not write (docs/io.md "What rasm writes, what it
// never touches, what it refuses"): `rasm run --out` into a user's folder is refused and leaves
// it byte-identical, --force writes beside the user's files and replaces only rasm's names;
// `rasm bench` works in a mkdtemp folder of its own, never at a fixed name in $TMPDIR, removes it
// and writes no map file; --out creates no parent folders.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <string>

#include "RasmProcess.h"

namespace fs = std::filesystem;
using namespace rasm::app::testing;

namespace {
const std::string kSimRawlog =
    std::string(RASM_SOURCE_DIR) + "/rawlogs/sim_office_handheld_320x240.rawlog";

/// Every entry of `dir` (hidden ones included) with its bytes, or "-> target" for a link.
std::map<std::string, std::string> snapshot(const std::string& dir) {
  std::map<std::string, std::string> s;
  for (const auto& e : fs::directory_iterator(dir)) {
    const std::string name = e.path().filename().string();
    s[name] = e.is_symlink()     ? "-> " + fs::read_symlink(e.path()).string()
              : e.is_directory() ? "<folder>"
                                 : readFile(e.path().string());
  }
  return s;
}

/// The probe's folder: a user's files, two of them with names rasm writes too.
const std::map<std::string, std::string> kUserFiles = {
    {"notes.txt", "my notes\n"},         {"important.ply", "ply\nmine\n"},
    {"ubuntu.iso.part", "half an iso"},  {"thesis.tex.part", "\\chapter{One}\n"},
    {"config.ini", "[user]\nkey = 1\n"}, {"map.ply", "the user's map\n"}};

std::string runArgs(const std::string& out) {
  return "run --set source.type=rawlog --set source.path=" + kSimRawlog + " --max-frames 2 --out " +
         out;
}
}  // namespace

TEST(FileSafety, RunRefusesAUsersFolderAndForceReplacesOnlyRasmNames) {
  const std::string dir = freshDir("victim");
  for (const auto& [f, bytes] : kUserFiles) std::ofstream(dir + "/" + f) << bytes;
  const auto before = snapshot(dir);
  const Result refused = runRasm(runArgs(dir));
  EXPECT_EQ(refused.status, 3) << refused.output;
  EXPECT_NE(refused.output.find(dir), std::string::npos) << refused.output;
  EXPECT_NE(refused.output.find("'thesis.tex.part'"), std::string::npos) << refused.output;
  EXPECT_EQ(refused.output.find("removed"), std::string::npos) << refused.output;
  EXPECT_EQ(snapshot(dir), before);

  const Result forced = runRasm(runArgs(dir) + " --force");
  ASSERT_EQ(forced.status, 0) << forced.output;
  for (const auto& [f, bytes] : kUserFiles) {
    SCOPED_TRACE(f);
    const std::string now = readFile(dir + "/" + f);
    if (f == "config.ini" || f == "map.ply")
      EXPECT_NE(now, bytes);  // rasm's names: rasm's files now
    else
      EXPECT_EQ(now, bytes);
  }
  EXPECT_EQ(readFile(dir + "/map.ply").rfind("ply\nformat binary", 0), 0u);
  fs::remove_all(dir);
}

// --out creates the run's folder, never a chain of folders above it (a mistyped path).
TEST(FileSafety, RunRefusesAMissingParentOfItsFolderAndCreatesNothing) {
  const std::string dir = freshDir("out_parent");
  const Result r = runRasm(runArgs(dir + "/no/such/run"));
  EXPECT_EQ(r.status, 3) << r.output;
  EXPECT_NE(r.output.find("its folder '" + dir + "/no/such' does not exist"), std::string::npos)
      << r.output;
  EXPECT_TRUE(fs::is_empty(dir)) << r.output;
  // The run's own folder is created when its parent exists.
  const Result ok = runRasm(runArgs(dir + "/run/"));
  EXPECT_EQ(ok.status, 0) << ok.output;
  EXPECT_TRUE(fs::is_regular_file(dir + "/run/report.json")) << ok.output;
  fs::remove_all(dir);
}

TEST(FileSafety, BenchWorksInAScratchFolderOfItsOwnAndWritesNoMap) {
  const std::string dir = freshDir("bench");
  const std::string tmp = dir + "/tmp", victim = dir + "/victim";
  fs::create_directories(tmp);
  fs::create_directories(victim);
  std::ofstream(victim + "/config.ini") << "the victim's";
  std::ofstream(victim + "/download.part") << "half";
  fs::create_directory_symlink(victim, tmp + "/rasm_bench");  // the old fixed name
  const auto victim_before = snapshot(victim);
  // Two benches at once.
  const std::string bench =
      "TMPDIR=" + tmp + " " + RASM_BINARY + " bench " + kSimRawlog + " --frames 3 2>/dev/null";
  const Result r = shell("(" + bench + " > " + dir + "/a.json; echo $? > " + dir + "/a.rc) & " +
                         bench + " > " + dir + "/b.json; echo $? > " + dir + "/b.rc; wait");
  for (const char* run : {"a", "b"}) {
    SCOPED_TRACE(run);
    EXPECT_EQ(readFile(dir + "/" + run + ".rc"), "0\n") << r.output;
    const nlohmann::json j = nlohmann::json::parse(readFile(dir + "/" + run + ".json"));
    EXPECT_EQ(j["frames"], 3);
    for (const auto& f : j["files"]) {
      const std::string ext = fs::path(f.get<std::string>()).extension().string();
      EXPECT_TRUE(ext != ".ply" && ext != ".3Dscene" && ext != ".surfelmap") << f;
    }
  }
  EXPECT_EQ(snapshot(tmp), (std::map<std::string, std::string>{{"rasm_bench", "-> " + victim}}));
  EXPECT_EQ(snapshot(victim), victim_before);
  fs::remove_all(dir);
}
