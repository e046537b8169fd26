// Simulated diff-drive robot: stops at walls, passes under table tops above its height band,
// planar scan in the robot frame, odometry noise, camera mount.
#include <gtest/gtest.h>

#include <cmath>

#include "rasm/core/Error.h"
#include "rasm/sim/RayScene.h"
#include "rasm/sim/SimulatedDiffDriveRobot.h"
#include "rasm/sim/World.h"

using namespace rasm::sim;

namespace {

/// Floor plus a wall whose face is the plane x = 3 (and whatever `extra` adds).
World wallWorld(const std::string& extra = "") {
  return loadWorldFromString(
      "objects:\n"
      "  - {id: 1, class: floor, primitive: box, size: [20, 20, 0.1], position: [0, 0, -0.05]}\n"
      "  - {id: 2, class: wall, primitive: box, size: [0.2, 10, 2.5], position: [3.1, 0, 1.25]}\n" +
          extra,
      "robot_test");
}

TRobotParams quietParams() {
  TRobotParams p;
  p.odometry_noise = false;
  return p;
}

}  // namespace

TEST(SimulatedDiffDriveRobot, StopsAtAWall) {
  const RayScene scene(wallWorld());
  const TRobotParams p = quietParams();
  SimulatedDiffDriveRobot robot(scene, p, Eigen::Vector3d(0, 0, 0));
  robot.setVelocityCommand(0.5, 0.0);
  bool hit = false;
  for (int i = 0; i < 200 && !hit; ++i) {
    robot.step(0.05);
    hit = robot.collided();
  }
  ASSERT_TRUE(hit);
  const double gap = 3.0 - robot.pose().x();  // wall face to robot centre
  // It stops before touching (gap >= radius) and no further than one raster cell plus one
  // internal step of travel away.
  EXPECT_GE(gap, p.footprint_radius_m);
  EXPECT_LE(gap, p.footprint_radius_m + p.collision_cell_m + 0.5 * p.max_substep_s + 1e-6);
  EXPECT_NEAR(robot.pose().y(), 0.0, 1e-9);
  EXPECT_NEAR(robot.velocity().x(), 0.0, 1e-9);
  // Further pushing keeps it there (within one internal step); backing off frees it.
  const double x_stop = robot.pose().x();
  robot.setVelocityCommand(0.5, 0.0);
  robot.step(0.5);
  EXPECT_TRUE(robot.collided());
  EXPECT_GE(robot.pose().x(), x_stop - 1e-9);
  EXPECT_LE(robot.pose().x(), std::min(x_stop + 0.5 * p.max_substep_s, 3.0 - p.footprint_radius_m));
  robot.setVelocityCommand(-0.2, 0.0);
  robot.step(0.5);
  EXPECT_FALSE(robot.collided());
  EXPECT_NEAR(robot.pose().x(), x_stop - 0.1, 0.5 * p.max_substep_s);
}

TEST(SimulatedDiffDriveRobot, SimulatedClockAdvancesOnlyInStep) {
  const RayScene scene(wallWorld());
  SimulatedDiffDriveRobot robot(scene, quietParams(), Eigen::Vector3d(0, 0, 0));
  EXPECT_DOUBLE_EQ(robot.time_s(), 0.0);
  robot.setVelocityCommand(0.2, 0.5);
  EXPECT_DOUBLE_EQ(robot.time_s(), 0.0);
  robot.step(0.3);
  robot.step(0.3);
  EXPECT_NEAR(robot.time_s(), 0.6, 1e-9);
  EXPECT_NEAR(robot.pose().z(), 0.3, 1e-3);  // w * t, less one 0.5 ms firmware period of lag
}

