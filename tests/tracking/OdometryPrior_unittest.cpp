// The odometry prior of tracking (issue 14): exact odometry predicts the exact camera motion
// through the mount, the covariance follows the base, and the planar constraint keeps poses a
// ground robot can have.
#include <gtest/gtest.h>

#include <cmath>

#include "rasm/core/FrameProcessing.h"
#include "rasm/core/SE3.h"
#include "rasm/tracking/IcpTracker.h"
#include "rasm/tracking/OdometryPrior.h"
#include "tracking/SyntheticScene.h"
#if __has_include("rasm/sim/SimulatedDiffDriveRobot.h")
#define RASM_TEST_HAVE_SIM 1
#include "rasm/sim/SimulatedDiffDriveRobot.h"
#endif

using namespace rasm;
using namespace rasm::tracking;

namespace {
constexpr double kDeg = M_PI / 180.0;

Eigen::Isometry3d base(double x, double y, double yaw) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = Eigen::Vector3d(x, y, 0);
  T.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  return T;
}
}  // namespace

TEST(OdometryPrior, MountLooksForwardAndDown) {
  const TRobotParams p;
  const Eigen::Isometry3d T = p.T_base_cam();
  EXPECT_NEAR(T.translation().x(), 0.10, 1e-12);
  EXPECT_NEAR(T.translation().z(), 0.55, 1e-12);
  // Optical z (viewing direction) points forward and 10 degrees down; optical x to the right.
  const Eigen::Vector3d z = T.linear().col(2), x = T.linear().col(0);
  EXPECT_NEAR(z.x(), std::cos(10 * kDeg), 1e-12);
  EXPECT_NEAR(z.z(), -std::sin(10 * kDeg), 1e-12);
  EXPECT_NEAR(x.y(), -1.0, 1e-12);
#ifdef RASM_TEST_HAVE_SIM
  // The simulated robot's mount is the default, so its rawlogs track without an INI.
  const Eigen::Isometry3d T_sim = sim::TRobotParams().T_base_cam();
  EXPECT_LT(translationDistance(T, T_sim), 1e-9);
  EXPECT_LT(rotationAngle(T, T_sim), 1e-9);
#endif
}

