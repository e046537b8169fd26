#include "rasm/sim/SimulatedDiffDriveRobot.h"

#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/kinematics/CVehicleSimul_DiffDriven.h>
#include <mrpt/math/TPose2D.h>

#include <cmath>
#include <sstream>

#include "ParamsWrite.h"
#include "rasm/core/Error.h"
#include "rasm/core/Params.h"
#include "rasm/sim/CameraPoses.h"

namespace rasm::sim {

// ---- params -------------------------------------------------------------------------------------

std::vector<Eigen::Vector2f> TRobotParams::footprintPolygon() const {
  std::vector<Eigen::Vector2f> poly;
  if (footprint_radius_m > 0) {
    for (int i = 0; i < 16; ++i) {
      const double a = 2.0 * M_PI * i / 16;
      poly.emplace_back(float(footprint_radius_m * std::cos(a)),
                        float(footprint_radius_m * std::sin(a)));
    }
  } else {
    for (std::size_t i = 0; i < footprint_xs.size(); ++i)
      poly.emplace_back(float(footprint_xs[i]), float(footprint_ys[i]));
  }
  return poly;
}

Eigen::Isometry3d TRobotParams::T_base_cam() const {
  return cameraPoseFromHeading(Eigen::Vector3d(camera_x_m, 0.0, camera_height_m), 0.0,
                               camera_pitch_deg);
}

void TRobotParams::loadFromConfigFile(const mrpt::config::CConfigFileBase& c,
                                      const std::string& s) {
  MRPT_LOAD_CONFIG_VAR_CS(footprint_radius_m, double);
  c.read_vector(s, "footprint_xs", std::vector<double>(footprint_xs), footprint_xs);
  c.read_vector(s, "footprint_ys", std::vector<double>(footprint_ys), footprint_ys);
  MRPT_LOAD_CONFIG_VAR_CS(ground_clearance_m, double);
  MRPT_LOAD_CONFIG_VAR_CS(height_m, double);
  MRPT_LOAD_CONFIG_VAR_CS(collision_cell_m, double);
  MRPT_LOAD_CONFIG_VAR_CS(camera_x_m, double);
  MRPT_LOAD_CONFIG_VAR_CS(camera_height_m, double);
  MRPT_LOAD_CONFIG_VAR_CS(camera_pitch_deg, double);
  MRPT_LOAD_CONFIG_VAR_CS(max_v_mps, double);
  MRPT_LOAD_CONFIG_VAR_CS(max_w_degps, double);
  MRPT_LOAD_CONFIG_VAR_CS(velocity_tau_s, double);
  MRPT_LOAD_CONFIG_VAR_CS(max_substep_s, double);
  MRPT_LOAD_CONFIG_VAR_CS(odometry_noise, bool);
  MRPT_LOAD_CONFIG_VAR_CS(odo_sigma_xy_per_sqrt_m, double);
  MRPT_LOAD_CONFIG_VAR_CS(odo_sigma_yaw_per_sqrt_rad, double);
  MRPT_LOAD_CONFIG_VAR_CS(odo_sigma_yaw_per_sqrt_m, double);
  MRPT_LOAD_CONFIG_VAR_CS(odometry_heading, string);
  MRPT_LOAD_CONFIG_VAR_CS(gyro_scale_error, double);
  MRPT_LOAD_CONFIG_VAR_CS(gyro_bias_degps, double);
  MRPT_LOAD_CONFIG_VAR_CS(gyro_arw_deg_per_sqrt_s, double);
  MRPT_LOAD_CONFIG_VAR_CS(scan_height_m, double);
  MRPT_LOAD_CONFIG_VAR_CS(scan_rays, int);
  MRPT_LOAD_CONFIG_VAR_CS(scan_max_range_m, double);
  validate(s);
}

void TRobotParams::saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const {
  RASM_SIM_SAVE(footprint_radius_m, "disc footprint (m); 0 = use footprint_xs/ys");
  RASM_SIM_SAVE(footprint_xs, "polygon footprint x (m, robot frame, CCW)");
  RASM_SIM_SAVE(footprint_ys, "polygon footprint y (m)");
  RASM_SIM_SAVE(ground_clearance_m, "collision band bottom above the floor (m)");
  RASM_SIM_SAVE(height_m, "collision band top (m)");
  RASM_SIM_SAVE(collision_cell_m, "collision raster resolution (m)");
  RASM_SIM_SAVE(camera_x_m, "camera forward offset on the base (m)");
  RASM_SIM_SAVE(camera_height_m, "camera height above the floor (m)");
  RASM_SIM_SAVE(camera_pitch_deg, "camera pitch (deg, negative = down)");
  RASM_SIM_SAVE(max_v_mps, "linear velocity limit");
  RASM_SIM_SAVE(max_w_degps, "angular velocity limit");
  RASM_SIM_SAVE(velocity_tau_s, "first-order velocity lag (CVehicleSimul_DiffDriven TAU)");
  RASM_SIM_SAVE(max_substep_s, "longest internal simulation step (s)");
  RASM_SIM_SAVE(odometry_noise, "corrupt odometry with random-walk noise");
  RASM_SIM_SAVE(odo_sigma_xy_per_sqrt_m, "xy error std after 1 m (m)");
  RASM_SIM_SAVE(odo_sigma_yaw_per_sqrt_rad, "yaw error std after 1 rad turned (rad)");
  RASM_SIM_SAVE(odo_sigma_yaw_per_sqrt_m, "yaw error std after 1 m travelled (rad)");
  RASM_SIM_SAVE(odometry_heading, "heading from: wheels (odo_sigma_yaw_*) | gyro (gyro_*)");
  RASM_SIM_SAVE(gyro_scale_error, "gyro scale factor error std, drawn per run (fraction)");
  RASM_SIM_SAVE(gyro_bias_degps, "gyro bias std after calibration, drawn per run (deg/s)");
  RASM_SIM_SAVE(gyro_arw_deg_per_sqrt_s, "gyro angle random walk (deg per sqrt(s))");
  RASM_SIM_SAVE(scan_height_m, "planar obstacle scan height (m)");
  RASM_SIM_SAVE(scan_rays, "rays of the planar obstacle scan over 360 deg");
  RASM_SIM_SAVE(scan_max_range_m, "obstacle scan range (m)");
}

void TRobotParams::validate(const std::string& s) const {
  requireInRange(footprint_radius_m, 0.0, 10.0, s, "footprint_radius_m");
  if (footprint_radius_m <= 0) {
    if (footprint_xs.size() != footprint_ys.size() || footprint_xs.size() < 3)
      throwInputError("[" + s + "] footprint_xs/footprint_ys",
                      "with footprint_radius_m = 0 expected two lists of the same length >= 3");
  }
  requireInRange(ground_clearance_m, 0.0, 10.0, s, "ground_clearance_m");
  requireInRange(height_m, ground_clearance_m + 1e-3, 10.0, s, "height_m");
  requireInRange(collision_cell_m, 0.002, 0.5, s, "collision_cell_m");
  requireInRange(camera_height_m, 0.0, 10.0, s, "camera_height_m");
  requireInRange(camera_pitch_deg, -89.0, 89.0, s, "camera_pitch_deg");
  requireInRange(max_v_mps, 0.0, 20.0, s, "max_v_mps");
  requireInRange(max_w_degps, 0.0, 3600.0, s, "max_w_degps");
  requireInRange(velocity_tau_s, 0.0, 10.0, s, "velocity_tau_s");
  requireInRange(max_substep_s, 1e-4, 1.0, s, "max_substep_s");
  requireInRange(odo_sigma_xy_per_sqrt_m, 0.0, 1.0, s, "odo_sigma_xy_per_sqrt_m");
  requireInRange(odo_sigma_yaw_per_sqrt_rad, 0.0, 1.0, s, "odo_sigma_yaw_per_sqrt_rad");
  requireInRange(odo_sigma_yaw_per_sqrt_m, 0.0, 1.0, s, "odo_sigma_yaw_per_sqrt_m");
  if (odometry_heading != "wheels" && odometry_heading != "gyro")
    throwInputError("[" + s + "] odometry_heading",
                    "expected wheels or gyro, got '" + odometry_heading + "'");
  requireInRange(gyro_scale_error, 0.0, 0.5, s, "gyro_scale_error");
  requireInRange(gyro_bias_degps, 0.0, 10.0, s, "gyro_bias_degps");
  requireInRange(gyro_arw_deg_per_sqrt_s, 0.0, 10.0, s, "gyro_arw_deg_per_sqrt_s");
  requireInRange(scan_height_m, 0.0, 10.0, s, "scan_height_m");
  requireInRange(scan_rays, 1, 100000, s, "scan_rays");
  requireInRange(scan_max_range_m, 0.01, 1000.0, s, "scan_max_range_m");
}

// ---- robot --------------------------------------------------------------------------------------

namespace {
double wrapPi(double a) {
  return std::atan2(std::sin(a), std::cos(a));
}

/// p (+) d for planar poses.
Eigen::Vector3d compose(const Eigen::Vector3d& p, const Eigen::Vector3d& d) {
  const double c = std::cos(p.z()), s = std::sin(p.z());
  return {p.x() + c * d.x() - s * d.y(), p.y() + s * d.x() + c * d.y(), wrapPi(p.z() + d.z())};
}

/// d such that a (+) d = b.
Eigen::Vector3d between(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  const double c = std::cos(a.z()), s = std::sin(a.z());
  const double dx = b.x() - a.x(), dy = b.y() - a.y();
  return {c * dx + s * dy, -s * dx + c * dy, wrapPi(b.z() - a.z())};
}

Eigen::Vector3d fromTPose(const mrpt::math::TPose2D& p) {
  return {p.x, p.y, p.phi};
}

}  // namespace

/// MRPT's simulator with an exact time step: simulateOneTimeStep(dt) loops
/// `while (time <= time + dt)` over firmware periods, i.e. floor(dt / period) + 1 of them, which
/// overshoots dt by up to a period (0.5 ms) per call. advance(dt) sets the period to dt / n and
/// asks for (n - 1/2) periods, so exactly n run and the motion covers exactly dt.
class SimulatedDiffDriveRobot::ExactStepSimulator
    : public mrpt::kinematics::CVehicleSimul_DiffDriven {
 public:
  void advance(double dt) {
    const int n = std::max(1, int(std::ceil(dt / 5e-4 - 1e-9)));
    m_firmware_control_period = dt / n;
    simulateOneTimeStep((n - 0.5) * m_firmware_control_period);
  }
  /// Zero velocity now, including the velocity MRPT integrates in its next firmware period.
  void halt() {
    movementCommand(0.0, 0.0);
    setV(0.0);
    setW(0.0);
    m_GT_vel = mrpt::math::TTwist2D(0, 0, 0);
    m_odometric_vel = mrpt::math::TTwist2D(0, 0, 0);
  }
};

namespace {

/// Standard normal variate by Box-Muller on the raw engine output: unlike
/// std::normal_distribution, the sequence is the same with every standard library.
double gaussian(std::mt19937_64& rng) {
  const double u1 = (double(rng() >> 11) + 1.0) * (1.0 / 9007199254740992.0);
  const double u2 = double(rng() >> 11) * (1.0 / 9007199254740992.0);
  return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * M_PI * u2);
}
}  // namespace

