// SegwayRmpRobot against a stand-in RMP on loopback (FakeRmpServer: a real UDP socket in a
// thread): configuration at connection, command encoding, odometry, watchdog, shutdown, and a
// clear error (never a hang) when nothing answers.
#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>

#include <chrono>
#include <thread>

#include "FakeRmpServer.h"
#include "rasm/core/Error.h"
#include "rasm/robot/SegwayRmpRobot.h"

using namespace rasm::robot;
using rasm::robot::test::FakeRmpServer;

namespace {
TSegwayRmpParams paramsFor(int port) {
  TSegwayRmpParams p;
  p.host = "127.0.0.1";
  p.port = port;
  p.connect_timeout_s = 1.0;
  p.response_timeout_s = 0.3;
  p.watchdog_timeout_s = 0.25;
  p.command_rate_hz = 50;
  return p;
}
void sleepS(double s) {
  std::this_thread::sleep_for(std::chrono::duration<double>(s));
}
double secondsSince(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}
}  // namespace

TEST(SegwayRmpRobot, ConfiguresTheRmpAndEncodesCommands) {
  FakeRmpServer rmp;
  SegwayRmpRobot robot(paramsFor(rmp.port()), Eigen::Isometry3d::Identity());
  const auto cfg = rmp.record().config;
  // Bitmaps 1-3, the two limits, tractor mode, then the no-op that got the first feedback.
  ASSERT_GE(cfg.size(), 7u);
  const rmp::FeedbackLayout layout;
  EXPECT_EQ(cfg[0].word1, 17u);
  EXPECT_EQ(cfg[0].word2, layout.bitmap1);
  EXPECT_EQ(cfg[1].word1, 18u);
  EXPECT_EQ(cfg[1].word2, layout.bitmap2);
  EXPECT_EQ(cfg[3].word1, 1u);
  EXPECT_FLOAT_EQ(cfg[3].float2(), 2.2f);
  EXPECT_EQ(cfg[4].word1, 6u);
  EXPECT_FLOAT_EQ(cfg[4].float2(), 3.0f);
  EXPECT_EQ(cfg[5].word1, 32u);
  EXPECT_EQ(cfg[5].word2, 5u);  // tractor
  EXPECT_TRUE(robot.status().link_ok);
  EXPECT_EQ(robot.status().operational_state, 3u);
  EXPECT_FLOAT_EQ(robot.status().battery_soc_pct, 87.5f);

  // 0.44 m/s and 0.3 rad/s are 0.2 and 0.1 of the RMP's limits (2.2 m/s, 3 rad/s).
  robot.setVelocityCommand(0.44, 0.3);
  sleepS(0.1);
  auto m = rmp.record().motion;
  ASSERT_FALSE(m.empty());
  EXPECT_NEAR(m.back().float1(), 0.2f, 1e-6);
  EXPECT_NEAR(m.back().float2(), 0.1f, 1e-6);
  // Beyond rasm's own clamps (max_v_mps 0.5, max_w_degps 60): clamped before normalising.
  robot.setVelocityCommand(5.0, -10.0);
  sleepS(0.1);
  m = rmp.record().motion;
  EXPECT_NEAR(m.back().float1(), 0.5 / 2.2, 1e-6);
  EXPECT_NEAR(m.back().float2(), -(60.0 * M_PI / 180.0) / 3.0, 1e-6);
  EXPECT_EQ(rmp.record().bad_packets, 0u);
}

TEST(SegwayRmpRobot, OdometryFollowsTheWheels) {
  FakeRmpServer rmp;
  SegwayRmpRobot robot(paramsFor(rmp.port()), Eigen::Isometry3d::Identity());
  // Forward, then an arc; commands refreshed faster than the watchdog.
  for (int i = 0; i < 10; ++i) {
    robot.setVelocityCommand(0.4, 0.0);
    robot.step(0.05);
  }
  for (int i = 0; i < 16; ++i) {
    robot.setVelocityCommand(0.2, 0.8);
    robot.step(0.05);
  }
  robot.setVelocityCommand(0.0, 0.0);
  sleepS(0.2);  // the last responses in
  const auto rec = rmp.record();
  const Eigen::Vector3d odo = robot.odometry();
  // The base moved (about 0.2 m straight, then an arc of ~0.6 rad) ...
  EXPECT_GT(rec.x, 0.15);
  EXPECT_GT(rec.yaw, 0.3);
  // ... and the odometry from the wheel positions agrees with the base's own integration.
  EXPECT_NEAR(odo.x(), rec.x, 2e-3);
  EXPECT_NEAR(odo.y(), rec.y, 2e-3);
  EXPECT_NEAR(odo.z(), rec.yaw, 2e-3);
  // odometryAt: the newest for times after the last response, the oldest before the first.
  const auto now_s =
      std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
  ASSERT_TRUE(robot.odometryAt(now_s + 10.0));
  EXPECT_NEAR((*robot.odometryAt(now_s + 10.0) - odo).norm(), 0.0, 1e-9);
  EXPECT_NEAR(robot.odometryAt(now_s - 1e6)->norm(), 0.0, 1e-9);
}