TEST(OdometryPrior, ExactOdometryPredictsTheCameraMotion) {
  TRobotParams p;
  p.floor_prior = false;          // the relative model alone (FloorPrior* below: with the floor)
  p.odometry_heading = "wheels";  // the heading's random walks (a gyro's: below)
  p.camera_yaw_deg = 20;          // a mount not aligned with the base: the conjugation matters
  p.camera_roll_deg = 3;
  OdometryPrior op(p);
  const Eigen::Isometry3d M = p.T_base_cam();
  // The world frame is not the odometry frame: the first camera pose is arbitrary.
  const Eigen::Isometry3d T_world_odom =
      Eigen::Translation3d(1, -2, 0.3) *
      Eigen::AngleAxisd(0.4, Eigen::Vector3d(0.1, 0.2, 1).normalized());
  const Eigen::Vector3d odo0(0.5, 0.2, 0.3), odo1(0.53, 0.215, 0.34);
  const Eigen::Isometry3d cam0 = T_world_odom * base(odo0.x(), odo0.y(), odo0.z()) * M;
  const Eigen::Isometry3d cam1 = T_world_odom * base(odo1.x(), odo1.y(), odo1.z()) * M;
  op.start(cam0, odo0);
  const auto prior = op.predict(odo1, cam0);
  ASSERT_TRUE(prior.has_value());
  EXPECT_LT(translationDistance(prior->T_world_cam, cam1), 1e-9);
  EXPECT_LT(rotationAngle(prior->T_world_cam, cam1), 1e-9);
  // Noise of a 3.4 cm, 2.3 deg increment: sigma_xy, sigma_yaw by the random-walk model.
  const double d = std::hypot(0.03, 0.015), a = 0.04;
  const double s_yaw = p.odometry_sigma_yaw_deg * kDeg +
                       p.odometry_sigma_yaw_per_sqrt_rad * std::sqrt(a) +
                       p.odometry_sigma_yaw_per_sqrt_m * std::sqrt(d);
  // Rotation about the base's z (world: T_world_odom's z) has information 1 / s_yaw^2.
  const Eigen::Vector3d up = T_world_odom.linear().col(2);
  const double info_yaw = up.dot(prior->information.bottomRightCorner<3, 3>() * up);
  EXPECT_NEAR(info_yaw, 1.0 / (s_yaw * s_yaw), 1e-6 / (s_yaw * s_yaw));
  // Height: tight.
  const double info_z = up.dot(prior->information.topLeftCorner<3, 3>() * up);
  EXPECT_NEAR(info_z, 1.0 / (p.odometry_sigma_z_m * p.odometry_sigma_z_m), 1e-3 * info_z);
  // With a gyro the heading's sigma grows with the turn as its scale error, not as the wheels'
  // random walks: 0.05 deg + 0.4% of 2.3 deg, five times tighter here.
  TRobotParams g = p;
  g.odometry_heading = "gyro";
  OdometryPrior opg(g);
  opg.start(cam0, odo0);
  const auto prior_g = opg.predict(odo1, cam0);
  ASSERT_TRUE(prior_g.has_value());
  const double s_yaw_g = g.odometry_sigma_yaw_deg * kDeg + g.gyro_sigma_yaw_per_rad * a;
  const double info_yaw_g = up.dot(prior_g->information.bottomRightCorner<3, 3>() * up);
  EXPECT_NEAR(info_yaw_g, 1.0 / (s_yaw_g * s_yaw_g), 1e-6 / (s_yaw_g * s_yaw_g));
  EXPECT_LT(s_yaw_g, 0.25 * s_yaw);

  // No reading on this frame or the one before: no prior.
  EXPECT_FALSE(op.predict(std::nullopt, cam1).has_value());
  EXPECT_FALSE(op.predict(odo1, cam1).has_value());
  TRobotParams off = p;
  off.use_odometry = false;
  OdometryPrior op2(off);
  op2.start(cam0, odo0);
  EXPECT_FALSE(op2.predict(odo1, cam0).has_value());
}

TEST(OdometryPrior, PlanarProjectionKeepsRobotPosesAndRemovesTilt) {
  const TRobotParams p;
  OdometryPrior op(p);
  const Eigen::Isometry3d M = p.T_base_cam();
  const Eigen::Isometry3d cam0 = base(1.2, 2.5, 0.0) * M;
  op.start(cam0, std::nullopt);
  // A pose the robot can have is unchanged.
  const Eigen::Isometry3d cam = base(3.0, 1.0, 1.2) * M;
  const Eigen::Isometry3d pc = op.projectToFloor(cam);
  EXPECT_LT(translationDistance(pc, cam), 1e-9);
  EXPECT_LT(rotationAngle(pc, cam), 1e-9);
  // Height and tilt errors go; the camera's position in the plane and its heading stay.
  const Eigen::Isometry3d bad = Eigen::Translation3d(0, 0, 0.02) * cam *
                                Eigen::AngleAxisd(1.0 * kDeg, Eigen::Vector3d::UnitX()) *
                                Eigen::AngleAxisd(-0.7 * kDeg, Eigen::Vector3d::UnitZ());
  const Eigen::Isometry3d pb = op.projectToFloor(bad);
  EXPECT_NEAR(pb.translation().z(), 0.55, 1e-9);
  EXPECT_NEAR(pb.translation().x(), bad.translation().x(), 1e-9);
  EXPECT_NEAR(pb.translation().y(), bad.translation().y(), 1e-9);
  EXPECT_LT(rotationAngle(pb, cam), 1.3 * kDeg)
      << "only the tilt (and the heading error it implies) is removed";
  const Eigen::Vector3d z_gt = cam.linear().col(2), z_pb = pb.linear().col(2);
  EXPECT_NEAR(z_pb.z(), z_gt.z(), 1e-9) << "the viewing direction keeps the mount's pitch";
}

