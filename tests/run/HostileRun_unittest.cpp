// Runs and INI files that used to give a silent wrong result (docs/io.md "Refused or reported"):
// a run that fused nothing is `failed`, blank first frames are skipped until the map can start,
// the intrinsics used are in report.json (a guess says so), INI keys before any section or given
// twice, an unterminated [section, a UTF-8 BOM, and paths relative to the INI's folder.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "rasm/classification/DnnDetector.h"
#include "rasm/core/Error.h"
#include "rasm/core/Params.h"
#include "rasm/core/SharedData.h"
#include "rasm/run/MappingRun.h"
#include "rasm/run/RunConfig.h"
#include "run/RunTestFiles.h"

namespace fs = std::filesystem;
using namespace rasm;
using namespace rasm::pipeline;
using namespace rasm::autonomy;
using namespace rasm::run;
using namespace rasm::run::testing;

namespace {

std::string iniError(const std::string& text) {
  try {
    RunConfig::fromString(text, "h.ini");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

bool has(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

/// A TUM folder of `n` 640x480 frames whose depth images all hold `depth_units` (TUM: 5000 per
/// metre; 0 = no depth, 1 = 0.2 mm).
void writeTumFolder(const std::string& folder, int n, std::uint16_t depth_units) {
  fs::create_directories(folder + "/rgb");
  fs::create_directories(folder + "/depth");
  std::ofstream rgb(folder + "/rgb.txt"), depth(folder + "/depth.txt");
  const cv::Mat d(480, 640, CV_16UC1, cv::Scalar(depth_units));
  const cv::Mat c(480, 640, CV_8UC3, cv::Scalar(90, 120, 150));
  for (int i = 0; i < n; ++i) {
    const std::string t = std::to_string(100 + i) + ".000000";
    cv::imwrite(folder + "/depth/" + t + ".png", d);
    cv::imwrite(folder + "/rgb/" + t + ".png", c);
    depth << t << " depth/" << t << ".png\n";
    rgb << t << " rgb/" << t << ".png\n";
  }
}

/// Runs `cfg` into `out`; returns the error (empty when the run succeeded) and report.json.
std::pair<std::string, nlohmann::json> runInto(RunConfig cfg, const std::string& out) {
  cfg.set("output", "dir", out);
  cfg.set("output", "write_3dscene", "false");
  std::string error;
  try {
    MappingRun run(cfg);
    run.run();
  } catch (const InputError& e) {
    error = e.what();
  }
  return {error, readJson(out + "/report.json")};
}

}  // namespace

TEST(HostileIni, KeyBeforeAnySectionNamesItsLine) {
  const std::string e = iniError("; a comment\nmax_depth_m = 3\n[mapper]\n");
  EXPECT_TRUE(has(e, "h.ini:2")) << e;
  EXPECT_TRUE(has(e, "key 'max_depth_m' before any [section]")) << e;
}

TEST(HostileIni, DuplicateKeyNamesBothLines) {
  const std::string e =
      iniError("[mapper]\nmax_depth_m = 3\n\n[source]\n[mapper]\nmax_depth_m = 4\n");
  EXPECT_TRUE(has(e, "h.ini:6")) << e;
  EXPECT_TRUE(has(e, "[mapper] max_depth_m given twice (first at line 2)")) << e;
  // The same key in two sections is two keys.
  EXPECT_EQ(iniError("[mapper]\nmax_depth_m = 3\n[fusion]\nmax_depth_m = 4\n"), "");
}

TEST(HostileIni, UnterminatedSectionNamesItsLine) {
  const std::string e = iniError("[source]\ntype = sim\n[mapper\nmax_depth_m = 3\n");
  EXPECT_TRUE(has(e, "h.ini:3")) << e;
  EXPECT_TRUE(has(e, "unterminated section header '[mapper'")) << e;
}

TEST(HostileIni, Utf8BomIsAccepted) {
  const RunConfig c = RunConfig::fromString("\xEF\xBB\xBF[source]\ntype = rawlog\n", "h.ini");
  EXPECT_EQ(c.ini().read_string("source", "type", ""), "rawlog");
}

TEST(HostileIni, PathsAreRelativeToTheIniFolder) {
  const std::string dir = tempDir("ini_paths");
  fs::create_directories(dir + "/conf");
  {
    std::ofstream f(dir + "/conf/run.ini");
    f << "[source]\ntype = rawlog\npath = data/seq.rawlog\n"
         "[dnn_detector]\nmodel = ../models/m.onnx\nnames = /abs/coco.names\n"
         "[sim]\nworld = office\n";
  }
  const RunConfig c = RunConfig::fromFile(dir + "/conf/run.ini");
  EXPECT_EQ(c.ini().read_string("source", "path", ""), dir + "/conf/data/seq.rawlog");
  EXPECT_EQ(c.ini().read_string("dnn_detector", "model", ""), dir + "/models/m.onnx");
  EXPECT_EQ(c.ini().read_string("dnn_detector", "names", ""), "/abs/coco.names");
  EXPECT_EQ(c.ini().read_string("sim", "world", ""), "office");  // a name, not a path
  fs::remove_all(dir);
}

TEST(HostileRun, NoValidDepthIsFailedAndIntrinsicsAreReported) {
  const std::string dir = tempDir("blank_depth");
  writeTumFolder(dir + "/my_camera", 3, 0);  // no fr1/fr2/fr3 in the name: intrinsics guessed
  const auto [error, rep] =
      runInto(RunConfig::fromString("[source]\ntype = tum\npath = " + dir + "/my_camera\n", "test"),
              dir + "/out");
  EXPECT_TRUE(has(error, "nothing was fused")) << error;
  EXPECT_EQ(rep["status"], "failed");
  EXPECT_TRUE(has(rep["error"].get<std::string>(), "the map is empty after 3 frames")) << rep;
  EXPECT_EQ(rep["surfels"], 0);
  ASSERT_TRUE(rep.contains("intrinsics")) << rep;
  EXPECT_DOUBLE_EQ(rep["intrinsics"]["fx"].get<double>(), 525.0);
  EXPECT_EQ(rep["intrinsics"]["width"], 640);
  EXPECT_TRUE(has(rep["source"].get<std::string>(), "WARNING: intrinsics guessed")) << rep;
  fs::remove_all(dir);
}

/// A first frame without depth lost the whole run: the map started on it, empty, and every
/// later frame was lost. The map now starts on the first frame with enough valid depth; the
/// frames before it are counted and reported.
TEST(HostileRun, BlankFirstFramesAreSkippedAndTheMapStartsAfterThem) {
  const std::string dir = tempDir("blank_start");
  writeTumFolder(dir + "/fr1_blank_start", 5, 7500);  // a wall at 1.5 m
  const cv::Mat blank(480, 640, CV_16UC1, cv::Scalar(0));
  for (const char* t : {"100.000000", "101.000000"})
    cv::imwrite(dir + "/fr1_blank_start/depth/" + t + ".png", blank);
  const auto [error, rep] = runInto(
      RunConfig::fromString("[source]\ntype = tum\npath = " + dir + "/fr1_blank_start\n", "test"),
      dir + "/out");
  EXPECT_EQ(error, "");
  EXPECT_EQ(rep["status"], "ok") << rep;
  EXPECT_GT(rep["surfels"].get<int>(), 1000) << rep;
  EXPECT_EQ(rep["frames_before_map"], 2) << rep;
  ASSERT_TRUE(rep.contains("warnings")) << rep;
  EXPECT_TRUE(has(rep["warnings"][0].get<std::string>(), "the map started after 2 frame(s)"))
      << rep;
  // No depth in any frame: still failed, every frame skipped.
  writeTumFolder(dir + "/fr1_all_blank", 3, 0);
  const auto [error_blank, rep_blank] = runInto(
      RunConfig::fromString("[source]\ntype = tum\npath = " + dir + "/fr1_all_blank\n", "test"),
      dir + "/out_blank");
  EXPECT_TRUE(has(error_blank, "nothing was fused")) << error_blank;
  EXPECT_EQ(rep_blank["status"], "failed");
  EXPECT_EQ(rep_blank["frames_before_map"], 3) << rep_blank;
  EXPECT_FALSE(rep_blank.contains("warnings")) << rep_blank;
  fs::remove_all(dir);
}

/// The same on a real sequence: TUM fr1/xyz with its first two frames' depth images blanked
/// maps normally from its third frame on.
TEST(HostileRun, RealSequenceWithBlankFirstFramesMapsNormally) {
  const fs::path data = fs::path(RASM_SHARED_DATA) / "tum" / "fr1_xyz_first37";
  if (!fs::exists(data / "depth.txt")) GTEST_SKIP() << data << " not found";
  const std::string dir = tempDir("blank_start_real");
  const std::string seq = dir + "/fr1_xyz_blank_start";
  fs::create_directories(seq + "/depth");
  for (const char* f : {"rgb.txt", "depth.txt", "groundtruth.txt"})
    fs::copy_file(data / f, seq + "/" + f);
  fs::create_directory_symlink(data / "rgb", seq + "/rgb");
  std::ifstream list(data / "depth.txt");
  std::string line;
  int k = 0;
  while (std::getline(list, line)) {
    if (line.empty() || line[0] == '#') continue;
    const std::string name = line.substr(line.find(' ') + 1);
    if (k++ < 3)  // the first two associated frames (the first depth image has no colour)
      cv::imwrite(seq + "/" + name, cv::Mat(480, 640, CV_16UC1, cv::Scalar(0)));
    else
      fs::copy_file(data / name, seq + "/" + name);
  }
  RunConfig cfg = RunConfig::fromString("[source]\ntype = tum\npath = " + seq + "\n", "test");
  cfg.set("source", "max_frames", "10");
  const auto [error, rep] = runInto(cfg, dir + "/out");
  EXPECT_EQ(error, "");
  EXPECT_EQ(rep["status"], "ok") << rep;
  EXPECT_EQ(rep["frames_before_map"], 2) << rep;
  EXPECT_EQ(rep["frames_lost"], 2) << rep;  // the two blank frames, and no other
  EXPECT_GT(rep["surfels"].get<int>(), 10000) << rep;
  fs::remove_all(dir);
}

TEST(HostileRun, SubMillimetreDepthIsFailed) {
  const std::string dir = tempDir("tiny_depth");
  writeTumFolder(dir + "/fr1_tiny", 3, 1);  // 0.2 mm everywhere
  const auto [error, rep] =
      runInto(RunConfig::fromString("[source]\ntype = tum\npath = " + dir + "/fr1_tiny\n", "test"),
              dir + "/out");
  EXPECT_TRUE(has(error, "nothing was fused")) << error;
  EXPECT_EQ(rep["status"], "failed");
  EXPECT_DOUBLE_EQ(rep["intrinsics"]["fx"].get<double>(), 517.3);  // tum_fr1, by its name
  EXPECT_FALSE(has(rep["source"].get<std::string>(), "WARNING")) << rep;
  fs::remove_all(dir);
}

TEST(HostileRun, AbsurdFocalLengthIsRefused) {
  RunConfig cfg = RunConfig::fromString(
      "[source]\ntype = rawlog\npath = " RASM_MRPT_TEST_RAWLOG
      "\n[camera]\nfx = 1e30\nfy = 1e30\ncx = 319.5\ncy = 239.5\nwidth = 640\nheight = 480\n",
      "cam.ini");
  try {
    MappingRun run(cfg);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_TRUE(has(e.what(), "camera.fx = 1e30 in cam.ini:5")) << e.what();
    EXPECT_TRUE(has(e.what(), "(0, 100000]")) << e.what();
  }
}

TEST(HostileRun, MapOfAnotherSceneLosesEveryFrameAndIsFailed) {
  const std::string dir = tempDir("foreign_map");
  RunConfig office =
      RunConfig::fromString("[source]\ntype = rawlog\npath = " RASM_SOURCE_DIR
                            "/rawlogs/sim_office_handheld_320x240.rawlog\nmax_frames = 5\n",
                            "test");
  const auto [office_error, office_rep] = runInto(office, dir + "/office");
  ASSERT_EQ(office_error, "");
  ASSERT_EQ(office_rep["status"], "ok");
  ASSERT_TRUE(fs::exists(dir + "/office/map.surfelmap"));
  // The MRPT Kinect frame (a lab) against the simulated office's map.
  RunConfig lab =
      RunConfig::fromString("[source]\ntype = rawlog\npath = " RASM_MRPT_TEST_RAWLOG "\n", "test");
  lab.set("mapper", "load_map", dir + "/office/map.surfelmap");
  const auto [error, rep] = runInto(lab, dir + "/lab");
  EXPECT_TRUE(has(error, "tracking lost all 1 frames")) << error;
  EXPECT_TRUE(has(error, "is it a map of this scene?")) << error;
  EXPECT_EQ(rep["status"], "failed");
  EXPECT_EQ(rep["frames_lost"], 1);
  fs::remove_all(dir);
}

/// The shipped INIs name their data relative to themselves, and their detector presets the shared
/// data folder: the detector and the sequence are found whatever the working directory (the
/// tests run in build/tests).
TEST(HostileIni, ShippedIniFindsItsDataFromAnyFolder) {
  for (const char* name : {"7scenes_redkitchen.ini", "7scenes_redkitchen_yolo_fastest.ini"}) {
    const RunConfig c = RunConfig::fromFile(std::string(RASM_SOURCE_DIR) + "/ini/" + name);
    rasm::classification::TDnnDetectorParams dnn;
    rasm::loadParamsStrict(c.ini(), "dnn_detector", dnn, name);
    const std::string model = rasm::resolveSharedData(dnn.model);
    const std::string path = c.ini().read_string("source", "path", "");
    EXPECT_TRUE(has(model, "/shared/data/detectors/")) << name << ": " << model;
    if (!fs::exists(std::string(RASM_SHARED_DATA))) continue;
    EXPECT_TRUE(fs::is_regular_file(model)) << name << ": " << model;
    EXPECT_TRUE(fs::is_directory(path)) << name << ": " << path;
  }
}