TEST(SegwayRmpRobot, WatchdogStopsAStaleCommandAndShutdownStops) {
  FakeRmpServer rmp;
  {
    SegwayRmpRobot robot(paramsFor(rmp.port()), Eigen::Isometry3d::Identity());
    robot.setVelocityCommand(0.3, 0.0);
    sleepS(0.1);
    EXPECT_NEAR(rmp.record().motion.back().float1(), 0.3 / 2.2, 1e-6);
    EXPECT_EQ(robot.status().watchdog_stops, 0u);
    sleepS(0.4);  // > watchdog_timeout_s (0.25) without a command
    EXPECT_EQ(rmp.record().motion.back().float1(), 0.0f);
    EXPECT_EQ(robot.status().watchdog_stops, 1u);
    // A new command drives again.
    robot.setVelocityCommand(0.1, 0.0);
    sleepS(0.1);
    EXPECT_NEAR(rmp.record().motion.back().float1(), 0.1 / 2.2, 1e-6);
  }
  // Destroyed while driving: zero velocity, then standby (given the datagrams time to land).
  sleepS(0.1);
  const auto rec = rmp.record();
  EXPECT_EQ(rec.motion.back().float1(), 0.0f);
  EXPECT_EQ(rec.motion.back().float2(), 0.0f);
  EXPECT_EQ(rec.config.back().word1, 32u);
  EXPECT_EQ(rec.config.back().word2, 4u);  // standby
}

TEST(SegwayRmpRobot, NoRmpGivesAClearErrorWithinTheTimeout) {
  FakeRmpServer rmp;
  rmp.responsive = false;  // reads, never answers
  TSegwayRmpParams p = paramsFor(rmp.port());
  p.connect_timeout_s = 0.4;
  const auto t0 = std::chrono::steady_clock::now();
  try {
    SegwayRmpRobot robot(p, Eigen::Isometry3d::Identity());
    FAIL() << "connected to a silent RMP";
  } catch (const rasm::InputError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("[segway_rmp] host = 127.0.0.1, port = " + std::to_string(rmp.port())),
              std::string::npos)
        << msg;
    EXPECT_NE(msg.find("no response from the Segway RMP within 0.4 s"), std::string::npos) << msg;
  }
  EXPECT_LT(secondsSince(t0), 1.0);
  EXPECT_GT(rmp.record().config.size(), 0u);  // it did try

  // Nothing listening at all (a closed port): the same error, as fast.
  int closed_port = 0;
  {
    UdpSocket s("127.0.0.1", 0);
    closed_port = s.localPort();
  }
  const auto t1 = std::chrono::steady_clock::now();
  EXPECT_THROW(SegwayRmpRobot(paramsFor(closed_port), Eigen::Isometry3d::Identity()),
               rasm::InputError);
  EXPECT_LT(secondsSince(t1), 1.6);
}

TEST(SegwayRmpRobot, LostLinkStopsAndStepThrows) {
  FakeRmpServer rmp;
  SegwayRmpRobot robot(paramsFor(rmp.port()), Eigen::Isometry3d::Identity());
  robot.setVelocityCommand(0.2, 0.0);
  robot.step(0.05);
  rmp.responsive = false;
  const auto t0 = std::chrono::steady_clock::now();
  bool threw = false;
  while (!threw && secondsSince(t0) < 2.0) {
    robot.setVelocityCommand(0.2, 0.0);
    try {
      robot.step(0.05);
    } catch (const RobotLinkError& e) {
      threw = true;
      EXPECT_NE(std::string(e.what()).find("no valid response"), std::string::npos) << e.what();
    }
  }
  EXPECT_TRUE(threw);
  EXPECT_LT(secondsSince(t0), 1.0);  // response_timeout_s 0.3 + a few periods (+ load)
  EXPECT_FALSE(robot.status().link_ok);
  // While the link is lost the robot is sent zero velocity, whatever it is commanded.
  sleepS(0.1);
  EXPECT_EQ(rmp.record().motion.back().float1(), 0.0f);
}

TEST(SegwayRmpRobot, ParamsAreValidatedByName) {
  TSegwayRmpParams p;
  mrpt::config::CConfigFileMemory ini;
  ini.write("segway_rmp", "max_v_mps", "3.0");
  try {
    p.loadFromConfigFile(ini, "segway_rmp");
    FAIL();
  } catch (const rasm::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("max_v_mps"), std::string::npos) << e.what();
  }
}
