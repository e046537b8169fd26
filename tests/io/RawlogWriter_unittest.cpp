// RawlogWriter -> RawlogFrameSource round trips on synthetic frames.
#include "rasm/io/RawlogWriter.h"

#include <gtest/gtest.h>
#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/obs/CObservationImage.h>
#include <mrpt/serialization/CArchive.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>

#include "IoTestUtils.h"
#include "rasm/core/Error.h"
#include "rasm/core/SE3.h"
#include "rasm/io/RawlogFrameSource.h"

namespace fs = std::filesystem;
using namespace rasm;
using namespace rasm::io;
using rasm::io::test::ScratchDir;
using rasm::io::test::syntheticFrame;

namespace {

std::vector<RgbdFrame> readAll(const std::string& path, const RawlogSourceOptions& opt = {}) {
  RawlogFrameSource src(path, opt);
  std::vector<RgbdFrame> out;
  while (auto f = src.next()) out.push_back(std::move(*f));
  return out;
}

void expectSameFrame(const RgbdFrame& a, const RgbdFrame& b, float range_units_m) {
  ASSERT_EQ(a.width(), b.width());
  ASSERT_EQ(a.height(), b.height());
  // Depth is quantized to range_units_m: error <= half a unit (+ float rounding).
  for (int y = 0; y < a.height(); ++y)
    for (int x = 0; x < a.width(); ++x) {
      ASSERT_NEAR(a.depth_m(x, y), b.depth_m(x, y), 0.5f * range_units_m + 1e-6f) << x << "," << y;
      ASSERT_EQ(a.depth_m(x, y) == 0.0f, b.depth_m(x, y) == 0.0f);
      const Bgr8 ca = a.colour(x, y), cb = b.colour(x, y);
      ASSERT_TRUE(ca.b == cb.b && ca.g == cb.g && ca.r == cb.r) << x << "," << y;
    }
  EXPECT_EQ(a.intrinsics, b.intrinsics);
  // mrpt::Clock ticks are 100 ns; a double at 1.3e9 s resolves ~0.24 us.
  EXPECT_NEAR(a.timestamp_s, b.timestamp_s, 1e-6);
}

}  // namespace

TEST(RawlogWriter, RoundTripDepthColourIntrinsicsTimestampsPoseOdometry) {
  ScratchDir dir("rt");
  const std::string path = dir / "synthetic.rawlog";
  std::vector<RgbdFrame> frames;
  for (int i = 0; i < 4; ++i) frames.push_back(syntheticFrame(i));
  frames[2].odometry_xyyaw.reset();
  {
    RawlogWriter w(path);
    for (const auto& f : frames) w.write(f);
    EXPECT_EQ(w.framesWritten(), 4u);
    EXPECT_TRUE(fs::exists(path + ".part"));
    EXPECT_FALSE(fs::exists(path));
    w.close();
  }
  EXPECT_FALSE(fs::exists(path + ".part"));
  const auto back = readAll(path);
  ASSERT_EQ(back.size(), frames.size());
  for (std::size_t i = 0; i < frames.size(); ++i) {
    SCOPED_TRACE(i);
    expectSameFrame(frames[i], back[i], 0.001f);
    EXPECT_EQ(back[i].index, i);
    ASSERT_TRUE(back[i].gt_T_world_cam.has_value());
    EXPECT_LT(translationDistance(*frames[i].gt_T_world_cam, *back[i].gt_T_world_cam), 1e-6);
    EXPECT_LT(rotationAngle(*frames[i].gt_T_world_cam, *back[i].gt_T_world_cam), 1e-6);
    ASSERT_EQ(back[i].odometry_xyyaw.has_value(), frames[i].odometry_xyyaw.has_value());
    if (frames[i].odometry_xyyaw) {
      EXPECT_LT((*back[i].odometry_xyyaw - *frames[i].odometry_xyyaw).norm(), 1e-12);
    }
  }
}

TEST(RawlogWriter, FinerRangeUnitsKeepFinerDepth) {
  ScratchDir dir("units");
  const std::string path = dir / "fine.rawlog";
  RawlogWriterOptions opt;
  opt.range_units_m = 0.0001f;
  const RgbdFrame f = syntheticFrame(0);
  {
    RawlogWriter w(path, opt);
    w.write(f);
    w.close();
  }
  const auto back = readAll(path);
  ASSERT_EQ(back.size(), 1u);
  expectSameFrame(f, back[0], 0.0001f);
}