/// A turn in place at 3 deg per frame, tracked `under_deg` per frame behind the odometry (0: an
/// agreeing track that alternates +-noise_deg around it). The heading drift test's largest
/// statistic, the frame it first passed 3 sigmas (-1: never), and the window's correction.
struct HeadingDriftRun {
  double worst = 0.0, correction = 0.0;
  int first_over = -1;
};
HeadingDriftRun turnInPlace(const TRobotParams& p, double under_deg, double noise_deg) {
  const Eigen::Isometry3d M = p.T_base_cam();
  OdometryPrior op(p);
  Eigen::Vector3d odo(0, 0, 0);
  Eigen::Isometry3d cam = base(0, 0, 0) * M;  // the tracked pose
  op.start(cam, odo);
  HeadingDriftRun r;
  for (int k = 1; k <= 30; ++k) {
    odo.z() += 3.0 * kDeg;
    const std::optional<tracking::MotionPrior> prior = op.predict(odo, cam);
    if (!prior) ADD_FAILURE() << "no prior at frame " << k;
    if (!prior) return r;
    // Tracked: the prior's pose, turned back by under_deg about the floor normal, or +-noise.
    const double e = under_deg > 0 ? -under_deg * kDeg : (k % 2 ? noise_deg : -noise_deg) * kDeg;
    cam = prior->T_world_cam;
    cam.linear() = Eigen::AngleAxisd(e, op.up()).toRotationMatrix() * cam.linear();
    const double s = op.addHeadingResidual(*prior, cam, r.correction);
    r.worst = std::max(r.worst, s);
    if (s > 3.0 && r.first_over < 0) r.first_over = k;
  }
  return r;
}

TEST(OdometryPrior, UnderRotatedTurnIsExposedAndAnAgreeingOneIsNot) {
  // Wheels: tracked poses that under-rotate by 0.4 deg per frame (each well within one frame's
  // 0.57 deg sigma) add up past 3 sigmas of the summed noise within the 30-frame window:
  // 0.4 n > 3 * 0.57 sqrt(n) for n >= 20; an agreeing track (+-0.3 deg) stays small.
  TRobotParams wheels;
  wheels.odometry_heading = "wheels";
  EXPECT_LT(turnInPlace(wheels, 0.0, 0.3).worst, 1.0);
  const HeadingDriftRun under = turnInPlace(wheels, 0.4, 0.0);
  EXPECT_GE(under.first_over, 15);
  EXPECT_LE(under.first_over, 25);
  EXPECT_NEAR(under.correction, -30 * 0.4 * kDeg, 1e-9) << "the window's accumulated residual";
  // A gyro (one frame's sigma 0.05 + 0.4% of 3 deg = 0.062 deg): 0.1 deg per frame behind is
  // exposed once 0.1 n > 3 * 0.062 sqrt(n), n >= 4; an agreeing track (+-0.03 deg) is not.
  TRobotParams gyro;
  gyro.odometry_heading = "gyro";
  EXPECT_LT(turnInPlace(gyro, 0.0, 0.03).worst, 1.0);
  const HeadingDriftRun gyro_under = turnInPlace(gyro, 0.1, 0.0);
  EXPECT_GE(gyro_under.first_over, 3);
  EXPECT_LE(gyro_under.first_over, 5);
}

