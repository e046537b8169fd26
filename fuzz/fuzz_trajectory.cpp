// libFuzzer target: the trajectory and ground-truth readers. First byte % 4 selects:
// 0 a TUM trajectory file (rasm::io::readTumTrajectory, then ATE / RPE of it against itself and
// pose interpolation), 1 a 7-Scenes frame-NNNNNN.pose.txt, 2 a 7-Scenes camera-intrinsics.txt,
// 3 a TUM folder's groundtruth.txt (read by rasm::io::TumFrameSource with association).
#include <opencv2/imgcodecs.hpp>

#include <cstdint>
#include <filesystem>
#include <fstream>

#include "FuzzUtil.h"
#include "rasm/io/SevenScenesFrameSource.h"
#include "rasm/io/Trajectory.h"
#include "rasm/io/TrajectoryEvaluator.h"
#include "rasm/io/TumFrameSource.h"

namespace fs = std::filesystem;

namespace {
/// A 7-Scenes folder and a TUM folder of one tiny frame each, made once per process.
struct Folders {
  std::string seven, tum;
  Folders() {
    seven = rasm::fuzz::scratchPath("7scenes");
    tum = rasm::fuzz::scratchPath("tum");
    fs::create_directories(seven);
    fs::create_directories(fs::path(tum) / "rgb");
    fs::create_directories(fs::path(tum) / "depth");
    const cv::Mat d(6, 8, CV_16UC1, cv::Scalar(5000)), c(6, 8, CV_8UC3, cv::Scalar(1, 2, 3));
    cv::imwrite(seven + "/frame-000000.depth.png", d);
    cv::imwrite(seven + "/frame-000000.color.png", c);
    cv::imwrite(tum + "/depth/1.000000.png", d);
    cv::imwrite(tum + "/rgb/1.000000.png", c);
    std::ofstream(tum + "/rgb.txt") << "1.000000 rgb/1.000000.png\n";
    std::ofstream(tum + "/depth.txt") << "1.000000 depth/1.000000.png\n";
  }
  ~Folders() {
    std::error_code ec;
    fs::remove_all(seven, ec);
    fs::remove_all(tum, ec);
  }
};
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  static Folders folders;
  const int mode = data[0] % 4;
  rasm::fuzz::expectOnlyInputErrors([&] {
    if (mode == 0) {
      const std::string path = rasm::fuzz::scratchPath("trajectory.txt");
      rasm::fuzz::writeFile(path, data + 1, size - 1);
      const auto t = rasm::io::readTumTrajectory(path);
      if (t.empty()) return;
      (void)rasm::io::interpolatePose(t, t.front().timestamp_s + 0.5, 0.02);
      rasm::fuzz::expectOnlyInputErrors(
          [&] { (void)rasm::io::TrajectoryEvaluator::computeAte(t, t, {}); });
      rasm::io::RpeOptions rpe;
      rpe.delta = 1;
      rpe.delta_in_frames = true;
      (void)rasm::io::TrajectoryEvaluator::computeRpe(t, t, rpe);
    } else if (mode == 3) {
      rasm::fuzz::writeFile(folders.tum + "/groundtruth.txt", data + 1, size - 1);
      rasm::io::TumFrameSource src(folders.tum);
      while (src.next()) {
      }
    } else {
      fs::remove(folders.seven + "/frame-000000.pose.txt");
      fs::remove(folders.seven + "/camera-intrinsics.txt");
      rasm::fuzz::writeFile(
          folders.seven + (mode == 1 ? "/frame-000000.pose.txt" : "/camera-intrinsics.txt"),
          data + 1, size - 1);
      rasm::io::SevenScenesSourceOptions opt;
      opt.register_colour = false;
      rasm::io::SevenScenesFrameSource src(folders.seven, opt);
      while (src.next()) {
      }
    }
  });
  return 0;
}
