// Recorder: the rawlog reads back through rasm::io with the ground-truth poses of the TUM file,
// label PNGs match the rendered frames, and the same world, spec and seed give byte-identical
// files whatever the thread count.
#include "rasm/sim/Recorder.h"

#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <omp.h>
#include <unistd.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "rasm/core/Error.h"
#include "rasm/core/Params.h"
#include "rasm/core/SE3.h"
#include "rasm/models/ClassVocabulary.h"
#include "rasm/sim/FrameImages.h"

#ifdef RASM_SIM_HAVE_IO
#include "rasm/io/FrameSource.h"
#include "rasm/io/Trajectory.h"
#include "rasm/sim/SimFrameSource.h"
#endif

namespace fs = std::filesystem;
using namespace rasm;
using namespace rasm::sim;
using namespace rasm::models;

namespace {

/// A temporary folder removed at the end of the test.
struct TempDir {
  fs::path path;
  explicit TempDir(const std::string& name)
      : path(fs::temp_directory_path() / ("rasm_sim_" + name + "_" + std::to_string(::getpid()))) {
    fs::remove_all(path);
    fs::create_directories(path);
  }
  ~TempDir() { fs::remove_all(path); }
};

/// 160 x 120 camera (a quarter of Kinect v1) keeps the tests fast.
std::map<std::string, std::string> smallCamera() {
  return {{"width", "160"}, {"height", "120"}, {"fx", "131.25"},
          {"fy", "131.25"}, {"cx", "79.5"},    {"cy", "59.5"}};
}

const char* kHandheld =
    "type: handheld\n"
    "rate_hz: 30\n"
    "duration_s: 0.3\n"
    "keyframes:\n"
    "  - {t: 0.0, position: [6.5, 4.5, 1.55], look_at: [2.5, 0.6, 0.8]}\n"
    "  - {t: 0.3, position: [6.3, 4.3, 1.50], look_at: [2.0, 1.0, 0.8]}\n";

std::string readAll(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

/// Every regular file under `dir`, relative path -> contents.
std::map<std::string, std::string> snapshot(const fs::path& dir) {
  std::map<std::string, std::string> m;
  for (const auto& e : fs::recursive_directory_iterator(dir))
    if (e.is_regular_file()) m[fs::relative(e.path(), dir).string()] = readAll(e.path());
  return m;
}

RecordResult record(const fs::path& dir, const std::string& spec_yaml, std::uint64_t seed,
                    std::vector<RgbdFrame>* frames = nullptr) {
  RecordOptions opt;
  opt.out_rawlog = (dir / "seq.rawlog").string();
  opt.seed = seed;
  opt.sensor_overrides = smallCamera();
  const World world = loadWorld("office");
  const TrajectorySpec spec = loadTrajectorySpecFromString(spec_yaml, "inline_spec.yaml");
  return recordSequence(world, spec, opt, [&](const RgbdFrame& f) {
    if (frames) frames->push_back(f);
  });
}

}  // namespace

#ifdef RASM_SIM_HAVE_IO

TEST(Recorder, ReadsBackThroughIoWithTheGroundTruthPoses) {
  const TempDir tmp("recorder_roundtrip");
  std::vector<RgbdFrame> rendered;
  const RecordResult r = record(tmp.path, kHandheld, 3, &rendered);
  ASSERT_EQ(r.frames, 10u);  // 0.3 s at 30 Hz, both ends included
  EXPECT_EQ(r.groundtruth_path, (tmp.path / "seq_groundtruth.txt").string());
  EXPECT_TRUE(fs::exists(r.rawlog_path));
  EXPECT_FALSE(fs::exists(r.rawlog_path + ".part"));

  const io::Trajectory gt = io::readTumTrajectory(r.groundtruth_path);
  ASSERT_EQ(gt.size(), r.frames);
  auto source = io::openFrameSource(r.rawlog_path);
  std::size_t i = 0;
  while (auto f = source->next()) {
    ASSERT_LT(i, gt.size());
    const RgbdFrame& want = rendered[i];
    EXPECT_NEAR(f->timestamp_s, gt[i].timestamp_s, 1e-6);
    EXPECT_NEAR(gt[i].timestamp_s, i / 30.0, 1e-6);
    ASSERT_TRUE(f->gt_T_world_cam.has_value()) << "frame " << i;
    EXPECT_LT(translationDistance(*f->gt_T_world_cam, gt[i].T_world_cam), 1e-6) << "frame " << i;
    EXPECT_LT(rotationAngle(*f->gt_T_world_cam, gt[i].T_world_cam), 1e-6) << "frame " << i;
    EXPECT_LT(translationDistance(gt[i].T_world_cam, *want.gt_T_world_cam), 1e-8);
    EXPECT_TRUE(f->intrinsics == want.intrinsics);
    // Depth is stored in millimetres; colour losslessly.
    for (int y = 0; y < f->height(); ++y)
      for (int x = 0; x < f->width(); ++x) {
        ASSERT_NEAR(f->depth_m(x, y), want.depth_m(x, y), 0.0005 + 1e-6);
        ASSERT_EQ(f->colour(x, y).g, want.colour(x, y).g);
      }
    // Labels: 16-bit PNGs next to the rawlog, equal to the rendered ground truth.
    char name[64];
    std::snprintf(name, sizeof(name), "/instance_%06zu.png", i);
    const Image<std::uint16_t> inst = loadLabelPng(r.labels_dir + name);
    std::snprintf(name, sizeof(name), "/class_%06zu.png", i);
    const Image<std::uint16_t> cls = loadLabelPng(r.labels_dir + name);
    for (int y = 0; y < inst.height(); ++y)
      for (int x = 0; x < inst.width(); ++x) {
        ASSERT_EQ(inst(x, y), want.gt_instance(x, y));
        ASSERT_EQ(cls(x, y), want.gt_class(x, y));
      }
    ++i;
  }
  EXPECT_EQ(i, r.frames);

  // classes.json maps the ids in the label images to names.
  const auto j = nlohmann::json::parse(readAll(fs::path(r.labels_dir) / "classes.json"));
  EXPECT_EQ(j["frames"], r.frames);
  EXPECT_EQ(j["classes"][classIdFromName("cup")]["name"], "cup");
  bool found_phone = false;
  for (const auto& inst : j["instances"])
    found_phone = found_phone || inst["class"] == "conference_phone";
  EXPECT_TRUE(found_phone);
}

TEST(Recorder, SameSeedGivesByteIdenticalFilesWhateverTheThreadCount) {
  const TempDir a("recorder_det_a"), b("recorder_det_b"), c("recorder_det_c");
  const int threads = omp_get_max_threads();
  omp_set_num_threads(1);
  record(a.path, kHandheld, 11);
  omp_set_num_threads(std::max(2, threads));
  record(b.path, kHandheld, 11);
  record(c.path, kHandheld, 12);
  omp_set_num_threads(threads);
  const auto sa = snapshot(a.path), sb = snapshot(b.path), sc = snapshot(c.path);
  ASSERT_EQ(sa.size(), 10u * 2 + 3);  // labels, classes.json, rawlog, ground truth
  ASSERT_EQ(sa.size(), sb.size());
  for (const auto& [name, bytes] : sa) {
    ASSERT_TRUE(sb.count(name)) << name;
    EXPECT_TRUE(bytes == sb.at(name)) << name << " differs between two runs with the same seed";
  }
  EXPECT_FALSE(sa.at("seq.rawlog") == sc.at("seq.rawlog"))
      << "a different seed must change the noise";
}

/// The labels folder is emptied of an earlier recording's files only: a folder holding anything
/// else (the user's files) is refused and left as it was, and nothing is written (docs/io.md).
TEST(Recorder, LabelsFolderHoldingOtherFilesIsRefusedAndOnlyItsOwnFilesAreRemoved) {
  const TempDir tmp("recorder_labels");
  const RecordResult first = record(tmp.path, kHandheld, 3);
  const fs::path labels = first.labels_dir;
  // What a longer earlier recording, and a killed one, left: removed by the next recording.
  for (const char* f : {"instance_000099.png", "class_000099.png", "class_000004.png.part.png",
                        "classes.json.1a2b3c4d.part"})
    std::ofstream(labels / f) << "stale";
  record(tmp.path, kHandheld, 3);
  EXPECT_FALSE(fs::exists(labels / "instance_000099.png"));
  EXPECT_FALSE(fs::exists(labels / "class_000004.png.part.png"));
  EXPECT_FALSE(fs::exists(labels / "classes.json.1a2b3c4d.part"));
  EXPECT_TRUE(fs::exists(labels / "instance_000009.png"));
  // The user's files: refused, byte-identical, and no file of the recording is touched.
  std::ofstream(labels / "instance_000099.png") << "stale";
  std::ofstream(labels / "notes.txt") << "mine";
  std::ofstream(labels / "instance_final.png") << "mine too";
  const auto before = snapshot(tmp.path);
  try {
    record(tmp.path, kHandheld, 4);
    FAIL() << "no error";
  } catch (const InputError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("labels folder '" + labels.string() + "'"), std::string::npos) << msg;
    EXPECT_NE(msg.find("'notes.txt'"), std::string::npos) << msg;
    EXPECT_NE(msg.find("'instance_final.png'"), std::string::npos) << msg;
    EXPECT_EQ(msg.find("instance_000099"), std::string::npos) << msg;
  }
  EXPECT_EQ(snapshot(tmp.path), before);
  // A recording into a folder that does not exist is refused, nothing created.
  RecordOptions opt;
  opt.out_rawlog = (tmp.path / "missing" / "seq.rawlog").string();
  opt.sensor_overrides = smallCamera();
  EXPECT_THROW(recordSequence(loadWorld("office"),
                              loadTrajectorySpecFromString(kHandheld, "inline_spec.yaml"), opt),
               InputError);
  EXPECT_FALSE(fs::exists(tmp.path / "missing"));
}

