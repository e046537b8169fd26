// Timestamp association, TUM trajectory files, ATE and RPE against known answers.
#include "rasm/io/TrajectoryEvaluator.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>

#include "IoTestUtils.h"
#include "rasm/core/Error.h"
#include "rasm/core/SE3.h"
#include "rasm/io/EvaluationJson.h"
#include "rasm/io/TimestampAssociation.h"
#include "rasm/io/Trajectory.h"

using namespace rasm;
using namespace rasm::io;
using rasm::io::test::ScratchDir;

namespace {

/// A 3-D, non-planar hand-held-like trajectory at `rate_hz` for `duration_s`.
Trajectory wavyTrajectory(double t0, double rate_hz, double duration_s) {
  Trajectory tr;
  for (int i = 0; i <= int(duration_s * rate_hz); ++i) {
    const double t = t0 + i / rate_hz, s = t - t0;
    StampedPose p;
    p.timestamp_s = t;
    p.T_world_cam.linear() = (Eigen::AngleAxisd(0.3 * std::sin(0.7 * s), Eigen::Vector3d::UnitX()) *
                              Eigen::AngleAxisd(0.5 * s, Eigen::Vector3d::UnitY()))
                                 .toRotationMatrix();
    p.T_world_cam.translation() =
        Eigen::Vector3d(std::sin(0.4 * s), 0.5 * std::cos(0.3 * s), 0.2 * s);
    tr.push_back(p);
  }
  return tr;
}

}  // namespace

TEST(TimestampAssociation, GreedyBySmallestDifferenceEachUsedOnce) {
  // associate.py: candidates (0.01, 0.012) 0.002 first, then (0, 0.005); (0.01, 0.005) loses.
  const auto m = associateTimestamps({0.0, 0.01}, {0.005, 0.012}, 0.02);
  ASSERT_EQ(m.size(), 2u);
  EXPECT_EQ(m[0], std::make_pair(std::size_t(0), std::size_t(0)));
  EXPECT_EQ(m[1], std::make_pair(std::size_t(1), std::size_t(1)));
  // Unsorted input, a stamp without partner, the offset applied to the second list.
  const auto m2 = associateTimestamps({3.0, 1.0, 2.0}, {0.5, 1.45, 2.51}, 0.02, 0.5);
  ASSERT_EQ(m2.size(), 2u);
  EXPECT_EQ(m2[0], std::make_pair(std::size_t(1), std::size_t(0)));  // 1.0 <-> 0.5 + 0.5
  EXPECT_EQ(m2[1], std::make_pair(std::size_t(0), std::size_t(2)));  // 3.0 <-> 2.51 + 0.5
  EXPECT_TRUE(associateTimestamps({0.0}, {0.02}, 0.02).empty());     // strict < max_dt
  EXPECT_EQ(closestIndex({0.0, 1.0, 2.0}, 1.4), 1u);
  EXPECT_EQ(closestIndex({0.0, 1.0, 2.0}, 9.0), 2u);
  EXPECT_EQ(closestIndex({0.0, 1.0, 2.0}, -1.0), 0u);
}

TEST(Trajectory, TumFileRoundTripAtFullPrecision) {
  ScratchDir dir("traj");
  Trajectory tr = wavyTrajectory(1305031102.160407, 30.0, 1.0);
  writeTumTrajectory(dir / "t.txt", tr, "test\nsecond line");
  const Trajectory back = readTumTrajectory(dir / "t.txt");
  ASSERT_EQ(back.size(), tr.size());
  for (std::size_t i = 0; i < tr.size(); ++i) {
    EXPECT_NEAR(back[i].timestamp_s, tr[i].timestamp_s, 1e-6);  // %.6f of UNIX time
    EXPECT_LT(translationDistance(back[i].T_world_cam, tr[i].T_world_cam), 1e-8);
    EXPECT_LT(rotationAngle(back[i].T_world_cam, tr[i].T_world_cam), 1e-8);
  }
  EXPECT_FALSE(std::filesystem::exists(dir / "t.txt.part"));
  // Streaming writer gives the same lines.
  {
    TumTrajectoryWriter w(dir / "s.txt");
    for (const auto& p : tr) w.write(p);
    w.close();
  }
  EXPECT_EQ(readTumTrajectory(dir / "s.txt").size(), tr.size());
}

