// Live and real-time runs of `rasm run` (docs/hardware.md): a real-time replay drops frames a
// slowed mapper cannot take (and says which), a full-speed replay maps every frame; the shipped
// live INIs validate and, without their hardware, fail quickly with a clear error and a report;
// the Segway's odometry stamps the frames of the camera it carries.
#include <gtest/gtest.h>

#include <chrono>
#include <thread>

#include "pipeline/AnalyticScene.h"
#include "rasm/autonomy/RobotFrameSource.h"
#include "rasm/core/Error.h"
#include "rasm/io/OpenNI2FrameSource.h"
#include "rasm/io/RawlogFrameSource.h"
#include "rasm/io/RawlogWriter.h"
#include "rasm/run/MappingRun.h"
#include "robot/FakeRmpServer.h"
#include "run/RunTestFiles.h"

using namespace rasm;
using namespace rasm::pipeline;
using namespace rasm::autonomy;
using namespace rasm::run;
using namespace rasm::pipeline::testing;
using namespace rasm::run::testing;

namespace {
double secondsSince(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

/// `n` frames of the analytic room corner, the camera sliding sideways, at 30 Hz.
std::string writeCornerRawlog(const std::string& dir, int n, double t0_s = 0.0) {
  std::filesystem::create_directories(dir);
  const std::string path = dir + "/corner.rawlog";
  io::RawlogWriter w(path);
  const std::vector<Box> boxes = {{{-0.4, 0.2, 2.0}, {0.0, 0.6, 2.4}}};
  for (int i = 0; i < n; ++i) {
    RgbdFrame f = render(boxes, at(0.004 * i), i);
    f.timestamp_s = t0_s + i / 30.0;
    w.write(f);
  }
  w.close();
  return path;
}

RunConfig replayConfig(const std::string& rawlog, const std::string& out, bool real_time) {
  RunConfig cfg = RunConfig::fromString("[source]\ntype = rawlog\npath = " + rawlog +
                                            "\nprefetch_frames = 0\n[output]\nwrite_ply = "
                                            "false\nwrite_3dscene = false\npreview_png = false\n",
                                        "test");
  cfg.set("source", "real_time", real_time ? "true" : "false");
  cfg.set("output", "dir", out);
  return cfg;
}

std::size_t csvRows(const std::string& path) {
  const std::string text = readText(path);
  return std::size_t(std::count(text.begin(), text.end(), '\n')) - 1;  // minus the header
}

std::string shippedIni(const std::string& name) {
  return std::string(RASM_SOURCE_DIR) + "/ini/" + name;
}
}  // namespace

TEST(LiveRun, RealTimeReplayDropsFramesOfASlowMapperAndFullSpeedKeepsThemAll) {
  const std::string dir = tempDir("realtime");
  const int n = 45;  // 1.5 s at 30 Hz
  const std::string rawlog = writeCornerRawlog(dir, n);
  // The mapper slowed to at most 10 frames/s: 100 ms after every frame.
  const auto slow = [](const FrameResult&) {
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  };
  {
    MappingRun run(replayConfig(rawlog, dir + "/rt", true));
    const RunSummary s = run.run(slow);
    const nlohmann::json& rt = s.report.at("real_time");
    EXPECT_EQ(rt["paced_by"], "timestamps");
    EXPECT_EQ(rt["frames_offered"].get<long long>(), n);
    const long long dropped = rt["frames_dropped"].get<long long>();
    const long long processed = rt["frames_processed"].get<long long>();
    EXPECT_EQ(processed, (long long)s.frames);
    EXPECT_EQ(processed + dropped, n);
    EXPECT_GE(dropped, n / 2) << "processed " << processed;  // ~2 of every 3 frames
    EXPECT_NEAR(rt["offered_fps"].get<double>(), 30.0, 6.0);
    EXPECT_LE(rt["processed_fps"].get<double>(), 12.0);
    EXPECT_FALSE(rt["dropped_frames"].get<std::string>().empty());
    // frames.csv holds the processed frames only (their index column skips the dropped ones).
    EXPECT_EQ(csvRows(dir + "/rt/frames.csv"), s.frames);
  }
  {
    MappingRun run(replayConfig(rawlog, dir + "/full", false));
    const RunSummary s = run.run(slow);
    EXPECT_EQ(s.frames, std::size_t(n));
    EXPECT_FALSE(s.report.contains("real_time"));
    EXPECT_EQ(csvRows(dir + "/full/frames.csv"), std::size_t(n));
  }
}

TEST(LiveRun, RealTimeRejectsFrameSelectionsByName) {
  RunConfig cfg = replayConfig("/nonexistent.rawlog", tempDir("rt_bad"), true);
  cfg.set("source", "frame_step", "2");
  try {
    MappingRun run(cfg);
    FAIL() << "real_time with frame_step accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("[source] real_time"), std::string::npos) << e.what();
  }
}

TEST(LiveRun, ShippedLiveInisValidate) {
  for (const char* name : {"live_openni2.ini", "segway_rmp_explore.ini"}) {
    SCOPED_TRACE(name);
    const MappingRun run(RunConfig::fromFile(shippedIni(name)));  // what `rasm config` does
    const std::string cfg = run.effectiveConfig();
    EXPECT_NE(cfg.find("[openni2]"), std::string::npos);
    EXPECT_NE(cfg.find("[segway_rmp]"), std::string::npos);
  }
  // [robot] type = segway_rmp needs a camera on the robot.
  RunConfig bad = RunConfig::fromFile(shippedIni("segway_rmp_explore.ini"));
  bad.applyOverride("source.type=sim");
  EXPECT_THROW(MappingRun{bad}, InputError);
  // The Segway's heading is its wheels': a gyro's noise model for it is refused, named.
  RunConfig gyro = RunConfig::fromFile(shippedIni("segway_rmp_explore.ini"));
  gyro.applyOverride("robot.odometry_heading=gyro");
  try {
    const MappingRun run{gyro};
    ADD_FAILURE() << "a gyro's heading model on the Segway was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("[robot] odometry_heading = gyro"), std::string::npos)
        << e.what();
  }
}

TEST(LiveRun, OpenNI2IniWithoutACameraFailsClearlyWithAReport) {
  if (io::OpenNI2FrameSource::connectedDevices() > 0)
    GTEST_SKIP() << "an OpenNI2 camera is connected to this machine";
  const std::string out = tempDir("live_openni2");
  RunConfig cfg = RunConfig::fromFile(shippedIni("live_openni2.ini"));
  cfg.set("output", "dir", out);
  MappingRun run(cfg);
  const auto t0 = std::chrono::steady_clock::now();
  try {
    run.run();
    FAIL() << "a live run without a camera";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("[openni2] device_index = 0: no OpenNI2 device is "
                                         "connected"),
              std::string::npos)
        << e.what();
  }
  EXPECT_LT(secondsSince(t0), 10.0);
  const nlohmann::json rep = readJson(out + "/report.json");
  EXPECT_EQ(rep["status"], "failed");
  EXPECT_NE(rep["error"].get<std::string>().find("no OpenNI2 device"), std::string::npos);
  EXPECT_EQ(rep["frames"].get<long long>(), 0);
}

