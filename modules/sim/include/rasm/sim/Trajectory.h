#pragma once
// Scripted camera trajectories for the recorder (YAML spec, docs/sim.md):
//  - handheld: 6-DoF keyframe poses, positions on a cubic Hermite spline with Catmull-Rom
//    tangents, orientations on a cubic Bezier curve on SO(3) (De Casteljau with slerp) with
//    Catmull-Rom angular velocities, both C1 in time and exact at the keyframes; plus smooth
//    seeded hand jitter (a few sinusoids per axis with random frequencies and phases);
//  - robot: waypoints driven by a pure-pursuit controller through SimulatedDiffDriveRobot at a
//    fixed control rate; the camera rides on the robot's mount.

#include <Eigen/Geometry>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace rasm::sim {

struct HandheldKeyframe {
  double t_s = 0.0;
  Eigen::Isometry3d T_world_cam = Eigen::Isometry3d::Identity();  ///< optical frame
};

/// Hand tremor: zero-mean, smooth; RMS amplitudes per axis.
struct HandJitter {
  double translation_m = 0.003;
  double rotation_deg = 0.3;
  double frequency_hz = 1.5;  ///< centre of the random frequencies (0.5x..1.5x)
};

class HandheldTrajectory {
 public:
  /// Needs >= 2 keyframes with strictly increasing times.
  HandheldTrajectory(std::vector<HandheldKeyframe> keyframes, const HandJitter& jitter,
                     std::uint64_t seed);

  /// Pose at time t (clamped to [first, last] keyframe time), jitter included.
  Eigen::Isometry3d pose(double t_s) const;
  /// The smooth path alone (no jitter): passes exactly through the keyframes.
  Eigen::Isometry3d smoothPose(double t_s) const;
  double startTime() const { return m_kf.front().t_s; }
  double endTime() const { return m_kf.back().t_s; }

 private:
  std::vector<HandheldKeyframe> m_kf;
  std::vector<Eigen::Quaterniond> m_q;  ///< keyframe rotations (sign-aligned)
  std::vector<Eigen::Vector3d> m_w;     ///< body angular velocity at each keyframe (rad/s)
  HandJitter m_jitter;
  struct Wave {
    double freq_hz, phase, amp;
  };
  std::vector<Wave> m_waves[6];  ///< tx ty tz rx ry rz
};

struct PurePursuitParams {
  double lookahead_m = 0.6;
  double max_v_mps = 0.4;
  double max_w_degps = 60.0;
  /// Heading errors above this turn in place first.
  double rotate_in_place_deg = 60.0;
  double goal_tolerance_m = 0.1;
  /// Speed limit near the goal: v <= slowdown_gain * distance_to_goal.
  double slowdown_gain = 1.0;
};

/// Pure pursuit (Coulter 1992) along a polyline: steer towards the path point one lookahead
/// distance ahead of the robot's progress, curvature kappa = 2 sin(alpha) / L.
class PurePursuit {
 public:
  /// `path` >= 2 points; with loop = true the path is closed and driven `laps` times.
  PurePursuit(std::vector<Eigen::Vector2d> path, const PurePursuitParams& params, bool loop = false,
              int laps = 1);
  /// Velocity command (v, w) for the robot at `pose` (x, y, yaw); (0, 0) once done().
  Eigen::Vector2d command(const Eigen::Vector3d& pose);
  bool done() const { return m_done; }
  /// Arc length travelled along the path (progress of the closest point), metres.
  double progress() const { return m_progress; }
  double totalLength() const { return m_total; }

 private:
  Eigen::Vector2d pointAt(double s) const;
  std::vector<Eigen::Vector2d> m_path;
  std::vector<double> m_cum;  ///< arc length at each vertex (one lap)
  PurePursuitParams m_p;
  bool m_loop;
  double m_lap = 0.0, m_total = 0.0, m_progress = 0.0;
  bool m_done = false;
};

/// A recorder trajectory spec (YAML; docs/sim.md).
struct TrajectorySpec {
  enum class Kind { Handheld, Robot };
  Kind kind = Kind::Handheld;
  std::string source;  ///< file (for messages)
  /// The world the spec was made for (optional `world:` key; a relative path is relative to the
  /// spec file's folder). Informational: the recorder is always given its world.
  std::string world;
  double rate_hz = 30.0;  ///< camera frame rate
  /// Recording length; handheld default: the last keyframe time; robot default: until the
  /// path is done, at most max_duration_s.
  std::optional<double> duration_s;
  double max_duration_s = 600.0;

  // handheld
  std::vector<HandheldKeyframe> keyframes;
  HandJitter jitter;

  // robot
  Eigen::Vector3d start_pose = Eigen::Vector3d::Zero();  ///< x, y, yaw (rad)
  std::vector<Eigen::Vector2d> waypoints;
  bool loop = false;
  int laps = 1;
  PurePursuitParams controller;
  int control_substeps = 4;  ///< controller updates per camera frame
  /// [sim_robot] / [sim_sensor] keys from the spec's `robot:` / `sensor:` mappings (strings, as
  /// in an INI file); applied on top of the defaults by the recorder.
  std::map<std::string, std::string> robot_overrides, sensor_overrides;
};

/// Loads a spec file; errors name "<file>:<line>: <key>: <problem>". A bare name like
/// "office_handheld" resolves to <simDataDir>/trajectories/office_handheld.yaml.
TrajectorySpec loadTrajectorySpec(const std::string& name_or_path);
TrajectorySpec loadTrajectorySpecFromString(const std::string& yaml, const std::string& source);

}  // namespace rasm::sim
