#include "rasm/pipeline/SimSource.h"

#include <mrpt/config/CConfigFileMemory.h>

#include "rasm/core/Error.h"
#include "rasm/core/Params.h"

#ifdef RASM_HAVE_SIM
#include "rasm/sim/SimFrameSource.h"
#endif

namespace rasm::pipeline {

std::unique_ptr<io::FrameSource> openSimSource(const std::string& sim_ini,
                                               const std::string& source,
                                               const std::optional<CameraIntrinsics>& camera,
                                               bool commanded) {
#ifdef RASM_HAVE_SIM
  sim::TSimParams params;
  const mrpt::config::CConfigFileMemory ini(sim_ini);
  loadParamsStrict(ini, "sim", params, source);
  return std::make_unique<sim::SimFrameSource>(params, camera, commanded);
#else
  (void)sim_ini, (void)camera, (void)commanded;
  throwInputError(source + " [source] type = sim", "this build has no simulator (modules/sim)");
#endif
}

}  // namespace rasm::pipeline
