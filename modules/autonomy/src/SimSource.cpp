#include "rasm/autonomy/SimSource.h"

#include <mrpt/config/CConfigFileMemory.h>

#include "rasm/core/Error.h"
#include "rasm/core/Params.h"

#ifdef RASM_HAVE_SIM
#include "rasm/sim/SimFrameSource.h"
#include "rasm/sim/Trajectory.h"
#endif

namespace rasm::autonomy {

std::unique_ptr<io::FrameSource> openSimSource(const std::string& sim_ini,
                                               const std::string& source,
                                               const std::optional<CameraIntrinsics>& camera,
                                               bool commanded, double commanded_rate_hz) {
#ifdef RASM_HAVE_SIM
  sim::TSimParams params;
  const mrpt::config::CConfigFileMemory ini(sim_ini);
  loadParamsStrict(ini, "sim", params, source);
  // A driven robot's camera runs at [sim] rate_hz when set, else at the caller's rate.
  if (commanded && params.rate_hz == 0.0) params.rate_hz = commanded_rate_hz;
  return std::make_unique<sim::SimFrameSource>(params, camera, commanded);
#else
  (void)sim_ini, (void)camera, (void)commanded, (void)commanded_rate_hz;
  throwInputError(
      source + " [source] type = sim",
      "this rasm was built without the simulator (-DRASM_WITH_SIM=OFF): give a real source, "
      "e.g. rasm run FOLDER");
#endif
}

bool simTrajectoryIsRobot(const std::string& sim_ini, const std::string& source) {
#ifdef RASM_HAVE_SIM
  sim::TSimParams params;
  const mrpt::config::CConfigFileMemory ini(sim_ini);
  loadParamsStrict(ini, "sim", params, source);
  return sim::loadTrajectorySpec(params.trajectory).kind == sim::TrajectorySpec::Kind::Robot;
#else
  (void)sim_ini, (void)source;
  return false;
#endif
}

}  // namespace rasm::autonomy