TEST(OdometryPrior, LostFramesWidenTheNextPrediction) {
  // A turn in place at 5 deg per frame. While frames are lost their poses are odometry
  // propagations: after 3 lost frames the 4th prediction carries 4 increments' variance, so a
  // right ICP result 4 increments' noise off the propagated pose is within its sigmas; once a
  // frame is tracked, one increment again.
  const TRobotParams p;
  OdometryPrior op(p);
  Eigen::Vector3d odo(0, 0, 0);
  const Eigen::Isometry3d cam = base(0, 0, 0) * p.T_base_cam();
  op.start(cam, odo);
  auto yawSigma = [](const tracking::MotionPrior& m) {
    return 1.0 / std::sqrt(m.information(5, 5));  // world z = the floor normal here
  };
  odo.z() += 5 * kDeg;
  const double one = yawSigma(*op.predict(odo, cam));
  op.frameDone(true);
  for (int k = 0; k < 3; ++k) {
    odo.z() += 5 * kDeg;
    EXPECT_NEAR(yawSigma(*op.predict(odo, cam)), one * std::sqrt(k + 1.0), 1e-9);
    op.frameDone(false);
  }
  odo.z() += 5 * kDeg;
  EXPECT_NEAR(yawSigma(*op.predict(odo, cam)), 2.0 * one, 1e-9);
  op.frameDone(true);
  odo.z() += 5 * kDeg;
  EXPECT_NEAR(yawSigma(*op.predict(odo, cam)), one, 1e-9);
}

TEST(OdometryPrior, GyroWhenDegenerateHoldsTheHeadingAtTheGyrosNoiseInDegenerateFramesOnly) {
  // A turn in place at 5 deg per frame. gyro_when_degenerate: the prior and the check of a frame
  // the geometry constrains use the wheels' yaw sigma; the check of a degenerate frame uses the
  // gyro's, 0.05 deg + 0.4% of the turn = 0.07 deg, and over lost frames (propagated at the
  // gyro's heading) the gyro's variances add up, not the wheels'.
  TRobotParams p;
  p.floor_prior = false;  // world z = the floor normal; the information blocks are the base's
  p.odometry_heading = "gyro_when_degenerate";
  OdometryPrior op(p);
  Eigen::Vector3d odo(0, 0, 0);
  const Eigen::Isometry3d cam = base(0, 0, 0) * p.T_base_cam();
  op.start(cam, odo);
  const auto yawSigma = [](const Eigen::Matrix<double, 6, 6>& info) {
    return 1.0 / std::sqrt(info(5, 5));
  };
  const double gyro = (0.05 + 0.004 * 5.0) * kDeg;
  const double wheels =
      p.odometry_sigma_yaw_deg * kDeg + p.odometry_sigma_yaw_per_sqrt_rad * std::sqrt(5.0 * kDeg);
  for (int k = 0; k < 3; ++k) {
    odo.z() += 5 * kDeg;
    const tracking::MotionPrior m = *op.predict(odo, cam);
    EXPECT_NEAR(yawSigma(m.information), wheels * std::sqrt(k + 1.0), 1e-9);
    EXPECT_NEAR(yawSigma(m.odometry_information), wheels * std::sqrt(k + 1.0), 1e-9);
    EXPECT_NEAR(yawSigma(m.odometry_information_degenerate), gyro * std::sqrt(k + 1.0), 1e-9);
    op.frameDone(false);
  }
  // The wheels' model has no degenerate-frame part.
  TRobotParams w = p;
  w.odometry_heading = "wheels";
  OdometryPrior wheels_only(w);
  wheels_only.start(cam, Eigen::Vector3d(0, 0, 0));
  EXPECT_TRUE(wheels_only.predict(Eigen::Vector3d(0, 0, 5 * kDeg), cam)
                  ->odometry_information_degenerate.isZero());
}

TEST(OdometryPrior, FloorDeviationMeasuresHeightAndTiltOffTheFirstFloor) {
  // The drift report: a ground robot's camera stays at the mount's height and tilt over the
  // first frame's floor, wherever it drives and turns; a map whose floor rose or tilted moves it.
  const TRobotParams p;
  OdometryPrior op(p);
  op.start(base(0, 0, 0) * p.T_base_cam(), Eigen::Vector3d(0, 0, 0));
  const Eigen::Isometry3d driven = base(2.0, -1.0, 1.2) * p.T_base_cam();
  auto [h0, t0] = op.floorDeviation(driven);
  EXPECT_NEAR(h0, 0.0, 1e-9);
  EXPECT_NEAR(t0, 0.0, 1e-9);
  Eigen::Isometry3d risen = driven;
  risen.translation().z() += 0.04;
  EXPECT_NEAR(op.floorDeviation(risen).first, 0.04, 1e-9);
  const Eigen::Isometry3d tilted =
      driven * Eigen::Isometry3d(Eigen::AngleAxisd(2.0 * kDeg, Eigen::Vector3d::UnitX()));
  EXPECT_NEAR(op.floorDeviation(tilted).second / kDeg, 2.0, 1e-6);
}