TEST(Trajectory, CommasTabsCommentsAndErrors) {
  ScratchDir dir("trajerr");
  std::ofstream(dir / "ok.txt") << "# c\n\n2.5,1,2,3,0,0,0,2\n1.0\t0 0 0  0 0 0 1  # trailing\n";
  const Trajectory t = readTumTrajectory(dir / "ok.txt");
  ASSERT_EQ(t.size(), 2u);
  EXPECT_DOUBLE_EQ(t[0].timestamp_s, 1.0);                                           // sorted
  EXPECT_LT(rotationAngle(t[1].T_world_cam, Eigen::Isometry3d::Identity()), 1e-12);  // normalised

  std::ofstream(dir / "bad.txt") << "1 2 3\n";
  try {
    readTumTrajectory(dir / "bad.txt");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(dir / "bad.txt:1"), std::string::npos) << e.what();
  }
  std::ofstream(dir / "nan.txt") << "1 0 0 0 0 0 0 1\n2 0 x 0 0 0 0 1\n";
  try {
    readTumTrajectory(dir / "nan.txt");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("nan.txt:2"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("ty"), std::string::npos) << e.what();
  }
  EXPECT_THROW(readTumTrajectory(dir / "missing.txt"), InputError);
}

TEST(Trajectory, InterpolatePose) {
  Trajectory tr;
  for (int i = 0; i < 3; ++i) {
    StampedPose p;
    p.timestamp_s = i * 0.01;
    p.T_world_cam.linear() =
        Eigen::AngleAxisd(0.1 * i, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    p.T_world_cam.translation() = Eigen::Vector3d(i, 0, 0);
    tr.push_back(p);
  }
  const auto mid = interpolatePose(tr, 0.015);
  ASSERT_TRUE(mid.has_value());
  EXPECT_NEAR(mid->translation().x(), 1.5, 1e-12);
  EXPECT_NEAR(Eigen::AngleAxisd(mid->linear()).angle(), 0.15, 1e-12);
  EXPECT_TRUE(interpolatePose(tr, 0.035).has_value());   // 15 ms past the end: nearest
  EXPECT_FALSE(interpolatePose(tr, 0.045).has_value());  // 25 ms past the end
  EXPECT_FALSE(interpolatePose(tr, -0.021).has_value());
  EXPECT_FALSE(interpolatePose({}, 0.0).has_value());
}

TEST(TrajectoryEvaluator, AteOfARigidlyMovedEstimateIsZeroAfterAlignment) {
  const Trajectory gt = wavyTrajectory(100.0, 30.0, 10.0);
  const Eigen::Isometry3d T_est_gt = test::testPose(3);  // arbitrary rigid offset
  Trajectory est = gt;
  for (auto& p : est) {
    p.T_world_cam = T_est_gt * p.T_world_cam;
    p.timestamp_s += 0.004;  // within the association tolerance
  }
  const AteResult r = TrajectoryEvaluator::computeAte(gt, est);
  EXPECT_EQ(r.translation_m.count, gt.size());
  EXPECT_LT(r.translation_m.rmse, 1e-6);
  EXPECT_LT(r.translation_m.max, 1e-6);
  EXPECT_LT(translationDistance(r.T_gt_est, T_est_gt.inverse()), 1e-6);
  EXPECT_DOUBLE_EQ(r.scale, 1.0);

  AteOptions raw;
  raw.align = false;
  const AteResult r2 = TrajectoryEvaluator::computeAte(gt, est, raw);
  EXPECT_GT(r2.translation_m.rmse, 0.1);

  // Sim(3): a scaled copy aligns to ~0 and the scale is recovered.
  Trajectory scaled = est;
  for (auto& p : scaled) p.T_world_cam.translation() *= 0.5;
  AteOptions sim3;
  sim3.scale = true;
  const AteResult r3 = TrajectoryEvaluator::computeAte(gt, scaled, sim3);
  EXPECT_LT(r3.translation_m.rmse, 1e-6);
  EXPECT_NEAR(r3.scale, 2.0, 1e-9);
  EXPECT_GT(TrajectoryEvaluator::computeAte(gt, scaled).translation_m.rmse, 0.05);
}

TEST(TrajectoryEvaluator, AteOfGaussianNoiseIsSqrt3Sigma) {
  const Trajectory gt = wavyTrajectory(0.0, 30.0, 100.0);  // 3001 poses
  const double sigma = 0.01;
  std::mt19937 rng(7);
  std::normal_distribution<double> n(0.0, sigma);
  Trajectory est = gt;
  for (auto& p : est) p.T_world_cam.translation() += Eigen::Vector3d(n(rng), n(rng), n(rng));
  const AteResult r = TrajectoryEvaluator::computeAte(gt, est);
  // E[e^2] = 3 sigma^2 (the 6-dof fit removes ~6 / (3 N) of it); the sample mean of e^2 over N
  // poses has relative std sqrt(2 / (3 N)) ~ 1.5 %, so 5 % on RMSE is > 6 std.
  EXPECT_NEAR(r.translation_m.rmse, std::sqrt(3.0) * sigma, 0.05 * std::sqrt(3.0) * sigma);
  // Chi distribution with 3 dof: mean = 2 sqrt(2 / pi) sigma.
  EXPECT_NEAR(r.translation_m.mean, 2.0 * std::sqrt(2.0 / M_PI) * sigma, 0.05 * sigma);
  EXPECT_LE(r.translation_m.min, r.translation_m.median);
  EXPECT_LE(r.translation_m.median, r.translation_m.max);
  EXPECT_NEAR(
      r.translation_m.std * r.translation_m.std + r.translation_m.mean * r.translation_m.mean,
      r.translation_m.rmse * r.translation_m.rmse, 1e-12);
  const auto j = toJson(r, AteOptions{});
  EXPECT_EQ(j["pairs"].get<std::size_t>(), gt.size());
  EXPECT_DOUBLE_EQ(j["translation_m"]["rmse"].get<double>(), r.translation_m.rmse);
}

TEST(TrajectoryEvaluator, AteNeedsAssociatedPairs) {
  const Trajectory gt = wavyTrajectory(0.0, 30.0, 1.0);
  const Trajectory late = wavyTrajectory(50.0, 30.0, 1.0);
  try {
    TrajectoryEvaluator::computeAte(gt, late);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("0 pose pairs"), std::string::npos) << e.what();
  }
  AteOptions off;
  off.offset_s = -50.0;
  EXPECT_EQ(TrajectoryEvaluator::computeAte(gt, late, off).translation_m.count, gt.size());
}

