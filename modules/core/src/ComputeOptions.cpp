#include "rasm/core/ComputeOptions.h"

#include <mrpt/config/CConfigFileBase.h>

#include <atomic>

namespace rasm {

namespace {
std::atomic<bool> g_simd{true};
}

bool compute::simdEnabled() { return g_simd.load(std::memory_order_relaxed); }
void compute::setSimdEnabled(bool enabled) { g_simd.store(enabled, std::memory_order_relaxed); }

void TComputeParams::loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s) {
  MRPT_LOAD_CONFIG_VAR(simd, bool, c, s);
}

void TComputeParams::saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const {
  MRPT_SAVE_CONFIG_VAR(simd, c, s);
}

}  // namespace rasm
