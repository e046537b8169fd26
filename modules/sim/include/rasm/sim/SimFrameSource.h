#pragma once
// The simulator as a rasm::io::FrameSource: renders a world along a trajectory spec on demand
// (no rawlog), for `rasm run` with [source] type = sim and for end-to-end tests. Configured by
// the [sim] section (TSimParams); the camera intrinsics can come from the run's [camera].

#include <mrpt/config/CLoadableOptions.h>

#include <memory>
#include <optional>
#include <string>

#include "rasm/io/FrameSource.h"
#include "rasm/sim/SimulatedSequence.h"

namespace rasm::sim {

/// INI section [sim] of a run (keys as the member names).
struct TSimParams : public mrpt::config::CLoadableOptions {
  std::string world = "office";                ///< shipped world name or YAML path
  std::string trajectory = "office_handheld";  ///< shipped trajectory spec name or YAML path
  std::uint64_t seed = 0;
  bool noise = true;     ///< false: exact depth, no dropouts ([sim_sensor] noise and dropouts)
  int max_frames = -1;   ///< < 0: the whole trajectory
  double rate_hz = 0.0;  ///< camera frame rate; 0: the trajectory spec's

  void loadFromConfigFile(const mrpt::config::CConfigFileBase& cfg,
                          const std::string& section) override;
  void saveToConfigFile(mrpt::config::CConfigFileBase& cfg,
                        const std::string& section) const override;
};

class SimFrameSource : public io::FrameSource {
 public:
  SimFrameSource(const World& world, const TrajectorySpec& spec, const SequenceOptions& opt = {});
  /// Loads the world and the spec named in `params` (InputError naming them when they do not
  /// load); `intrinsics` replaces the sensor's camera when given.
  /// `commanded`: a robot spec's robot is driven from outside (SequenceOptions::commanded).
  explicit SimFrameSource(const TSimParams& params,
                          const std::optional<CameraIntrinsics>& intrinsics = std::nullopt,
                          bool commanded = false);

  std::optional<RgbdFrame> next() override;
  long long sizeHint() const override { return m_seq->plannedFrames(); }
  std::string describe() const override { return m_description; }

  /// The sequence behind it (its RayScene feeds SimulatedDetector).
  const SimulatedSequence& sequence() const { return *m_seq; }
  SimulatedSequence& sequence() { return *m_seq; }

 private:
  std::unique_ptr<SimulatedSequence> m_seq;
  std::string m_description;
};

}  // namespace rasm::sim
