// The command line as a new user meets it (issue 19, 4): `rasm --version`, `--help` / `-h` on
// every command and subcommand (usage, exit 0, nothing run), and `rasm convert` writing only into
// an existing folder (docs/io.md: no writer creates parent folders).
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

#include "RasmProcess.h"

namespace fs = std::filesystem;
using namespace rasm::app::testing;

TEST(RasmCli, VersionPrintsVersionCommitAndBuildDate) {
  const Result flag = runRasm("--version"), cmd = runRasm("version");
  EXPECT_EQ(flag.status, 0) << flag.output;
  EXPECT_EQ(flag.output, cmd.output);
  std::smatch m;
  ASSERT_TRUE(std::regex_match(flag.output, m,
                               std::regex("rasm ([0-9]+\\.[0-9]+\\.[0-9]+)\n"
                                          "commit ([0-9a-f]{40}(-dirty)?|unknown)\n"
                                          "built (20[0-9]{2}-[01][0-9]-[0-3][0-9])\n")))
      << flag.output;
  // Built from this checkout: the commit is its HEAD (the build records it at every build).
  const Result head = shell("git -C " RASM_SOURCE_DIR " rev-parse HEAD", true);
  if (head.status == 0 && head.output.size() >= 40) {
    EXPECT_EQ(m[2].str().substr(0, 40), head.output.substr(0, 40))
        << "the binary was built from another commit: rebuild (scripts/build.sh)";
  }
  EXPECT_NE(runRasm("version extra").status, 0);
}

namespace {
/// The commands `rasm help` lists.
std::vector<std::string> listedCommands() {
  const Result r = runRasm("help");
  EXPECT_EQ(r.status, 0) << r.output;
  std::vector<std::string> names;
  std::istringstream in(r.output);
  std::string line;
  bool in_list = false;
  while (std::getline(in, line)) {
    if (line == "commands:") in_list = true;
    if (in_list && line.rfind("  ", 0) == 0) names.push_back(line.substr(2, line.find('\t') - 2));
  }
  return names;
}
}  // namespace

TEST(RasmCli, EveryCommandAndSubcommandPrintsItsUsageOnHelp) {
  const std::vector<std::string> commands = listedCommands();
  for (const char* expected : {"run", "convert", "eval", "sim", "sweep", "version", "help"})
    EXPECT_NE(std::find(commands.begin(), commands.end(), expected), commands.end()) << expected;
  std::vector<std::string> invocations(commands.begin(), commands.end());
  for (const char* sub :
       {"convert tum", "convert 7scenes", "eval ate", "eval rpe", "eval segmentation",
        "eval classification", "eval exploration", "eval memory", "sim record", "sim render",
        "sim info", "sim make-models", "sim generate", "sim check-map", "zsc train", "zsc detect",
        "sweep gather", "run my.ini --set a.b=c"})
    invocations.emplace_back(sub);
  for (const std::string& inv : invocations) {
    const std::string command = inv.substr(0, inv.find(' '));
    const bool top = command == inv;  // -h too (each call starts the binary: keep the list short)
    for (const char* flag : {"--help", "-h"}) {
      if (!top && std::string(flag) == "-h") continue;
      const Result r = runRasm(inv + " " + flag);
      EXPECT_EQ(r.status, 0) << "rasm " << inv << " " << flag << ":\n" << r.output;
      EXPECT_EQ(r.output.rfind("usage:", 0), 0u) << "rasm " << inv << " " << flag << ":\n"
                                                 << r.output;
      EXPECT_NE(r.output.find("rasm " + command), std::string::npos) << inv << ":\n" << r.output;
    }
  }
  // A subcommand with its own usage prints that one.
  EXPECT_EQ(runRasm("eval exploration --help").output.rfind("usage: rasm eval exploration", 0), 0u);
  EXPECT_EQ(runRasm("help convert").output, runRasm("convert tum --help").output);
  EXPECT_EQ(runRasm("help eval memory").output, runRasm("eval memory -h").output);
}

