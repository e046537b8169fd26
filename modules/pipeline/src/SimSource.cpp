#include "rasm/pipeline/SimSource.h"

#include "rasm/core/Error.h"

namespace rasm::pipeline {

std::unique_ptr<io::FrameSource> openSimSource(const std::string& sim_ini, const std::string& source,
                                               const std::optional<CameraIntrinsics>& camera) {
  throwInputError(source + " [source] type = sim", "the simulator source is not available in this build yet");
}

}  // namespace rasm::pipeline
