// Bad input at the io boundary (issue 15): truncated images, folders where files are expected,
// trajectory options that cannot associate anything. Each error names the file (and frame).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <opencv2/imgcodecs.hpp>

#include "IoTestUtils.h"
#include "rasm/core/Error.h"
#include "rasm/io/SevenScenesFrameSource.h"
#include "rasm/io/Trajectory.h"
#include "rasm/io/TrajectoryEvaluator.h"
#include "rasm/io/TumFrameSource.h"

namespace fs = std::filesystem;
using namespace rasm;
using namespace rasm::io;
using rasm::io::test::ScratchDir;

namespace {

/// A 7-Scenes folder of three 64x48 frames (colour as JPEG, with enough texture that half of it
/// is a real truncation) without poses.
void writeSeven(const std::string& dir) {
  for (int k = 0; k < 3; ++k) {
    const std::string stem = dir + "/frame-00000" + std::to_string(k);
    cv::Mat d(48, 64, CV_16UC1, cv::Scalar(1000 + k)), c(48, 64, CV_8UC3);
    cv::randu(c, 0, 255);
    cv::randu(d, 500, 3000);
    cv::imwrite(stem + ".depth.png", d);
    cv::imwrite(stem + ".color.jpg", c);
  }
  std::ofstream(dir + "/camera-intrinsics.txt") << "60 0 31.5\n0 60 23.5\n0 0 1\n";
}

void truncateHalf(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::string b((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  in.close();
  std::ofstream(path, std::ios::binary | std::ios::trunc) << b.substr(0, b.size() / 2);
}

std::string readAllError(const std::string& dir) {
  try {
    SevenScenesSourceOptions opt;
    opt.register_colour = false;
    SevenScenesFrameSource src(dir, opt);
    while (src.next()) {
    }
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

/// A truncated JPEG was accepted with only libjpeg's "Premature end of JPEG file" on stderr.
TEST(BadInput, TruncatedJpegAndPngNameTheFrame) {
  ScratchDir dir("trunc");
  writeSeven(dir.str());
  EXPECT_EQ(readAllError(dir.str()), "");
  truncateHalf(dir / "frame-000001.color.jpg");
  std::string e = readAllError(dir.str());
  EXPECT_NE(e.find("frame 1"), std::string::npos) << e;
  EXPECT_NE(e.find("frame-000001.color.jpg"), std::string::npos) << e;
  EXPECT_NE(e.find("truncated JPEG"), std::string::npos) << e;

  writeSeven(dir.str());
  truncateHalf(dir / "frame-000002.depth.png");
  e = readAllError(dir.str());
  EXPECT_NE(e.find("frame 2"), std::string::npos) << e;
  EXPECT_NE(e.find("frame-000002.depth.png"), std::string::npos) << e;
  EXPECT_NE(e.find("truncated PNG"), std::string::npos) << e;

  // Only the last bytes missing (the IEND chunk): libpng decodes the pixels without complaint.
  writeSeven(dir.str());
  {
    std::ifstream in(dir / "frame-000002.depth.png", std::ios::binary);
    std::string b((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    in.close();
    std::ofstream(dir / "frame-000002.depth.png", std::ios::binary | std::ios::trunc)
        << b.substr(0, b.size() - 12);
  }
  e = readAllError(dir.str());
  EXPECT_NE(e.find("truncated PNG"), std::string::npos) << e;

  writeSeven(dir.str());
  std::ofstream(dir / "frame-000000.color.jpg", std::ios::trunc);  // empty file
  e = readAllError(dir.str());
  EXPECT_NE(e.find("frame-000000.color.jpg"), std::string::npos) << e;
  EXPECT_NE(e.find("empty file"), std::string::npos) << e;
}

/// `rasm eval ate` with a folder as the estimate said "0 poses".
TEST(BadInput, FolderWhereATrajectoryFileIsExpected) {
  ScratchDir dir("folder");
  try {
    (void)readTumTrajectory(dir.str());
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(dir.str()), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("is a folder"), std::string::npos) << e.what();
  }
}

/// --max-dt -1 / nan associated nothing and reported "0 pose pairs within nan s".
TEST(BadInput, AteAndRpeOptionsMustBeFiniteAndPositive) {
  Trajectory t;
  for (int i = 0; i < 5; ++i) {
    StampedPose p;
    p.timestamp_s = i;
    p.T_world_cam = rasm::io::test::testPose(i);
    t.push_back(p);
  }
  for (double bad : {-1.0, 0.0, std::numeric_limits<double>::quiet_NaN()}) {
    AteOptions o;
    o.max_dt_s = bad;
    try {
      (void)TrajectoryEvaluator::computeAte(t, t, o);
      FAIL() << bad;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("max_dt_s"), std::string::npos) << e.what();
    }
  }
  AteOptions o;
  o.offset_s = std::numeric_limits<double>::infinity();
  EXPECT_THROW((void)TrajectoryEvaluator::computeAte(t, t, o), InputError);
  RpeOptions r;
  r.delta = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW((void)TrajectoryEvaluator::computeRpe(t, t, r), InputError);
  EXPECT_NO_THROW((void)TrajectoryEvaluator::computeAte(t, t, AteOptions{}));
}
