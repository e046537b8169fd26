// `rasm view <run folder>` (issue 19, 3): without a display it renders the run's reloaded map
// offscreen (CFBORender, EGL) to a PNG of the requested size that shows the map; bad input is
// named. The built binary runs, as a user would.
#include <gtest/gtest.h>
#include <unistd.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <string>

#include "RasmProcess.h"
#include "run/RunTestFiles.h"

namespace fs = std::filesystem;
using namespace rasm::run::testing;

namespace {
using rasm::app::testing::Result;

/// `rasm <args>` without a display (DISPLAY unset), stdout and stderr together.
Result rasmCommand(const std::string& args) {
  return rasm::app::testing::shell("env -u DISPLAY " + std::string(RASM_BINARY) + " " + args);
}

}  // namespace

/// One run folder for the suite: the 20 frames of the simulated hand-held rawlog.
class ViewCommand : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    run_ = tempDir("view_run");
    const Result r =
        rasmCommand("run --out " + run_ + " --set source.type=rawlog --set source.path=" +
                    std::string(RASM_SOURCE_DIR) + "/rawlogs/sim_office_handheld_320x240.rawlog");
    ASSERT_EQ(r.status, 0) << r.output;
  }
  static void TearDownTestSuite() { fs::remove_all(run_); }
  static const std::string& runFolder() { return run_; }
  static std::string run_;
};
std::string ViewCommand::run_;

TEST_F(ViewCommand, OffscreenPngHasTheSizeAndShowsTheMap) {
  const std::string png = runFolder() + "_view.png";
  const Result r = rasmCommand("view " + runFolder() + " --png " + png + " --size 320x200");
  ASSERT_EQ(r.status, 0) << r.output;
  const cv::Mat img = cv::imread(png, cv::IMREAD_COLOR);
  ASSERT_FALSE(img.empty()) << png;
  EXPECT_EQ(img.cols, 320);
  EXPECT_EQ(img.rows, 200);
  // The background is the corner's colour; the map (and grid, paths) cover much of the view.
  const cv::Vec3b bg = img.at<cv::Vec3b>(0, 0);
  int other = 0;
  for (int y = 0; y < img.rows; ++y)
    for (int x = 0; x < img.cols; ++x) other += img.at<cv::Vec3b>(y, x) != bg;
  EXPECT_GT(other, img.total() / 4) << "pixels not background: " << other;
  // The segment colouring shows other colours than the measured one.
  const std::string seg = runFolder() + "_view_segments.png";
  ASSERT_EQ(
      rasmCommand("view " + runFolder() + " --colour segments --png " + seg + " --size 320x200")
          .status,
      0);
  const cv::Mat img2 = cv::imread(seg, cv::IMREAD_COLOR);
  ASSERT_EQ(img2.size(), img.size());
  EXPECT_GT(cv::norm(img, img2, cv::NORM_L1), 0.0);
  fs::remove(png);
  fs::remove(seg);
}

TEST(ViewCommandInput, BadInputIsNamed) {
  const std::string empty = tempDir("view_empty");
  fs::create_directories(empty);
  Result r = rasmCommand("view " + empty + " --png x.png");
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.output.find(empty + "/map.surfelmap: not found"), std::string::npos) << r.output;
  r = rasmCommand("view " + empty + " --size 12x5");
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.output.find("--size '12x5': expected WIDTHxHEIGHT"), std::string::npos) << r.output;
  r = rasmCommand("view " + empty + " --colour plaid");
  EXPECT_NE(r.output.find("expected rgb, segments or classes"), std::string::npos) << r.output;
  fs::remove_all(empty);
}
