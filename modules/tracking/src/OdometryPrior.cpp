#include "rasm/tracking/OdometryPrior.h"
#include "rasm/core/Angles.h"

#include <cmath>

namespace rasm::tracking {

namespace {

Eigen::Isometry3d planar(double x, double y, double yaw) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = Eigen::Vector3d(x, y, 0.0);
  T.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  return T;
}

double wrapAngle(double a) {
  return std::atan2(std::sin(a), std::cos(a));
}
}  // namespace

OdometryPrior::OdometryPrior(const TRobotParams& params)
    : m_params(params),
      m_T_base_cam(params.T_base_cam()),
      m_heading_model(params.odometry_heading == "gyro" ? HeadingModel::Gyro
                      : params.odometry_heading == "gyro_when_degenerate"
                          ? HeadingModel::GyroWhenDegenerate
                          : HeadingModel::Wheels) {}  // (auto, unresolved: the wheels')

void OdometryPrior::start(const Eigen::Isometry3d& T_world_cam0,
                          const std::optional<Eigen::Vector3d>& odometry) {
  m_T_world_floor = T_world_cam0 * m_T_base_cam.inverse();
  m_last = odometry;
  m_lost = m_pending = Variances{};
}

std::optional<MotionPrior> OdometryPrior::predict(const std::optional<Eigen::Vector3d>& odometry,
                                                  const Eigen::Isometry3d& T_world_cam_prev) {
  const std::optional<Eigen::Vector3d> last = m_last;
  m_last = odometry;
  m_pending = Variances{};
  if (!m_params.use_odometry || !odometry || !last) return std::nullopt;
  const Eigen::Isometry3d T_base_delta = planar((*last).x(), (*last).y(), (*last).z()).inverse() *
                                         planar(odometry->x(), odometry->y(), odometry->z());
  const Eigen::Isometry3d T_pred =
      T_world_cam_prev * m_T_base_cam.inverse() * T_base_delta * m_T_base_cam;

  // One increment's noise along the base's axes at t-1: random walks in distance and angle.
  const double d = T_base_delta.translation().head<2>().norm();
  const double a = std::abs(wrapAngle(odometry->z() - last->z()));
  const TRobotParams& p = m_params;
  // The heading's own noise: a gyro's scale error grows with the turn; the wheels' random walks
  // with the turn and the distance.
  const double s_yaw_gyro = p.odometry_sigma_yaw_deg * kRadPerDeg + p.gyro_sigma_yaw_per_rad * a;
  const double s_yaw = m_heading_model == HeadingModel::Gyro
                           ? s_yaw_gyro
                           : p.odometry_sigma_yaw_deg * kRadPerDeg +
                                 p.odometry_sigma_yaw_per_sqrt_rad * std::sqrt(a) +
                                 p.odometry_sigma_yaw_per_sqrt_m * std::sqrt(d);
  // The camera is off the base's rotation centre: a yaw error moves it by lever * s_yaw.
  const double lever = m_T_base_cam.translation().head<2>().norm();
  const double s_xy_inc = p.odometry_sigma_xy_m + p.odometry_sigma_xy_per_sqrt_m * std::sqrt(d);
  // After lost frames the previous pose is itself an odometry propagation: its error adds up
  // (frameDone), and a heading error accumulated while lost moves the camera over the distance.
  Variances v;
  v.yaw = m_lost.yaw + s_yaw * s_yaw;
  v.yaw_gyro = m_lost.yaw_gyro + s_yaw_gyro * s_yaw_gyro;
  v.xy = m_lost.xy + s_xy_inc * s_xy_inc + m_lost.yaw * d * d;
  const double s_tilt = p.odometry_sigma_tilt_deg * kRadPerDeg;
  v.tilt = m_lost.tilt + s_tilt * s_tilt;
  v.z = m_lost.z + p.odometry_sigma_z_m * p.odometry_sigma_z_m;
  m_pending = v;
  m_last_sigma_yaw = std::sqrt(v.yaw);
  const double s_xy = std::sqrt(v.xy + lever * lever * v.yaw);
  // A base on a flat floor: height, roll and pitch measured absolutely instead (the floor).
  MotionPrior prior;
  if (p.floor_prior) {
    prior = floorMeasurement(T_pred, s_xy, m_last_sigma_yaw);
  } else {
    const Eigen::Matrix3d R_world_base =
        T_world_cam_prev.linear() * m_T_base_cam.linear().transpose();
    prior = MotionPrior::fromStdDevs(
        T_pred, R_world_base, Eigen::Vector3d(s_xy, s_xy, std::sqrt(v.z)),
        Eigen::Vector3d(std::sqrt(v.tilt), std::sqrt(v.tilt), m_last_sigma_yaw));
    prior.odometry_information =
        MotionPrior::planarInformation(R_world_base, s_xy, m_last_sigma_yaw);
  }
  if (m_heading_model == HeadingModel::GyroWhenDegenerate) {
    // The same x, y and yaw directions at the gyro's heading noise: the odometry check of the
    // frames whose geometry leaves a direction free.
    const double var_yaw_gyro = v.yaw_gyro;  // (lost frames were propagated at the gyro's heading)
    const double var_xy_gyro = v.xy + lever * lever * var_yaw_gyro;
    prior.odometry_information_degenerate = prior.odometry_information;
    prior.odometry_information_degenerate.topLeftCorner<3, 3>() *= (s_xy * s_xy) / var_xy_gyro;
    prior.odometry_information_degenerate.bottomRightCorner<3, 3>() *= v.yaw / var_yaw_gyro;
  }
  return prior;
}

