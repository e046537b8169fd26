// The virtual obstacle scan from a depth frame (DepthObstacleScan.h): what a robot without a laser
// (the Segway) gives MRPT's reactive navigator.
#include <gtest/gtest.h>

#include <cmath>

#include "rasm/robot/DepthObstacleScan.h"

using namespace rasm;
using namespace rasm::robot;

namespace {
const CameraIntrinsics kK(262.5, 262.5, 159.5, 119.5, 320, 240);

/// Optical camera frame (x right, y down, z forward) on the base (x forward, y left, z up) at
/// (x_m, 0, z_m), pitched by pitch_deg (negative = looking down).
Eigen::Isometry3d mount(double x_m, double z_m, double pitch_deg = 0.0) {
  Eigen::Matrix3d R_base_optical;
  R_base_optical << 0, 0, 1, -1, 0, 0, 0, -1, 0;
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() =
      Eigen::AngleAxisd(-pitch_deg * M_PI / 180.0, Eigen::Vector3d::UnitY()) * R_base_optical;
  T.translation() = Eigen::Vector3d(x_m, 0.0, z_m);
  return T;
}

/// A camera facing a wall: depth `d` at every pixel (a fronto-parallel plane).
RgbdFrame wallFrame(float d) {
  RgbdFrame f;
  f.intrinsics = kK;
  f.depth_m.resize(kK.width, kK.height);
  f.depth_m.setTo(d);
  return f;
}

/// A robot at rest at a given odometry pose (for the scan's motion compensation).
class StillRobot : public IRobot {
 public:
  Eigen::Vector3d odo = Eigen::Vector3d::Zero();
  void setVelocityCommand(double, double) override {}
  void step(double) override {}
  double time_s() const override { return 0.0; }
  Eigen::Vector3d pose() const override { return odo; }
  Eigen::Vector2d velocity() const override { return Eigen::Vector2d::Zero(); }
  Eigen::Vector3d odometry() const override { return odo; }
  void senseObstacles(std::vector<Eigen::Vector3f>& p) const override { p.clear(); }
  bool collided() const override { return false; }
  Eigen::Isometry3d cameraPose() const override { return Eigen::Isometry3d::Identity(); }
};
}  // namespace

// A wall 1 m ahead of the base (camera at the rotation centre, 0.5 m up, level): every scan point
// lies on it, one per 2-degree bin across the camera's field of view.
TEST(DepthObstacleScan, AWallAtOneMetreGivesPointsAtOneMetreInTheBaseFrame) {
  const std::vector<Eigen::Vector3f> scan =
      virtualScanFromDepth(wallFrame(1.0f), mount(0.0, 0.5), TDepthScanParams{});
  // Half the horizontal field of view: atan(159.5 / 262.5) = 31.3 degrees, so 2 x 31.3 / 2 bins.
  EXPECT_GE(scan.size(), 30u);
  EXPECT_LE(scan.size(), 33u);
  float min_y = 1e9f, max_y = -1e9f;
  for (const Eigen::Vector3f& p : scan) {
    EXPECT_NEAR(p.x(), 1.0f, 1e-4f);
    EXPECT_GE(p.z(), 0.05f);
    EXPECT_LE(p.z(), 1.2f);
    min_y = std::min(min_y, p.y());
    max_y = std::max(max_y, p.y());
  }
  EXPECT_NEAR(max_y, 0.6f, 0.02f);  // tan(31.3 deg): the image's left edge is the robot's +y
  EXPECT_NEAR(min_y, -0.6f, 0.02f);
}

// The mount moves the points: a camera 0.2 m forward of the centre sees the wall at 1 m depth,
// which is 1.2 m from the base; the floor (a camera looking down at it) is not an obstacle.
TEST(DepthObstacleScan, MountOffsetAndHeightBandApply) {
  for (const Eigen::Vector3f& p :
       virtualScanFromDepth(wallFrame(1.0f), mount(0.2, 0.5), TDepthScanParams{}))
    EXPECT_NEAR(p.x(), 1.2f, 1e-4f);
  // Camera 0.5 m up pitched 90 degrees down: the whole image is floor 0.5 m below.
  EXPECT_TRUE(
      virtualScanFromDepth(wallFrame(0.5f), mount(0.0, 0.5, -90.0), TDepthScanParams{}).empty());
  // Out of range: a wall at 5 m is beyond max_range_m = 4.
  EXPECT_TRUE(virtualScanFromDepth(wallFrame(5.0f), mount(0.0, 0.5), TDepthScanParams{}).empty());
}

// The Segway's obstacle sensing: the scan of the last frame, moved by the odometry since it
// (the robot drove 0.3 m toward the wall and turned 90 degrees left: the wall is now 0.7 m to its
// right).
TEST(DepthObstacleScan, RobotSensesTheLastScanMovedByItsOdometry) {
  StillRobot base;
  DepthScanRobot robot(base, mount(0.0, 0.5), TDepthScanParams{});
  std::vector<Eigen::Vector3f> pts;
  robot.senseObstacles(pts);
  EXPECT_TRUE(pts.empty()) << "no frame yet";
  robot.offerDepthFrame(wallFrame(1.0f), base.odometry());
  robot.senseObstacles(pts);
  ASSERT_FALSE(pts.empty());
  for (const Eigen::Vector3f& p : pts) EXPECT_NEAR(p.x(), 1.0f, 1e-4f);
  base.odo = Eigen::Vector3d(0.3, 0.0, M_PI / 2);
  robot.senseObstacles(pts);
  ASSERT_FALSE(pts.empty());
  for (const Eigen::Vector3f& p : pts) EXPECT_NEAR(p.y(), -0.7f, 1e-4f);
}
