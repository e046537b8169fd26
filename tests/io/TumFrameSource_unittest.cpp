// TumFrameSource on a tiny TUM folder written by the test (known depths, colours, poses,
// timestamp jitter, a missing depth frame), conversion to rawlog, and the real fr1_xyz excerpt.
#include "rasm/io/TumFrameSource.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>

#include "IoTestUtils.h"
#include "rasm/core/Error.h"
#include "rasm/core/SE3.h"
#include "rasm/io/DatasetConverter.h"
#include "rasm/io/FrameSource.h"
#include "rasm/io/RawlogFrameSource.h"
#include "rasm/io/Trajectory.h"

namespace fs = std::filesystem;
using namespace rasm;
using namespace rasm::io;
using rasm::io::test::ScratchDir;

namespace {

constexpr int kW = 16, kH = 12;
constexpr double kT0 = 1305031102.0;

/// Ground-truth camera motion: linear in time, rotating about z at 0.5 rad/s.
Eigen::Isometry3d gtPose(double t) {
  const double s = t - kT0;
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(0.5 * s, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  T.translation() = Eigen::Vector3d(0.1 + 0.3 * s, -0.2 * s, 1.5);
  return T;
}

/// Depth of frame k in 1/5000 m units at (x, y), 0 at a few pixels.
std::uint16_t depthUnits(int k, int x, int y) {
  return (x == 3 && y == 4) ? 0 : std::uint16_t(5000 + 100 * k + 7 * x + 13 * y);
}

struct TinyTum {
  std::vector<double> depth_stamps;  // stamps of the frames expected after association
  std::string folder;
};

/// 6 depth images at 30 Hz; rgb stamps jittered by up to 9 ms; the 4th depth image (k = 3) is
/// missing from depth.txt; one extra rgb image far from any depth. Ground truth at 100 Hz.
TinyTum writeTinyTum(const std::string& folder) {
  fs::create_directories(folder + "/rgb");
  fs::create_directories(folder + "/depth");
  std::ofstream rgb(folder + "/rgb.txt"), depth(folder + "/depth.txt"),
      gt(folder + "/groundtruth.txt");
  rgb << "# color images\n# timestamp filename\n";
  depth << "# depth maps\n# timestamp filename\n";
  gt << "# ground truth trajectory\n# timestamp tx ty tz qx qy qz qw\n";
  const double jitter[6] = {0.004, -0.009, 0.006, 0.001, -0.003, 0.008};
  TinyTum out;
  out.folder = folder;
  char name[64];
  for (int k = 0; k < 6; ++k) {
    const double td = kT0 + 0.1 + k / 30.0, tr = td + jitter[k];
    cv::Mat d(kH, kW, CV_16UC1), c(kH, kW, CV_8UC3);
    for (int y = 0; y < kH; ++y)
      for (int x = 0; x < kW; ++x) {
        d.at<std::uint16_t>(y, x) = depthUnits(k, x, y);
        c.at<cv::Vec3b>(y, x) = cv::Vec3b(uchar(10 * k), uchar(x), uchar(y));  // B, G, R
      }
    std::snprintf(name, sizeof(name), "%.6f.png", td);
    if (k != 3) {
      cv::imwrite(folder + "/depth/" + name, d);
      depth << std::fixed;
      depth.precision(6);
      depth << td << " depth/" << name << "\n";
      out.depth_stamps.push_back(td);
    }
    std::snprintf(name, sizeof(name), "%.6f.png", tr);
    cv::imwrite(folder + "/rgb/" + name, c);
    rgb << std::fixed;
    rgb.precision(6);
    rgb << tr << " rgb/" << name << "\n";
  }
  rgb << std::fixed << kT0 + 5.0 << " rgb/none.png\n";  // never associated, never read
  gt << std::fixed;
  gt.precision(9);
  for (int i = 0; i <= 40; ++i) {  // 0 .. 0.4 s: covers the frames
    const double t = kT0 + 0.01 * i;
    const Eigen::Isometry3d T = gtPose(t);
    const Eigen::Quaterniond q(T.linear());
    gt << t << " " << T.translation().x() << " " << T.translation().y() << " "
       << T.translation().z() << " " << q.x() << " " << q.y() << " " << q.z() << " " << q.w()
       << "\n";
  }
  return out;
}

std::string errorOf(const std::function<void()>& fn) {
  try {
    fn();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(TumFrameSource, AssociatesReadsDepthColourAndInterpolatesGroundTruth) {
  ScratchDir dir("tum");
  const TinyTum tum = writeTinyTum(dir / "rgbd_dataset_freiburg1_tiny");
  TumFrameSource named(tum.folder);
  EXPECT_EQ(named.sizeHint(), 5);
  // Folder name says freiburg1; size from the images.
  EXPECT_DOUBLE_EQ(named.intrinsics().fx, 517.3);
  EXPECT_DOUBLE_EQ(named.intrinsics().cy, 255.3);
  EXPECT_EQ(named.intrinsics().width, kW);
  // freiburg1's principal point (318.6, 255.3) lies outside these 16x12 images: frames are
  // rejected naming it (issue 15), so they are read with intrinsics that fit them.
  const std::string bad = errorOf([&] { named.next(); });
  EXPECT_NE(bad.find("cx = 318.6: expected the principal point inside the image"),
            std::string::npos)
      << bad;
  TumSourceOptions fit;
  fit.intrinsics_override = CameraIntrinsics(517.3, 516.5, 7.6, 5.3, kW, kH);
  TumFrameSource src(tum.folder, fit);

  const int ks[5] = {0, 1, 2, 4, 5};
  for (int n = 0; n < 5; ++n) {
    SCOPED_TRACE(n);
    auto f = src.next();
    ASSERT_TRUE(f.has_value());
    const int k = ks[n];
    EXPECT_EQ(f->index, std::size_t(n));
    EXPECT_NEAR(f->timestamp_s, tum.depth_stamps[n], 1e-6);
    for (int y = 0; y < kH; ++y)
      for (int x = 0; x < kW; ++x) {
        ASSERT_FLOAT_EQ(f->depth_m(x, y), float(depthUnits(k, x, y) * (1.0 / 5000.0)));
        ASSERT_EQ(f->colour(x, y).b, 10 * k);  // the pairing took this frame's own colour image
        ASSERT_EQ(f->colour(x, y).g, x);
        ASSERT_EQ(f->colour(x, y).r, y);
      }
    // Ground truth sampled at 100 Hz with a linear / constant-rate motion: interpolation is exact
    // up to the 9 printed decimals.
    ASSERT_TRUE(f->gt_T_world_cam.has_value());
    EXPECT_LT(translationDistance(*f->gt_T_world_cam, gtPose(f->timestamp_s)), 1e-8);
    EXPECT_LT(rotationAngle(*f->gt_T_world_cam, gtPose(f->timestamp_s)), 1e-8);
  }
  EXPECT_FALSE(src.next().has_value());
}

TEST(TumFrameSource, IntrinsicsOverrideDepthFactorAndNegativeFy) {
  ScratchDir dir("icl");
  const TinyTum tum = writeTinyTum(dir / "living_room_traj0");
  EXPECT_DOUBLE_EQ(TumFrameSource(tum.folder).intrinsics().fx, 525.0);  // tum_default

  TumSourceOptions opt;
  opt.intrinsics_override = CameraIntrinsics(481.2, -480.0, 7.5, 3.5, 640, 480);
  opt.depth_factor = 1000.0;
  TumFrameSource src(tum.folder, opt);
  // fy < 0: rows flipped, fy' = 480, cy' = (H - 1) - cy.
  EXPECT_DOUBLE_EQ(src.intrinsics().fy, 480.0);
  EXPECT_DOUBLE_EQ(src.intrinsics().cy, kH - 1 - 3.5);
  auto f = src.next();
  ASSERT_TRUE(f.has_value());
  EXPECT_FLOAT_EQ(f->depth_m(5, 0), float(depthUnits(0, 5, kH - 1) / 1000.0));
  EXPECT_EQ(f->colour(5, 0).r, kH - 1);
  // The flip keeps the projection: a point maps to the flipped row of where fy < 0 put it.
  const Eigen::Vector3d p(0.1, 0.2, 1.0);
  const double v_neg = -480.0 * p.y() / p.z() + 3.5;
  const double v_pos = f->intrinsics.fy * p.y() / p.z() + f->intrinsics.cy;
  EXPECT_NEAR(v_pos, (kH - 1) - v_neg, 1e-12);
}

TEST(TumFrameSource, NotATumFolderNamesFolderAndMissingFile) {
  ScratchDir dir("bad");
  std::ofstream(dir / "rgb.txt") << "# nothing\n";
  const std::string msg = errorOf([&] { TumFrameSource src(dir.str()); });
  EXPECT_NE(msg.find(dir.str()), std::string::npos) << msg;
  EXPECT_NE(msg.find("depth.txt"), std::string::npos) << msg;

  const std::string msg2 = errorOf([&] { openFrameSource(dir.str()); });
  EXPECT_NE(msg2.find(dir.str()), std::string::npos) << msg2;

  const std::string msg3 = errorOf([&] { TumFrameSource src(dir / "nonexistent"); });
  EXPECT_NE(msg3.find("nonexistent"), std::string::npos) << msg3;
}

TEST(TumFrameSource, MissingImageFileIsNamed) {
  ScratchDir dir("missing");
  const TinyTum tum = writeTinyTum(dir / "seq");
  fs::remove_all(tum.folder + "/rgb");
  TumFrameSource src(tum.folder);
  const std::string msg = errorOf([&] { src.next(); });
  EXPECT_NE(msg.find("rgb/"), std::string::npos) << msg;
  EXPECT_NE(msg.find("not found"), std::string::npos) << msg;
}

TEST(TumFrameSource, ConvertToRawlogWritesFramesAndGroundTruth) {
  ScratchDir dir("convert");
  const TinyTum tum = writeTinyTum(dir / "fr1_tiny");
  // The tiny images need a principal point inside them (freiburg1's lies outside).
  auto src = openFrameSource(tum.folder, CameraIntrinsics(517.3, 516.5, 7.6, 5.3, kW, kH));
  std::size_t calls = 0;
  ConvertOptions opt;
  opt.max_frames = 4;
  const auto res =
      convertToRawlog(*src, dir / "out.rawlog", opt, [&](std::size_t done, long long total) {
        ++calls;
        EXPECT_EQ(total, 4);
        EXPECT_EQ(done, calls);
      });
  EXPECT_EQ(res.frames, 4u);
  EXPECT_EQ(res.frames_with_groundtruth, 4u);
  EXPECT_EQ(res.groundtruth_path, dir / "out_groundtruth.txt");
  const Trajectory gt = readTumTrajectory(res.groundtruth_path);
  ASSERT_EQ(gt.size(), 4u);

  RawlogFrameSource back(dir / "out.rawlog");
  const int ks[4] = {0, 1, 2, 4};
  for (std::size_t i = 0; i < 4; ++i) {
    auto f = back.next();
    ASSERT_TRUE(f.has_value());
    EXPECT_NEAR(f->timestamp_s, gt[i].timestamp_s, 1e-6);
    EXPECT_NEAR(f->timestamp_s, tum.depth_stamps[i], 1e-6);
    EXPECT_NEAR(f->depth_m(2, 2), depthUnits(ks[i], 2, 2) / 5000.0,
                0.0005 + 1e-6);  // 1 mm rawlog units
    ASSERT_TRUE(f->gt_T_world_cam.has_value());
    EXPECT_LT(translationDistance(*f->gt_T_world_cam, gt[i].T_world_cam), 1e-6);
    EXPECT_LT(rotationAngle(*f->gt_T_world_cam, gt[i].T_world_cam), 1e-6);
    EXPECT_DOUBLE_EQ(f->intrinsics.fx, 517.3);
  }
  EXPECT_FALSE(back.next().has_value());
}

TEST(TumFrameSource, RealFreiburg1XyzExcerpt) {
  const std::string folder = std::string(RASM_SHARED_DATA) + "/tum/fr1_xyz_first37";
  if (!fs::is_directory(folder)) GTEST_SKIP() << folder << " absent (shared data)";
  TumFrameSource src(folder);
  EXPECT_EQ(src.sizeHint(), 32);  // associate.py pairs 32 of the 37 rgb / depth images
  EXPECT_DOUBLE_EQ(src.intrinsics().fx, 517.3);
  for (int i = 0; i < 3; ++i) {
    auto f = src.next();
    ASSERT_TRUE(f.has_value());
    EXPECT_EQ(f->width(), 640);
    EXPECT_EQ(f->height(), 480);
    std::vector<float> d;
    for (int y = 0; y < 480; y += 4)
      for (int x = 0; x < 640; x += 4)
        if (f->depth_m(x, y) > 0) d.push_back(f->depth_m(x, y));
    ASSERT_GT(d.size(), 640u * 480u / 16u / 2u);
    std::nth_element(d.begin(), d.begin() + d.size() / 2, d.end());
    EXPECT_GT(d[d.size() / 2], 0.5f);  // a desk scene seen from ~1 m
    EXPECT_LT(d[d.size() / 2], 3.0f);
    EXPECT_LE(*std::max_element(d.begin(), d.end()), 10.0f);
    // fr1/xyz: the camera hovers around (1.3, 0.6, 1.6) in the mocap frame.
    ASSERT_TRUE(f->gt_T_world_cam.has_value());
    EXPECT_LT((f->gt_T_world_cam->translation() - Eigen::Vector3d(1.34, 0.63, 1.65)).norm(), 0.1);
  }
}
