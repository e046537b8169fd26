#include "rasm/navigation/Navigator.h"
#include "rasm/core/Angles.h"

#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/core/Clock.h>
#include <mrpt/math/wrap2pi.h>
#include <mrpt/nav/reactive/CReactiveNavigationSystem.h>
#include <mrpt/nav/reactive/TWaypoint.h>

#include <algorithm>
#include <cmath>
#include <deque>
#include <filesystem>
#include <functional>
#include <limits>

#include "ReactiveConfig.h"
#include "RobotNavInterface.h"
#include "rasm/core/Error.h"

namespace rasm::navigation {

namespace {

// Simulated-clock epoch: robot time 0 maps to this (a zero timestamp is MRPT's INVALID_TIMESTAMP).
constexpr double kEpoch_s = 1.0e9;

/// MRPT's navigator reads mrpt::Clock::now(): while alive, the process clock is the simulated one
/// at the robot's time; the previous source is restored on exit (IRobot.h, MRPT-NOTES: with the
/// real clock the navigator's waits never complete in simulation). A wall-clock robot (a real
/// one, IRobot::wallClock()) keeps the real clock: its time is wall time, and other threads (a
/// camera's) stamp their data with that clock meanwhile.
class SimulatedClockScope {
 public:
  explicit SimulatedClockScope(const robot::IRobot& robot)
      : m_active(!robot.wallClock()), m_prev(mrpt::Clock::getActiveClock()) {
    if (!m_active) return;
    mrpt::Clock::setActiveClock(mrpt::Clock::Simulated);
    mrpt::Clock::setSimulatedTime(mrpt::Clock::fromDouble(kEpoch_s + robot.time_s()));
  }
  ~SimulatedClockScope() {
    if (m_active) mrpt::Clock::setActiveClock(m_prev);
  }
  SimulatedClockScope(const SimulatedClockScope&) = delete;
  SimulatedClockScope& operator=(const SimulatedClockScope&) = delete;

 private:
  bool m_active;
  mrpt::Clock::Source m_prev;
};

}  // namespace

const char* toString(NavState s) {
  switch (s) {
    case NavState::Idle:
      return "idle";
    case NavState::Navigating:
      return "navigating";
    case NavState::Aligning:
      return "aligning";
    case NavState::Reached:
      return "reached";
    case NavState::Failed:
      return "failed";
  }
  return "?";
}

struct Navigator::Impl {
  Impl(robot::IRobot& r, const TNavigationParams& p, const std::vector<Eigen::Vector2f>& fp,
       std::function<Eigen::Vector3d()> loc)
      : robot(r),
        params(p),
        footprint(fp),
        localisation(loc),
        iface(r, std::move(loc)),
        nav(iface, /*enableConsoleOutput=*/false, /*enableLogFile=*/false) {}

  robot::IRobot& robot;
  TNavigationParams params;
  std::vector<Eigen::Vector2f> footprint;
  std::function<Eigen::Vector3d()> localisation;
  RobotNavInterface iface;
  mrpt::nav::CReactiveNavigationSystem nav;
  float radius_m = 0.f;  ///< largest footprint vertex distance (plus margin)

