#include "rasm/robot/DepthObstacleScan.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace rasm::robot {

std::vector<Eigen::Vector3f> virtualScanFromDepth(const RgbdFrame& frame,
                                                  const Eigen::Isometry3d& T_base_cam,
                                                  const TDepthScanParams& p) {
  const PinholeF K = frame.intrinsics.plain();
  const Eigen::Matrix3f R = T_base_cam.linear().cast<float>();
  const Eigen::Vector3f t = T_base_cam.translation().cast<float>();
  const int bins = std::max(1, p.bins), stride = std::max(1, p.stride);
  auto nearest = std::vector<Eigen::Vector3f>(std::size_t(bins));
  auto range = std::vector<float>(std::size_t(bins), std::numeric_limits<float>::infinity());
  for (int y = 0; y < frame.depth_m.height(); y += stride)
    for (int x = 0; x < frame.depth_m.width(); x += stride) {
      const float z = frame.depth_m(x, y);
      if (!(z > 0.f)) continue;
      const Vec3f c = K.backProject(float(x), float(y), z);
      const Eigen::Vector3f q = R * Eigen::Vector3f(c.x(), c.y(), c.z()) + t;
      if (q.z() < p.min_z_m || q.z() > p.max_z_m) continue;
      const float r = q.head<2>().norm();
      if (r > p.max_range_m) continue;
      const float bearing = std::atan2(q.y(), q.x());  // [-pi, pi]
      int b = int(std::floor((bearing + float(M_PI)) / float(2.0 * M_PI) * float(bins)));
      b = std::clamp(b, 0, bins - 1);
      if (r < range[std::size_t(b)]) {
        range[std::size_t(b)] = r;
        nearest[std::size_t(b)] = q;
      }
    }
  std::vector<Eigen::Vector3f> scan;
  for (int b = 0; b < bins; ++b)
    if (std::isfinite(range[std::size_t(b)])) scan.push_back(nearest[std::size_t(b)]);
  return scan;
}

DepthScanRobot::DepthScanRobot(IRobot& base, const Eigen::Isometry3d& T_base_cam,
                               const TDepthScanParams& p)
    : m_base(base), m_T_base_cam(T_base_cam), m_params(p) {}

void DepthScanRobot::offerDepthFrame(const RgbdFrame& frame,
                                     const Eigen::Vector3d& odometry_xyyaw) {
  std::vector<Eigen::Vector3f> scan = virtualScanFromDepth(frame, m_T_base_cam, m_params);
  std::lock_guard<std::mutex> lock(m_mx);
  m_scan.swap(scan);
  m_scan_odometry = odometry_xyyaw;
}

void DepthScanRobot::senseObstacles(std::vector<Eigen::Vector3f>& points_robot) const {
  const Eigen::Vector3d now = m_base.odometry();
  std::lock_guard<std::mutex> lock(m_mx);
  // The base at the frame, seen from the base now (SE(2)): T_now^-1 T_frame.
  const double dth = m_scan_odometry.z() - now.z();
  const double c = std::cos(now.z()), s = std::sin(now.z());
  const Eigen::Vector2d d = m_scan_odometry.head<2>() - now.head<2>();
  const Eigen::Vector2d t(c * d.x() + s * d.y(), -s * d.x() + c * d.y());
  const float cr = float(std::cos(dth)), sr = float(std::sin(dth));
  points_robot.clear();
  points_robot.reserve(m_scan.size());
  for (const Eigen::Vector3f& q : m_scan)
    points_robot.emplace_back(cr * q.x() - sr * q.y() + float(t.x()),
                              sr * q.x() + cr * q.y() + float(t.y()), q.z());
}

}  // namespace rasm::robot
