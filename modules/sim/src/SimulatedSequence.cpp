#include "rasm/sim/SimulatedSequence.h"

#include <mrpt/config/CConfigFileMemory.h>

#include <cmath>
#include <cstdio>

#include "rasm/core/Error.h"
#include "rasm/core/Params.h"

namespace rasm::sim {

void applyParamOverrides(mrpt::config::CLoadableOptions& params, const std::string& section,
                         const std::map<std::string, std::string>& kv, const std::string& source) {
  if (kv.empty()) return;
  mrpt::config::CConfigFileMemory mem;
  params.saveToConfigFile(mem, section);  // start from the current values
  for (const auto& [k, v] : kv) mem.write(section, k, v);
  loadParamsStrict(mem, section, params, source);
}

namespace {
long long framesIn(double duration_s, double rate_hz) {
  return (long long)(std::floor(duration_s * rate_hz + 1e-9)) + 1;  // both ends included
}
}  // namespace

SimulatedSequence::SimulatedSequence(const World& world, const TrajectorySpec& spec,
                                     const SequenceOptions& opt)
    : m_spec(spec), m_seed(opt.seed) {
  if (opt.rate_hz < 0.0 || !std::isfinite(opt.rate_hz))
    throwInputError("sequence rate_hz", "must be >= 0 (0: the spec's rate)");
  m_rate_hz = opt.rate_hz > 0.0 ? opt.rate_hz : spec.rate_hz;
  applyParamOverrides(m_sensor_params, "sim_sensor", spec.sensor_overrides,
                      spec.source + " sensor:");
  applyParamOverrides(m_sensor_params, "sim_sensor", opt.sensor_overrides, "sensor overrides");
  if (opt.intrinsics) {
    const CameraIntrinsics& K = *opt.intrinsics;
    m_sensor_params.width = K.width;
    m_sensor_params.height = K.height;
    m_sensor_params.fx = K.fx;
    m_sensor_params.fy = K.fy;
    m_sensor_params.cx = K.cx;
    m_sensor_params.cy = K.cy;
  }
  TRobotParams rp;
  applyParamOverrides(rp, "sim_robot", spec.robot_overrides, spec.source + " robot:");
  applyParamOverrides(rp, "sim_robot", opt.robot_overrides, "robot overrides");

  m_scene = std::make_unique<RayScene>(world);
  m_sensor = std::make_unique<RgbdSensor>(*m_scene, m_sensor_params);
  if (spec.kind == TrajectorySpec::Kind::Handheld) {
    m_hand = std::make_unique<HandheldTrajectory>(spec.keyframes, spec.jitter, opt.seed);
    m_planned =
        framesIn(spec.duration_s.value_or(m_hand->endTime() - m_hand->startTime()), m_rate_hz);
  } else {
    m_robot = std::make_unique<SimulatedDiffDriveRobot>(*m_scene, rp, spec.start_pose, opt.seed);
    if (!opt.commanded) {
      std::vector<Eigen::Vector2d> path{spec.start_pose.head<2>()};
      path.insert(path.end(), spec.waypoints.begin(), spec.waypoints.end());
      m_pursuit = std::make_unique<PurePursuit>(path, spec.controller, spec.loop, spec.laps);
    }
    if (spec.duration_s) m_planned = framesIn(*spec.duration_s, m_rate_hz);
  }
  if (opt.max_frames >= 0 && (m_planned < 0 || opt.max_frames < m_planned))
    m_planned = opt.max_frames;
  m_limit = m_planned >= 0 ? m_planned : framesIn(spec.max_duration_s, m_rate_hz);
}

SimulatedSequence::~SimulatedSequence() = default;

double SimulatedSequence::progress() const {
  if (m_planned > 0) return std::min(1.0, double(m_next) / double(m_planned));
  if (m_pursuit) return m_pursuit->progress() / m_pursuit->totalLength();
  return double(m_next) / double(std::max<long long>(1, m_limit));
}

bool SimulatedSequence::next(RgbdFrame& frame) {
  if (m_done || m_next >= m_limit) return false;
  const double dt = 1.0 / m_rate_hz;
  const double t = double(m_next) * dt;
  const Eigen::Isometry3d T =
      m_hand ? m_hand->pose(m_hand->startTime() + t) : m_robot->cameraPose();
  m_sensor->render(T, m_seed, std::size_t(m_next), frame);
  frame.timestamp_s = t;
  frame.index = std::size_t(m_next);
  if (m_robot)
    frame.odometry_xyyaw = m_robot->odometry();
  else
    frame.odometry_xyyaw.reset();
  ++m_next;

  // Drive the robot to the pose of the next frame: pure pursuit at control_substeps x rate.
  if (m_robot && !m_pursuit) {  // commanded: the hook sets the commands
    const int sub = m_spec.control_substeps;
    for (int k = 0; k < sub; ++k) {
      m_robot->step(dt / sub);
      if (m_substep_hook) m_substep_hook();
    }
    return true;
  }
  if (m_robot) {
    if (m_pursuit->done()) {
      m_done = true;  // this frame, at the goal, was the last one
      return true;
    }
    const int sub = m_spec.control_substeps;
    for (int k = 0; k < sub; ++k) {
      const Eigen::Vector2d cmd = m_pursuit->command(m_robot->pose());
      m_robot->setVelocityCommand(cmd.x(), cmd.y());
      m_robot->step(dt / sub);
      m_stuck_s = m_robot->collided() ? m_stuck_s + dt / sub : 0.0;
    }
    if (m_stuck_s >= 1.0) {
      m_stuck = m_done = true;
      std::fprintf(
          stderr,
          "sim: warning: the robot has been stuck against an obstacle for 1 s at (%.2f, %.2f); "
          "ending the sequence after frame %lld (check the waypoints of %s)\n",
          m_robot->pose().x(), m_robot->pose().y(), m_next - 1, m_spec.source.c_str());
    }
  }
  return true;
}

}  // namespace rasm::sim