TEST(RasmCli, UnknownCommandsAndHelpTopicsAreNamed) {
  Result r = runRasm("frobnicate");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.output.find("unknown command 'frobnicate'"), std::string::npos) << r.output;
  r = runRasm("help frobnicate");
  EXPECT_EQ(r.status, 3);
  EXPECT_NE(r.output.find("rasm help frobnicate"), std::string::npos) << r.output;
  r = runRasm("sweep frobnicate");
  EXPECT_EQ(r.status, 3);
  EXPECT_NE(r.output.find("rasm sweep frobnicate"), std::string::npos) << r.output;
}

TEST(RasmCli, ConvertRefusesAMissingOutputFolderAndCreatesNothing) {
  const std::string dir = freshDir("convert");
  writeTwoFrameTumSequence(dir + "/seq");
  // A missing folder is named and nothing is created (it made a folder at the filesystem root).
  const std::string out = dir + "/not/yet/there/seq.rawlog";
  const Result r = runRasm("convert tum " + dir + "/seq " + out + " --intrinsics 10,10,4,3");
  EXPECT_EQ(r.status, 3) << r.output;
  EXPECT_NE(r.output.find("its folder '" + dir + "/not/yet/there' does not exist"),
            std::string::npos)
      << r.output;
  EXPECT_FALSE(fs::exists(dir + "/not")) << r.output;
  // A file where the folder should be is named too.
  std::ofstream(dir + "/file") << "x";
  const Result bad = runRasm("convert tum " + dir + "/seq " + dir + "/file/seq.rawlog");
  EXPECT_EQ(bad.status, 3) << bad.output;
  EXPECT_NE(bad.output.find("its folder '" + dir + "/file' is not a folder"), std::string::npos)
      << bad.output;
  // An existing folder is written as before.
  fs::create_directories(dir + "/there");
  const Result ok =
      runRasm("convert tum " + dir + "/seq " + dir + "/there/seq.rawlog --intrinsics 10,10,4,3");
  EXPECT_EQ(ok.status, 0) << ok.output;
  EXPECT_TRUE(fs::is_regular_file(dir + "/there/seq.rawlog")) << ok.output;
  EXPECT_NE(ok.output.find("2 frames"), std::string::npos) << ok.output;
  fs::remove_all(dir);
}

// `rasm objects` prints objects.json's objects, each once with its segments; --all adds its
// other_segments with the reason.
TEST(RasmCli, ObjectsListsTheObjectsAndWithAllTheOtherSegmentsAndWhy) {
  const std::string dir = freshDir("objects");
  std::ofstream(dir + "/objects.json")
      << R"({"comment": "test", "objects": [{"id": 4, "segments": [7, 12], "class": "chair",
          "probability": 0.9, "existence_probability": 0.83, "surfels": 900,
          "detections_fused": 4, "frames": {"first_seen": 10, "last_seen": 85, "seen": 9,
          "detected": 4}}],
        "other_segments": [{"segment": 3, "object": 1, "class": "dining table",
          "probability": 0.83, "surfels": 509740, "detections_fused": 9,
          "not_an_object": "structure"},
          {"segment": 5, "object": 2, "class": "none", "probability": 0.55, "surfels": 1,
          "detections_fused": 1, "not_an_object": "unconfirmed"}]})";
  const Result plain = runRasm("objects " + dir);
  EXPECT_EQ(plain.status, 0) << plain.output;
  EXPECT_NE(plain.output.find("chair"), std::string::npos) << plain.output;
  EXPECT_NE(plain.output.find(" 7,12 "), std::string::npos) << plain.output;
  EXPECT_NE(plain.output.find("9 10-85"), std::string::npos) << plain.output;
  EXPECT_NE(plain.output.find(" 0.83 "), std::string::npos) << plain.output;
  EXPECT_EQ(plain.output.find("dining table"), std::string::npos) << plain.output;
  EXPECT_NE(plain.output.find("1 objects, 1 rows shown"), std::string::npos) << plain.output;
  const Result all = runRasm("objects " + dir + " --all");
  EXPECT_EQ(all.status, 0) << all.output;
  EXPECT_NE(all.output.find("(structure)"), std::string::npos) << all.output;
  EXPECT_NE(all.output.find("(unconfirmed)"), std::string::npos) << all.output;
  EXPECT_NE(all.output.find("1 objects, 3 rows shown"), std::string::npos) << all.output;
  // A run folder from before the object layer (one `segment` per entry) still reads.
  std::ofstream(dir + "/objects.json")
      << R"({"objects": [{"segment": 7, "class": "chair", "probability": 0.9}]})";
  const Result old_format = runRasm("objects " + dir);
  EXPECT_EQ(old_format.status, 0) << old_format.output;
  EXPECT_NE(old_format.output.find(" 7 "), std::string::npos) << old_format.output;
  fs::remove_all(dir);
}

