#include "rasm/core/ComputeOptions.h"

#include <mrpt/config/CConfigFileBase.h>

#include <array>
#include <atomic>
#include <stdexcept>

#include "rasm/core/Error.h"
#include "rasm/core/Params.h"

namespace rasm {

namespace {
constexpr int kPaths = int(compute::SimdPath::kCount);
constexpr std::array<const char*, kPaths> kNames = {"bilateral_filter", "fusion", "splat"};
// One flag per path, set when the path runs its scalar kernel (static storage: all false, SIMD on).
std::array<std::atomic<bool>, kPaths> g_scalar;
}  // namespace

const char* compute::simdPathName(SimdPath path) {
  return kNames.at(std::size_t(path));
}

std::vector<compute::SimdPath> compute::simdPaths() {
  std::vector<SimdPath> v;
  for (int i = 0; i < kPaths; ++i) v.push_back(SimdPath(i));
  return v;
}

bool compute::simdEnabled(SimdPath path) {
  return !g_scalar[std::size_t(path)].load(std::memory_order_relaxed);
}
void compute::setSimdEnabled(bool enabled) {
  for (auto& b : g_scalar) b.store(!enabled, std::memory_order_relaxed);
}
void compute::setSimdEnabled(SimdPath path, bool enabled) {
  g_scalar[std::size_t(path)].store(!enabled, std::memory_order_relaxed);
}

std::vector<compute::SimdPath> TComputeParams::simdOff() const {
  std::vector<compute::SimdPath> off;
  for (const std::string& name : splitList(simd_off)) {
    int found = -1;
    for (int i = 0; i < kPaths; ++i)
      if (name == kNames[std::size_t(i)]) found = i;
    if (found < 0) {
      std::string known;
      for (const char* n : kNames) known += std::string(known.empty() ? "" : ", ") + n;
      throwInputError(
          "[compute] simd_off",
          "unknown path '" + name + "' (expected a comma-separated list of: " + known + ")");
    }
    off.push_back(compute::SimdPath(found));
  }
  return off;
}

void TComputeParams::apply() const {
  const std::vector<compute::SimdPath> off = simdOff();
  compute::setSimdEnabled(simd);
  for (compute::SimdPath p : off) compute::setSimdEnabled(p, false);
}

void TComputeParams::loadFromConfigFile(const mrpt::config::CConfigFileBase& c,
                                        const std::string& s) {
  MRPT_LOAD_CONFIG_VAR(simd, bool, c, s);
  simd_off = c.read_string(s, "simd_off", simd_off);
  simdOff();  // an unknown name fails at loading, naming it
}

void TComputeParams::saveToConfigFile(mrpt::config::CConfigFileBase& c,
                                      const std::string& s) const {
  MRPT_SAVE_CONFIG_VAR(simd, c, s);
  c.write(s, "simd_off", simd_off);
}

}  // namespace rasm