SimulatedDiffDriveRobot::SimulatedDiffDriveRobot(const RayScene& scene, const TRobotParams& params,
                                                 const Eigen::Vector3d& start, std::uint64_t seed)
    : m_scene(scene),
      m_params(params),
      m_raster(scene.world(), float(params.ground_clearance_m), float(params.height_m),
               float(params.collision_cell_m)),
      m_footprint(params.footprintPolygon()),
      m_sim(std::make_unique<ExactStepSimulator>()),
      m_rng(seed) {
  m_params.validate();
  if (m_params.odometry_noise && m_params.odometry_heading == "gyro") {
    m_gyro_scale = m_params.gyro_scale_error * gaussian(m_rng);
    m_gyro_bias_radps = m_params.gyro_bias_degps * M_PI / 180.0 * gaussian(m_rng);
  }
  m_sim->setDelayModelParams(m_params.velocity_tau_s, 0.0);
  if (collidesAt(start)) {
    std::ostringstream s;
    s << "start pose (" << start.x() << ", " << start.y() << ", yaw " << start.z() * 180 / M_PI
      << " deg) collides with the world's geometry in the robot's height band";
    throwInputError("simulated robot in world " + scene.world().name, s.str());
  }
  setPose(start);
}

SimulatedDiffDriveRobot::~SimulatedDiffDriveRobot() = default;