// `rasm run FOLDER | FILE.rawlog` maps the data with the default's settings ([source] type =
// auto); a folder that holds no known dataset is refused with what was expected.
TEST(RasmCli, RunMapsADatasetGivenInsteadOfAnIni) {
  const std::string out = freshDir("run_dataset");
  const Result r =
      runRasm("run " + std::string(RASM_SOURCE_DIR) +
              "/rawlogs/sim_office_handheld_320x240.rawlog --max-frames 5 --out " + out + "/run");
  ASSERT_EQ(r.status, 0) << r.output;
  const std::string report = readFile(out + "/run/report.json");
  EXPECT_NE(report.find("\"source\": \"rawlog " + std::string(RASM_SOURCE_DIR) +
                        "/rawlogs/sim_office_handheld_320x240.rawlog\""),
            std::string::npos)
      << report.substr(0, 2000);
  EXPECT_NE(report.find("\"frames\": 5"), std::string::npos);
  fs::create_directories(out + "/not_a_dataset");
  const Result bad = runRasm("run " + out + "/not_a_dataset --out " + out + "/bad");
  EXPECT_NE(bad.status, 0);
  EXPECT_NE(bad.output.find("neither a TUM RGB-D folder"), std::string::npos) << bad.output;
  fs::remove_all(out);
}

// mesh.ply comes from the Open3D plugin (meshing/SurfelMesh.h), loaded only when a mesh is built:
// the binary itself does not link Open3D (it cost every run ~22 MB at start), and a run that
// writes the mesh finds the plugin beside the meshing library.
TEST(RasmCli, TheMeshComesFromAPluginThatOnlyMeshingRunsLoad) {
  const Result deps = shell("ldd " + std::string(RASM_BINARY));
  ASSERT_EQ(deps.status, 0) << deps.output;
  EXPECT_EQ(deps.output.find("Open3D"), std::string::npos) << deps.output;
  EXPECT_NE(deps.output.find("librasm_meshing.so"), std::string::npos) << deps.output;

  const std::string out = freshDir("run_mesh");
  const Result r =
      runRasm("run " + std::string(RASM_SOURCE_DIR) +
              "/rawlogs/sim_office_handheld_320x240.rawlog --max-frames 20 --out " + out + "/run");
  ASSERT_EQ(r.status, 0) << r.output;
  const std::string ply = readFile(out + "/run/mesh.ply");
  ASSERT_EQ(ply.rfind("ply\n", 0), 0u) << ply.substr(0, 200);
  const std::smatch face = [&] {
    std::smatch m;
    std::regex_search(ply.cbegin(), ply.cbegin() + std::min<std::size_t>(ply.size(), 2000), m,
                      std::regex("element face ([0-9]+)"));
    return m;
  }();
  ASSERT_EQ(face.size(), 2u) << ply.substr(0, 400);
  // Twenty frames of the office at 320x240 see a desk, walls and the floor: thousands of
  // triangles at 3 cm cells, not a handful.
  EXPECT_GT(std::stol(face[1].str()), 1000) << ply.substr(0, 400);
  fs::remove_all(out);
}