// A camera 2 cm too high and tilted by 0.5 deg (a roll about the world's x axis), otherwise on
// the true path: the world-frame error says exactly that; the SE(3)-aligned ATE of the same pair
// is ~0, since the alignment lifts the estimate back down.
TEST(TrajectoryEvaluator, WorldFrameErrorOfAConstantHeightOffsetAndTilt) {
  const Trajectory gt = wavyTrajectory(0.0, 30.0, 10.0);
  const Eigen::Matrix3d R_tilt =
      Eigen::AngleAxisd(0.5 * M_PI / 180.0, Eigen::Vector3d::UnitX()).toRotationMatrix();
  Trajectory est = gt;
  for (auto& p : est) {
    p.T_world_cam.translation().z() += 0.02;
    p.T_world_cam.linear() = R_tilt * p.T_world_cam.linear();
    p.timestamp_s += 0.004;
  }
  const WorldFrameError w = TrajectoryEvaluator::computeWorldFrameError(gt, est);
  EXPECT_EQ(w.position_m.count, gt.size());
  EXPECT_NEAR(w.position_m.rmse, 0.02, 1e-9);
  EXPECT_NEAR(w.position_m.max, 0.02, 1e-9);
  EXPECT_NEAR(w.vertical_m.rmse, 0.02, 1e-9);
  EXPECT_NEAR(w.vertical_m.max, 0.02, 1e-9);
  EXPECT_LT(w.horizontal_m.max, 1e-9);
  EXPECT_NEAR(w.tilt_deg.rmse, 0.5, 1e-9);
  EXPECT_NEAR(w.tilt_deg.min, 0.5, 1e-9);
  EXPECT_NEAR(w.tilt_deg.max, 0.5, 1e-9);
  EXPECT_NEAR(w.start_position_error_m, 0.02, 1e-9);
  EXPECT_NEAR(w.start_rotation_error_deg, 0.5, 1e-9);
  EXPECT_FALSE(w.startsAtGroundTruth());
  EXPECT_LT(TrajectoryEvaluator::computeAte(gt, est).translation_m.max, 1e-6);

  const auto j = toJson(w, WorldFrameOptions{});
  EXPECT_EQ(j["pairs"].get<std::size_t>(), gt.size());
  EXPECT_DOUBLE_EQ(j["tilt_deg"]["max"].get<double>(), w.tilt_deg.max);
  EXPECT_DOUBLE_EQ(j["vertical_m"]["rmse"].get<double>(), w.vertical_m.rmse);
}

