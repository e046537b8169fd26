#pragma once
// The Segway RMP 220 / 440 as a rasm robot ([robot] type = segway_rmp, section [segway_rmp]):
// velocity commands, wheel odometry and status over the RMP's UDP interface (RmpProtocol.h),
// behind the interface the simulated robot implements (IRobot), so MRPT's reactive navigator and
// the tracker's odometry prior use it as they use the simulator's.
//
//  - Connecting (constructor): with configure_rmp, the user feedback bitmaps rasm reads
//    (rmp::FeedbackLayout), the RMP's maximum velocity and yaw rate (the normalisation of motion
//    commands) and tractor mode are sent; then the RMP must answer a no-op command with feedback
//    in that layout within connect_timeout_s, or the constructor throws InputError naming
//    host:port and what was expected (no hang when nothing answers).
//  - Commands: a thread sends the current velocity command at command_rate_hz (the RMP expects a
//    steady stream) and reads the responses. Commands are clamped to max_v_mps / max_w_degps.
//  - Watchdog: a command older than watchdog_timeout_s is replaced by zero velocity (counted:
//    status().watchdog_stops) until the next setVelocityCommand.
//  - Link: no valid response for response_timeout_s marks the link lost (status().link_ok);
//    step() then throws RobotLinkError, and zero velocity keeps being sent.
//  - Shutdown (destructor or shutdown()): zero velocity, then a standby request (configure_rmp).
//  - Odometry: integrated from the left / right front wheel positions (m travelled) and
//    track_width_m; it starts at (0, 0, 0). pose() is the odometry (a real robot has no ground
//    truth). Timestamps: this computer's clock at reception (UNIX seconds), so odometryAt()
//    pairs camera frames (stamped by the same clock) with the odometry of their time.
//  - No obstacle sensing of its own: senseObstacles() returns nothing (a base without a laser).
//    An exploring run wraps it in a DepthScanRobot (DepthObstacleScan.h): a virtual scan from the
//    camera's depth in the height band obstacle_min_z_m .. obstacle_max_z_m. collided() is
//    always false.
//  - Time: wall clock (wallClock() is true); step(dt) waits dt.

#include <mrpt/config/CLoadableOptions.h>

#include <Eigen/Geometry>
#include <atomic>
#include <chrono>
#include <deque>
#include <memory>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "rasm/robot/DepthObstacleScan.h"
#include "rasm/robot/IRobot.h"
#include "rasm/robot/RmpProtocol.h"

namespace rasm::robot {

class UdpSocket;

/// [segway_rmp]: where the RMP is and how it is driven.
struct TSegwayRmpParams : mrpt::config::CLoadableOptions {
  std::string host = "192.168.0.40";  ///< the RMP's IP address (its factory default)
  int port = 8080;                    ///< the RMP's UDP port (its factory default)
  int local_port = 0;                 ///< this computer's UDP port (0: any free one)
  double connect_timeout_s = 2.0;     ///< the first valid response must arrive within this
  double response_timeout_s = 0.5;    ///< longer without a valid response: link lost
  double command_rate_hz = 50.0;      ///< commands sent per second (the RMP accepts <= 100)
  double watchdog_timeout_s = 0.3;    ///< a velocity command older than this is replaced by 0
  double max_v_mps = 0.5;             ///< rasm's clamp of velocity commands
  double max_w_degps = 60.0;          ///< rasm's clamp of yaw-rate commands
  /// The RMP's own limits, which motion commands are normalised by (written to the RMP at
  /// connection when configure_rmp; otherwise they must equal its stored values).
  double rmp_max_velocity_mps = 2.2;
  double rmp_max_yaw_rate_radps = 3.0;
  /// Lateral distance between the wheels (m), for the odometry's heading: must equal the RMP's
  /// fram_wheel_track_width_m (0.7112 m: the x2 default of Segway's reference code; measure it).
  double track_width_m = 0.7112;
  /// At connection: set the feedback bitmaps and the limits above and request tractor mode; on
  /// shutdown request standby. false: the RMP is configured already (bitmaps as
  /// rmp::FeedbackLayout) and only motion commands are sent.
  bool configure_rmp = true;
  /// The base's footprint for the navigator: a rectangle centred on the rotation centre (m).
  double footprint_length_m = 0.65;
  double footprint_width_m = 0.78;
  /// The virtual obstacle scan from the depth camera (DepthObstacleScan.h): heights above the
  /// floor that are obstacles (the floor and what the base passes under are not), and its range.
  double obstacle_min_z_m = 0.05;
  double obstacle_max_z_m = 1.2;
  double obstacle_max_range_m = 4.0;

