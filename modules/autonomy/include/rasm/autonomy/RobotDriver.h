#pragma once
// How the exploration loop's navigator is stepped (paper VI: "navigation stepping at its own
// rate"), the one place where a simulated and a real robot differ for the loop:
//   substeps      (ExplorationLoop.cpp, SimulatedRobotDriver) the simulated sequence steps its
//                 robot control_substeps times between two frames and the navigator after each
//                 step, on the mapping thread at simulated times: a seed gives one run;
//   wall clock    (WallClockRobotDriver) a thread of its own steps the robot by period_s of wall
//                 time (IRobot::step waits it out on a real robot) and then the navigator, while
//                 frames arrive from a live camera at their own rate.
// The owner serialises the navigator's calls: the step function it passes to start() and its own
// calls into the navigator take one mutex (the Navigator is not thread-safe).

#include <Eigen/Geometry>
#include <atomic>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>

#include "rasm/core/RgbdFrame.h"
#include "rasm/robot/DepthObstacleScan.h"
#include "rasm/robot/IRobot.h"

namespace rasm::autonomy {

class RobotDriver {
 public:
  virtual ~RobotDriver() = default;
  /// The robot the navigator drives.
  virtual robot::IRobot& robot() = 0;
  /// Starts calling `navigation_step` after every robot step.
  virtual void start(std::function<void()> navigation_step) = 0;
  /// Stops calling it (the thread, if any, has ended when this returns); idempotent.
  virtual void stop() = 0;
  /// Every frame the mapper processed, on the mapping thread (a depth obstacle scan).
  virtual void frameArrived(const RgbdFrame& /*frame*/) {}
  /// After the exploration stopped: ends the frames where the driver owns them (the simulated
  /// sequence); a live source's frame loop checks ExplorationLoop::finished() instead.
  virtual void endFrames() {}
  /// What ended the stepping early (the robot's link lost), empty while it runs or ran fine.
  virtual std::string error() const { return {}; }
  /// "substeps" or "thread" (report.json exploration.navigation).
  virtual const char* stepping() const = 0;
  /// Navigation steps run so far (wall-clock driver; 0 for substeps: the navigator counts).
  virtual std::size_t steps() const { return 0; }
  /// Wall seconds the stepping ran (wall-clock driver).
  virtual double seconds() const { return 0.0; }
};

/// A robot on the wall clock (the Segway; a simulated robot stepped in real time in tests): a
/// thread steps it by period_s ([navigation] period_s) and then calls the navigation step. When
/// the robot's step() throws (robot::RobotLinkError: the base stopped answering), the thread
/// commands zero velocity, ends and error() says why; the loop then ends the run.
class WallClockRobotDriver : public RobotDriver {
 public:
  WallClockRobotDriver(robot::IRobot& robot, double period_s);
  ~WallClockRobotDriver() override;

  /// Obstacles from the camera's depth (a robot without a laser): the navigator then drives a
  /// DepthScanRobot over `robot`, fed the frames of frameArrived(). Before start().
  void enableDepthScan(const Eigen::Isometry3d& T_base_cam, const robot::TDepthScanParams& p);

  robot::IRobot& robot() override;
  void start(std::function<void()> navigation_step) override;
  void stop() override;
  void frameArrived(const RgbdFrame& frame) override;
  std::string error() const override;
  const char* stepping() const override { return "thread"; }
  std::size_t steps() const override { return m_steps; }
  double seconds() const override;

 private:
  void run();

  robot::IRobot& m_robot;
  double m_period_s;
  std::unique_ptr<robot::DepthScanRobot> m_scan_robot;
  std::function<void()> m_step;
  std::thread m_thread;
  std::atomic<bool> m_quit{false};
  std::atomic<std::size_t> m_steps{0};
  std::atomic<double> m_seconds{0.0};
  mutable std::mutex m_mx;
  std::string m_error;
};

}  // namespace rasm::autonomy