namespace {
/// A previous camera pose 3 cm too high and tilted 0.5 deg about a horizontal axis through the
/// camera (the map's floor drifted), and the odometry reading of the true one.
struct DriftedStart {
  TRobotParams params;
  Eigen::Vector3d odo0{1.0, 0.5, 0.3}, odo1{1.03, 0.51, 0.33};
  Eigen::Isometry3d cam0, cam1, cam0_drifted;
  DriftedStart() {
    params.odometry_heading = "wheels";  // the sigmas written out below are the wheels'
    cam0 = base(odo0.x(), odo0.y(), odo0.z()) * params.T_base_cam();
    cam1 = base(odo1.x(), odo1.y(), odo1.z()) * params.T_base_cam();
    cam0_drifted = cam0;
    cam0_drifted.translation().z() += 0.03;
    cam0_drifted.linear() =
        Eigen::AngleAxisd(0.5 * kDeg, Eigen::Vector3d(0.6, 0.8, 0.0)).toRotationMatrix() *
        cam0.linear();
  }
  /// Primed with the first frame at the origin of the floor and the reading of cam0.
  OdometryPrior primed(bool floor_prior) const {
    TRobotParams p = params;
    p.floor_prior = floor_prior;
    OdometryPrior op(p);
    op.start(base(0, 0, 0) * p.T_base_cam(), Eigen::Vector3d::Zero());
    op.predict(odo0, cam0);  // the previous frame's reading
    op.frameDone(true);
    return op;
  }
};
}  // namespace

TEST(OdometryPrior, FloorPriorTakesHeightAndTiltFromTheMountAndTheRestFromTheOdometry) {
  const DriftedStart s;
  OdometryPrior op = s.primed(true);
  const auto prior = op.predict(s.odo1, s.cam0_drifted);
  ASSERT_TRUE(prior.has_value());
  // Height and tilt: the mount's on the first floor, not the drifted previous pose's.
  const auto [height, tilt] = op.floorDeviation(prior->T_world_cam);
  EXPECT_NEAR(height, 0.0, 1e-9);
  EXPECT_NEAR(tilt, 0.0, 1e-9);
  EXPECT_NEAR(prior->T_world_cam.translation().z(), s.params.camera_z_m, 1e-9);
  // x, y and yaw: the increment applied to the previous pose (its tilt turns the 3.2 cm step by
  // 0.5 deg at most: 0.3 mm).
  EXPECT_NEAR(prior->T_world_cam.translation().x(), s.cam1.translation().x(), 3e-4);
  EXPECT_NEAR(prior->T_world_cam.translation().y(), s.cam1.translation().y(), 3e-4);
  EXPECT_LT(rotationAngle(prior->T_world_cam, s.cam1) / kDeg, 0.01) << "only yaw can differ";

  // Information: the floor's sigmas in height, roll and pitch (the first floor is the world's
  // z = 0 here), the relative odometry's in x, y and yaw.
  const double sz = s.params.floor_prior_sigma_z_m;
  const double st = s.params.floor_prior_sigma_tilt_deg * kDeg;
  const Eigen::Matrix<double, 6, 6>& I = prior->information;
  EXPECT_NEAR(I(2, 2), 1.0 / (sz * sz), 1e-9 / (sz * sz));
  EXPECT_NEAR(I(3, 3), 1.0 / (st * st), 1e-9 / (st * st));
  EXPECT_NEAR(I(4, 4), 1.0 / (st * st), 1e-9 / (st * st));
  EXPECT_NEAR(I(3, 4), 0.0, 1e-9 / (st * st));
  OdometryPrior rel = s.primed(false);
  const auto relative = rel.predict(s.odo1, s.cam0);  // from the true (level) pose
  ASSERT_TRUE(relative.has_value());
  for (const int i : {0, 1, 5})
    EXPECT_NEAR(I(i, i), relative->information(i, i), 1e-9 * I(i, i)) << "axis " << i;
  EXPECT_NEAR(relative->information(2, 2),
              1.0 / (s.params.odometry_sigma_z_m * s.params.odometry_sigma_z_m), 1e-6);
}

