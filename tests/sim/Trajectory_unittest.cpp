// Trajectories: the hand-held spline passes through its keyframes smoothly, jitter is seeded and
// small, specs parse (and fail naming file, line and key), pure pursuit drives the shipped robot
// specs to their end without collisions.
#include "rasm/sim/Trajectory.h"

#include <gtest/gtest.h>

#include <cmath>

#include "rasm/core/Error.h"
#include "rasm/core/SE3.h"
#include "rasm/sim/CameraPoses.h"
#include "rasm/sim/RayScene.h"
#include "rasm/sim/SimulatedDiffDriveRobot.h"
#include "rasm/sim/World.h"

using namespace rasm::sim;

namespace {

std::vector<HandheldKeyframe> someKeyframes() {
  return {{0.0, cameraPoseLookingAt({0, 0, 1.5}, {3, 1, 1})},
          {2.0, cameraPoseLookingAt({1, 0.5, 1.4}, {3, 3, 0.8})},
          {3.0, cameraPoseLookingAt({1.5, 1.5, 1.5}, {0, 3, 1})},
          {5.0, cameraPoseFromHeading({1.0, 2.5, 1.6}, 200.0, -20.0, 5.0)}};
}

std::string specError(const std::string& yaml) {
  try {
    loadTrajectorySpecFromString(yaml, "spec.yaml");
  } catch (const rasm::InputError& e) {
    return e.what();
  }
  return "";
}

/// Drives a robot spec (no rendering) until pure pursuit is done; returns the robot.
struct DriveResult {
  bool done = false, collided = false;
  double time_s = 0.0;
  Eigen::Vector3d pose;
};
DriveResult drive(const std::string& world, const std::string& spec_name) {
  const TrajectorySpec spec = loadTrajectorySpec(spec_name);
  const RayScene scene(loadWorld(world));
  TRobotParams rp;
  if (spec.robot_overrides.count("footprint_radius_m"))
    rp.footprint_radius_m = std::stod(spec.robot_overrides.at("footprint_radius_m"));
  SimulatedDiffDriveRobot robot(scene, rp, spec.start_pose, 1);
  std::vector<Eigen::Vector2d> path{spec.start_pose.head<2>()};
  path.insert(path.end(), spec.waypoints.begin(), spec.waypoints.end());
  PurePursuit pp(path, spec.controller, spec.loop, spec.laps);
  DriveResult r;
  const double dt = 1.0 / (spec.rate_hz * spec.control_substeps);
  for (int i = 0; i < 200000 && !pp.done(); ++i) {
    const Eigen::Vector2d cmd = pp.command(robot.pose());
    robot.setVelocityCommand(cmd.x(), cmd.y());
    robot.step(dt);
    r.collided = r.collided || robot.collided();
  }
  r.done = pp.done();
  r.time_s = robot.time_s();
  r.pose = robot.pose();
  return r;
}

}  // namespace

TEST(HandheldTrajectory, PassesThroughKeyframesSmoothly) {
  const auto kf = someKeyframes();
  const HandheldTrajectory traj(kf, HandJitter{}, 1);
  for (const auto& k : kf) {
    const Eigen::Isometry3d T = traj.smoothPose(k.t_s);
    EXPECT_LT(rasm::translationDistance(T, k.T_world_cam), 1e-9);
    EXPECT_LT(rasm::rotationAngle(T, k.T_world_cam), 1e-6);
  }
  // C1 at interior keyframes: one-sided finite-difference velocities agree.
  const double h = 1e-4;
  for (std::size_t i = 1; i + 1 < kf.size(); ++i) {
    const double t = kf[i].t_s;
    const Eigen::Vector3d vl =
        (traj.smoothPose(t).translation() - traj.smoothPose(t - h).translation()) / h;
    const Eigen::Vector3d vr =
        (traj.smoothPose(t + h).translation() - traj.smoothPose(t).translation()) / h;
    EXPECT_LT((vl - vr).norm(), 0.01 * std::max(1.0, vl.norm())) << "keyframe " << i;
    const double wl = rasm::rotationAngle(traj.smoothPose(t - h), traj.smoothPose(t)) / h;
    const double wr = rasm::rotationAngle(traj.smoothPose(t), traj.smoothPose(t + h)) / h;
    EXPECT_NEAR(wl, wr, 0.05 * std::max(0.2, wl)) << "keyframe " << i;
  }
  // Continuous everywhere (no jumps between samples 1 ms apart).
  for (double t = 0; t < 5.0; t += 0.001)
    ASSERT_LT(rasm::translationDistance(traj.smoothPose(t), traj.smoothPose(t + 0.001)), 0.01);
  // Clamped outside the keyframe times.
  EXPECT_LT(rasm::translationDistance(traj.smoothPose(-1.0), kf.front().T_world_cam), 1e-9);
  EXPECT_LT(rasm::translationDistance(traj.smoothPose(9.0), kf.back().T_world_cam), 1e-9);
}