  NavState state = NavState::Idle;
  std::string reason;
  Eigen::Vector3d goal = Eigen::Vector3d::Zero();
  std::vector<Eigen::Vector2d> via;  ///< the route's waypoints before the goal
  std::size_t via_next = 0;          ///< the first one not yet passed
  std::vector<double> via_tail_m;    ///< per waypoint: the route's length from it to the goal
  double path_m = 0.0;
  Eigen::Vector3d last_pose = Eigen::Vector3d::Zero();
  double last_step_t = -std::numeric_limits<double>::infinity();
  double goal_t = 0.0;
  double best_dist = 0.0, best_t = 0.0;  ///< progress for the stuck check
  bool mrpt_active = false;              ///< a navigateWaypoints() request is running
  bool facing = false;  ///< turning in place toward the goal before the reactive approach
  /// Escape from a wedged spot (no progress for stuck_timeout_s): turn toward the most open
  /// direction of the scan, drive up to escape_distance_m along it, then navigate again; a goal
  /// fails "stuck" only when it makes no progress after escape_attempts escapes.
  enum class Escape { None, Turning, Driving } escape = Escape::None;
  int escapes = 0;
  double escape_heading = 0.0, escape_t = 0.0;
  Eigen::Vector2d escape_from = Eigen::Vector2d::Zero();
  /// Retreat after a collision: the obstacle hit was one the robot's obstacle sensing did not
  /// show (a 2-D scan misses a chair seat or a low box inside the footprint's height band), so
  /// the most open direction of the scan may lead straight back into it. The goal that collided
  /// fails "collision"; the next goal first backs the robot up along the path it came by (known
  /// free: it was just driven) for escape_distance_m, then navigates.
  std::deque<Eigen::Vector2d> trail;  ///< recent positions, newest last, ~2 cm apart
  bool retreat_pending = false;
  bool retreating = false;
  double retreat_t = 0.0, retreat_driven_m = 0.0;
  Eigen::Vector2d retreat_last = Eigen::Vector2d::Zero();