void SimulatedDiffDriveRobot::setPose(const Eigen::Vector3d& p) {
  m_sim->setCurrentGTPose(mrpt::math::TPose2D(p.x(), p.y(), p.z()));
  m_odometry = p;
  m_collided = false;
}

void SimulatedDiffDriveRobot::setVelocityCommand(double v, double w) {
  const double vmax = m_params.max_v_mps, wmax = m_params.max_w_degps * M_PI / 180.0;
  m_cmd_v = std::clamp(v, -vmax, vmax);
  m_cmd_w = std::clamp(w, -wmax, wmax);
  m_sim->movementCommand(m_cmd_v, m_cmd_w);
  m_collided = false;  // latched from the contact until the next command (IRobot::collided)
}

bool SimulatedDiffDriveRobot::collidesAt(const Eigen::Vector3d& p) const {
  if (m_params.footprint_radius_m > 0)
    return m_raster.collidesDisc(Eigen::Vector2f(float(p.x()), float(p.y())),
                                 float(m_params.footprint_radius_m));
  std::vector<Eigen::Vector2f> poly;
  const float c = float(std::cos(p.z())), s = float(std::sin(p.z()));
  for (const auto& v : m_footprint)
    poly.emplace_back(float(p.x()) + c * v.x() - s * v.y(), float(p.y()) + s * v.x() + c * v.y());
  return m_raster.collidesPolygon(poly);
}

