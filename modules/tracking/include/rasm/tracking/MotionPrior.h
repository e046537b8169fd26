#pragma once
// A motion prior for IcpTracker::track: the pose predicted for the frame (from wheel
// odometry through the camera's mounting pose, or a motion model) with its uncertainty. ICP adds
// it to its normal equations as a Gaussian prior, so the directions the scene constrains follow
// the data and the ones it does not (a floor and a far wall, a corridor) follow the prediction
// instead of being declared degenerate.
//
// Coordinates: the increment of IcpKernels.h, xi = [rho; omega] along the WORLD axes about the
// camera centre. `information` is the inverse covariance of the predicted pose in those
// coordinates (1/m^2 for rho, 1/rad^2 for omega).

#include <Eigen/Geometry>

namespace rasm::tracking {

struct MotionPrior {
  Eigen::Isometry3d T_world_cam = Eigen::Isometry3d::Identity();
  Eigen::Matrix<double, 6, 6> information = Eigen::Matrix<double, 6, 6>::Zero();

  /// A prior with independent errors along the axes of a frame A (rotation R_world_A): standard
  /// deviations of the translation (m) and rotation (rad) along A's x, y, z.
  static MotionPrior fromStdDevs(const Eigen::Isometry3d& T_world_cam,
                                 const Eigen::Matrix3d& R_world_A,
                                 const Eigen::Vector3d& sigma_translation_m,
                                 const Eigen::Vector3d& sigma_rotation_rad) {
    MotionPrior p;
    p.T_world_cam = T_world_cam;
    const Eigen::Matrix3d It = R_world_A *
                               sigma_translation_m.cwiseInverse().cwiseAbs2().asDiagonal() *
                               R_world_A.transpose();
    const Eigen::Matrix3d Ir = R_world_A *
                               sigma_rotation_rad.cwiseInverse().cwiseAbs2().asDiagonal() *
                               R_world_A.transpose();
    p.information.topLeftCorner<3, 3>() = It;
    p.information.bottomRightCorner<3, 3>() = Ir;
    return p;
  }
};

}  // namespace rasm::tracking