// The whole estimate rotated rigidly about its first position by 0.5 deg of pitch (a tilted
// floor): the ATE aligns it away; the world-frame error grows with the distance from the start
// and every frame is tilted by 0.5 deg. A pure heading error is no tilt.
TEST(TrajectoryEvaluator, WorldFrameErrorSeesATiltTheAlignmentHides) {
  const Trajectory gt = wavyTrajectory(0.0, 30.0, 10.0);
  const Eigen::Vector3d p0 = gt.front().T_world_cam.translation();
  Eigen::Isometry3d T_tilt = Eigen::Isometry3d::Identity();
  T_tilt.linear() =
      Eigen::AngleAxisd(0.5 * M_PI / 180.0, Eigen::Vector3d::UnitY()).toRotationMatrix();
  T_tilt.translation() = p0 - T_tilt.linear() * p0;  // about the start
  Trajectory est = gt, yawed = gt;
  for (auto& p : est) p.T_world_cam = T_tilt * p.T_world_cam;
  Eigen::Isometry3d T_yaw = Eigen::Isometry3d::Identity();
  T_yaw.linear() = Eigen::AngleAxisd(0.1, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  for (auto& p : yawed) p.T_world_cam.linear() = T_yaw.linear() * p.T_world_cam.linear();

  const WorldFrameError w = TrajectoryEvaluator::computeWorldFrameError(gt, est);
  EXPECT_LT(w.start_position_error_m, 1e-12);
  EXPECT_NEAR(w.start_rotation_error_deg, 0.5, 1e-9);
  EXPECT_FALSE(w.startsAtGroundTruth());  // started tilted: not at a known pose
  EXPECT_NEAR(w.tilt_deg.min, 0.5, 1e-9);
  EXPECT_NEAR(w.tilt_deg.max, 0.5, 1e-9);
  double max_m = 0, max_z_m = 0;
  for (const auto& p : gt) {
    const Eigen::Vector3d d = T_tilt * p.T_world_cam.translation() - p.T_world_cam.translation();
    max_m = std::max(max_m, d.norm());
    max_z_m = std::max(max_z_m, std::abs(d.z()));
  }
  EXPECT_NEAR(w.position_m.max, max_m, 1e-12);
  EXPECT_NEAR(w.vertical_m.max, max_z_m, 1e-12);
  EXPECT_GT(max_z_m, 0.005);
  EXPECT_LT(TrajectoryEvaluator::computeAte(gt, est).translation_m.max, 1e-6);

  // A tilt is no heading error; a yaw about the world's up is, the same on every frame.
  EXPECT_LT(w.heading_deg.max, 1e-9);
  const WorldFrameError y = TrajectoryEvaluator::computeWorldFrameError(gt, yawed);
  EXPECT_NEAR(y.heading_deg.min, 0.1 * 180.0 / M_PI, 1e-9);
  EXPECT_NEAR(y.heading_deg.max, 0.1 * 180.0 / M_PI, 1e-9);
  EXPECT_LT(y.tilt_deg.max, 1e-9);
  EXPECT_LT(y.position_m.max, 1e-12);
  EXPECT_NEAR(y.start_rotation_error_deg, 0.1 * 180.0 / M_PI, 1e-9);
  EXPECT_FALSE(y.startsAtGroundTruth());
}

TEST(TrajectoryEvaluator, WorldFrameErrorNeedsTwoAssociatedPairs) {
  const Trajectory gt = wavyTrajectory(0.0, 30.0, 1.0);
  auto expectError = [&](const Trajectory& est, const char* what) {
    try {
      TrajectoryEvaluator::computeWorldFrameError(gt, est);
      FAIL() << "no error for " << what;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("world-frame error"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("need 2"), std::string::npos) << e.what();
    }
  };
  expectError(wavyTrajectory(50.0, 30.0, 1.0), "mismatched timestamps");
  expectError(Trajectory(gt.begin(), gt.begin() + 1), "one pose");
  expectError(Trajectory{}, "no pose");
  EXPECT_EQ(TrajectoryEvaluator::computeWorldFrameError(gt, Trajectory(gt.begin(), gt.begin() + 2))
                .position_m.count,
            2u);
}

// Estimate = ground truth plus a world-frame drift of v metres per second: every 1 s interval has
// a relative translation error of exactly |v|, whatever the rotation (E.t = R_j^T v dt).
TEST(TrajectoryEvaluator, RpeOfConstantVelocityDrift) {
  const Trajectory gt = wavyTrajectory(10.0, 30.0, 6.0);
  const Eigen::Vector3d v(0.03, -0.04, 0.0);  // 5 cm/s
  Trajectory est = gt;
  for (auto& p : est) p.T_world_cam.translation() += v * (p.timestamp_s - 10.0);
  const RpeResult r = TrajectoryEvaluator::computeRpe(gt, est);
  EXPECT_EQ(r.pairs, 151u);  // 30 Hz * (6 s - 1 s) + 1 intervals
  EXPECT_NEAR(r.translation_m.rmse, 0.05, 1e-9);
  EXPECT_NEAR(r.translation_m.max - r.translation_m.min, 0.0, 1e-9);
  EXPECT_LT(r.rotation_deg.max, 1e-6);

  RpeOptions per_frame;
  per_frame.delta = 1;
  per_frame.delta_in_frames = true;
  const RpeResult rf = TrajectoryEvaluator::computeRpe(gt, est, per_frame);
  EXPECT_EQ(rf.pairs, gt.size() - 1);
  EXPECT_NEAR(rf.translation_m.rmse, 0.05 / 30.0, 1e-9);
}

// Rotation drift about the axis the ground truth turns about: E = exp(w dt), angle |w| dt.
TEST(TrajectoryEvaluator, RpeOfConstantRotationDrift) {
  Trajectory gt, est;
  const double w = 2.0 * M_PI / 180.0;  // 2 deg/s
  for (int i = 0; i <= 90; ++i) {
    const double t = i / 30.0;
    StampedPose p;
    p.timestamp_s = t;
    p.T_world_cam.linear() =
        Eigen::AngleAxisd(0.3 * t, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    gt.push_back(p);
    p.T_world_cam.linear() =
        Eigen::AngleAxisd((0.3 + w) * t, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    est.push_back(p);
  }
  const RpeResult r = TrajectoryEvaluator::computeRpe(gt, est);
  EXPECT_NEAR(r.rotation_deg.mean, 2.0, 1e-9);
  EXPECT_LT(r.translation_m.max, 1e-12);
  const auto j = toJson(r, RpeOptions{});
  EXPECT_EQ(j["delta_unit"], "s");
}

TEST(TrajectoryEvaluator, UmeyamaRecoversSim3) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<Eigen::Vector3d> src, dst;
  const Eigen::Matrix3d R0 =
      Eigen::AngleAxisd(1.1, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  const Eigen::Vector3d t0(0.5, -2, 3);
  for (int i = 0; i < 20; ++i) {
    src.emplace_back(u(rng), u(rng), u(rng));
    dst.push_back(1.7 * R0 * src.back() + t0);
  }
  Eigen::Matrix3d R;
  Eigen::Vector3d t;
  double s;
  alignUmeyama(src, dst, true, R, t, s);
  EXPECT_NEAR(s, 1.7, 1e-12);
  EXPECT_LT((R - R0).norm(), 1e-12);
  EXPECT_LT((t - t0).norm(), 1e-12);
  // A reflection is never returned.
  for (auto& p : dst) p.x() = -p.x();
  alignUmeyama(src, dst, false, R, t, s);
  EXPECT_NEAR(R.determinant(), 1.0, 1e-12);
}
