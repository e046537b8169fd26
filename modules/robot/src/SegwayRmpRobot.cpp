#include "rasm/robot/SegwayRmpRobot.h"
#include "rasm/core/Angles.h"
#include "rasm/core/Log.h"

#include <mrpt/config/CConfigFileBase.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "rasm/core/Error.h"
#include "rasm/core/Params.h"
#include "rasm/robot/UdpSocket.h"

namespace rasm::robot {

using Clock = std::chrono::steady_clock;

namespace {
double secondsSince(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}
double unixNow() {
  return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
}
double wrapAngle(double a) {
  return std::atan2(std::sin(a), std::cos(a));
}
/// Sleeps out the rest of a slot of `slot_s` that began at `start` (a refused datagram on
/// loopback returns from receive at once: without this a dead server would be polled flat out).
void sleepRest(Clock::time_point start, double slot_s) {
  const double rest = slot_s - secondsSince(start);
  if (rest > 0) std::this_thread::sleep_for(std::chrono::duration<double>(rest));
}
constexpr std::size_t kHistory = 1024;  ///< odometry samples kept for odometryAt (~10 s at 100 Hz)
}  // namespace

void TSegwayRmpParams::loadFromConfigFile(const mrpt::config::CConfigFileBase& c,
                                          const std::string& s) {
  MRPT_LOAD_CONFIG_VAR(host, string, c, s);
  MRPT_LOAD_CONFIG_VAR(port, int, c, s);
  MRPT_LOAD_CONFIG_VAR(local_port, int, c, s);
  MRPT_LOAD_CONFIG_VAR(connect_timeout_s, double, c, s);
  MRPT_LOAD_CONFIG_VAR(response_timeout_s, double, c, s);
  MRPT_LOAD_CONFIG_VAR(command_rate_hz, double, c, s);
  MRPT_LOAD_CONFIG_VAR(watchdog_timeout_s, double, c, s);
  MRPT_LOAD_CONFIG_VAR(max_v_mps, double, c, s);
  MRPT_LOAD_CONFIG_VAR(max_w_degps, double, c, s);
  MRPT_LOAD_CONFIG_VAR(rmp_max_velocity_mps, double, c, s);
  MRPT_LOAD_CONFIG_VAR(rmp_max_yaw_rate_radps, double, c, s);
  MRPT_LOAD_CONFIG_VAR(track_width_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(configure_rmp, bool, c, s);
  MRPT_LOAD_CONFIG_VAR(footprint_length_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(footprint_width_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(obstacle_min_z_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(obstacle_max_z_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(obstacle_max_range_m, double, c, s);
  if (host.empty()) throwInputError("[" + s + "] host", "empty (expected the RMP's IP address)");
  requireInRange(port, 1, 65535, s, "port");
  requireInRange(local_port, 0, 65535, s, "local_port");
  requireInRange(connect_timeout_s, 0.01, 60, s, "connect_timeout_s");
  requireInRange(response_timeout_s, 0.01, 10, s, "response_timeout_s");
  requireInRange(command_rate_hz, 1, 100, s, "command_rate_hz");
  requireInRange(watchdog_timeout_s, 0.01, 10, s, "watchdog_timeout_s");
  // The RMP's own ranges (Segway's reference code): velocity <= 8.047 m/s, yaw rate <= 4.5 rad/s.
  requireInRange(rmp_max_velocity_mps, 0.01, 8.047, s, "rmp_max_velocity_mps");
  requireInRange(rmp_max_yaw_rate_radps, 0.01, 4.5, s, "rmp_max_yaw_rate_radps");
  requireInRange(max_v_mps, 0, rmp_max_velocity_mps, s, "max_v_mps");
  requireInRange(max_w_degps, 0, rmp_max_yaw_rate_radps / kRadPerDeg, s, "max_w_degps");
  requireInRange(track_width_m, 0.2, 2.0, s, "track_width_m");
  requireInRange(footprint_length_m, 0.1, 3.0, s, "footprint_length_m");
  requireInRange(footprint_width_m, 0.1, 3.0, s, "footprint_width_m");
  requireInRange(obstacle_min_z_m, 0.0, 3.0, s, "obstacle_min_z_m");
  requireInRange(obstacle_max_z_m, obstacle_min_z_m, 5.0, s, "obstacle_max_z_m");
  requireInRange(obstacle_max_range_m, 0.1, 20.0, s, "obstacle_max_range_m");
}

std::vector<Eigen::Vector2f> TSegwayRmpParams::footprintPolygon() const {
  const float x = float(0.5 * footprint_length_m), y = float(0.5 * footprint_width_m);
  return {{x, y}, {-x, y}, {-x, -y}, {x, -y}};
}

TDepthScanParams TSegwayRmpParams::depthScanParams() const {
  TDepthScanParams p;
  p.min_z_m = float(obstacle_min_z_m);
  p.max_z_m = float(obstacle_max_z_m);
  p.max_range_m = float(obstacle_max_range_m);
  return p;
}

void TSegwayRmpParams::saveToConfigFile(mrpt::config::CConfigFileBase& c,
                                        const std::string& s) const {
  MRPT_SAVE_CONFIG_VAR(host, c, s);
  MRPT_SAVE_CONFIG_VAR(port, c, s);
  MRPT_SAVE_CONFIG_VAR(local_port, c, s);
  MRPT_SAVE_CONFIG_VAR(connect_timeout_s, c, s);
  MRPT_SAVE_CONFIG_VAR(response_timeout_s, c, s);
  MRPT_SAVE_CONFIG_VAR(command_rate_hz, c, s);
  MRPT_SAVE_CONFIG_VAR(watchdog_timeout_s, c, s);
  MRPT_SAVE_CONFIG_VAR(max_v_mps, c, s);
  MRPT_SAVE_CONFIG_VAR(max_w_degps, c, s);
  MRPT_SAVE_CONFIG_VAR(rmp_max_velocity_mps, c, s);
  MRPT_SAVE_CONFIG_VAR(rmp_max_yaw_rate_radps, c, s);
  MRPT_SAVE_CONFIG_VAR(track_width_m, c, s);
  MRPT_SAVE_CONFIG_VAR(configure_rmp, c, s);
  MRPT_SAVE_CONFIG_VAR(footprint_length_m, c, s);
  MRPT_SAVE_CONFIG_VAR(footprint_width_m, c, s);
  MRPT_SAVE_CONFIG_VAR(obstacle_min_z_m, c, s);
  MRPT_SAVE_CONFIG_VAR(obstacle_max_z_m, c, s);
  MRPT_SAVE_CONFIG_VAR(obstacle_max_range_m, c, s);
}

// ---------------------------------------------------------------------------------------------
SegwayRmpRobot::SegwayRmpRobot(const TSegwayRmpParams& params, const Eigen::Isometry3d& T_base_cam)
    : m_params(params), m_T_base_cam(T_base_cam), m_t0(Clock::now()) {
  try {
    m_socket = std::make_unique<UdpSocket>("0.0.0.0", m_params.local_port);
  } catch (const std::exception& e) {
    throwInputError("[segway_rmp] local_port = " + std::to_string(m_params.local_port), e.what());
  }
  connect();
  m_cmd_time = Clock::now();
  m_thread = std::thread([this] { ioLoop(); });
}

SegwayRmpRobot::~SegwayRmpRobot() {
  try {
    shutdown();
  } catch (const std::exception& e) {
    log::error(describe() + ": shutdown: " + e.what());
  }
}

std::string SegwayRmpRobot::describe() const {
  return "segway_rmp " + m_params.host + ":" + std::to_string(m_params.port);
}

void SegwayRmpRobot::send(const rmp::CommandPacket& p) {
  m_socket->sendTo(m_params.host, m_params.port, p.data(), p.size());
  std::lock_guard<std::mutex> lock(m_mx);
  ++m_status.commands_sent;
}

/// Configuration, then a no-op command until feedback in the configured layout arrives.
void SegwayRmpRobot::connect() {
  using rmp::ConfigCommand;
  const std::string what =
      "[segway_rmp] host = " + m_params.host + ", port = " + std::to_string(m_params.port);
  const auto deadline = Clock::now() + std::chrono::duration<double>(m_params.connect_timeout_s);
  auto left = [&] { return std::chrono::duration<double>(deadline - Clock::now()).count(); };
  std::vector<rmp::CommandPacket> setup;
  if (m_params.configure_rmp) {
    setup = {
        rmp::encodeConfig(ConfigCommand::SetUserFeedback1, m_layout.bitmap1),
        rmp::encodeConfig(ConfigCommand::SetUserFeedback2, m_layout.bitmap2),
        rmp::encodeConfig(ConfigCommand::SetUserFeedback3, m_layout.bitmap3),
        rmp::encodeConfig(ConfigCommand::SetMaxVelocity, float(m_params.rmp_max_velocity_mps)),
        rmp::encodeConfig(ConfigCommand::SetMaxTurnRate, float(m_params.rmp_max_yaw_rate_radps)),
        rmp::encodeConfig(ConfigCommand::SetOperationalMode,
                          std::uint32_t(rmp::ModeRequest::Tractor))};
  }
  bool answered = false;
  std::vector<std::uint8_t> buf;
  try {
    // Each configuration command is answered (in whatever layout was in force); resend a
    // command that got no answer until the deadline.
    for (const auto& p : setup) {
      bool ok = false;
      while (!ok && left() > 0) {
        const auto t = Clock::now();
        send(p);
        ok = m_socket->receive(buf, std::min(0.1, std::max(0.0, left())));
        if (!ok) sleepRest(t, std::min(0.1, std::max(0.0, left())));
      }
      answered = answered || ok;
      if (!ok) break;
    }
    while (left() > 0) {
      const auto t = Clock::now();
      const double slot = std::min(0.1, std::max(0.0, left()));
      send(rmp::encodeConfig(ConfigCommand::None, std::uint32_t(0)));
      if (readResponses(slot)) {
        m_last_response = Clock::now();
        m_status.link_ok = true;
        return;
      }
      answered = answered || m_status.bad_responses > 0;
      sleepRest(t, slot);
    }
  } catch (const std::exception& e) {
    throwInputError(what, e.what());
  }
  if (answered)
    throwInputError(what, "the RMP answered but not with feedback in the layout rasm configures (" +
                              m_status.last_error +
                              "; docs/hardware.md lists the feedback bitmaps expected)");
  char timeout[32];
  std::snprintf(timeout, sizeof timeout, "%.2g", m_params.connect_timeout_s);
  throwInputError(what, std::string("no response from the Segway RMP within ") + timeout +
                            " s (connect_timeout_s; expected its UDP feedback to a command: is "
                            "it powered on, is its Ethernet link up, and is this computer on its "
                            "subnet?)");
}

bool SegwayRmpRobot::readResponses(double wait_s) {
  std::vector<std::uint8_t> buf;
  bool any = false;
  const auto until = Clock::now() + std::chrono::duration<double>(wait_s);
  double left = wait_s;
  while (m_socket->receive(buf, std::max(0.0, left))) {
    rmp::Feedback fb;
    std::string why;
    if (rmp::decodeFeedback(buf.data(), buf.size(), m_layout, fb, why)) {
      applyFeedback(fb, unixNow());
      any = true;
    } else {
      std::lock_guard<std::mutex> lock(m_mx);
      ++m_status.bad_responses;
      m_status.last_error = why;
    }
    left = std::chrono::duration<double>(until - Clock::now()).count();
    if (left <= 0) break;
  }
  return any;
}

void SegwayRmpRobot::applyFeedback(const rmp::Feedback& fb, double t_unix) {
  std::lock_guard<std::mutex> lock(m_mx);
  ++m_status.responses;
  m_status.operational_state = fb.operational_state;
  m_status.fault_status = fb.fault_status;
  m_status.battery_soc_pct = fb.battery_soc_pct;
  m_status.link_ok = true;
  m_last_response = Clock::now();
  m_vel = {fb.linear_vel_mps, fb.yaw_rate_rps};
  // Wheel odometry: the arc of this increment (ds along the mean heading, dth turned).
  if (m_wheels) {
    const double dl = double(fb.left_wheel_m) - double(m_wheels->first);
    const double dr = double(fb.right_wheel_m) - double(m_wheels->second);
    const double ds = 0.5 * (dl + dr), dth = (dr - dl) / m_params.track_width_m;
    const double mid = m_odo.z() + 0.5 * dth;
    m_odo.x() += ds * std::cos(mid);
    m_odo.y() += ds * std::sin(mid);
    m_odo.z() = wrapAngle(m_odo.z() + dth);
  }
  m_wheels = std::make_pair(fb.left_wheel_m, fb.right_wheel_m);
  m_history.emplace_back(t_unix, m_odo);
  while (m_history.size() > kHistory) m_history.pop_front();
}

void SegwayRmpRobot::ioLoop() {
  const double period = 1.0 / m_params.command_rate_hz;
  while (!m_quit) {
    const auto t = Clock::now();
    float v = 0, w = 0;
    {
      std::lock_guard<std::mutex> lock(m_mx);
      if (!m_cmd_stale && secondsSince(m_cmd_time) > m_params.watchdog_timeout_s) {
        m_cmd_stale = true;
        if (m_cmd_v != 0.0 || m_cmd_w != 0.0) ++m_status.watchdog_stops;
      }
      if (!m_cmd_stale && m_status.link_ok) {
        v = float(m_cmd_v / m_params.rmp_max_velocity_mps);
        w = float(m_cmd_w / m_params.rmp_max_yaw_rate_radps);
      }
    }
    try {
      send(rmp::encodeMotion(v, w));
      readResponses(std::max(0.0, period - secondsSince(t)));
    } catch (const std::exception& e) {
      std::lock_guard<std::mutex> lock(m_mx);
      m_status.last_error = e.what();
    }
    {
      std::lock_guard<std::mutex> lock(m_mx);
      if (secondsSince(m_last_response) > m_params.response_timeout_s) m_status.link_ok = false;
    }
    sleepRest(t, period);
  }
}

void SegwayRmpRobot::shutdown() {
  if (m_shut_down) return;
  m_shut_down = true;
  m_quit = true;
  if (m_thread.joinable()) m_thread.join();
  // Zero velocity a few times (UDP may drop one), then standby.
  for (int i = 0; i < 3; ++i) send(rmp::encodeMotion(0.0f, 0.0f));
  if (m_params.configure_rmp)
    send(rmp::encodeConfig(rmp::ConfigCommand::SetOperationalMode,
                           std::uint32_t(rmp::ModeRequest::Standby)));
}

void SegwayRmpRobot::setVelocityCommand(double v_mps, double w_radps) {
  const double max_w = m_params.max_w_degps * kRadPerDeg;
  std::lock_guard<std::mutex> lock(m_mx);
  m_cmd_v = std::isfinite(v_mps) ? std::clamp(v_mps, -m_params.max_v_mps, m_params.max_v_mps) : 0;
  m_cmd_w = std::isfinite(w_radps) ? std::clamp(w_radps, -max_w, max_w) : 0;
  m_cmd_time = Clock::now();
  m_cmd_stale = false;
}

void SegwayRmpRobot::step(double dt_s) {
  if (dt_s > 0) std::this_thread::sleep_for(std::chrono::duration<double>(dt_s));
  std::lock_guard<std::mutex> lock(m_mx);
  if (!m_status.link_ok) {
    char buf[160];
    std::snprintf(buf, sizeof buf, "%s: no valid response for %.2f s (response_timeout_s %.2g)",
                  describe().c_str(), secondsSince(m_last_response), m_params.response_timeout_s);
    throw RobotLinkError(buf + (m_status.last_error.empty() ? "" : "; " + m_status.last_error));
  }
}

double SegwayRmpRobot::time_s() const {
  return secondsSince(m_t0);
}

Eigen::Vector2d SegwayRmpRobot::velocity() const {
  std::lock_guard<std::mutex> lock(m_mx);
  return m_vel;
}

Eigen::Vector3d SegwayRmpRobot::odometry() const {
  std::lock_guard<std::mutex> lock(m_mx);
  return m_odo;
}

Eigen::Isometry3d SegwayRmpRobot::cameraPose() const {
  const Eigen::Vector3d o = odometry();
  Eigen::Isometry3d T_world_base = Eigen::Isometry3d::Identity();
  T_world_base.translation() = Eigen::Vector3d(o.x(), o.y(), 0.0);
  T_world_base.linear() = Eigen::AngleAxisd(o.z(), Eigen::Vector3d::UnitZ()).toRotationMatrix();
  return T_world_base * m_T_base_cam;
}

SegwayRmpRobot::Status SegwayRmpRobot::status() const {
  std::lock_guard<std::mutex> lock(m_mx);
  return m_status;
}

std::optional<Eigen::Vector3d> SegwayRmpRobot::odometryAt(double t_s) const {
  std::lock_guard<std::mutex> lock(m_mx);
  if (m_history.empty()) return std::nullopt;
  if (t_s <= m_history.front().first) return m_history.front().second;
  if (t_s >= m_history.back().first) return m_history.back().second;
  const auto hi = std::lower_bound(m_history.begin(), m_history.end(), t_s,
                                   [](const auto& e, double t) { return e.first < t; });
  const auto lo = hi - 1;
  const double span = hi->first - lo->first;
  const double a = span > 0 ? (t_s - lo->first) / span : 1.0;
  Eigen::Vector3d p = lo->second + a * (hi->second - lo->second);
  p.z() = wrapAngle(lo->second.z() + a * wrapAngle(hi->second.z() - lo->second.z()));
  return p;
}

}  // namespace rasm::robot
