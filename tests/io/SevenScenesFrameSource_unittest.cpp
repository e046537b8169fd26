// SevenScenesFrameSource on a tiny folder written by the test and on the redkitchen excerpt.
#include "rasm/io/SevenScenesFrameSource.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>

#include "IoTestUtils.h"
#include "rasm/core/Error.h"
#include "rasm/core/SE3.h"
#include "rasm/io/FrameSource.h"

namespace fs = std::filesystem;
using namespace rasm;
using namespace rasm::io;
using rasm::io::test::ScratchDir;
using rasm::io::test::testPose;

namespace {

void writeFrame(const std::string& folder, int k, bool with_pose = true) {
  char name[32];
  std::snprintf(name, sizeof(name), "frame-%06d", k);
  const std::string stem = folder + "/" + name;
  cv::Mat d(6, 8, CV_16UC1, cv::Scalar(1000 + k)), c(6, 8, CV_8UC3, cv::Scalar(k, 2 * k, 3 * k));
  d.at<std::uint16_t>(1, 2) = 0;
  d.at<std::uint16_t>(2, 3) = 65535;
  cv::imwrite(std::string(stem) + ".depth.png", d);
  cv::imwrite(std::string(stem) + ".color.png", c);
  if (with_pose) {
    std::ofstream p(std::string(stem) + ".pose.txt");
    p.precision(17);
    const Eigen::Matrix4d M = testPose(k).matrix();
    for (int r = 0; r < 4; ++r)
      p << M(r, 0) << " " << M(r, 1) << " " << M(r, 2) << " " << M(r, 3) << "\n";
  }
}

}  // namespace

TEST(SevenScenesFrameSource, ReadsDepthColourPoseIntrinsicsAndTimestamps) {
  ScratchDir dir("7s");
  for (int k : {0, 1, 2, 5}) writeFrame(dir.str(), k);
  std::ofstream(dir / "camera-intrinsics.txt") << "5.9e+02 0 3.1e+00\n0 5.8e+02 2.5e+00\n0 0 1\n";
  SevenScenesSourceOptions opt;
  opt.register_colour = false;  // the tiny images have no colour calibration
  auto src = std::make_unique<SevenScenesFrameSource>(dir.str(), opt);
  EXPECT_EQ(src->sizeHint(), 4);
  EXPECT_TRUE(SevenScenesFrameSource::looksLikeSevenScenesFolder(dir.str()));
  const int ks[4] = {0, 1, 2, 5};
  for (int n = 0; n < 4; ++n) {
    SCOPED_TRACE(n);
    auto f = src->next();
    ASSERT_TRUE(f.has_value());
    const int k = ks[n];
    EXPECT_NEAR(f->timestamp_s, k / 30.0, 1e-12);
    EXPECT_DOUBLE_EQ(f->intrinsics.fx, 590.0);
    EXPECT_DOUBLE_EQ(f->intrinsics.fy, 580.0);
    EXPECT_DOUBLE_EQ(f->intrinsics.cx, 3.1);
    EXPECT_EQ(f->intrinsics.width, 8);
    EXPECT_FLOAT_EQ(f->depth_m(0, 0), (1000 + k) * 0.001f);
    EXPECT_EQ(f->depth_m(2, 1), 0.0f);
    EXPECT_EQ(f->depth_m(3, 2), 0.0f);  // 65535 = invalid
    EXPECT_EQ(f->colour(4, 4).b, k);
    EXPECT_EQ(f->colour(4, 4).r, 3 * k);
    ASSERT_TRUE(f->gt_T_world_cam.has_value());
    EXPECT_LT(translationDistance(*f->gt_T_world_cam, testPose(k)), 1e-12);
  }
  EXPECT_FALSE(src->next().has_value());
}

TEST(SevenScenesFrameSource, RegistrationWithTheDepthCalibrationKeepsColour) {
  ScratchDir dir("7sreg");
  writeFrame(dir.str(), 4);
  SevenScenesSourceOptions opt;
  opt.intrinsics_override = CameraIntrinsics(8, 8, 3.5, 2.5, 8, 6);
  opt.colour_registration = SevenScenesSourceOptions::ColourRegistration{
      *opt.intrinsics_override, Eigen::Isometry3d::Identity()};
  SevenScenesFrameSource src(dir.str(), opt);
  auto f = src.next();
  ASSERT_TRUE(f.has_value());
  for (int y = 0; y < 6; ++y)
    for (int x = 0; x < 8; ++x) {
      ASSERT_EQ(f->colour(x, y).g, 8) << x << "," << y;  // including the two pixels without depth
    }
}

TEST(SevenScenesFrameSource, ErrorsNameTheFolder) {
  ScratchDir dir("7sbad");
  fs::create_directories(dir / "seq-01");
  try {
    SevenScenesFrameSource src(dir.str());
    FAIL();
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find(dir.str()), std::string::npos) << m;
    EXPECT_NE(m.find("frame-000000.depth.png"), std::string::npos) << m;
    EXPECT_NE(m.find("seq-NN"), std::string::npos) << m;
  }
  writeFrame(dir.str(), 0);
  std::ofstream(dir / "camera-intrinsics.txt") << "8 0 3.5\n0 8 2.5\n0 0 1\n";
  std::ofstream(dir / "frame-000000.pose.txt") << "1 0 0\n";
  SevenScenesFrameSource src(dir.str());
  try {
    src.next();
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("frame-000000.pose.txt"), std::string::npos) << e.what();
  }
}