TEST(HandheldTrajectory, JitterIsSmallSmoothAndSeeded) {
  HandJitter j;
  j.translation_m = 0.004;
  j.rotation_deg = 0.5;
  const HandheldTrajectory a(someKeyframes(), j, 7), b(someKeyframes(), j, 7),
      c(someKeyframes(), j, 8);
  double sum2 = 0;
  int n = 0;
  for (double t = 0; t <= 5.0; t += 0.01, ++n) {
    const double d = rasm::translationDistance(a.pose(t), a.smoothPose(t));
    sum2 += d * d;
    EXPECT_TRUE(a.pose(t).isApprox(b.pose(t)));
    EXPECT_LT(rasm::rotationAngle(a.pose(t), a.smoothPose(t)),
              4 * 0.5 * M_PI / 180 * std::sqrt(3.0));
  }
  // Three axes of RMS 4 mm: about 7 mm RMS in 3-D.
  EXPECT_NEAR(std::sqrt(sum2 / n), 0.004 * std::sqrt(3.0), 0.004);
  EXPECT_FALSE(a.pose(1.0).isApprox(c.pose(1.0)));
  // Smooth: at 30 Hz consecutive jitter offsets differ by much less than their size.
  const Eigen::Vector3d j0 = (a.smoothPose(1.0).inverse() * a.pose(1.0)).translation();
  const Eigen::Vector3d j1 =
      (a.smoothPose(1.0 + 1 / 30.0).inverse() * a.pose(1.0 + 1 / 30.0)).translation();
  EXPECT_LT((j1 - j0).norm(), 0.004);
}

TEST(TrajectorySpec, ShippedSpecsLoad) {
  const TrajectorySpec h = loadTrajectorySpec("office_handheld");
  EXPECT_EQ(h.kind, TrajectorySpec::Kind::Handheld);
  EXPECT_EQ(h.rate_hz, 30.0);
  EXPECT_GE(h.keyframes.size(), 4u);
  const TrajectorySpec r = loadTrajectorySpec("office_robot_loop");
  EXPECT_EQ(r.kind, TrajectorySpec::Kind::Robot);
  EXPECT_TRUE(r.loop);
  EXPECT_EQ(r.robot_overrides.at("camera_height_m"), "0.55");
  for (const char* s : {"two_rooms_robot", "cluttered_lab_handheld"})
    EXPECT_NO_THROW(loadTrajectorySpec(s)) << s;
}

TEST(TrajectorySpec, ErrorsNameFileLineAndKey) {
  std::string e = specError("rate_hz: 30\nkeyframes: []\n");
  EXPECT_NE(e.find("spec.yaml:1"), std::string::npos) << e;
  EXPECT_NE(e.find("missing key 'type'"), std::string::npos) << e;
  e = specError(
      "type: handheld\nkeyframes:\n  - {t: 0, position: [0, 0, 1], look_at: [1, 0, 1]}\n"
      "  - {t: 1, position: [0, 0, 1], look_at: [1, 0, 1], fov: 3}\n");
  EXPECT_NE(e.find("spec.yaml:4"), std::string::npos) << e;
  EXPECT_NE(e.find("keyframes[1].fov: unknown key"), std::string::npos) << e;
  e = specError(
      "type: handheld\nkeyframes:\n  - {t: 2, position: [0, 0, 1], look_at: [1, 0, 1]}\n"
      "  - {t: 1, position: [0, 0, 1], look_at: [1, 0, 1]}\n");
  EXPECT_NE(e.find("keyframes[1].t: keyframe times must increase"), std::string::npos) << e;
  e = specError("type: robot\nstart: {x: 0, y: 0}\nwaypoints: [[1, 2], [3]]\n");
  EXPECT_NE(e.find("waypoints[1]: expected a sequence of 2 numbers"), std::string::npos) << e;
  e = specError("type: boat\n");
  EXPECT_NE(e.find("unknown trajectory type 'boat'"), std::string::npos) << e;
  EXPECT_THROW(loadTrajectorySpec("no_such_spec"), rasm::InputError);
}

TEST(PurePursuit, DrivesASquareAndStops) {
  PurePursuitParams p;
  p.lookahead_m = 0.4;
  PurePursuit pp({{0, 0}, {2, 0}, {2, 2}, {0, 2}}, p);
  Eigen::Vector3d pose(0, 0, 0);
  double max_dev = 0;
  for (int i = 0; i < 20000 && !pp.done(); ++i) {
    const Eigen::Vector2d c = pp.command(pose);
    const double dt = 0.01;
    pose.x() += c.x() * std::cos(pose.z()) * dt;
    pose.y() += c.x() * std::sin(pose.z()) * dt;
    pose.z() += c.y() * dt;
    // Distance to the polyline.
    const double dx =
        std::min({std::abs(pose.y()), std::abs(pose.x() - 2), std::abs(pose.y() - 2)});
    max_dev = std::max(max_dev, dx);
  }
  EXPECT_TRUE(pp.done());
  EXPECT_LT((pose.head<2>() - Eigen::Vector2d(0, 2)).norm(), p.goal_tolerance_m + 1e-9);
  EXPECT_LT(max_dev, p.lookahead_m);  // corners are cut by at most about the lookahead
}

TEST(PurePursuit, ShippedRobotSpecsReachTheirEndWithoutCollisions) {
  const DriveResult office = drive("office", "office_robot_loop");
  EXPECT_TRUE(office.done);
  EXPECT_FALSE(office.collided);
  EXPECT_LT(office.time_s, 120.0);
  EXPECT_LT((office.pose.head<2>() - Eigen::Vector2d(1.2, 2.5)).norm(), 0.2);  // the loop closes
  const DriveResult rooms = drive("two_rooms", "two_rooms_robot");
  EXPECT_TRUE(rooms.done);
  EXPECT_FALSE(rooms.collided);
  EXPECT_LT((rooms.pose.head<2>() - Eigen::Vector2d(10.4, 4.3)).norm(), 0.2);
}