TEST(Recorder, GroundRobotWritesOdometry) {
  const TempDir tmp("recorder_robot");
  const char* spec =
      "type: robot\n"
      "rate_hz: 10\n"
      "duration_s: 0.7\n"
      "start: {x: 1.2, y: 2.5, yaw_deg: 0}\n"
      "waypoints: [[4.0, 2.5]]\n"
      "controller: {max_v_mps: 0.3}\n"
      "robot: {odometry_noise: false}\n";
  std::vector<RgbdFrame> rendered;
  const RecordResult r = record(tmp.path, spec, 1, &rendered);
  ASSERT_EQ(r.frames, 8u);
  EXPECT_FALSE(r.robot_collided);
  auto source = io::openFrameSource(r.rawlog_path);
  std::size_t i = 0;
  double last_x = -1;
  while (auto f = source->next()) {
    ASSERT_TRUE(f->odometry_xyyaw.has_value()) << "frame " << i;
    ASSERT_TRUE(f->gt_T_world_cam.has_value());
    // Noise-free odometry equals the ground-truth base pose (camera 0.1 m ahead of the base).
    EXPECT_NEAR(f->odometry_xyyaw->x() + 0.1, f->gt_T_world_cam->translation().x(), 1e-3);
    EXPECT_NEAR(f->gt_T_world_cam->translation().z(), 0.55, 1e-6);
    EXPECT_GT(f->gt_T_world_cam->translation().x(), last_x);
    last_x = f->gt_T_world_cam->translation().x();
    ++i;
  }
  EXPECT_EQ(i, r.frames);
  EXPECT_NEAR(rendered.front().odometry_xyyaw->x(), 1.2, 1e-9);
  EXPECT_GT(last_x, 1.3 + 0.1);  // it moved (0.3 m/s for 0.7 s, after accelerating)
}