void OdometryPrior::frameDone(bool tracked) {
  m_lost = tracked ? Variances{} : m_pending;
}

double OdometryPrior::addHeadingResidual(const MotionPrior& prior,
                                         const Eigen::Isometry3d& T_tracked,
                                         double& correction_rad) {
  // Rotation from the predicted to the tracked orientation (world frame), about the floor normal.
  const Eigen::AngleAxisd d(T_tracked.linear() * prior.T_world_cam.linear().transpose());
  const double e = d.angle() * d.axis().dot(up());
  m_heading.emplace_back(e, m_last_sigma_yaw * m_last_sigma_yaw);
  while (int(m_heading.size()) > m_params.heading_drift_window_frames) m_heading.pop_front();
  double sum = 0.0, var = 0.0;
  for (const auto& [r, v] : m_heading) {
    sum += r;
    var += v;
  }
  correction_rad = sum;
  return var > 0.0 ? std::abs(sum) / std::sqrt(var) : 0.0;
}

std::pair<double, double> OdometryPrior::floorDeviation(
    const Eigen::Isometry3d& T_world_cam) const {
  const Eigen::Isometry3d T_floor = projectToFloor(T_world_cam);
  const double height = up().dot(T_world_cam.translation() - T_floor.translation());
  const double tilt =
      Eigen::AngleAxisd(T_world_cam.linear() * T_floor.linear().transpose()).angle();
  return {height, tilt};
}

MotionPrior OdometryPrior::floorMeasurement(const Eigen::Isometry3d& T_world_cam_pred,
                                            double sigma_xy_m, double sigma_yaw_rad) const {
  // Height, roll and pitch are absolute (the mount on the first frame's floor), not increments:
  // their uncertainty is the floor's, whatever the previous pose or lost frames accumulated.
  const Eigen::Isometry3d T_floor_pred = projectToFloor(T_world_cam_pred);
  const Eigen::Matrix3d R_world_floorbase =
      T_floor_pred.linear() * m_T_base_cam.linear().transpose();
  const double s_tilt = m_params.floor_prior_sigma_tilt_deg * kRadPerDeg;
  MotionPrior prior = MotionPrior::fromStdDevs(
      T_floor_pred, R_world_floorbase,
      Eigen::Vector3d(sigma_xy_m, sigma_xy_m, m_params.floor_prior_sigma_z_m),
      Eigen::Vector3d(s_tilt, s_tilt, sigma_yaw_rad));
  prior.odometry_information =
      MotionPrior::planarInformation(R_world_floorbase, sigma_xy_m, sigma_yaw_rad);
  return prior;
}

Eigen::Isometry3d OdometryPrior::projectToFloor(const Eigen::Isometry3d& T_world_cam) const {
  // The camera's position is what ICP estimates best: keep it (in the floor plane) and the yaw
  // of the base; drop the height, roll and pitch the base cannot have. (Projecting the implied
  // base origin instead would turn a small tilt error into a lateral shift of the camera, by
  // the mount's height times the tilt.)
  const Eigen::Isometry3d T_floor_cam = m_T_world_floor.inverse() * T_world_cam;
  const Eigen::Matrix3d R = T_floor_cam.linear() * m_T_base_cam.linear().transpose();
  const double yaw = std::atan2(R(1, 0), R(0, 0));
  const Eigen::Isometry3d T_yaw = planar(0.0, 0.0, yaw);
  const Eigen::Vector3d base_xy = T_floor_cam.translation() - T_yaw * m_T_base_cam.translation();
  return m_T_world_floor * planar(base_xy.x(), base_xy.y(), yaw) * m_T_base_cam;
}

}  // namespace rasm::tracking