TEST(OdometryPrior, FloorPriorOffPredictsExactlyTheRelativeModel) {
  // The relative model, written out: the previous pose composed with the increment through the
  // mount, the increment's sigmas along the base's axes at t-1 (no lost frames).
  const DriftedStart s;
  OdometryPrior op = s.primed(false);
  const auto prior = op.predict(s.odo1, s.cam0_drifted);
  ASSERT_TRUE(prior.has_value());
  const TRobotParams& p = s.params;
  const Eigen::Isometry3d M = p.T_base_cam();
  const Eigen::Isometry3d delta =
      base(s.odo0.x(), s.odo0.y(), s.odo0.z()).inverse() * base(s.odo1.x(), s.odo1.y(), s.odo1.z());
  const Eigen::Isometry3d T_pred = s.cam0_drifted * M.inverse() * delta * M;
  const double d = delta.translation().head<2>().norm();
  const double a =
      std::abs(std::atan2(std::sin(s.odo1.z() - s.odo0.z()), std::cos(s.odo1.z() - s.odo0.z())));
  const double s_yaw = p.odometry_sigma_yaw_deg * kDeg +
                       p.odometry_sigma_yaw_per_sqrt_rad * std::sqrt(a) +
                       p.odometry_sigma_yaw_per_sqrt_m * std::sqrt(d);
  const double lever = M.translation().head<2>().norm();
  const double s_xy_inc = p.odometry_sigma_xy_m + p.odometry_sigma_xy_per_sqrt_m * std::sqrt(d);
  const double v_xy = 0.0 + s_xy_inc * s_xy_inc + 0.0 * d * d;
  const double v_yaw = 0.0 + s_yaw * s_yaw;
  const double s_tilt = p.odometry_sigma_tilt_deg * kDeg;
  const double v_tilt = 0.0 + s_tilt * s_tilt;
  const double v_z = 0.0 + p.odometry_sigma_z_m * p.odometry_sigma_z_m;
  const double s_xy = std::sqrt(v_xy + lever * lever * v_yaw);
  const tracking::MotionPrior expected = tracking::MotionPrior::fromStdDevs(
      T_pred, s.cam0_drifted.linear() * M.linear().transpose(),
      Eigen::Vector3d(s_xy, s_xy, std::sqrt(v_z)),
      Eigen::Vector3d(std::sqrt(v_tilt), std::sqrt(v_tilt), std::sqrt(v_yaw)));
  EXPECT_TRUE(prior->T_world_cam.matrix() == expected.T_world_cam.matrix()) << "bit-identical";
  EXPECT_TRUE(prior->information == expected.information) << "bit-identical";
}

