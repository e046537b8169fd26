#pragma once
// The simulator as a frame source of `rasm run` ([source] type = sim, configured by [sim]).

#include <memory>
#include <optional>
#include <string>

#include "rasm/core/CameraIntrinsics.h"
#include "rasm/io/FrameSource.h"

namespace rasm::autonomy {

/// `sim_ini` holds the [sim] section; `source` names the config for messages; `commanded`: the
/// run drives the simulated robot (exploration). Throws InputError when the build has no
/// simulator or the section is invalid.
std::unique_ptr<io::FrameSource> openSimSource(const std::string& sim_ini,
                                               const std::string& source,
                                               const std::optional<CameraIntrinsics>& camera,
                                               bool commanded = false,
                                               double commanded_rate_hz = 0.0);

/// Whether the [sim] section's trajectory is a robot spec (a robot the run could drive); false
/// without a simulator. Throws InputError for an invalid section or an unknown spec.
bool simTrajectoryIsRobot(const std::string& sim_ini, const std::string& source);

}  // namespace rasm::autonomy
