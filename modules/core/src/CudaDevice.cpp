#include "rasm/compute/Device.h"

namespace rasm::compute {
#ifndef RASM_HAVE_CUDA
CudaAvailability cudaAvailability() {
  return {false, "rasm was built without CUDA (RASM_WITH_CUDA=OFF or no CUDA compiler found)"};
}
#endif
}  // namespace rasm::compute