TEST(RawlogWriter, GroundTruthMarkersKeepIdentityPosesAndFramesWithout) {
  ScratchDir dir("gt");
  const std::string path = dir / "gt.rawlog";
  std::vector<RgbdFrame> frames;
  for (int i = 0; i < 4; ++i) frames.push_back(syntheticFrame(i));
  frames[0].gt_T_world_cam = Eigen::Isometry3d::Identity();  // identity IS ground truth here
  frames[2].gt_T_world_cam.reset();                          // no ground truth for this one
  {
    RawlogWriter w(path);
    for (const auto& f : frames) w.write(f);
    w.close();
  }
  auto back = readAll(path);
  ASSERT_EQ(back.size(), 4u);
  ASSERT_TRUE(back[0].gt_T_world_cam.has_value());
  EXPECT_LT(translationDistance(*back[0].gt_T_world_cam, Eigen::Isometry3d::Identity()), 1e-12);
  EXPECT_LT(rotationAngle(*back[0].gt_T_world_cam, Eigen::Isometry3d::Identity()), 1e-6);
  EXPECT_TRUE(back[1].gt_T_world_cam.has_value());
  EXPECT_FALSE(back[2].gt_T_world_cam.has_value());
  EXPECT_TRUE(back[3].gt_T_world_cam.has_value());

  RawlogSourceOptions never;
  never.ground_truth = RawlogSourceOptions::GroundTruthPolicy::Never;
  back = readAll(path, never);
  for (const auto& f : back) EXPECT_FALSE(f.gt_T_world_cam.has_value());
}

TEST(RawlogWriter, ExternalImagesAreWrittenBesideAndLoadedBack) {
  ScratchDir dir("ext");
  const std::string path = dir / "ext.rawlog";
  RawlogWriterOptions opt;
  opt.external_images = true;
  const RgbdFrame f0 = syntheticFrame(0), f1 = syntheticFrame(1);
  {
    RawlogWriter w(path, opt);
    w.write(f0);
    w.write(f1);
    w.close();
  }
  EXPECT_TRUE(fs::is_regular_file(dir / "ext_Images/RGBD_000000.png"));
  EXPECT_TRUE(fs::is_regular_file(dir / "ext_Images/RGBD_000001.png"));
  const auto back = readAll(path);
  ASSERT_EQ(back.size(), 2u);
  expectSameFrame(f0, back[0], 0.001f);
  expectSameFrame(f1, back[1], 0.001f);
}

TEST(RawlogWriter, WithoutCloseLeavesNoFile) {
  ScratchDir dir("abort");
  const std::string path = dir / "aborted.rawlog";
  {
    RawlogWriterOptions opt;
    opt.external_images = true;
    RawlogWriter w(path, opt);
    w.write(syntheticFrame(0));
  }
  EXPECT_FALSE(fs::exists(path));
  EXPECT_FALSE(fs::exists(path + ".part"));
  EXPECT_FALSE(fs::exists(dir / "aborted_Images"));
}

TEST(RawlogWriter, RejectsNonFiniteDepth) {
  ScratchDir dir("nan");
  RawlogWriter w(dir / "nan.rawlog");
  RgbdFrame f = syntheticFrame(0);
  f.depth_m(3, 4) = std::numeric_limits<float>::quiet_NaN();
  try {
    w.write(f);
    FAIL() << "NaN depth accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("(3,4)"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("nan.rawlog"), std::string::npos) << e.what();
  }
  f.depth_m(3, 4) = std::numeric_limits<float>::infinity();
  EXPECT_THROW(w.write(f), InputError);
}

TEST(RawlogWriter, MissingOutputFolderIsAnInputError) {
  try {
    RawlogWriter w("/nonexistent_rasm_folder/x.rawlog");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent_rasm_folder"), std::string::npos)
        << e.what();
  }
}

TEST(RawlogWriter, OtherObjectsAreWrittenAndSkippedByTheReader) {
  ScratchDir dir("obj");
  const std::string path = dir / "obj.rawlog";
  {
    RawlogWriter w(path);
    w.write(syntheticFrame(0));
    mrpt::obs::CObservationImage img;
    img.sensorLabel = "LABELS";
    img.image = mrpt::img::CImage(8, 6, mrpt::img::CH_GRAY);
    w.writeObject(img);
    w.write(syntheticFrame(1));
    w.close();
  }
  EXPECT_EQ(readAll(path).size(), 2u);
}

TEST(RawlogWriter, RawlogEditAcceptsTheOutput) {
  if (std::system("command -v rawlog-edit > /dev/null 2>&1") != 0)
    GTEST_SKIP() << "rawlog-edit not installed (mrpt-apps)";
  ScratchDir dir("edit");
  const std::string path = dir / "edit.rawlog";
  {
    RawlogWriter w(path);
    for (int i = 0; i < 3; ++i) w.write(syntheticFrame(i));
    w.close();
  }
  const std::string out = dir / "info.txt";
  ASSERT_EQ(std::system(("rawlog-edit --info -i '" + path + "' > '" + out + "' 2>&1").c_str()), 0);
  std::ifstream in(out);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("RGBD"), std::string::npos) << text;
  EXPECT_NE(text.find("Observations format               : Yes"), std::string::npos) << text;
  EXPECT_NE(text.find("ODOMETRY"), std::string::npos) << text;
}
