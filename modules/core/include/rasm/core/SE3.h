#pragma once
// SE(3) helpers on Eigen. Poses are named by frames: T_a_b maps coordinates in frame b into
// frame a (p_a = T_a_b * p_b). Camera frames are OPTICAL (x right, y down, z forward).
// Twists are xi = [rho (translation part); omega (rotation part)] and exp/log are the true
// SE(3) maps (translation through the left Jacobian), unlike mrpt::poses::Lie::SE<3>.

#include <Eigen/Geometry>

namespace mrpt::poses {
class CPose3D;
}

namespace rasm {

using Vector6d = Eigen::Matrix<double, 6, 1>;

Eigen::Matrix3d skew(const Eigen::Vector3d& w);
Eigen::Matrix3d so3Exp(const Eigen::Vector3d& omega);
Eigen::Vector3d so3Log(const Eigen::Matrix3d& R);
Eigen::Isometry3d se3Exp(const Vector6d& xi);
Vector6d se3Log(const Eigen::Isometry3d& T);

/// Re-orthonormalises the rotation part (after long chains of products).
Eigen::Isometry3d orthonormalize(const Eigen::Isometry3d& T);

/// Translation distance (m) and rotation angle (rad) of T_a^-1 * T_b.
double translationDistance(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b);
double rotationAngle(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b);

/// Plain pose conversion (same frames): CPose3D <-> Isometry3d.
Eigen::Isometry3d fromCPose3D(const mrpt::poses::CPose3D& p);
mrpt::poses::CPose3D toCPose3D(const Eigen::Isometry3d& T);

/// MRPT's camera/sensor frame has +X forward, +Y left, +Z up; the optical frame has
/// +Z forward, +X right, +Y down. T_mrptSensor_optical is CPose3D(0,0,0,-90deg,0,-90deg).
const Eigen::Isometry3d& T_mrptSensor_optical();
/// T_world_optical from a CObservation3DRangeScan-style sensor pose T_world_mrptSensor.
Eigen::Isometry3d opticalFromMrptSensorPose(const mrpt::poses::CPose3D& T_world_sensor);
/// The sensor pose to store in an MRPT observation for an optical-frame camera pose.
mrpt::poses::CPose3D mrptSensorPoseFromOptical(const Eigen::Isometry3d& T_world_cam);

}  // namespace rasm
