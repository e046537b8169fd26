#pragma once
// Whether a usable CUDA device is present. Defined in every build: without RASM_HAVE_CUDA it
// reports "built without CUDA". Tests call it and skip with the returned message.

#include <string>

namespace rasm::compute {

struct CudaAvailability {
  bool available = false;
  std::string reason;  ///< why not, e.g. the driver's "CUDA driver version is insufficient ..."
};

/// Implemented in core (src/CudaDevice.cpp / cuda/CudaDevice.cu).
CudaAvailability cudaAvailability();

}  // namespace rasm::compute