TEST(Recorder, BadSensorKeyInTheSpecNamesFileAndKey) {
  const TempDir tmp("recorder_bad");
  try {
    record(tmp.path, std::string(kHandheld) + "sensor: {noize: false}\n", 0);
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("inline_spec.yaml"), std::string::npos) << m;
    EXPECT_NE(m.find("noize"), std::string::npos) << m;
  }
}

#else
TEST(Recorder, DISABLED_NeedsTheIoModule) {}
#endif

#ifdef RASM_SIM_HAVE_IO
TEST(SimFrameSource, StreamsTheRecordersFramesAndTakesSimParams) {
  // [sim] as a pipeline run would hand it over, with its [camera] intrinsics.
  mrpt::config::CConfigFileMemory ini;
  ini.write("sim", "world", "office");
  ini.write("sim", "trajectory", "office_handheld");
  ini.write("sim", "seed", "4");
  ini.write("sim", "max_frames", "3");
  TSimParams p;
  loadParamsStrict(ini, "sim", p, "run.ini");
  const CameraIntrinsics K(131.25, 131.25, 79.5, 59.5, 160, 120);
  SimFrameSource source(p, K);
  EXPECT_EQ(source.sizeHint(), 3);
  EXPECT_NE(source.describe().find("office"), std::string::npos);
  std::vector<RgbdFrame> frames;
  while (auto f = source.next()) {
    EXPECT_NO_THROW(f->validate(source.describe()));
    frames.push_back(*f);
  }
  ASSERT_EQ(frames.size(), 3u);
  EXPECT_TRUE(frames[0].intrinsics == K);
  EXPECT_NEAR(frames[2].timestamp_s, 2.0 / 30.0, 1e-12);
  // Same frames as the sequence the recorder writes with the same seed and camera.
  SequenceOptions o;
  o.seed = 4;
  o.intrinsics = K;
  o.max_frames = 3;
  SimulatedSequence seq(loadWorld("office"), loadTrajectorySpec("office_handheld"), o);
  RgbdFrame g;
  for (const RgbdFrame& f : frames) {
    ASSERT_TRUE(seq.next(g));
    for (int y = 0; y < f.height(); ++y)
      ASSERT_EQ(std::memcmp(f.depth_m.row(y), g.depth_m.row(y), sizeof(float) * f.width()), 0);
  }
  EXPECT_FALSE(seq.next(g));
  // Unknown [sim] keys are errors naming the file.
  ini.write("sim", "wrld", "office");
  TSimParams bad;
  EXPECT_THROW(loadParamsStrict(ini, "sim", bad, "run.ini"), InputError);
}
#endif
