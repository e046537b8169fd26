#pragma once
// A world rendered along a trajectory spec, one frame at a time: what the recorder writes and
// SimFrameSource streams. Frame i is at simulated time i / rate_hz and carries the rendered
// colour, noisy depth, ground-truth pose and labels, and (robot specs) the odometry.

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>

#include "rasm/core/CameraIntrinsics.h"
#include "rasm/core/RgbdFrame.h"
#include "rasm/sim/RayScene.h"
#include "rasm/sim/RgbdSensor.h"
#include "rasm/sim/SimulatedDiffDriveRobot.h"
#include "rasm/sim/Trajectory.h"
#include "rasm/sim/World.h"

namespace rasm::sim {

struct SequenceOptions {
  std::uint64_t seed = 0;
  /// [sim_sensor] / [sim_robot] keys applied after the spec's own `sensor:` / `robot:` blocks.
  std::map<std::string, std::string> sensor_overrides, robot_overrides;
  /// Replaces the sensor's intrinsics last (e.g. the [camera] of a pipeline run).
  std::optional<CameraIntrinsics> intrinsics;
  /// Stop after this many frames (< 0: as the spec says).
  long long max_frames = -1;
  /// Camera frame rate (Hz) replacing the spec's rate_hz; 0 keeps the spec's.
  double rate_hz = 0.0;
  /// Robot specs: the robot is driven from outside (exploration: a navigator sets its velocity
  /// commands from the substep hook) instead of pure pursuit along the spec's waypoints, which are
  /// ignored; the sequence then runs until max_duration_s / max_frames, or finish().
  bool commanded = false;
};

class SimulatedSequence {
 public:
  /// Throws InputError for bad overrides or a robot start pose inside an obstacle.
  SimulatedSequence(const World& world, const TrajectorySpec& spec,
                    const SequenceOptions& opt = {});
  ~SimulatedSequence();

  /// Renders the next frame into `frame` (buffers reused); false at the end of the sequence.
  bool next(RgbdFrame& frame);

  /// Frames the sequence will produce, or -1 when not known in advance (robot until done).
  long long plannedFrames() const { return m_planned; }
  std::size_t framesRendered() const { return std::size_t(m_next); }
  /// Fraction done in [0, 1] (frames, or path progress for a robot of unknown duration).
  double progress() const;
  /// The robot ended the sequence by staying stuck against an obstacle for 1 s.
  bool robotStuck() const { return m_stuck; }

  const RayScene& scene() const { return *m_scene; }
  const TrajectorySpec& spec() const { return m_spec; }
  const TSensorParams& sensorParams() const { return m_sensor_params; }
  const RgbdSensor& sensor() const { return *m_sensor; }
  /// The simulated robot (robot specs), else null.
  const SimulatedDiffDriveRobot* robot() const { return m_robot.get(); }
  SimulatedDiffDriveRobot* robot() { return m_robot.get(); }

  /// Commanded robot: called after each of the control_substeps robot steps between two frames
  /// (the navigator's update: it reads the robot's clock and sets its next velocity command).
  void setSubstepHook(std::function<void()> hook) { m_substep_hook = std::move(hook); }
  /// Ends the sequence: next() returns false from now on (an exploration that stopped).
  void finish() { m_done = true; }
  /// Seconds between two frames.
  double frameInterval() const { return 1.0 / m_rate_hz; }

 private:
  TrajectorySpec m_spec;
  std::uint64_t m_seed;
  TSensorParams m_sensor_params;
  std::unique_ptr<RayScene> m_scene;
  std::unique_ptr<RgbdSensor> m_sensor;
  std::unique_ptr<HandheldTrajectory> m_hand;
  std::unique_ptr<SimulatedDiffDriveRobot> m_robot;
  std::unique_ptr<PurePursuit> m_pursuit;  ///< null for a commanded robot
  std::function<void()> m_substep_hook;
  double m_rate_hz = 30.0;
  long long m_planned = -1, m_limit = 0, m_next = 0;
  double m_stuck_s = 0.0;
  bool m_stuck = false, m_done = false;
};

/// Applies key = value overrides to a params struct through rasm::loadParamsStrict, so unknown
/// keys and bad values fail as in an INI file ("<source> [section] key: ...").
void applyParamOverrides(mrpt::config::CLoadableOptions& params, const std::string& section,
                         const std::map<std::string, std::string>& kv, const std::string& source);

}  // namespace rasm::sim