TEST(SimulatedDiffDriveRobot, HeightBandDecidesWhatIsAnObstacle) {
  // A table top at 0.72-0.75 m (above the 0.6 m robot) and a 0.15 m high box (in the band).
  const RayScene scene(
      wallWorld("  - {id: 3, class: dining table, primitive: box, size: [1.0, 1.0, 0.03], "
                "position: [1.0, 0, 0.735]}\n"
                "  - {id: 4, class: box, primitive: box, size: [0.3, 0.3, 0.15], position: [1.0, "
                "1.5, 0.075]}\n"));
  SimulatedDiffDriveRobot robot(scene, quietParams(), Eigen::Vector3d(0, 0, 0));
  robot.setVelocityCommand(0.4, 0.0);
  for (int i = 0; i < 10; ++i) robot.step(0.5);  // drives 2 m, right under the table top
  EXPECT_FALSE(robot.collided());
  EXPECT_NEAR(robot.pose().x(), 2.0, 1e-3);
  EXPECT_FALSE(robot.collidesAt(Eigen::Vector3d(1.0, 0.0, 0.0)));
  EXPECT_TRUE(robot.collidesAt(Eigen::Vector3d(1.0, 1.5, 0.0)));
  EXPECT_TRUE(robot.collidesAt(Eigen::Vector3d(1.0, 1.5 - 0.15 - 0.2, 0.0)));  // 0.2 < radius away
  EXPECT_FALSE(
      robot.collidesAt(Eigen::Vector3d(1.0, 1.5 - 0.15 - 0.3, 0.0)));  // 0.3 > radius + cell
  EXPECT_THROW(SimulatedDiffDriveRobot(scene, quietParams(), Eigen::Vector3d(1.0, 1.5, 0.0)),
               rasm::InputError);
}

TEST(SimulatedDiffDriveRobot, PolygonFootprint) {
  const RayScene scene(wallWorld());
  TRobotParams p = quietParams();
  p.footprint_radius_m = 0;
  p.footprint_xs = {-0.2, 0.4, 0.4, -0.2};  // long nose: 0.4 m ahead of the rotation centre
  p.footprint_ys = {-0.2, -0.2, 0.2, 0.2};
  SimulatedDiffDriveRobot robot(scene, p, Eigen::Vector3d(1.0, 0, 0));
  robot.setVelocityCommand(0.5, 0.0);
  for (int i = 0; i < 100 && !robot.collided(); ++i) robot.step(0.05);
  ASSERT_TRUE(robot.collided());
  EXPECT_GE(3.0 - robot.pose().x(), 0.4 - 1e-9);  // the nose may touch, never penetrate
  EXPECT_LE(3.0 - robot.pose().x(), 0.4 + p.collision_cell_m + 0.5 * p.max_substep_s + 1e-6);
  // Turned sideways the nose no longer reaches the wall.
  EXPECT_FALSE(robot.collidesAt(Eigen::Vector3d(robot.pose().x(), 0, M_PI / 2)));
}

TEST(SimulatedDiffDriveRobot, ObstacleScanInTheRobotFrame) {
  const RayScene scene(wallWorld());
  TRobotParams p = quietParams();
  p.scan_rays = 360;
  SimulatedDiffDriveRobot robot(scene, p, Eigen::Vector3d(1.0, 0.5, M_PI / 2));  // facing +y
  std::vector<Eigen::Vector3f> pts;
  robot.senseObstacles(pts);
  ASSERT_FALSE(pts.empty());
  // The wall (x = 3 in the world) is 2 m to the robot's right: robot-frame y = -2.
  int on_wall = 0;
  for (const auto& q : pts) {
    EXPECT_NEAR(q.z(), p.scan_height_m, 1e-6);
    if (std::abs(q.x()) < 0.5) {
      EXPECT_NEAR(q.y(), -2.0, 1e-3);
      ++on_wall;
    }
  }
  EXPECT_GT(on_wall, 10);
  const auto r = robot.scanRanges();
  EXPECT_NEAR(r[270], 2.0, 1e-3);                     // ray 270 points to the robot's right
  EXPECT_FLOAT_EQ(r[90], float(p.scan_max_range_m));  // nothing to the left
}

