// LoopClosure: the trajectory graph, the decision on a registration against the inactive map,
// and the map moved with the solved graph (LoopClosure.h).
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "rasm/tracking/LoopClosure.h"

namespace rasm::tracking {
namespace {

constexpr double kDeg = M_PI / 180.0;

Eigen::Isometry3d planarPose(double x, double y, double yaw) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  T.translation() = Eigen::Vector3d(x, y, 0.5);
  return T;
}

/// A robot driving a 4 m x 4 m square once (world z up), a node every 0.5 s at 0.4 m/s, turning
/// on the spot at the corners; its estimate drifts in heading by `drift_deg_per_m` per metre
/// driven (the estimate integrates the true motion with that extra rotation).
struct SquareLoop {
  std::vector<double> t_s;
  std::vector<Eigen::Isometry3d> truth, estimate;

  std::vector<double> weak;  ///< per node: the fraction of weak frames since the previous node

  /// `drift_side`: only that side (0-3) drifts, its frames weak (degenerate); -1: every side.
  explicit SquareLoop(double drift_deg_per_m, int drift_side = -1) {
    const double step_m = 0.2;
    double t = 0.0;
    Eigen::Isometry3d T_true = planarPose(0, 0, 0), T_est = T_true;
    bool weak_now = false;
    auto push = [&]() {
      weak.push_back(weak_now ? 1.0 : 0.0);
      t_s.push_back(t);
      truth.push_back(T_true);
      estimate.push_back(T_est);
      t += 0.5;
    };
    push();
    for (int side = 0; side < 4; ++side) {
      const bool drifts = drift_side < 0 || drift_side == side;
      weak_now = drift_side >= 0 && drifts;
      for (int k = 0; k < 20; ++k) {
        Eigen::Isometry3d step = Eigen::Isometry3d::Identity();
        step.translation() = Eigen::Vector3d(step_m, 0, 0);
        Eigen::Isometry3d drift = Eigen::Isometry3d::Identity();
        drift.linear() = Eigen::AngleAxisd((drifts ? drift_deg_per_m : 0.0) * step_m * kDeg,
                                           Eigen::Vector3d::UnitZ())
                             .toRotationMatrix();
        T_true = T_true * step;
        T_est = T_est * step * drift;
        push();
      }
      weak_now = false;
      Eigen::Isometry3d turn = Eigen::Isometry3d::Identity();
      turn.linear() = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix();
      T_true = T_true * turn;
      T_est = T_est * turn;
      push();
    }
  }
  std::size_t size() const { return t_s.size(); }
};

/// One surfel 1.5 m to the robot's left at each node (a wall along the path), fused where the
/// estimate put it: the map drifts with the trajectory.
maps::SurfelStore wallSeenAlongTheLoop(const SquareLoop& loop,
                                       std::vector<Eigen::Vector3d>& truth) {
  maps::SurfelStore store;
  for (std::size_t k = 0; k < loop.size(); ++k) {
    const Eigen::Vector3d p_cam(0.3, 1.5, 0.2);
    maps::Surfel s;
    s.position = (loop.estimate[k] * p_cam).cast<float>();
    s.normal = (loop.estimate[k].linear() * Eigen::Vector3d(0, -1, 0)).cast<float>();
    s.basis = (loop.estimate[k].linear() * Eigen::Vector3d(1, 0, 0)).cast<float>();
    s.radius = 0.01f;
    s.confidence = 5.0f;
    s.t_init_s = s.t_last_s = loop.t_s[k];
    store.append(s);
    truth.push_back(loop.truth[k] * p_cam);
  }
  return store;
}

TEST(LoopClosure, ADriftedLoopIsClosedAndItsSurfelsMoveOntoTheWorld) {
  // 16 m at 0.5 deg/m: the estimate comes back 8 deg and ~0.5 m off the start, the map with it.
  const SquareLoop loop(0.5);
  std::vector<Eigen::Vector3d> truth;
  maps::SurfelStore store = wallSeenAlongTheLoop(loop, truth);
  TLoopClosureParams p;
  p.node_every_s = 0.5;
  LoopClosure lc(p);
  lc.setUpAxis(Eigen::Vector3d::UnitZ());
  for (std::size_t k = 0; k + 1 < loop.size(); ++k)
    ASSERT_TRUE(lc.addNode(loop.t_s[k], loop.estimate[k]));

  // Back at the start, the frame registered against the inactive map (the first pass, made
  // at the start where the estimate was right) gives the true pose.
  const std::size_t last = loop.size() - 1;
  const double before_m =
      (loop.estimate[last].translation() - loop.truth[last].translation()).norm();
  ASSERT_GT(before_m, 0.3);
  const LoopVerdict v = lc.judge(loop.estimate[last], loop.truth[last], 0.0, loop.t_s[last]);
  ASSERT_TRUE(v.accepted()) << v.name() << " " << v.correction_m << " m, bound " << v.bound_m;
  EXPECT_NEAR(v.correction_m, before_m, 1e-6);
  EXPECT_NEAR(v.path_m, 16.0, 0.3);

  double max_before = 0;
  for (int i = 0; i < store.size(); ++i)
    max_before = std::max(max_before, (store.get(i).position.cast<double>() - truth[i]).norm());
  const TrajectoryCorrection c = lc.close(loop.t_s[last], loop.estimate[last], v.T_loop, 0.0);
  ASSERT_FALSE(c.empty());
  EXPECT_EQ(lc.numLoopEdges(), 1u);
  const int moved = deformSurfels(store, c);
  EXPECT_GT(moved, int(loop.size()) / 2);

  // The surfels of the end of the loop land on the first pass (the loop edge's 3 mm), the
  // whole wall is far nearer the world than before, and nothing left the floor's height.
  double max_after = 0, sq_before = 0, sq_after = 0;
  for (int i = 0; i < store.size(); ++i) {
    const maps::Surfel s = store.get(i);
    const double e = (s.position.cast<double>() - truth[i]).norm();
    max_after = std::max(max_after, e);
    sq_after += e * e;
    sq_before +=
        (loop.estimate[std::size_t(i)] * Eigen::Vector3d(0.3, 1.5, 0.2) - truth[i]).squaredNorm();
    EXPECT_NEAR(s.position.z(), truth[i].z(), 1e-4) << "surfel " << i;
    EXPECT_NEAR(s.normal.norm(), 1.0f, 1e-5);
    if (i == 0 || i + 1 == store.size()) {
      EXPECT_LT(e, 0.01) << "surfel " << i;
    }
  }
  // The drift grew along the whole path; the graph spreads the correction over the chain by
  // the edges' sigmas (per metre travelled, [loop_closure] chain_sigma_deg_per_m).
  // With the drift the chain's sigmas expect (heading per metre), the wall ends within the
  // world-frame target of 3 cm everywhere.
  EXPECT_LT(max_after, 0.03) << "before " << max_before << " m";
  EXPECT_LT(std::sqrt(sq_after), 0.1 * std::sqrt(sq_before));
  // The spatial index follows the moved surfels.
  EXPECT_TRUE(store.allIndexed());
}

/// The largest distance of the wall's surfels from the world after closing the loop of `loop`
/// back at its start, the chain's edges weighed by the loop's weak fractions or not.
double wallErrorAfterClosing(const SquareLoop& loop, bool use_weak) {
  std::vector<Eigen::Vector3d> truth;
  maps::SurfelStore store = wallSeenAlongTheLoop(loop, truth);
  LoopClosure lc;
  lc.setUpAxis(Eigen::Vector3d::UnitZ());
  for (std::size_t k = 0; k + 1 < loop.size(); ++k)
    lc.addNode(loop.t_s[k], loop.estimate[k], false, use_weak ? loop.weak[k] : 0.0);
  const std::size_t last = loop.size() - 1;
  const LoopVerdict v = lc.judge(loop.estimate[last], loop.truth[last], 0.0, loop.t_s[last]);
  EXPECT_TRUE(v.accepted());
  deformSurfels(store, lc.close(loop.t_s[last], loop.estimate[last], v.T_loop, 0.0,
                                use_weak ? loop.weak[last] : 0.0));
  double worst = 0;
  for (int i = 0; i < store.size(); ++i)
    worst = std::max(worst, (store.get(i).position.cast<double>() - truth[i]).norm());
  return worst;
}

TEST(LoopClosure, TheCorrectionGoesWhereTheFramesWereWeak) {
  // Only the third side drifts (2 deg/m: degenerate frames, a corridor); the other sides were
  // held by the data. With those frames marked weak the graph puts the correction there and the
  // wall ends within the 3 cm world-frame target; spread evenly it does not.
  const SquareLoop loop(2.0, 2);
  const double weighted = wallErrorAfterClosing(loop, true);
  const double even = wallErrorAfterClosing(loop, false);
  EXPECT_LT(weighted, 0.03);
  EXPECT_GT(even, 0.03);
  EXPECT_LT(weighted, 0.5 * even);
}

TEST(LoopClosure, ACorrectionBeyondTheDriftSinceTheOldMapIsRefused) {
  // A false loop: a similar room 1 m over, after 3 m of path; and a registration 4 mm off that is
  // agreement, not a loop.
  TLoopClosureParams p;
  LoopClosure lc(p);
  lc.setUpAxis(Eigen::Vector3d::UnitZ());
  for (int k = 0; k <= 15; ++k) lc.addNode(0.5 * k, planarPose(0.2 * k, 0, 0));
  const Eigen::Isometry3d T_now = planarPose(3.0, 0, 0);
  const LoopVerdict far = lc.judge(T_now, planarPose(3.0, 1.0, 0), 0.0, 7.5);
  EXPECT_EQ(far.kind, LoopVerdict::Kind::Refused);
  EXPECT_NEAR(far.bound_m, p.max_correction_m + p.drift_m_per_m * 3.0, 0.02);
  const LoopVerdict turned = lc.judge(T_now, planarPose(3.0, 0, 10 * kDeg), 0.0, 7.5);
  EXPECT_EQ(turned.kind, LoopVerdict::Kind::Refused);
  const LoopVerdict near = lc.judge(T_now, planarPose(3.004, 0, 0), 0.0, 7.5);
  EXPECT_EQ(near.kind, LoopVerdict::Kind::Agrees);
  const LoopVerdict drifted = lc.judge(T_now, planarPose(3.0, 0.08, 0), 0.0, 7.5);
  EXPECT_EQ(drifted.kind, LoopVerdict::Kind::Accepted);
  EXPECT_EQ(lc.numLoopEdges(), 0u);
}

TEST(LoopClosure, WithAnUpAxisTheCorrectionOnlyTurnsAboutItAndShiftsAcrossIt) {
  LoopClosure lc;
  lc.setUpAxis(Eigen::Vector3d::UnitZ());
  Eigen::Isometry3d C = Eigen::Isometry3d::Identity();
  C.linear() = (Eigen::AngleAxisd(0.1, Eigen::Vector3d::UnitZ()) *
                Eigen::AngleAxisd(0.02, Eigen::Vector3d::UnitX()))
                   .toRotationMatrix();
  C.translation() = Eigen::Vector3d(0.1, -0.2, 0.03);
  const Eigen::Isometry3d P = lc.constrain(C);
  const Eigen::AngleAxisd aa(P.linear());
  EXPECT_NEAR(std::abs(aa.axis().z()), 1.0, 1e-9);
  EXPECT_NEAR(aa.angle(), 0.1, 2e-3);
  EXPECT_NEAR(P.translation().z(), 0.0, 1e-12);
  EXPECT_NEAR(P.translation().x(), 0.1, 1e-12);
}

TEST(TrajectoryCorrection, InterpolatesBetweenNodesAndHoldsBeyondThem) {
  TrajectoryCorrection c;
  c.t_s = {1.0, 3.0};
  c.q = {Eigen::Quaterniond::Identity(),
         Eigen::Quaterniond(Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitZ()))};
  c.t = {Eigen::Vector3d::Zero(), Eigen::Vector3d(0.4, 0, 0)};
  EXPECT_NEAR(c.at(2.0).translation().x(), 0.2, 1e-12);
  EXPECT_NEAR(Eigen::AngleAxisd(c.at(2.0).linear()).angle(), 0.1, 1e-9);
  EXPECT_NEAR(c.at(0.0).translation().norm(), 0.0, 1e-12);
  EXPECT_NEAR(c.at(9.0).translation().x(), 0.4, 1e-12);

  // Keyframes move with the correction of their time.
  maps::Keyframe kf;
  kf.timestamp_s = 3.0;
  kf.points_world = {Eigen::Vector3f(1, 0, 0)};
  std::vector<maps::Keyframe> kfs{kf};
  correctKeyframes(kfs, c);
  EXPECT_NEAR(kfs[0].T_world_cam.translation().x(), 0.4, 1e-9);
  EXPECT_NEAR(kfs[0].points_world[0].x(), 0.4 + std::cos(0.2), 1e-6);
  EXPECT_NEAR(kfs[0].points_world[0].y(), std::sin(0.2), 1e-6);
}

}  // namespace
}  // namespace rasm::tracking