void SimulatedDiffDriveRobot::addOdometryNoise(Eigen::Vector3d& d, double dt) {
  const double dist = std::hypot(d.x(), d.y()), turn = std::abs(d.z());
  const double sxy = m_params.odo_sigma_xy_per_sqrt_m * std::sqrt(dist);
  d.x() += sxy * gaussian(m_rng);
  d.y() += sxy * gaussian(m_rng);
  if (m_params.odometry_heading == "gyro") {
    // The gyro's rate, integrated: scaled, biased, with white rate noise (angle random walk).
    const double arw = m_params.gyro_arw_deg_per_sqrt_s * M_PI / 180.0;
    d.z() += m_gyro_scale * d.z() + m_gyro_bias_radps * dt + arw * std::sqrt(dt) * gaussian(m_rng);
    return;
  }
  const double syaw = std::sqrt(std::pow(m_params.odo_sigma_yaw_per_sqrt_rad, 2) * turn +
                                std::pow(m_params.odo_sigma_yaw_per_sqrt_m, 2) * dist);
  d.z() += syaw * gaussian(m_rng);
}

void SimulatedDiffDriveRobot::step(double dt) {
  if (!(dt > 0)) return;
  m_time_s += dt;
  const int n = std::max(1, int(std::ceil(dt / m_params.max_substep_s - 1e-9)));
  const double h = dt / n;
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector3d before = pose();
    m_sim->advance(h);
    const Eigen::Vector3d after = pose();
    if (collidesAt(after)) {
      // Stop at the last collision-free pose, velocities zeroed (no bounce, no sliding).
      m_sim->setCurrentGTPose(mrpt::math::TPose2D(before.x(), before.y(), before.z()));
      m_cmd_v = m_cmd_w = 0.0;
      m_sim->halt();
      m_collided = true;
      continue;
    }
    Eigen::Vector3d d = between(before, after);
    if (m_params.odometry_noise) addOdometryNoise(d, h);
    m_odometry = compose(m_odometry, d);
  }
}

double SimulatedDiffDriveRobot::time_s() const {
  return m_time_s;
}

Eigen::Vector3d SimulatedDiffDriveRobot::pose() const {
  return fromTPose(m_sim->getCurrentGTPose());
}

Eigen::Vector2d SimulatedDiffDriveRobot::velocity() const {
  const mrpt::math::TTwist2D t = m_sim->getCurrentGTVelLocal();
  return {t.vx, t.omega};
}

Eigen::Vector3d SimulatedDiffDriveRobot::odometry() const {
  return m_odometry;
}

Eigen::Isometry3d SimulatedDiffDriveRobot::cameraPose() const {
  const Eigen::Vector3d p = pose();
  return basePose(p.x(), p.y(), p.z()) * m_params.T_base_cam();
}

std::vector<float> SimulatedDiffDriveRobot::scanRanges() const {
  const Eigen::Vector3d p = pose();
  const int n = m_params.scan_rays;
  const float rmax = float(m_params.scan_max_range_m);
  std::vector<float> r(std::size_t(n), rmax);
  const Eigen::Vector3f o(float(p.x()), float(p.y()), float(m_params.scan_height_m));
  for (int i = 0; i < n; ++i) {
    const double a = p.z() + 2.0 * M_PI * i / n;
    const RayHit h =
        m_scene.castRay(o, Eigen::Vector3f(float(std::cos(a)), float(std::sin(a)), 0.f), 0.f, rmax);
    if (h.hit) r[std::size_t(i)] = h.t;
  }
  return r;
}

void SimulatedDiffDriveRobot::senseObstacles(std::vector<Eigen::Vector3f>& pts) const {
  pts.clear();
  const std::vector<float> r = scanRanges();
  const int n = int(r.size());
  for (int i = 0; i < n; ++i) {
    if (r[std::size_t(i)] >= float(m_params.scan_max_range_m)) continue;
    const double a = 2.0 * M_PI * i / n;
    pts.emplace_back(float(r[std::size_t(i)] * std::cos(a)), float(r[std::size_t(i)] * std::sin(a)),
                     float(m_params.scan_height_m));
  }
}

}  // namespace rasm::sim
