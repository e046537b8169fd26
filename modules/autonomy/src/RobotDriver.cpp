#include "rasm/autonomy/RobotDriver.h"
#include "rasm/core/Log.h"

#include <chrono>
#include <cstdio>

namespace rasm::autonomy {

WallClockRobotDriver::WallClockRobotDriver(robot::IRobot& robot, double period_s)
    : m_robot(robot), m_period_s(period_s) {}

WallClockRobotDriver::~WallClockRobotDriver() {
  stop();
}

void WallClockRobotDriver::enableDepthScan(const Eigen::Isometry3d& T_base_cam,
                                           const robot::TDepthScanParams& p) {
  m_scan_robot = std::make_unique<robot::DepthScanRobot>(m_robot, T_base_cam, p);
}

robot::IRobot& WallClockRobotDriver::robot() {
  return m_scan_robot ? *m_scan_robot : m_robot;
}

void WallClockRobotDriver::start(std::function<void()> navigation_step) {
  m_step = std::move(navigation_step);
  m_quit = false;
  m_thread = std::thread([this] { run(); });
}

void WallClockRobotDriver::stop() {
  m_quit = true;
  if (m_thread.joinable()) m_thread.join();
}

/// The navigation thread (VI): the robot advances by one period of wall time, then the navigator
/// steps on the pose and obstacles of now. Ends at stop() or when the robot fails.
void WallClockRobotDriver::run() {
  const auto t0 = std::chrono::steady_clock::now();
  while (!m_quit) {
    try {
      m_robot.step(m_period_s);  // a real robot waits the period and checks its link
      if (m_quit) break;
      m_step();
      ++m_steps;
    } catch (const std::exception& e) {
      {
        std::lock_guard<std::mutex> lock(m_mx);
        m_error = e.what();
      }
      try {
        m_robot.stop();
      } catch (const std::exception& e2) {
        log::error(std::string("navigation thread: stopping the robot: ") + e2.what());
      }
      break;
    }
    m_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }
}

void WallClockRobotDriver::frameArrived(const RgbdFrame& frame) {
  if (m_scan_robot)
    m_scan_robot->offerDepthFrame(frame, frame.odometry_xyyaw.value_or(m_robot.odometry()));
}

std::string WallClockRobotDriver::error() const {
  std::lock_guard<std::mutex> lock(m_mx);
  return m_error;
}

double WallClockRobotDriver::seconds() const {
  return m_seconds;
}

}  // namespace rasm::autonomy
