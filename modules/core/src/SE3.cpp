#include "rasm/core/SE3.h"

#include <mrpt/poses/CPose3D.h>

#include <cmath>

namespace rasm {

Eigen::Matrix3d skew(const Eigen::Vector3d& w) {
  Eigen::Matrix3d S;
  S << 0, -w.z(), w.y(), w.z(), 0, -w.x(), -w.y(), w.x(), 0;
  return S;
}

Eigen::Matrix3d so3Exp(const Eigen::Vector3d& omega) {
  const double th = omega.norm();
  if (th < 1e-10) return Eigen::Matrix3d::Identity() + skew(omega);
  return Eigen::AngleAxisd(th, omega / th).toRotationMatrix();
}

Eigen::Vector3d so3Log(const Eigen::Matrix3d& R) {
  const Eigen::AngleAxisd aa(R);
  return aa.angle() * aa.axis();
}

// Left Jacobian of SO(3): V = I + (1-cos)/th^2 W + (th - sin)/th^3 W^2.
static Eigen::Matrix3d leftJacobian(const Eigen::Vector3d& w) {
  const double th = w.norm();
  const Eigen::Matrix3d W = skew(w);
  if (th < 1e-6) return Eigen::Matrix3d::Identity() + 0.5 * W + W * W / 6.0;
  return Eigen::Matrix3d::Identity() + (1 - std::cos(th)) / (th * th) * W +
         (th - std::sin(th)) / (th * th * th) * W * W;
}

Eigen::Isometry3d se3Exp(const Vector6d& xi) {
  const Eigen::Vector3d rho = xi.head<3>(), w = xi.tail<3>();
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = so3Exp(w);
  T.translation() = leftJacobian(w) * rho;
  return T;
}

Vector6d se3Log(const Eigen::Isometry3d& T) {
  const Eigen::Vector3d w = so3Log(T.linear());
  Vector6d xi;
  xi.head<3>() = leftJacobian(w).inverse() * T.translation();
  xi.tail<3>() = w;
  return xi;
}

Eigen::Isometry3d orthonormalize(const Eigen::Isometry3d& T) {
  Eigen::Isometry3d out = T;
  out.linear() = Eigen::Quaterniond(T.linear()).normalized().toRotationMatrix();
  return out;
}

double translationDistance(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  return (a.inverse() * b).translation().norm();
}

double rotationAngle(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  return Eigen::AngleAxisd((a.inverse() * b).linear()).angle();
}

Eigen::Isometry3d fromCPose3D(const mrpt::poses::CPose3D& p) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = p.getRotationMatrix().asEigen();
  T.translation() = Eigen::Vector3d(p.x(), p.y(), p.z());
  return T;
}

mrpt::poses::CPose3D toCPose3D(const Eigen::Isometry3d& T) {
  mrpt::math::CMatrixDouble44 M;
  M.asEigen() = T.matrix();
  return mrpt::poses::CPose3D(M);
}

const Eigen::Isometry3d& T_mrptSensor_optical() {
  static const Eigen::Isometry3d T =
      fromCPose3D(mrpt::poses::CPose3D(0, 0, 0, -M_PI / 2, 0, -M_PI / 2));
  return T;
}

Eigen::Isometry3d opticalFromMrptSensorPose(const mrpt::poses::CPose3D& T_world_sensor) {
  return fromCPose3D(T_world_sensor) * T_mrptSensor_optical();
}

mrpt::poses::CPose3D mrptSensorPoseFromOptical(const Eigen::Isometry3d& T_world_cam) {
  return toCPose3D(orthonormalize(T_world_cam * T_mrptSensor_optical().inverse()));
}

}  // namespace rasm
