// The tracker on real RGB-D sequences (RASM_SHARED_DATA): frame-to-frame tracking, the model being
// the previous frame's maps at its tracked pose (a stand-in for the map rendered from the last
// good pose, without fusion), against the datasets' ground truth. Frames come through the
// product's readers (io::openFrameSource: depth, intrinsics and ground truth as `rasm run` sees
// them). Skips when the data is absent.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "rasm/core/FrameProcessing.h"
#include "rasm/core/SE3.h"
#include "rasm/io/FrameSource.h"
#include "rasm/tracking/IcpTracker.h"
#include "tracking/SyntheticScene.h"

using namespace rasm;
using namespace rasm::tracking;
namespace fs = std::filesystem;

namespace {

constexpr double kDeg = M_PI / 180.0;

/// Depth (metres) and ground truth of the first `max_frames` frames of a sequence.
struct Sequence {
  CameraIntrinsics K;
  std::vector<Image<float>> depth;
  std::vector<Eigen::Isometry3d> gt;  ///< T_world_cam per frame
};

Sequence load(const fs::path& dir, std::size_t max_frames) {
  Sequence s;
  const std::unique_ptr<io::FrameSource> src = io::openFrameSource(dir.string());
  while (s.depth.size() < max_frames) {
    std::optional<RgbdFrame> f = src->next();
    if (!f) break;
    if (!f->gt_T_world_cam) continue;  // (every frame of both datasets has one)
    s.K = f->intrinsics;
    s.depth.push_back(std::move(f->depth_m));
    s.gt.push_back(*f->gt_T_world_cam);
  }
  return s;
}

struct RunStats {
  int frames = 0, lost = 0;
  double ate_rmse_m = 0, max_rpe_m = 0, max_rpe_deg = 0, iterations_mean = 0;
};

RunStats run(const Sequence& s, const TTrackingParams& P, bool bilateral, int step = 1) {
  IcpTracker tr(P);
  tr.reset(s.gt[0]);
  std::vector<FrameLevel> prev, cur;
  auto prepare = [&](std::size_t i, std::vector<FrameLevel>& pyr) {
    Image<float> d = s.depth[i];
    if (bilateral) {
      Image<float> f;
      bilateralFilterDepth(d, f);
      d = std::move(f);
    }
    buildFramePyramid(d, s.K, P.num_levels, pyr);
  };
  prepare(0, prev);
  Eigen::Isometry3d T_prev_est = s.gt[0];
  RunStats st;
  double se = 0;
  for (std::size_t i = step; i < s.depth.size(); i += step) {
    prepare(i, cur);
    const test::WorldMaps model(prev[0], tr.lastGoodPose());
    ModelMaps m;
    m.vertex_world = model.vertex.view();
    m.normal_world = model.normal.view();
    m.K = s.K;
    m.T_world_model = tr.lastGoodPose();
    const TrackingResult r = tr.track(cur, m);
    ++st.frames;
    st.iterations_mean += r.iterations;
    if (!r.ok) {
      ++st.lost;
      continue;
    }
    const Eigen::Isometry3d rel_est = T_prev_est.inverse() * r.T_world_cam;
    const Eigen::Isometry3d rel_gt = s.gt[i - step].inverse() * s.gt[i];
    st.max_rpe_m = std::max(st.max_rpe_m, translationDistance(rel_gt, rel_est));
    st.max_rpe_deg = std::max(st.max_rpe_deg, rotationAngle(rel_gt, rel_est) / kDeg);
    se += std::pow(translationDistance(s.gt[i], r.T_world_cam), 2);
    T_prev_est = r.T_world_cam;
    prev.swap(cur);
  }
  st.ate_rmse_m = std::sqrt(se / std::max(1, st.frames - st.lost));
  st.iterations_mean /= std::max(1, st.frames);
  ::testing::Test::RecordProperty("iterations_mean", std::to_string(st.iterations_mean));
  ::testing::Test::RecordProperty("ate_mm", std::to_string(st.ate_rmse_m * 1e3));
  ::testing::Test::RecordProperty("max_rpe_mm", std::to_string(st.max_rpe_m * 1e3));
  ::testing::Test::RecordProperty("max_rpe_deg", std::to_string(st.max_rpe_deg));
  std::printf(
      "frames %d lost %d ATE %.2f mm, max frame-to-frame error %.2f mm %.3f deg, %.1f iterations\n",
      st.frames, st.lost, st.ate_rmse_m * 1e3, st.max_rpe_m * 1e3, st.max_rpe_deg,
      st.iterations_mean);
  return st;
}

}  // namespace

// TUM fr1/xyz, first 37 frames; io associates depth, colour and ground truth as `rasm run` does,
// which keeps 32 of them. Measured with the defaults: ATE 7.7 mm, max frame-to-frame error
// 6.8 mm / 0.97 deg (a hand-written depth-only reader kept all 37: 6.4 mm, 4.5 mm / 1.0 deg).
// Variants (37 frames, 30 deg level-0 normal limit, ATE 6.2 mm): bilateral-filtered depth
// 7.9 mm, Huber 1 cm 5.8 mm, level-0 stride 1 5.5 mm; on 7-Scenes (300 frames) the same variants
// went 122 -> 111, 144 and 121 mm: none is consistently better, so the defaults stay plain least
// squares on raw depth, stride 2.
TEST(RealSequences, TumFr1XyzFrameToFrame) {
  const fs::path dir = fs::path(RASM_SHARED_DATA) / "tum/fr1_xyz_first37";
  if (!fs::exists(dir / "depth.txt"))
    GTEST_SKIP() << "TUM fr1_xyz_first37 not found under " << RASM_SHARED_DATA;
  const Sequence s = load(dir, 1000);
  ASSERT_GE(s.depth.size(), 30u);
  const RunStats st = run(s, TTrackingParams(), false);
  EXPECT_EQ(st.lost, 0);
  EXPECT_LT(st.ate_rmse_m, 0.015);
  EXPECT_LT(st.max_rpe_m, 0.01);
  EXPECT_LT(st.max_rpe_deg, 1.5);
}

// 7-Scenes redkitchen, first 60 frames (every frame; the full 300 take long for a unit test).
// Measured: ATE 49.0 mm after 60 frames of pure frame-to-frame tracking (no map), max
// frame-to-frame error 7.8 mm / 0.31 deg. Over all 300 frames: ATE 122 mm, max error 36 mm at frame
// 122, where the ground truth itself jumps 36 mm between consecutive frames while the depth
// images align to within 3 mm of the constant-velocity guess (a ground-truth glitch).
TEST(RealSequences, SevenScenesRedkitchenFrameToFrame) {
  const fs::path dir = fs::path(RASM_SHARED_DATA) / "7scenes/redkitchen_first300";
  if (!fs::exists(dir / "frame-000000.pose.txt"))
    GTEST_SKIP() << "7scenes/redkitchen_first300 not found under " << RASM_SHARED_DATA;
  const Sequence s = load(dir, 60);
  ASSERT_EQ(s.depth.size(), 60u);
  const RunStats st = run(s, TTrackingParams(), false);
  EXPECT_EQ(st.lost, 0);
  EXPECT_LT(st.ate_rmse_m, 0.08);
  EXPECT_LT(st.max_rpe_m, 0.015);
  EXPECT_LT(st.max_rpe_deg, 0.6);
}
