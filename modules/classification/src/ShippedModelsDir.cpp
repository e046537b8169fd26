// The folder of the shipped zero-shot models files, compiled in (classification/CMakeLists.txt).
#include "rasm/classification/ZeroShotDetector.h"

namespace rasm::classification {

std::string shippedModelsDir() {
  return RASM_CLASSIFICATION_MODELS_DIR;
}

}  // namespace rasm::classification