  /// The footprint polygon (robot frame, counter-clockwise).
  std::vector<Eigen::Vector2f> footprintPolygon() const;
  /// The depth scan's parameters from the obstacle_* keys.
  TDepthScanParams depthScanParams() const;

  void loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s) override;
  void saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const override;
};

/// The robot stopped answering while it was driven.
class RobotLinkError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class SegwayRmpRobot : public IRobot {
 public:
  struct Status {
    bool link_ok = false;
    std::size_t commands_sent = 0, responses = 0, bad_responses = 0;
    std::size_t watchdog_stops = 0;  ///< times the watchdog replaced a stale command by zero
    std::uint32_t operational_state = 0;
    std::array<std::uint32_t, 4> fault_status{};
    float battery_soc_pct = 0.0f;
    std::string last_error;  ///< the last bad response's reason
  };

  /// Connects (see above); `T_base_cam` is the camera mount ([robot] camera_*).
  SegwayRmpRobot(const TSegwayRmpParams& params, const Eigen::Isometry3d& T_base_cam);
  ~SegwayRmpRobot() override;
  /// Stops the robot and the command thread (zero velocity, standby); idempotent.
  void shutdown();

  void setVelocityCommand(double v_mps, double w_radps) override;
  /// Waits dt_s of wall time; throws RobotLinkError when the link is lost.
  void step(double dt_s) override;
  double time_s() const override;
  Eigen::Vector3d pose() const override { return odometry(); }
  Eigen::Vector2d velocity() const override;
  Eigen::Vector3d odometry() const override;
  void senseObstacles(std::vector<Eigen::Vector3f>& points_robot) const override {
    points_robot.clear();
  }
  bool collided() const override { return false; }
  Eigen::Isometry3d cameraPose() const override;
  bool wallClock() const override { return true; }

  Status status() const;
  /// The odometry at UNIX time `t_s`, interpolated between the responses around it (the oldest
  /// or newest kept when outside; about the last 10 s are kept); nullopt before any response.
  std::optional<Eigen::Vector3d> odometryAt(double t_s) const;
  /// "segway_rmp 192.168.0.40:8080" for messages.
  std::string describe() const;

 private:
  void connect();
  void ioLoop();
  /// Reads responses for up to `wait_s`; true when a valid one arrived.
  bool readResponses(double wait_s);
  void applyFeedback(const rmp::Feedback& fb, double t_unix);
  void send(const rmp::CommandPacket& p);

  TSegwayRmpParams m_params;
  Eigen::Isometry3d m_T_base_cam;
  rmp::FeedbackLayout m_layout;
  std::unique_ptr<UdpSocket> m_socket;
  std::chrono::steady_clock::time_point m_t0;

  mutable std::mutex m_mx;
  double m_cmd_v = 0, m_cmd_w = 0;
  std::chrono::steady_clock::time_point m_cmd_time;
  bool m_cmd_stale = true;  ///< the watchdog has zeroed the current command
  std::chrono::steady_clock::time_point m_last_response;
  Status m_status;
  Eigen::Vector3d m_odo = Eigen::Vector3d::Zero();
  Eigen::Vector2d m_vel = Eigen::Vector2d::Zero();
  std::optional<std::pair<float, float>> m_wheels;           ///< last (left, right) positions
  std::deque<std::pair<double, Eigen::Vector3d>> m_history;  ///< (UNIX s, odometry)

  std::atomic<bool> m_quit{false};
  bool m_shut_down = false;
  std::thread m_thread;
};

}  // namespace rasm::robot
