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
//
// `odometry_information` is the part of `information` that wheel odometry measures: the
// translation along the floor (x, y of the base) and the yaw about the floor's normal, zero in
// the other directions and zero for a prior that does not come from odometry. IcpTracker's
// odometry conflict (TTrackingParams::max_odometry_sigmas) is measured with it alone, so that
// the directions an absolute floor measurement holds tightly do not hide a slide along the floor.
// `odometry_information_degenerate`, when not zero, replaces it for that rule in a frame whose
// geometry leaves a direction unconstrained (TrackingResult::unconstrained_directions): an
// odometry whose heading is a gyro's is trusted at the gyro's precision where the data cannot
// check it, and at the wheels' where they can (so that ICP may still turn the camera back onto
// the map after a heading error).

#include <Eigen/Geometry>

namespace rasm::tracking {

struct MotionPrior {
  Eigen::Isometry3d T_world_cam = Eigen::Isometry3d::Identity();
  Eigen::Matrix<double, 6, 6> information = Eigen::Matrix<double, 6, 6>::Zero();
  Eigen::Matrix<double, 6, 6> odometry_information = Eigen::Matrix<double, 6, 6>::Zero();
  Eigen::Matrix<double, 6, 6> odometry_information_degenerate = Eigen::Matrix<double, 6, 6>::Zero();

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

  /// The information of x, y (translation) and yaw (rotation about z) of frame A alone, with
  /// standard deviations sigma_xy_m and sigma_yaw_rad: what `odometry_information` holds for a
  /// base whose axes are A's (its z the floor's normal).
  static Eigen::Matrix<double, 6, 6> planarInformation(const Eigen::Matrix3d& R_world_A,
                                                       double sigma_xy_m, double sigma_yaw_rad) {
    Eigen::Matrix<double, 6, 6> I = Eigen::Matrix<double, 6, 6>::Zero();
    const double wxy = 1.0 / (sigma_xy_m * sigma_xy_m);
    I.topLeftCorner<3, 3>() =
        R_world_A * Eigen::Vector3d(wxy, wxy, 0.0).asDiagonal() * R_world_A.transpose();
    const Eigen::Vector3d z = R_world_A.col(2);
    I.bottomRightCorner<3, 3>() = z * z.transpose() / (sigma_yaw_rad * sigma_yaw_rad);
    return I;
  }
};

}  // namespace rasm::tracking
