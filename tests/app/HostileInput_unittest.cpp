// The rasm binary on hostile input (docs/io.md "Refused or reported"): NaN and far camera poses
// are errors before the ray tracer (it used to abort, exit 134, leaving a .part behind), MRPT's
// backtraces only with --verbose, control characters in echoed names escaped.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "RasmProcess.h"

namespace fs = std::filesystem;
using namespace rasm::app::testing;

namespace {
bool has(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}
}  // namespace

TEST(HostileCli, SimRenderRefusesNonFiniteAndFarPoses) {
  const std::string dir = freshDir("render_pose");
  fs::create_directories(dir);
  const std::pair<const char*, const char*> cases[] = {
      {"--eye 3,2,1e30 --yaw 0", "--eye 3,2,1e30: value 1e+30 out of range"},
      {"--eye 3,2,1 --yaw inf", "--yaw inf: expected a finite number"},
      {"--eye nan,2,1 --yaw 0", "--eye nan,2,1: expected x,y,z"},
      {"--eye 3,2,1 --look-at inf,1,1", "--look-at inf,1,1: expected x,y,z"}};
  for (const auto& [pose, message] : cases) {
    const Result r = runRasm("sim render office " + dir + "/view " + pose);
    EXPECT_EQ(r.status, 3) << pose << "\n" << r.output;  // an input error, not an abort (134)
    EXPECT_TRUE(has(r.output, message)) << r.output;
  }
  EXPECT_TRUE(fs::is_empty(dir)) << "files left behind";
  fs::remove_all(dir);
}

TEST(HostileCli, MrptBacktraceOnlyWithVerbose) {
  const std::string dir = freshDir("bad_map");
  fs::create_directories(dir);
  {
    std::ofstream f(dir + "/bad.surfelmap", std::ios::binary);
    f << std::string(3000, '\x5a');
  }
  const std::string args =
      "run --map " + dir + "/bad.surfelmap --out " + dir + "/out --set source.max_frames=2";
  const Result r = runRasm(args);
  EXPECT_EQ(r.status, 3) << r.output;
  EXPECT_TRUE(has(r.output, "cannot be read as a rasm surfel map")) << r.output;
  EXPECT_FALSE(has(r.output, "Call stack backtrace")) << r.output;
  EXPECT_FALSE(has(r.output, "==== MRPT exception")) << r.output;
  const Result v = runRasm(args + " --verbose");
  EXPECT_EQ(v.status, 3) << v.output;
  EXPECT_TRUE(has(v.output, "Call stack backtrace")) << v.output;
  fs::remove_all(dir);
}

TEST(HostileCli, ControlCharactersInNamesAreEscaped) {
  const Result r = runRasm("run '/nonexistent/a\x1b[31mred.ini'");
  EXPECT_EQ(r.status, 3) << r.output;
  EXPECT_FALSE(has(r.output, "\x1b")) << r.output;
  EXPECT_TRUE(has(r.output, "a\\x1b[31mred.ini")) << r.output;
  // A world's name, as `rasm sim info` prints it.
  const std::string world = freshDir("escape_world") + ".yaml";
  std::ofstream(world)
      << "world: \"a\\e[31mred\"\nobjects:\n  - {id: 1, class: cup, primitive: box, "
         "size: [1, 1, 1], position: [0, 0, 0]}\n";
  const Result info = runRasm("sim info " + world);
  EXPECT_EQ(info.status, 0) << info.output;
  EXPECT_TRUE(has(info.output, "world a\\x1b[31mred")) << info.output;
  fs::remove(world);
  // A run's first line names its source and output folder.
  const std::string dir = freshDir("escape") + "\x1b[31m";
  const Result run = runRasm("run --out '" + dir + "' " + shortRunArgs(1));
  EXPECT_EQ(run.status, 0) << run.output;
  EXPECT_FALSE(has(run.output, "\x1b")) << run.output;
  EXPECT_TRUE(has(run.output, "\\x1b[31m")) << run.output;
  fs::remove_all(dir);
}

TEST(HostileCli, ConvertRefusesToOverwriteItsInput) {
  const std::string dir = freshDir("convert_self");
  writeTwoFrameTumSequence(dir + "/seq");
  const std::string depth_txt = readFile(dir + "/seq/depth.txt");
  const Result r =
      runRasm("convert tum " + dir + "/seq " + dir + "/seq/depth.txt --intrinsics 10,10,4,3");
  EXPECT_EQ(r.status, 3) << r.output;
  EXPECT_TRUE(has(r.output, "is a file of the input folder")) << r.output;
  EXPECT_EQ(readFile(dir + "/seq/depth.txt"), depth_txt);
  // A new rawlog inside the folder is fine, and so is converting again over it.
  for (int i = 0; i < 2; ++i) {
    const Result ok =
        runRasm("convert tum " + dir + "/seq " + dir + "/seq/seq.rawlog --intrinsics 10,10,4,3");
    EXPECT_EQ(ok.status, 0) << ok.output;
  }
  fs::remove_all(dir);
}

// The compiled-in default detector files ("../shared/data/detectors/...") were relative to the
// working directory: a run started elsewhere silently had no detector. They are now looked up in
// the compiled-in shared data folder.
TEST(HostileCli, DefaultDetectorIsFoundFromAnyWorkingDirectory) {
  const std::string weights =
      std::string(RASM_SHARED_DATA) + "/detectors/yolo-fastest-1.1-coco/yolo-fastest-1.1.weights";
  if (!fs::exists(weights)) GTEST_SKIP() << weights << " not found";
  const std::string dir = freshDir("default_detector");
  const Result r = shell("cd " + dir + " && env -u RASM_SHARED_DATA " + RASM_BINARY +
                         " run --out run " + shortRunArgs(2) +
                         " --set classification.detectors=dnn_detector"
                         " --set classification.every_n_frames=1");
  EXPECT_EQ(r.status, 0) << r.output;
  EXPECT_FALSE(has(r.output, "not found")) << r.output;
  EXPECT_FALSE(has(r.output, "running without")) << r.output;
  const nlohmann::json rep = nlohmann::json::parse(readFile(dir + "/run/report.json"));
  const nlohmann::json& cls = rep.at("classification");
  ASSERT_EQ(cls.at("detectors").size(), 1u) << cls;
  EXPECT_FALSE(cls["detectors"][0].contains("disabled")) << cls;
  EXPECT_TRUE(cls.value("warnings", nlohmann::json::array()).empty()) << cls;
  fs::remove_all(dir);
}