TEST(OdometryPrior, FloorPriorHoldsTheHeightTheDataLeaveFree) {
  // A corner of two walls and no floor in view: the data fix x, y and every rotation, not the
  // height. The previous estimate was 3 cm high and 0.5 deg tilted; ICP fuses the prior in its
  // normal equations. With the floor, the height comes back to the mount's; with the relative
  // prior alone, it stays where the drifted previous pose put it.
  using test::Scene;
  const DriftedStart s;
  const CameraIntrinsics K = CameraIntrinsics::preset("kinect_v1").level(1);
  Scene scene;
  scene.planes.push_back({{1, 0, 0}, 2.5});
  scene.planes.push_back({{0, 1, 0}, 1.5});
  auto pyramidOf = [&](const Eigen::Isometry3d& T) {
    std::vector<FrameLevel> pyr;
    buildFramePyramid(scene.render(K, T), K, tracking::TTrackingParams::kMaxLevels, pyr);
    return pyr;
  };
  const test::WorldMaps model(pyramidOf(s.cam0)[0], s.cam0);  // the map is right
  tracking::ModelMaps mm;
  mm.vertex_world = model.vertex.view();
  mm.normal_world = model.normal.view();
  mm.K = K;
  mm.T_world_model = s.cam0;
  const std::vector<FrameLevel> frame = pyramidOf(s.cam1);
  for (const bool floor : {true, false}) {
    OdometryPrior op = s.primed(floor);
    const auto prior = op.predict(s.odo1, s.cam0_drifted);
    ASSERT_TRUE(prior.has_value());
    tracking::IcpTracker icp;
    const tracking::TrackingResult r = icp.align(frame, mm, prior->T_world_cam, {}, &*prior);
    EXPECT_TRUE(r.ok) << tracking::toString(r.status);
    const double dz = r.T_world_cam.translation().z() - s.cam1.translation().z();
    if (floor) {
      EXPECT_NEAR(dz, 0.0, 0.002) << "the floor's height";
      EXPECT_LT(translationDistance(r.T_world_cam, s.cam1), 0.003);
      EXPECT_LT(rotationAngle(r.T_world_cam, s.cam1) / kDeg, 0.1);
      EXPECT_LT(r.prior_sigmas, 2.0) << "a right result agrees with the floor";
    } else {
      EXPECT_GT(dz, 0.02) << "the relative prior keeps the drift";
    }
  }
}

TEST(OdometryPrior, FloorPartOfTheConflictTestIsTheMapsFloorDrift) {
  // A floor and a far wall: the data fix the height. When the map's floor is h too high, the
  // data pull the camera up by h, the floor measurement holds it down, and the result's distance
  // from the prior (prior_sigmas, the conflict test) grows with h in floor sigmas: a map within
  // a few sigmas of its floor is tracked, one far off it is refused (prior_conflict).
  using test::Scene;
  const DriftedStart s;
  const CameraIntrinsics K = CameraIntrinsics::preset("kinect_v1").level(1);
  Scene scene;
  scene.planes.push_back({{0, 0, 1}, 0.0});
  scene.planes.push_back({{1, 0, 0}, 4.0});
  auto pyramidOf = [&](const Eigen::Isometry3d& T) {
    std::vector<FrameLevel> pyr;
    buildFramePyramid(scene.render(K, T), K, tracking::TTrackingParams::kMaxLevels, pyr);
    return pyr;
  };
  const std::vector<FrameLevel> frame = pyramidOf(s.cam1);
  const std::vector<FrameLevel> model_frame = pyramidOf(s.cam0);
  for (const double h : {0.002, 0.03}) {
    Eigen::Isometry3d T_model = s.cam0;  // the map's surfels placed h higher than the world's
    T_model.translation().z() += h;
    const test::WorldMaps model(model_frame[0], T_model);
    tracking::ModelMaps mm;
    mm.vertex_world = model.vertex.view();
    mm.normal_world = model.normal.view();
    mm.K = K;
    mm.T_world_model = T_model;
    OdometryPrior op = s.primed(true);
    const auto prior = op.predict(s.odo1, s.cam0);
    ASSERT_TRUE(prior.has_value());
    tracking::IcpTracker icp;
    const tracking::TrackingResult r = icp.align(frame, mm, prior->T_world_cam, {}, &*prior);
    const double dz = r.T_world_cam.translation().z() - s.cam1.translation().z();
    if (h < 0.01) {
      EXPECT_TRUE(r.ok) << tracking::toString(r.status);
      EXPECT_GT(dz, 0.5 * h) << "the data outweigh the floor where they fix the height";
      EXPECT_LT(r.prior_sigmas, 3.0);
    } else {
      EXPECT_EQ(r.status, tracking::TrackingStatus::PriorConflict);
      EXPECT_GT(r.prior_sigmas, 6.0);
    }
  }
}
