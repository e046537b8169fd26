#include <gtest/gtest.h>
#include <mrpt/poses/CPose3D.h>

#include "rasm/core/SE3.h"

using namespace rasm;

TEST(SE3, ExpLogRoundTrip) {
  Vector6d xi;
  xi << 0.3, -0.2, 0.5, 0.4, -0.7, 0.2;
  const Eigen::Isometry3d T = se3Exp(xi);
  EXPECT_LT((se3Log(T) - xi).norm(), 1e-10);
  // Pure translation: exp is the translation itself.
  Vector6d t = Vector6d::Zero();
  t.head<3>() << 1, 2, 3;
  EXPECT_LT((se3Exp(t).translation() - Eigen::Vector3d(1, 2, 3)).norm(), 1e-12);
}

TEST(SE3, ScrewMotionUsesLeftJacobian) {
  // Rotating 90 deg about z while "moving" rho = (pi/2, 0, 0) traces a quarter circle of radius 1:
  // the end point is (1, 1, 0), not (pi/2, 0, 0).
  Vector6d xi;
  xi << M_PI / 2, 0, 0, 0, 0, M_PI / 2;
  EXPECT_LT((se3Exp(xi).translation() - Eigen::Vector3d(1, 1, 0)).norm(), 1e-12);
}

TEST(SE3, MrptConversionsAndOpticalFrame) {
  const mrpt::poses::CPose3D p(1.0, 2.0, 0.5, 0.3, -0.2, 0.1);
  const Eigen::Isometry3d T = fromCPose3D(p);
  const mrpt::poses::CPose3D back = toCPose3D(T);
  EXPECT_NEAR((back.asVectorVal() - p.asVectorVal()).norm(), 0.0, 1e-12);
  // The optical z axis is MRPT's sensor +X (forward); optical x (right) is sensor -Y.
  const Eigen::Isometry3d& S = T_mrptSensor_optical();
  EXPECT_LT((S.linear() * Eigen::Vector3d::UnitZ() - Eigen::Vector3d::UnitX()).norm(), 1e-12);
  EXPECT_LT((S.linear() * Eigen::Vector3d::UnitX() + Eigen::Vector3d::UnitY()).norm(), 1e-12);
  EXPECT_LT((S.linear() * Eigen::Vector3d::UnitY() + Eigen::Vector3d::UnitZ()).norm(), 1e-12);
  // Round trip through an MRPT sensor pose.
  Vector6d xi;
  xi << 0.1, 0.2, 0.3, 0.2, 0.1, -0.3;
  const Eigen::Isometry3d T_world_cam = se3Exp(xi);
  const Eigen::Isometry3d again = opticalFromMrptSensorPose(mrptSensorPoseFromOptical(T_world_cam));
  EXPECT_LT(translationDistance(again, T_world_cam), 1e-9);
  EXPECT_LT(rotationAngle(again, T_world_cam), 1e-9);
}
