// Built with the io module only (rasm::io::FrameSource).
#ifdef RASM_SIM_HAVE_IO
#include "rasm/sim/SimFrameSource.h"

#include <mrpt/config/CConfigFileBase.h>

#include "ParamsWrite.h"
#include "rasm/core/Error.h"

namespace rasm::sim {

void TSimParams::loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s) {
  MRPT_LOAD_CONFIG_VAR_CS(world, string);
  MRPT_LOAD_CONFIG_VAR_CS(trajectory, string);
  seed = c.read_uint64_t(s, "seed", seed);
  MRPT_LOAD_CONFIG_VAR_CS(noise, bool);
  MRPT_LOAD_CONFIG_VAR_CS(max_frames, int);
  MRPT_LOAD_CONFIG_VAR_CS(rate_hz, double);
  if (!(rate_hz >= 0.0) || rate_hz > 1000.0)
    throwInputError("[" + s + "] rate_hz",
                    "expected 0 (the spec's rate) or a rate in (0, 1000] Hz");
  if (world.empty()) throwInputError("[" + s + "] world", "empty; expected a world name or file");
  if (trajectory.empty())
    throwInputError("[" + s + "] trajectory", "empty; expected a spec name or file");
}

void TSimParams::saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const {
  RASM_SIM_SAVE(world,
                "shipped world (office, cluttered_lab, two_rooms) or YAML file (docs/sim.md)");
  RASM_SIM_SAVE(trajectory, "shipped trajectory spec (office_handheld, ...) or YAML file");
  RASM_SIM_SAVE(seed, "sensor noise, jitter and odometry noise seed");
  RASM_SIM_SAVE(noise, "false: exact depth without dropouts");
  RASM_SIM_SAVE(max_frames, "stop after this many frames (< 0: whole trajectory)");
  RASM_SIM_SAVE(rate_hz, "camera frame rate in Hz (0: the trajectory spec's rate_hz)");
}

SimFrameSource::SimFrameSource(const World& world, const TrajectorySpec& spec,
                               const SequenceOptions& opt)
    : m_seq(std::make_unique<SimulatedSequence>(world, spec, opt)),
      m_description("simulator world " + world.name + ", trajectory " + spec.source) {}

namespace {
SequenceOptions sequenceOptions(const TSimParams& p, const std::optional<CameraIntrinsics>& K,
                                bool commanded) {
  SequenceOptions o;
  o.commanded = commanded;
  o.rate_hz = p.rate_hz;
  o.seed = p.seed;
  o.max_frames = p.max_frames;
  o.intrinsics = K;
  if (!p.noise) o.sensor_overrides = {{"noise", "false"}, {"dropouts", "false"}};
  return o;
}
}  // namespace

SimFrameSource::SimFrameSource(const TSimParams& p, const std::optional<CameraIntrinsics>& K,
                               bool commanded)
    : SimFrameSource(loadWorld(p.world), loadTrajectorySpec(p.trajectory),
                     sequenceOptions(p, K, commanded)) {
  if (commanded && !m_seq->robot())
    throwInputError("[sim] trajectory '" + p.trajectory + "'",
                    "is a hand-held spec; a run that drives the robot needs a robot spec (its "
                    "start pose, rate and robot: block; its waypoints are ignored)");
  if (commanded)
    m_description = "simulator world " + p.world + ", robot driven by the run from the start of " +
                    p.trajectory;
}

std::optional<RgbdFrame> SimFrameSource::next() {
  RgbdFrame f;
  if (!m_seq->next(f)) return std::nullopt;
  return f;
}

}  // namespace rasm::sim
#endif  // RASM_SIM_HAVE_IO