TEST(LiveRun, SegwayIniWithoutTheRobotFailsClearlyWithAReport) {
  const std::string out = tempDir("segway");
  RunConfig cfg = RunConfig::fromFile(shippedIni("segway_rmp_explore.ini"));
  cfg.set("output", "dir", out);
  MappingRun run(cfg);
  const auto t0 = std::chrono::steady_clock::now();
  try {
    run.run();
    FAIL() << "a Segway run without the Segway";
  } catch (const InputError& e) {
    // No answer within connect_timeout_s, or no route to its network: either names the robot.
    EXPECT_NE(std::string(e.what()).find("[segway_rmp] host = 192.168.0.40, port = 8080"),
              std::string::npos)
        << e.what();
  }
  EXPECT_LT(secondsSince(t0), 10.0);
  const nlohmann::json rep = readJson(out + "/report.json");
  EXPECT_EQ(rep["status"], "failed");
  EXPECT_NE(rep["error"].get<std::string>().find("[segway_rmp] host"), std::string::npos);
}

TEST(LiveRun, SegwayOdometryStampsTheFramesOfItsCamera) {
  robot::test::FakeRmpServer rmp;
  robot::TSegwayRmpParams p;
  p.host = "127.0.0.1";
  p.port = rmp.port();
  // A loaded 2-core machine starved the fake server for 0.54 s once (a linker running): the
  // link's 0.5 s default would fail the test for nothing it checks.
  p.response_timeout_s = 3.0;
  auto seg = std::make_unique<robot::SegwayRmpRobot>(p, Eigen::Isometry3d::Identity());
  robot::SegwayRmpRobot& robot = *seg;
  // Drive forward for 0.6 s, then stop.
  const double t_start =
      std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
  for (int i = 0; i < 12; ++i) {
    robot.setVelocityCommand(0.3, 0.0);
    robot.step(0.05);
  }
  robot.setVelocityCommand(0.0, 0.0);
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  // Camera frames stamped during the drive (this computer's clock, as a live camera's).
  const std::string dir = tempDir("segway_stamp");
  const std::string rawlog = writeCornerRawlog(dir, 18, t_start);
  RobotFrameSource source(std::make_unique<io::RawlogFrameSource>(rawlog), std::move(seg));
  double last_x = -1.0;
  int frames = 0;
  while (auto f = source.next()) {
    ASSERT_TRUE(f->odometry_xyyaw) << "frame " << f->index;
    const auto expected = source.robot().odometryAt(f->timestamp_s);
    EXPECT_NEAR((*f->odometry_xyyaw - *expected).norm(), 0.0, 1e-12);
    EXPECT_GE(f->odometry_xyyaw->x(), last_x);  // moving forward through the frames
    last_x = f->odometry_xyyaw->x();
    ++frames;
  }
  EXPECT_EQ(frames, 18);
  // The last frame (0.57 s into the drive) saw most of the ~0.18 m driven.
  EXPECT_GT(last_x, 0.08);
  EXPECT_LT(last_x, 0.2);
}
