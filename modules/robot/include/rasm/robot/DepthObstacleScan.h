#pragma once
// Obstacle sensing for a robot without a laser (paper VI: the reactive navigator avoids what the
// robot senses): a virtual planar scan from the latest depth frame of the robot's own RGB-D
// camera. Every stride-th valid pixel is back-projected, moved into the robot base frame through
// the camera mount T_base_cam, kept when its height lies in the robot's band [min_z_m, max_z_m]
// and its range within max_range_m, and the nearest point per bearing bin is the scan (as a 2-D
// laser sees the nearest return per ray). Only what the camera sees is sensed: a Kinect-class
// camera covers ~57 degrees ahead, so obstacles beside or behind the robot are not.
//
// DepthScanRobot adds this scan to any IRobot (the Segway, whose senseObstacles() returns
// nothing): offerDepthFrame() (the mapping thread, per frame) replaces the scan, and
// senseObstacles() (the navigation thread) returns it moved by the odometry since that frame.

#include <Eigen/Geometry>
#include <mutex>
#include <vector>

#include "rasm/core/RgbdFrame.h"
#include "rasm/robot/IRobot.h"

namespace rasm::robot {

struct TDepthScanParams {
  float min_z_m = 0.05f;  ///< lowest obstacle height above the floor (the floor itself is below)
  float max_z_m = 1.2f;   ///< highest (the robot's height)
  float max_range_m = 4.0f;
  int bins = 180;  ///< bearing bins over 360 degrees (2 degrees each)
  int stride = 4;  ///< every stride-th pixel in x and y
};

/// The virtual scan of `frame` in the base frame (x forward, y left, z up): at most one point per
/// bearing bin, the nearest in the plane.
std::vector<Eigen::Vector3f> virtualScanFromDepth(const RgbdFrame& frame,
                                                  const Eigen::Isometry3d& T_base_cam,
                                                  const TDepthScanParams& params);

class DepthScanRobot : public IRobot {
 public:
  /// `base` must outlive this; `T_base_cam`: the camera mount ([robot] camera_*).
  DepthScanRobot(IRobot& base, const Eigen::Isometry3d& T_base_cam, const TDepthScanParams& p);

  /// The scan of `frame`, taken where the odometry was `odometry_xyyaw` (the frame's time).
  void offerDepthFrame(const RgbdFrame& frame, const Eigen::Vector3d& odometry_xyyaw);
  /// Points of the last scan (robot frame now): none before the first frame.
  void senseObstacles(std::vector<Eigen::Vector3f>& points_robot) const override;

  void setVelocityCommand(double v_mps, double w_radps) override {
    m_base.setVelocityCommand(v_mps, w_radps);
  }
  void step(double dt_s) override { m_base.step(dt_s); }
  double time_s() const override { return m_base.time_s(); }
  Eigen::Vector3d pose() const override { return m_base.pose(); }
  Eigen::Vector2d velocity() const override { return m_base.velocity(); }
  Eigen::Vector3d odometry() const override { return m_base.odometry(); }
  bool collided() const override { return m_base.collided(); }
  Eigen::Isometry3d cameraPose() const override { return m_base.cameraPose(); }
  bool wallClock() const override { return m_base.wallClock(); }

  IRobot& base() { return m_base; }

 private:
  IRobot& m_base;
  Eigen::Isometry3d m_T_base_cam;
  TDepthScanParams m_params;
  mutable std::mutex m_mx;
  std::vector<Eigen::Vector3f> m_scan;  ///< base frame at m_scan_odometry
  Eigen::Vector3d m_scan_odometry = Eigen::Vector3d::Zero();
};

}  // namespace rasm::robot
