#include "rasm/sim/CameraPoses.h"

#include <cmath>
#include <stdexcept>

namespace rasm::sim {

namespace {
/// Optical rotation from a forward and a left unit vector: columns [right, down, forward].
Eigen::Matrix3d opticalFrom(const Eigen::Vector3d& fwd, const Eigen::Vector3d& left) {
  const Eigen::Vector3d up = fwd.cross(left);
  Eigen::Matrix3d R;
  R.col(0) = -left;
  R.col(1) = -up;
  R.col(2) = fwd;
  return R;
}
}  // namespace

Eigen::Isometry3d cameraPoseFromHeading(const Eigen::Vector3d& eye, double yaw_deg,
                                        double pitch_deg, double roll_deg) {
  const double y = yaw_deg * M_PI / 180.0, p = pitch_deg * M_PI / 180.0;
  const Eigen::Vector3d fwd(std::cos(p) * std::cos(y), std::cos(p) * std::sin(y), std::sin(p));
  const Eigen::Vector3d left(-std::sin(y), std::cos(y), 0.0);
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() =
      opticalFrom(fwd, left) * Eigen::AngleAxisd(roll_deg * M_PI / 180.0, Eigen::Vector3d::UnitZ());
  T.translation() = eye;
  return T;
}

Eigen::Isometry3d cameraPoseLookingAt(const Eigen::Vector3d& eye, const Eigen::Vector3d& target) {
  const Eigen::Vector3d d = target - eye;
  if (d.norm() < 1e-9) throw std::invalid_argument("cameraPoseLookingAt: target == eye");
  const Eigen::Vector3d fwd = d.normalized();
  Eigen::Vector3d left = Eigen::Vector3d::UnitZ().cross(fwd);
  if (left.norm() < 1e-9)
    throw std::invalid_argument("cameraPoseLookingAt: vertical view direction");
  left.normalize();
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = opticalFrom(fwd, left);
  T.translation() = eye;
  return T;
}

Eigen::Isometry3d basePose(double x, double y, double yaw) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  T.translation() = Eigen::Vector3d(x, y, 0.0);
  return T;
}

}  // namespace rasm::sim