TEST(SimulatedDiffDriveRobot, OdometryNoiseIsSeededAndBounded) {
  const World w = wallWorld();
  const RayScene scene(w);
  auto drive = [&](bool noise, std::uint64_t seed) {
    TRobotParams p;
    p.odometry_noise = noise;
    SimulatedDiffDriveRobot robot(scene, p, Eigen::Vector3d(-4, -3, 0.3), seed);
    robot.setVelocityCommand(0.4, 0.1);
    for (int i = 0; i < 100; ++i) robot.step(0.1);  // 4 m along an arc
    return std::make_pair(robot.pose(), robot.odometry());
  };
  const auto [gt0, odo0] = drive(false, 1);
  EXPECT_LT((gt0 - odo0).norm(), 1e-9);
  const auto [gt1, odo1] = drive(true, 1);
  const auto [gt2, odo2] = drive(true, 1);
  const auto [gt3, odo3] = drive(true, 2);
  EXPECT_LT((gt1 - gt0).norm(), 1e-12);  // noise affects odometry only
  EXPECT_EQ(odo1, odo2);
  EXPECT_NE(odo1, odo3);
  const double err = (odo1 - gt1).head<2>().norm();
  EXPECT_GT(err, 1e-4);
  EXPECT_LT(err, 0.3);  // 0.01 m/sqrt(m) and 0.005 rad/sqrt(m) over 4 m: a few cm
}

// The heading's error through a half turn in place, over many runs (seeds): a gyro's (its scale
// factor and bias drawn per run, angle random walk) against the wheels' random walk per radian.
TEST(SimulatedDiffDriveRobot, GyroHeadingErrorThroughATurnIsItsScaleBiasAndRandomWalk) {
  const RayScene scene(wallWorld());
  auto headingErrors = [&](const std::string& heading) {
    std::vector<double> errors;
    for (std::uint64_t seed = 1; seed <= 300; ++seed) {
      TRobotParams p;
      p.odometry_heading = heading;
      SimulatedDiffDriveRobot robot(scene, p, Eigen::Vector3d(-4, -3, 0.0), seed);
      robot.setVelocityCommand(0.0, M_PI / 4);       // 45 deg/s
      for (int i = 0; i < 40; ++i) robot.step(0.1);  // 4 s: a half turn
      const double turned = robot.pose().z(), measured = robot.odometry().z();
      errors.push_back(std::remainder(measured - turned, 2 * M_PI));
    }
    return errors;
  };
  auto stddev = [](const std::vector<double>& v) {
    double mean = 0, sq = 0;
    for (double x : v) mean += x / double(v.size());
    for (double x : v) sq += (x - mean) * (x - mean);
    return std::sqrt(sq / double(v.size() - 1));
  };
  const TRobotParams d;
  const double turn = M_PI, t = 4.0, deg = M_PI / 180.0;
  const double gyro_expected =
      std::sqrt(std::pow(d.gyro_scale_error * turn, 2) + std::pow(d.gyro_bias_degps * deg * t, 2) +
                std::pow(d.gyro_arw_deg_per_sqrt_s * deg, 2) * t);
  const double wheels_expected = d.odo_sigma_yaw_per_sqrt_rad * std::sqrt(turn);
  // 300 draws: the sample standard deviation is within ~4% (1 sigma) of the true one.
  EXPECT_NEAR(stddev(headingErrors("gyro")), gyro_expected, 0.15 * gyro_expected);
  EXPECT_NEAR(stddev(headingErrors("wheels")), wheels_expected, 0.15 * wheels_expected);
  EXPECT_LT(gyro_expected, 0.25 * wheels_expected);  // what the gyro is for
  TRobotParams bad;
  bad.odometry_heading = "compass";
  EXPECT_THROW({ SimulatedDiffDriveRobot r(scene, bad, Eigen::Vector3d(-4, -3, 0.0)); },
               rasm::InputError);
}

TEST(SimulatedDiffDriveRobot, CameraMount) {
  const RayScene scene(wallWorld());
  TRobotParams p = quietParams();
  p.camera_height_m = 0.55;
  p.camera_pitch_deg = -10;
  p.camera_x_m = 0.1;
  SimulatedDiffDriveRobot robot(scene, p, Eigen::Vector3d(1.0, 2.0, M_PI / 2));
  const Eigen::Isometry3d T = robot.cameraPose();
  EXPECT_TRUE(T.translation().isApprox(Eigen::Vector3d(1.0, 2.1, 0.55), 1e-9));
  const Eigen::Vector3d forward = T.linear().col(2);  // optical z
  EXPECT_NEAR(forward.y(), std::cos(10 * M_PI / 180), 1e-9);
  EXPECT_NEAR(forward.z(), -std::sin(10 * M_PI / 180), 1e-9);
  EXPECT_NEAR(T.linear().col(0).x(), 1.0, 1e-9);  // image x (right) = world +x when facing +y
}