  void initialise();
  void step(double t);
  void stepNavigating(double t, const Eigen::Vector3d& pose);
  /// The point steered at now: the next waypoint of the route, else the goal.
  Eigen::Vector2d target() const { return via_next < via.size() ? via[via_next] : goal.head<2>(); }
  /// Distance left along the route from `xy` (to the target, then the rest of the route).
  double remaining_m(const Eigen::Vector2d& xy) const {
    return (target() - xy).norm() + (via_next < via.size() ? via_tail_m[via_next] : 0.0);
  }
  void stepAligning(const Eigen::Vector3d& pose);
  void stepReactive(const Eigen::Vector2d& target);
  void driveDirect(const Eigen::Vector3d& pose, const Eigen::Vector2d& target);
  void rotate(double heading_error_rad, double max_w_radps);
  void driveLeg(const Eigen::Vector3d& pose, const Eigen::Vector2d& target);
  bool waypointPassed(const Eigen::Vector3d& pose) const;
  double frontClearance_m() const;
  double clearanceAlong_m(double bearing_rad, double half_width_m, double cap_m) const;
  /// clearanceAlong_m with the margin-grown footprint, capped at escape_distance_m + radius.
  double clearanceAlong_m(double bearing_rad) const;
  bool corridorFree(double bearing_rad, double distance_m) const;
  /// The bare footprint's radius (no PTG margin) plus 1 cm: the corridor controller's disc.
  double bodyRadius_m() const { return radius_m - params.footprint_margin_m + 0.01; }
  double mostOpenBearing(double goal_bearing_rad) const;
  void startEscape(double t, const Eigen::Vector3d& pose, double goal_bearing_rad);
  void stepEscape(double t, const Eigen::Vector3d& pose);
  void recordTrail(const Eigen::Vector3d& pose);
  void stepRetreat(double t, const Eigen::Vector3d& pose);
  void stopMrpt();
  void finish(NavState s, const std::string& why);
};

void Navigator::Impl::initialise() {
  params.validate();
  if (footprint.size() < 3)
    throwInputError("navigation footprint",
                    "needs at least 3 vertices, got " + std::to_string(footprint.size()));
  for (const Eigen::Vector2f& v : footprint) radius_m = std::max(radius_m, v.norm());
  radius_m += float(params.footprint_margin_m);
  const std::string cfg_text = reactiveConfigText(params, footprint);
  mrpt::config::CConfigFileMemory cfg(cfg_text);
  nav.setMinLoggingLevel(mrpt::system::LVL_ERROR);
  iface.setMinLoggingLevel(mrpt::system::LVL_ERROR);  // "not implemented" INFO lines per event
  // The delays time logger dumps its table at INFO level when the navigator is destroyed; it is
  // exposed only as const, but the object itself is not const.
  const_cast<mrpt::system::CTimeLogger&>(nav.getDelaysTimeLogger())
      .setMinLoggingLevel(mrpt::system::LVL_ERROR);
  nav.enableRethrowNavExceptions(true);  // errors come back as exceptions: reason "mrpt: ..."
  const SimulatedClockScope clock(robot);
  nav.loadConfigFile(cfg);
  // MRPT trap: the ptg_cache_files_directory key is not read from the config in 2.5.8 and the
  // default "." writes ReacNavGrid_*.dat.gz into the cwd. The file names do not encode the PTG
  // settings, so each configuration gets its own sub-folder (named by a hash of the config).
  ensurePrivateCacheDir(params.effectiveCacheDir());
  const std::filesystem::path cache_dir = std::filesystem::path(params.effectiveCacheDir()) /
                                          std::to_string(std::hash<std::string>{}(cfg_text));
  std::filesystem::create_directories(cache_dir);
  nav.params_abstract_ptg_navigator.ptg_cache_files_directory = cache_dir.string();
  nav.initialize();  // builds (or loads from ptg_cache_dir) the PTG tables: ~1 s
  last_pose = localisation();
}

void Navigator::Impl::stopMrpt() {
  if (mrpt_active) {
    const SimulatedClockScope clock(robot);
    nav.cancel();
    if (nav.getCurrentState() == mrpt::nav::CAbstractNavigator::NAV_ERROR) nav.resetNavError();
  }
  mrpt_active = false;
}

void Navigator::Impl::finish(NavState s, const std::string& why) {
  stopMrpt();
  robot.stop();
  state = s;
  reason = why;
}

void Navigator::Impl::step(double t) {
  const Eigen::Vector3d pose = localisation();
  path_m += (pose.head<2>() - last_pose.head<2>()).norm();
  last_pose = pose;
  if (state == NavState::Navigating || state == NavState::Aligning) {
    if (robot.collided()) {
      retreat_pending = true;
      return finish(NavState::Failed, "collision");
    }
    if (t - goal_t > params.goal_timeout_s) return finish(NavState::Failed, "timeout");
  }
  if (state == NavState::Navigating && retreating) return stepRetreat(t, pose);
  recordTrail(pose);
  if (state == NavState::Navigating) stepNavigating(t, pose);
  if (state == NavState::Aligning) stepAligning(pose);
}

void Navigator::Impl::stepNavigating(double t, const Eigen::Vector3d& pose) {
  while (via_next < via.size() && waypointPassed(pose)) {
    ++via_next;  // passed: steer at the next one (a new request to MRPT)
    stopMrpt();
  }
  const Eigen::Vector2d to = target() - pose.head<2>();
  const double d = to.norm();
  if (via_next == via.size() && d <= params.goal_tolerance_m) {
    stopMrpt();
    state = NavState::Aligning;
    return;
  }
  const double bearing = mrpt::math::wrapToPi(std::atan2(to.y(), to.x()) - pose.z());
  if (escape != Escape::None) return stepEscape(t, pose);
  const double left = remaining_m(pose.head<2>());
  if (left < best_dist - params.stuck_distance_m) {
    best_dist = left;
    best_t = t;
  } else if (t - best_t > params.stuck_timeout_s) {
    if (escapes >= params.escape_attempts) return finish(NavState::Failed, "stuck");
    return startEscape(t, pose, bearing);
  }
  if (params.follow_route && !via.empty() && corridorFree(bearing, d)) {
    stopMrpt();
    return driveLeg(pose, target());
  }
  if (d < params.direct_range_m) {
    // MRPT trap: the PTGs fail on targets nearer than their reach; our controller drives there.
    stopMrpt();
    return driveDirect(pose, target());
  }
  // Target behind at the start: turn in place first rather than letting the forward PTGs loop
  // around; only once per goal (the reactive navigator's own detours may point away later).
  if (facing && std::abs(bearing) > 10.0 * kRadPerDeg)
    return rotate(bearing, params.max_w_degps * kRadPerDeg);
  facing = false;
  stepReactive(target());
}

/// Whether the robot at `pose` has passed the route's next waypoint: within via_reach_m, or,
/// with follow_route, within follow_reach_m where the corridor to the target after it is free,
/// else within kCornerReach_m. Cutting a corner leaves the next leg grazing the door jamb or the
/// wall the corner keeps its distance from; the corner is then driven to and turned at in place.
bool Navigator::Impl::waypointPassed(const Eigen::Vector3d& pose) const {
  constexpr double kCornerReach_m = 0.03;
  const double d = (via[via_next] - pose.head<2>()).norm();
  if (!params.follow_route) return d <= params.via_reach_m;
  if (d <= kCornerReach_m) return true;
  if (d > std::min(params.via_reach_m, params.follow_reach_m)) return false;
  const Eigen::Vector2d next = via_next + 1 < via.size() ? via[via_next + 1] : goal.head<2>();
  const Eigen::Vector2d to = next - pose.head<2>();
  return corridorFree(mrpt::math::wrapToPi(std::atan2(to.y(), to.x()) - pose.z()), to.norm());
}

/// One step of MRPT's reactive navigator toward `target`; its state and error reason are read
/// after every step (MRPT trap: an error is only visible there and in the event callbacks).
void Navigator::Impl::stepReactive(const Eigen::Vector2d& target) {
  using mrpt::nav::CAbstractNavigator;
  const SimulatedClockScope clock(robot);
  try {
    if (!mrpt_active) {
      // navigateWaypoints(), not navigate(): see docs/navigation.md (MRPT trap).
      mrpt::nav::TWaypointSequence seq;
      seq.waypoints.emplace_back(target.x(), target.y(), params.goal_tolerance_m,
                                 /*allow_skip=*/false);
      iface.clearEvents();
      nav.navigateWaypoints(seq);
      mrpt_active = true;
    }
    nav.navigationStep();
  } catch (const std::exception& e) {
    return finish(NavState::Failed, std::string("mrpt: ") + e.what());
  }
  const CAbstractNavigator::TState s = nav.getCurrentState();
  if (s == CAbstractNavigator::NAV_ERROR) {
    const auto& err = nav.getErrorReason();
    if (err.error_code == CAbstractNavigator::ERR_CANNOT_REACH_TARGET || iface.target_blocked)
      return finish(NavState::Failed, "unreachable");
    return finish(NavState::Failed, "mrpt: " + err.error_msg);
  }
  if (iface.target_blocked) return finish(NavState::Failed, "unreachable");
  // IDLE: MRPT considers the waypoint reached; the next step re-checks the distance ourselves.
  if (s == CAbstractNavigator::IDLE) mrpt_active = false;
}

/// Distance from the footprint's front to the nearest obstacle point in the corridor ahead.
double Navigator::Impl::frontClearance_m() const {
  return clearanceAlong_m(0.0, radius_m, std::numeric_limits<double>::infinity());
}

/// Free distance ahead of a disc of `half_width_m` along `bearing_rad` (robot frame): the nearest
/// obstacle point in the corridor of that half-width in that direction, minus the half-width;
/// at most `cap_m` (nothing further matters to the caller).
double Navigator::Impl::clearanceAlong_m(double bearing_rad, double half_width_m,
                                         double cap_m) const {
  std::vector<Eigen::Vector3f> pts;
  robot.senseObstacles(pts);
  const double c = std::cos(bearing_rad), s = std::sin(bearing_rad);
  double clear = cap_m;
  for (const Eigen::Vector3f& q : pts) {
    const double along = c * q.x() + s * q.y(), across = -s * q.x() + c * q.y();
    if (along > 0.0 && std::abs(across) < half_width_m)
      clear = std::min(clear, along - half_width_m);
  }
  return clear;
}

double Navigator::Impl::clearanceAlong_m(double bearing_rad) const {
  return clearanceAlong_m(bearing_rad, radius_m, params.escape_distance_m + radius_m);
}

/// Whether the straight corridor of the bare footprint (no PTG margin, 1 cm of slack) toward a
/// target `distance_m` away along `bearing_rad` holds no obstacle point of the scan: the legs of
/// a route run over the planning grid's free cells, which keep the footprint radius from walls
/// but not the PTG margin beyond it.
bool Navigator::Impl::corridorFree(double bearing_rad, double distance_m) const {
  const double body = bodyRadius_m();
  return clearanceAlong_m(bearing_rad, body, distance_m) >= distance_m - body;
}

/// The bearing (robot frame, 10 degree steps) with the most free distance ahead; among equally
/// open ones (within 5 cm) the one nearest the goal's bearing.
double Navigator::Impl::mostOpenBearing(double goal_bearing_rad) const {
  double best = goal_bearing_rad, best_clear = -1.0, best_off = 0.0;
  for (int k = 0; k < 36; ++k) {
    const double b = mrpt::math::wrapToPi(k * 10.0 * kRadPerDeg);
    const double clear = clearanceAlong_m(b),
                 off = std::abs(mrpt::math::wrapToPi(b - goal_bearing_rad));
    if (clear > best_clear + 0.05 || (clear > best_clear - 0.05 && off < best_off)) {
      best = b;
      best_clear = std::max(best_clear, clear);
      best_off = off;
    }
  }
  return best;
}

void Navigator::Impl::startEscape(double t, const Eigen::Vector3d& pose, double goal_bearing_rad) {
  stopMrpt();
  ++escapes;
  escape = Escape::Turning;
  escape_heading = mrpt::math::wrapToPi(pose.z() + mostOpenBearing(goal_bearing_rad));
  escape_from = pose.head<2>();
  escape_t = t;
}

/// Turn to the escape heading, drive straight until escape_distance_m, an obstacle ahead or
/// stuck_timeout_s; then navigation resumes with a fresh progress check.
void Navigator::Impl::stepEscape(double t, const Eigen::Vector3d& pose) {
  const double e = mrpt::math::wrapToPi(escape_heading - pose.z());
  const bool done = t - escape_t > params.stuck_timeout_s ||
                    (pose.head<2>() - escape_from).norm() >= params.escape_distance_m;
  // Turn to 2 degrees, not the goal's heading tolerance: the open direction may pass a wall at
  // a centimetre, and 8 degrees off it the corridor ahead is blocked.
  if (escape == Escape::Turning && std::abs(e) <= 2.0 * kRadPerDeg) escape = Escape::Driving;
  if (escape == Escape::Turning && !done) return rotate(e, params.max_w_degps * kRadPerDeg);
  const double v = std::min(0.5 * params.max_v_mps, frontClearance_m() / 1.0);
  if (done || v < 0.02) {
    robot.stop();
    escape = Escape::None;
    best_dist = remaining_m(pose.head<2>());
    best_t = t;
    facing = true;  // face the goal again before handing over to the reactive navigator
    return;
  }
  robot.setVelocityCommand(v, std::clamp(2.0 * e, -0.5, 0.5));
}

/// Appends the position to the trail when it moved 2 cm from the last one; keeps about twice
/// escape_distance_m of path.
void Navigator::Impl::recordTrail(const Eigen::Vector3d& pose) {
  if (!trail.empty() && (pose.head<2>() - trail.back()).norm() < 0.02) return;
  trail.push_back(pose.head<2>());
  const std::size_t keep = std::size_t(std::ceil(2.0 * params.escape_distance_m / 0.02)) + 1;
  while (trail.size() > keep) trail.pop_front();
}

/// Backs up along the trail (newest point first) until escape_distance_m is driven, the trail
/// ends, the scan shows something behind, or stuck_timeout_s passes; then normal navigation
/// resumes facing the goal. Steering in reverse: the rear points at the trail point, and a
/// positive turn rate turns the rear the same way as the front.
void Navigator::Impl::stepRetreat(double t, const Eigen::Vector3d& pose) {
  retreat_driven_m += (pose.head<2>() - retreat_last).norm();
  retreat_last = pose.head<2>();
  while (!trail.empty() && (trail.back() - pose.head<2>()).norm() < 0.05) trail.pop_back();
  const double behind = clearanceAlong_m(M_PI);
  if (trail.empty() || retreat_driven_m >= params.escape_distance_m || behind < 0.02 ||
      t - retreat_t > params.stuck_timeout_s) {
    robot.stop();
    retreating = false;
    best_dist = remaining_m(pose.head<2>());
    best_t = t;
    facing = true;
    return;
  }
  const Eigen::Vector2d to = trail.back() - pose.head<2>();
  const double rear = mrpt::math::wrapToPi(pose.z() + M_PI);
  const double e = mrpt::math::wrapToPi(std::atan2(to.y(), to.x()) - rear);
  const double max_w = params.max_w_degps * kRadPerDeg;
  if (std::abs(e) > 45.0 * kRadPerDeg)
    return robot.setVelocityCommand(0.0, std::clamp(2.0 * e, -max_w, max_w));
  const double v = std::min({0.5 * params.max_v_mps, behind, to.norm() / params.period_s});
  robot.setVelocityCommand(-v * std::cos(e), std::clamp(2.0 * e, -max_w, max_w));
}

/// Own controller for near targets: turn toward the target, then drive with a speed that falls
/// with the distance; stops short of obstacles in the corridor ahead (the stuck check then ends
/// the goal).
void Navigator::Impl::driveDirect(const Eigen::Vector3d& pose, const Eigen::Vector2d& target) {
  const Eigen::Vector2d to = target - pose.head<2>();
  const double d = to.norm();
  const double bearing = mrpt::math::wrapToPi(std::atan2(to.y(), to.x()) - pose.z());
  const double max_w = params.max_w_degps * kRadPerDeg;
  const double w = std::clamp(2.0 * bearing, -max_w, max_w);
  if (std::abs(bearing) > 30.0 * kRadPerDeg) return robot.setVelocityCommand(0.0, w);
  double v = std::min(params.max_v_mps, 0.8 * d) * std::cos(bearing);
  // At most what keeps 1 cm of the clearance ahead after one period: the robot may creep up to
  // an obstacle at the goal (a view next to a chair) instead of stopping 2 cm short for good.
  v = std::min(v, std::max(0.0, (frontClearance_m() - 0.01) / params.period_s));
  robot.setVelocityCommand(v, w);
}

/// Corridor controller for a route's leg: turn in place while the target lies more than 10
/// degrees off (an arc would leave the leg's line, which keeps the footprint's distance from the
/// walls), else drive at min(max_v, 0.8 d) cos(bearing) (a corner is reached within centimetres
/// when the next leg needs it), at most what keeps 1 cm of the bare footprint's clearance ahead
/// after one period.
void Navigator::Impl::driveLeg(const Eigen::Vector3d& pose, const Eigen::Vector2d& target) {
  const Eigen::Vector2d to = target - pose.head<2>();
  const double d = to.norm();
  const double bearing = mrpt::math::wrapToPi(std::atan2(to.y(), to.x()) - pose.z());
  const double max_w = params.max_w_degps * kRadPerDeg;
  if (std::abs(bearing) > 10.0 * kRadPerDeg && d > 0.05) return rotate(bearing, max_w);
  double v = std::min(params.max_v_mps, 0.8 * d) * std::cos(bearing);
  const double ahead_m =
      clearanceAlong_m(0.0, bodyRadius_m(), std::numeric_limits<double>::infinity());
  v = std::min(v, std::max(0.0, (ahead_m - 0.01) / params.period_s));
  robot.setVelocityCommand(v, std::clamp(2.0 * bearing, -max_w, max_w));
}

/// Rotation in place toward `heading_error_rad`: proportional, at least 10 deg/s so it converges,
/// at most max_w_radps; the gain keeps one period's turn below the heading tolerance band.
void Navigator::Impl::rotate(double heading_error_rad, double max_w_radps) {
  const double mag = std::clamp(2.0 * std::abs(heading_error_rad), 10.0 * kRadPerDeg, max_w_radps);
  robot.setVelocityCommand(0.0, std::copysign(mag, heading_error_rad));
}

void Navigator::Impl::stepAligning(const Eigen::Vector3d& pose) {
  const double e = mrpt::math::wrapToPi(goal.z() - pose.z());
  if (std::abs(e) <= params.heading_tolerance_deg * kRadPerDeg)
    return finish(NavState::Reached, "");
  rotate(e, params.align_w_degps * kRadPerDeg);
}

Navigator::Navigator(robot::IRobot& robot, const TNavigationParams& params,
                     const std::vector<Eigen::Vector2f>& footprint,
                     std::function<Eigen::Vector3d()> localisation)
    : m_impl(std::make_unique<Impl>(robot, params, footprint, std::move(localisation))) {
  m_impl->initialise();
}

Navigator::~Navigator() {
  if (m_impl->state == NavState::Navigating || m_impl->state == NavState::Aligning)
    m_impl->finish(NavState::Idle, "");
}

void Navigator::setGoal(const Eigen::Vector3d& goal_xyyaw,
                        const std::vector<Eigen::Vector2d>& via) {
  Impl& m = *m_impl;
  m.stopMrpt();
  m.goal = goal_xyyaw;
  m.goal.z() = mrpt::math::wrapToPi(m.goal.z());
  for (const Eigen::Vector2d& w : via)
    if (!w.allFinite()) throwInputError("navigation route", "a waypoint is not finite");
  m.via = via;
  m.via_next = 0;
  m.via_tail_m.assign(via.size(), 0.0);
  for (std::size_t k = via.size(); k-- > 0;)
    m.via_tail_m[k] =
        ((k + 1 < via.size() ? via[k + 1] : Eigen::Vector2d(m.goal.head<2>())) - via[k]).norm() +
        (k + 1 < via.size() ? m.via_tail_m[k + 1] : 0.0);
  m.state = NavState::Navigating;
  m.reason.clear();
  m.goal_t = m.best_t = m.robot.time_s();
  const Eigen::Vector3d pose = m.localisation();
  m.best_dist = m.remaining_m(pose.head<2>());
  m.last_step_t = -std::numeric_limits<double>::infinity();  // step at the next update()
  const Eigen::Vector2d to = m.target() - pose.head<2>();
  m.facing = std::abs(mrpt::math::wrapToPi(std::atan2(to.y(), to.x()) - pose.z())) >
             m.params.face_goal_deg * kRadPerDeg;
  m.escape = Impl::Escape::None;
  m.escapes = 0;
  m.retreating = m.retreat_pending && !m.trail.empty();
  m.retreat_pending = false;
  m.retreat_t = m.goal_t;
  m.retreat_driven_m = 0.0;
  m.retreat_last = pose.head<2>();
}

void Navigator::cancel() {
  m_impl->finish(NavState::Idle, "");
}

void Navigator::update() {
  Impl& m = *m_impl;
  const double t = m.robot.time_s();
  if (t - m.last_step_t < m.params.period_s - 1e-9) return;
  m.last_step_t = t;
  m.step(t);
}

NavState Navigator::state() const {
  return m_impl->state;
}
const std::string& Navigator::failureReason() const {
  return m_impl->reason;
}
const Eigen::Vector3d& Navigator::goal() const {
  return m_impl->goal;
}
double Navigator::pathLength_m() const {
  return m_impl->path_m;
}

}  // namespace rasm::navigation