namespace {
/// The InputError message of reading every frame of `folder` ("" when none).
std::string readAllError(const std::string& folder) {
  try {
    SevenScenesSourceOptions opt;
    opt.register_colour = false;
    SevenScenesFrameSource src(folder, opt);
    while (src.next()) {
    }
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}
}  // namespace

/// Non-finite, non-rigid and missing poses are errors naming the file (and line), as the TUM
/// reader's; a sequence without any pose file has no ground truth.
TEST(SevenScenesFrameSource, BadOrMissingPosesAreNamed) {
  ScratchDir dir("7spose");
  for (int k : {0, 1, 2}) writeFrame(dir.str(), k);
  std::ofstream(dir / "camera-intrinsics.txt") << "8 0 3.5\n0 8 2.5\n0 0 1\n";
  EXPECT_EQ(readAllError(dir.str()), "");

  std::ofstream(dir / "frame-000001.pose.txt") << "1 0 0 0.5\n0 1 0 nan\n0 0 1 0\n0 0 0 1\n";
  std::string e = readAllError(dir.str());
  EXPECT_NE(e.find("frame-000001.pose.txt:2"), std::string::npos) << e;
  EXPECT_NE(e.find("'nan'"), std::string::npos) << e;

  std::ofstream(dir / "frame-000001.pose.txt") << "1 0 0 0.5\n0 1 0 0\n0 0 1 -inf\n0 0 0 1\n";
  e = readAllError(dir.str());
  EXPECT_NE(e.find("frame-000001.pose.txt:3"), std::string::npos) << e;

  std::ofstream(dir / "frame-000001.pose.txt") << "2 0 0 0\n0 1 0 0\n0 0 1 0\n0 0 0 1\n";
  e = readAllError(dir.str());
  EXPECT_NE(e.find("frame-000001.pose.txt"), std::string::npos) << e;
  EXPECT_NE(e.find("not a rigid transform"), std::string::npos) << e;

  fs::remove(dir / "frame-000001.pose.txt");
  e = readAllError(dir.str());
  EXPECT_NE(e.find("missing"), std::string::npos) << e;
  EXPECT_NE(e.find("frame-000001.pose.txt"), std::string::npos) << e;
  EXPECT_NE(e.find("frame 1"), std::string::npos) << e;

  for (int k : {0, 2}) fs::remove(dir / ("frame-00000" + std::to_string(k) + ".pose.txt"));
  EXPECT_EQ(readAllError(dir.str()), "");  // no pose at all: no ground truth, not an error
}

TEST(SevenScenesFrameSource, RealRedkitchenExcerpt) {
  const std::string folder = std::string(RASM_SHARED_DATA) + "/7scenes/redkitchen_first300";
  if (!fs::is_directory(folder)) GTEST_SKIP() << folder << " absent (shared data)";
  SevenScenesFrameSource src(folder);
  EXPECT_EQ(src.sizeHint(), 300);
  EXPECT_DOUBLE_EQ(src.intrinsics().fx, 585.0);
  EXPECT_DOUBLE_EQ(src.intrinsics().cx, 320.0);
  Eigen::Isometry3d first = Eigen::Isometry3d::Identity();
  for (int i = 0; i < 3; ++i) {
    auto f = src.next();
    ASSERT_TRUE(f.has_value());
    EXPECT_EQ(f->width(), 640);
    int valid = 0;
    float dmin = 1e9f, dmax = 0;
    for (int y = 0; y < 480; ++y)
      for (int x = 0; x < 640; ++x)
        if (const float d = f->depth_m(x, y); d > 0)
          ++valid, dmin = std::min(dmin, d), dmax = std::max(dmax, d);
    EXPECT_GT(valid, 640 * 480 / 2);
    EXPECT_GT(dmin, 0.3f);  // Kinect v1 range
    EXPECT_LT(dmax, 8.0f);
    // Colour resampled into the depth camera with the approximate calibration: holes filled, and
    // only the border the wider colour view cannot cover is black.
    int black = 0;
    for (int y = 0; y < 480; ++y)
      for (int x = 0; x < 640; ++x)
        black += (f->colour(x, y).b | f->colour(x, y).g | f->colour(x, y).r) == 0;
    EXPECT_LT(black, 640 * 480 / 50);
    ASSERT_TRUE(f->gt_T_world_cam.has_value());
    if (i == 0) first = *f->gt_T_world_cam;
    // Hand-held at 30 Hz: consecutive poses a few mm / a fraction of a degree apart.
    EXPECT_LT(translationDistance(first, *f->gt_T_world_cam), 0.05);
    EXPECT_LT(rotationAngle(first, *f->gt_T_world_cam), 0.05);
  }
  EXPECT_NEAR(first.translation().x(), -0.3404563, 1e-6);  // frame-000000.pose.txt
}
