// The tracker on real RGB-D sequences (RASM_SHARED_DATA): frame-to-frame tracking, the model being
// the previous frame's maps at its tracked pose (a stand-in for the map rendered from the last
// good pose, without fusion), against the datasets' ground truth. Skips when the data is absent.
#include <gtest/gtest.h>
#include <mrpt/img/CImage.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "rasm/core/FrameProcessing.h"
#include "rasm/core/SE3.h"
#include "rasm/tracking/IcpTracker.h"
#include "tracking/SyntheticScene.h"

using namespace rasm;
using namespace rasm::tracking;
namespace fs = std::filesystem;

namespace {

constexpr double kDeg = M_PI / 180.0;

/// 16-bit depth PNG to metres (0 = invalid).
Image<float> loadDepthPng(const std::string& path, double metres_per_unit) {
  mrpt::img::CImage img;
  if (!img.loadFromFile(path, -1)) throw std::runtime_error("cannot read " + path);
  if (img.getPixelDepth() != mrpt::img::PixelDepth::D16U) throw std::runtime_error(path + ": not 16-bit");
  Image<float> d(int(img.getWidth()), int(img.getHeight()));
  for (int y = 0; y < d.height(); ++y)
    // Not img.at<uint16_t>(x, y): MRPT 2.5 offsets it by x bytes, not x pixels, for 16-bit images.
    for (int x = 0; x < d.width(); ++x) d(x, y) = float(img.ptrLine<uint16_t>(y)[x] * metres_per_unit);
  return d;
}

struct Sequence {
  CameraIntrinsics K;
  std::vector<std::string> depth_files;
  std::vector<Eigen::Isometry3d> gt;  ///< T_world_cam per depth frame
};

Sequence loadTum(const fs::path& dir) {
  Sequence s;
  s.K = CameraIntrinsics(517.3, 516.5, 318.6, 255.3, 640, 480);
  std::map<double, Eigen::Isometry3d> gt;
  std::ifstream g(dir / "groundtruth.txt");
  for (std::string line; std::getline(g, line);) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream is(line);
    double t, tx, ty, tz, qx, qy, qz, qw;
    is >> t >> tx >> ty >> tz >> qx >> qy >> qz >> qw;
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = Eigen::Quaterniond(qw, qx, qy, qz).normalized().toRotationMatrix();
    T.translation() = Eigen::Vector3d(tx, ty, tz);
    gt[t] = T;
  }
  std::ifstream d(dir / "depth.txt");
  for (std::string line; std::getline(d, line);) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream is(line);
    double t;
    std::string f;
    is >> t >> f;
    auto it = gt.lower_bound(t);
    if (it == gt.end() || std::abs(it->first - t) > 0.02) continue;
    s.depth_files.push_back((dir / f).string());
    s.gt.push_back(it->second);
  }
  return s;
}

Sequence loadSevenScenes(const fs::path& dir, int frames) {
  Sequence s;
  s.K = CameraIntrinsics(585.0, 585.0, 320.0, 240.0, 640, 480);
  for (int i = 0; i < frames; ++i) {
    char name[64];
    std::snprintf(name, sizeof(name), "frame-%06d", i);
    const fs::path pose = dir / (std::string(name) + ".pose.txt");
    if (!fs::exists(pose)) break;
    std::ifstream p(pose);
    Eigen::Matrix4d M;
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 4; ++c) p >> M(r, c);
    Eigen::Isometry3d T(M);
    s.gt.push_back(orthonormalize(T));
    s.depth_files.push_back((dir / (std::string(name) + ".depth.png")).string());
  }
  return s;
}

struct RunStats {
  int frames = 0, lost = 0;
  double ate_rmse_m = 0, max_rpe_m = 0, max_rpe_deg = 0, iterations_mean = 0;
};

RunStats run(const Sequence& s, double metres_per_unit, const TTrackingParams& P, bool bilateral, int step = 1) {
  IcpTracker tr(P);
  tr.reset(s.gt[0]);
  std::vector<FrameLevel> prev, cur;
  auto prepare = [&](std::size_t i, std::vector<FrameLevel>& pyr) {
    Image<float> d = loadDepthPng(s.depth_files[i], metres_per_unit);
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
  for (std::size_t i = step; i < s.depth_files.size(); i += step) {
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
  return st;
}

}  // namespace

// TUM fr1/xyz, first 37 frames (hand-held, ~1.5 cm per frame). Measured with the defaults: ATE
// 6.4 mm, max frame-to-frame error 4.5 mm / 1.0 deg. Variants (measured with a 30 deg level-0
// normal limit, ATE 6.2 mm): bilateral-filtered depth 7.9 mm, Huber 1 cm 5.8 mm, level-0
// stride 1 5.5 mm; on 7-Scenes (300 frames) the same variants went 122 -> 111, 144 and 121 mm:
// none is consistently better, so the defaults stay plain least squares on raw depth, stride 2.
TEST(RealSequences, TumFr1XyzFrameToFrame) {
  const fs::path dir = fs::path(RASM_SHARED_DATA) / "tum/fr1_xyz_first37";
  if (!fs::exists(dir / "depth.txt")) GTEST_SKIP() << "TUM fr1_xyz_first37 not found under " << RASM_SHARED_DATA;
  const Sequence s = loadTum(dir);
  ASSERT_GE(s.depth_files.size(), 30u);
  const RunStats st = run(s, 1.0 / 5000, TTrackingParams(), false);
  EXPECT_EQ(st.lost, 0);
  EXPECT_LT(st.ate_rmse_m, 0.015);
  EXPECT_LT(st.max_rpe_m, 0.01);
  EXPECT_LT(st.max_rpe_deg, 1.5);
}

// 7-Scenes redkitchen, first 60 frames (every frame; the full 300 take long for a unit test).
// Measured: ATE 48.6 mm after 60 frames of pure frame-to-frame tracking (no map), max
// frame-to-frame error 8 mm / 0.3 deg. Over all 300 frames: ATE 122 mm, max error 36 mm at frame
// 122, where the ground truth itself jumps 36 mm between consecutive frames while the depth
// images align to within 3 mm of the constant-velocity guess (a ground-truth glitch).
TEST(RealSequences, SevenScenesRedkitchenFrameToFrame) {
  const fs::path dir = fs::path(RASM_SHARED_DATA) / "7scenes/redkitchen_first300";
  if (!fs::exists(dir / "frame-000000.pose.txt"))
    GTEST_SKIP() << "7scenes/redkitchen_first300 not found under " << RASM_SHARED_DATA;
  const Sequence s = loadSevenScenes(dir, 60);
  ASSERT_EQ(s.depth_files.size(), 60u);
  const RunStats st = run(s, 1e-3, TTrackingParams(), false);
  EXPECT_EQ(st.lost, 0);
  EXPECT_LT(st.ate_rmse_m, 0.08);
  EXPECT_LT(st.max_rpe_m, 0.015);
  EXPECT_LT(st.max_rpe_deg, 0.6);
}
