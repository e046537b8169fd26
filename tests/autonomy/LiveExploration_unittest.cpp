// Closed-loop exploration on a real robot's path through `rasm run` (issue 19, VI), without
// hardware: the Segway interface (SegwayRmpRobot over UDP) talks to the fake RMP on loopback that
// tests/robot has, and a synthetic live camera renders the simulated office from the pose the fake
// base has driven to, at 10 Hz of wall time, stamped with UNIX time like a live camera. Everything
// between them is what `rasm run ini/segway_rmp_explore.ini` runs: RobotFrameSource (odometry
// stamps), real-time dropping, the mapper, the exploration loop with the planner in its thread,
// MRPT's reactive navigator stepping in a thread of its own (WallClockRobotDriver), and the
// obstacle scan from the camera's depth.
#include <gtest/gtest.h>

#include <chrono>
#include <csignal>
#include <cstdio>
#include <thread>

#include "rasm/core/Error.h"
#include "rasm/pipeline/Interrupts.h"
#include "rasm/pipeline/stages/TrackingStage.h"
#include "rasm/run/MappingRun.h"
#include "rasm/sim/SimFrameSource.h"
#include "robot/FakeRmpServer.h"
#include "run/RunTestFiles.h"

namespace fs = std::filesystem;
using namespace rasm;
using namespace rasm::pipeline;
using namespace rasm::autonomy;
using namespace rasm::run;
using namespace rasm::run::testing;

namespace {
double unixNow() {
  return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
}

/// The simulated office seen by a camera on the fake RMP's base: the base's pose is the fake's own
/// integration of the velocity commands it received, started at the office robot's start pose.
class OfficeCameraOnFakeRmp : public io::FrameSource {
 public:
  OfficeCameraOnFakeRmp(const robot::test::FakeRmpServer& rmp, const Eigen::Isometry3d& T_base_cam,
                        const CameraIntrinsics& K)
      : m_rmp(rmp), m_T_base_cam(T_base_cam), m_sim(simParams(), K, /*commanded=*/true) {}
  std::optional<RgbdFrame> next() override {
    // A camera paces itself: frame i at i / 10 s after the first.
    const auto due = m_t0 + std::chrono::milliseconds(100 * m_index);
    std::this_thread::sleep_until(due);
    RgbdFrame f;
    const Eigen::Isometry3d T_world_cam = cameraPose();
    m_sim.sequence().sensor().render(T_world_cam, 1, m_index, f);
    f.gt_T_world_cam = T_world_cam;
    f.timestamp_s = unixNow();
    f.index = m_index++;
    f.odometry_xyyaw.reset();  // RobotFrameSource stamps the Segway's odometry
    return f;
  }
  std::string describe() const override { return "office camera on the fake RMP"; }
  /// Where the fake base starts in the office: office_robot_loop's start pose (x, y, yaw).
  static inline const Eigen::Vector3d kStart{1.2, 2.5, 0.0};
  /// The fake base's pose in the office (x, y, yaw).
  static Eigen::Vector3d basePose(const robot::test::FakeRmpServer& rmp) {
    const auto r = rmp.record();
    const double c = std::cos(kStart.z()), s = std::sin(kStart.z());
    return {kStart.x() + c * r.x - s * r.y, kStart.y() + s * r.x + c * r.y, kStart.z() + r.yaw};
  }

 private:
  static sim::TSimParams simParams() {
    sim::TSimParams p;
    p.world = "office";
    p.trajectory = "office_robot_loop";
    p.seed = 1;
    return p;
  }
  Eigen::Isometry3d cameraPose() const {
    const Eigen::Vector3d b = basePose(m_rmp);
    Eigen::Isometry3d T_world_base = Eigen::Isometry3d::Identity();
    T_world_base.translation() = Eigen::Vector3d(b.x(), b.y(), 0.0);
    T_world_base.linear() = Eigen::AngleAxisd(b.z(), Eigen::Vector3d::UnitZ()).toRotationMatrix();
    return T_world_base * m_T_base_cam;
  }

