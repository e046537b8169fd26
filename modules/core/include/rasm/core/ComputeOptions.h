#pragma once
// [compute]: how the CPU runs the per-pixel and per-surfel work (issue 13, 5). With simd = false
// every launcher that has a hand-written SSE path runs the stage's RASM_HD kernel body instead
// (the code the CUDA path runs), so the kernels are the code that is tested: the end-to-end tests
// run in both modes. Process-wide: the Mapper sets it from its [compute] section.

#include <mrpt/config/CLoadableOptions.h>

namespace rasm {

struct TComputeParams : mrpt::config::CLoadableOptions {
  bool simd = true;  ///< false: kernel bodies only (no SSE launchers)

  void loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s) override;
  void saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const override;
};

namespace compute {
/// Whether the CPU launchers may use their SSE paths ([compute] simd; default true).
bool simdEnabled();
void setSimdEnabled(bool enabled);
}  // namespace compute

}  // namespace rasm
