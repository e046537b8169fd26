#pragma once
// Helpers shared by the io tests: scratch folders and synthetic frames with known content.

#include <gtest/gtest.h>
#include <unistd.h>

#include <Eigen/Geometry>
#include <filesystem>
#include <string>

#include "rasm/core/RgbdFrame.h"

namespace rasm::io::test {

/// A fresh folder under the system temp dir, removed with its contents on destruction.
class ScratchDir {
 public:
  explicit ScratchDir(const std::string& name) {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    path_ = std::filesystem::temp_directory_path() /
            ("rasm_io_" + std::to_string(::getpid()) + "_" +
             (info ? std::string(info->name()) : "x") + "_" + name);
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
  }
  ~ScratchDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  std::string str() const { return path_.string(); }
  std::string operator/(const std::string& f) const { return (path_ / f).string(); }

 private:
  std::filesystem::path path_;
};

/// Pose with a rotation about a non-trivial axis (exercises every element of the conversions).
inline Eigen::Isometry3d testPose(int i) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(0.3 + 0.1 * i, Eigen::Vector3d(0.2, -0.5, 1.0).normalized())
                   .toRotationMatrix();
  T.translation() = Eigen::Vector3d(1.25 + 0.01 * i, -0.5 + 0.02 * i, 0.75 - 0.003 * i);
  return T;
}

/// w x h frame: depth 0.5 m .. ~1.3 m with sub-millimetre parts and a few invalid pixels, colour
/// encoding (x, y, i), ground truth and odometry.
inline RgbdFrame syntheticFrame(int i, int w = 32, int h = 24) {
  RgbdFrame f;
  f.index = std::size_t(i);
  f.timestamp_s = 1305031102.160407 + 0.033333 * i;
  f.intrinsics = CameraIntrinsics(30.0 + i, 29.5, 15.5, 11.25, w, h);
  f.depth_m.resize(w, h);
  f.colour.resize(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      f.depth_m(x, y) =
          ((x + y) % 11 == 0) ? 0.0f : 0.5f + 0.0137f * x + 0.0211f * y + 0.01f * i + 0.00031f;
      f.colour(x, y) =
          Bgr8{std::uint8_t(x * 7 + i), std::uint8_t(y * 11), std::uint8_t(255 - x - y)};
    }
  f.gt_T_world_cam = testPose(i);
  f.odometry_xyyaw = Eigen::Vector3d(0.1 * i, -0.05 * i, 0.02 * i);
  return f;
}

}  // namespace rasm::io::test