  const robot::test::FakeRmpServer& m_rmp;
  Eigen::Isometry3d m_T_base_cam;
  sim::SimFrameSource m_sim;
  std::size_t m_index = 0;
  std::chrono::steady_clock::time_point m_t0 = std::chrono::steady_clock::now();
};

/// ini/segway_rmp_explore.ini with the RMP at the loopback stand-in, the office's box as the
/// workspace, turns in place at 90 deg/s, and the map at the camera's true poses (these tests
/// are about the loop's threads, not tracking).
RunConfig segwayInOfficeConfig(const std::string& out, int rmp_port) {
  RunConfig cfg = RunConfig::fromFile(std::string(RASM_SOURCE_DIR) + "/ini/segway_rmp_explore.ini");
  cfg.set("output", "dir", out);
  cfg.set("segway_rmp", "host", "127.0.0.1");
  cfg.set("segway_rmp", "port", std::to_string(rmp_port));
  cfg.set("segway_rmp", "max_w_degps", "90");
  // A loaded 2-core machine starves the stand-in's thread for 0.5 s at times (seen while a
  // linker ran): the link counts as lost only after 3 s here.
  cfg.set("segway_rmp", "response_timeout_s", "3");
  cfg.set("navigation", "align_w_degps", "90");  // the initial turn in place in ~4 s
  cfg.set("navigation", "max_w_degps", "90");
  setQuarterVgaCamera(cfg);
  for (const auto& [k, v] :
       std::vector<std::pair<std::string, std::string>>{{"workspace_min_x_m", "0"},
                                                        {"workspace_max_x_m", "8"},
                                                        {"workspace_min_y_m", "0"},
                                                        {"workspace_max_y_m", "6"}})
    cfg.set("exploration", k, v);
  cfg.set("mapper", "poses", "groundtruth");
  cfg.set("output", "write_rawlog", "false");
  cfg.set("output", "write_3dscene", "false");
  return cfg;
}

/// The run's camera: the office seen from the fake RMP's base.
void onFakeRmpInOffice(MappingRun& run, const robot::test::FakeRmpServer& rmp) {
  const Eigen::Isometry3d T_base_cam =
      run.mapper().stage<TrackingStage>().robotParams().T_base_cam();
  run.setLiveCamera([&rmp, T_base_cam]() -> std::unique_ptr<io::FrameSource> {
    return std::make_unique<OfficeCameraOnFakeRmp>(
        rmp, T_base_cam, CameraIntrinsics(262.5, 262.5, 159.5, 119.5, 320, 240));
  });
}
}  // namespace

// Deliverable 2 on the Segway: a goal is planned, the navigation thread sends velocity commands,
// the base drives toward the goal, and Ctrl-C stops every thread and writes the outputs.
TEST(LiveRun, SegwayExploresWithNavigationInItsOwnThreadAndStopsOnCtrlC) {
  robot::test::FakeRmpServer rmp;
  const std::string out = tempDir("live_explore");
  MappingRun run(segwayInOfficeConfig(out, rmp.port()));
  onFakeRmpInOffice(run, rmp);
  const auto basePose = [&] { return OfficeCameraOnFakeRmp::basePose(rmp); };

  // Ctrl-C once the base has driven 0.4 m from its start (toward a planned view: the initial
  // turn is in place), or after 150 s of wall time (then the assertions below fail).
  installInterruptHandlers();
  const auto t0 = std::chrono::steady_clock::now();
  Eigen::Vector3d start = Eigen::Vector3d::Constant(NAN);
  const RunSummary s = run.run([&](const FrameResult&) {
    if (std::isnan(start.x())) start = basePose();
    const double driven = (basePose().head<2>() - start.head<2>()).norm();
    const double wall =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if ((driven > 0.4 || wall > 150.0) && stopSignal() == 0) std::raise(SIGINT);
  });
  const double ran_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  uninstallInterruptHandlers();
  const Eigen::Vector3d end = basePose();

  // Stopped by the signal (no hang: run() returned), with a complete report.
  EXPECT_EQ(s.status, "interrupted");
  EXPECT_LT(ran_s, 200.0);
  const nlohmann::json rep = readJson(out + "/report.json");
  EXPECT_EQ(rep.at("stop_reason"), "interrupted");
  EXPECT_TRUE(rep.at("coverage_fraction").is_null()) << "no ground truth on a robot";
  const nlohmann::json& ex = rep.at("exploration");
  EXPECT_FALSE(ex.at("ground_truth").get<bool>());
  EXPECT_EQ(ex.at("navigation").at("stepping"), "thread");
  // The navigation thread stepped at [navigation] period_s = 0.1 s: ~10 Hz of wall time.
  EXPECT_GT(ex.at("navigation").at("rate_hz").get<double>(), 7.0);
  EXPECT_LT(ex.at("navigation").at("rate_hz").get<double>(), 10.5);
  EXPECT_GE(ex.at("plans").get<int>(), 1);
  ASSERT_GE(ex.at("goals").get<int>(), 1);
  EXPECT_TRUE(rep.at("robot").at("link_ok").get<bool>());

  // The goal driven to: the base ended nearer to it than it started.
  const nlohmann::json goals = readJson(out + "/exploration.json").at("goals");
  ASSERT_GE(goals.size(), 1u);
  const auto& g = goals.back().at("goal");
  const Eigen::Vector2d goal(g[0].get<double>(), g[1].get<double>());
  EXPECT_LT((goal - end.head<2>()).norm(), (goal - start.head<2>()).norm() - 0.2)
      << "start " << start.transpose() << " end " << end.transpose() << " goal "
      << goal.transpose();

  // The velocity commands the RMP received: the navigator's (forward and turning ones), then
  // zero after the stop (the navigator stopped the robot, then the Segway's shutdown).
  const auto rec = rmp.record();
  std::size_t forward = 0, turning = 0;
  for (const auto& c : rec.motion) {
    forward += c.float1() > 0.01f;
    turning += std::abs(c.float2()) > 0.01f;
  }
  EXPECT_GT(forward, 10u);
  EXPECT_GT(turning, 10u);
  ASSERT_FALSE(rec.motion.empty());
  EXPECT_EQ(rec.motion.back().float1(), 0.0f);
  EXPECT_EQ(rec.motion.back().float2(), 0.0f);
  std::printf(
      "live exploration: %.1f s, frames %zu processed / %lld dropped, navigation %zu steps at "
      "%.2f Hz, plans %d, goals %d, goal (%.2f, %.2f) at %.2f m from the start, %.2f m at the "
      "end; motion commands %zu (%zu forward, %zu turning)\n",
      ran_s, s.frames, rep.at("real_time").at("frames_dropped").get<long long>(),
      ex.at("navigation").at("steps").get<std::size_t>(),
      ex.at("navigation").at("rate_hz").get<double>(), ex.at("plans").get<int>(),
      ex.at("goals").get<int>(), goal.x(), goal.y(), (goal - start.head<2>()).norm(),
      (goal - end.head<2>()).norm(), rec.motion.size(), forward, turning);
  for (const char* f : {"trajectory.txt", "frames.csv", "exploration.json", "map.ply"})
    EXPECT_TRUE(fs::is_regular_file(out + "/" + f)) << f;
  fs::remove_all(out);
}

// The base stops answering mid-run: the navigation thread ends (zero velocity), the loop ends the
// run as failed with the Segway's reason, and the outputs of the frames done are written.
TEST(LiveRun, SegwayLinkLostMidExplorationFailsTheRunClearly) {
  robot::test::FakeRmpServer rmp;
  const std::string out = tempDir("live_explore_link");
  MappingRun run(segwayInOfficeConfig(out, rmp.port()));
  onFakeRmpInOffice(run, rmp);
  std::size_t frames = 0;
  const auto t0 = std::chrono::steady_clock::now();
  try {
    run.run([&](const FrameResult&) {
      if (++frames == 10) rmp.responsive = false;  // powered off after ten mapped frames
    });
    FAIL() << "a run whose robot stopped answering";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("navigation: segway_rmp 127.0.0.1:"), std::string::npos)
        << e.what();
    EXPECT_NE(std::string(e.what()).find("no valid response"), std::string::npos) << e.what();
  }
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 120.0);
  const nlohmann::json rep = readJson(out + "/report.json");
  EXPECT_EQ(rep.at("status"), "failed");
  EXPECT_EQ(rep.at("stop_reason"), "error");
  EXPECT_FALSE(rep.at("robot").at("link_ok").get<bool>());
  EXPECT_GE(rep.at("frames").get<std::size_t>(), 10u);
  EXPECT_TRUE(fs::is_regular_file(out + "/trajectory.txt"));
  fs::remove_all(out);
}
