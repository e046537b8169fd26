#pragma once
// [compute]: how the CPU runs the per-pixel and per-surfel work. Three CPU launchers
// keep a hand-written SSE path beside their stage's RASM_HD kernel body, the three that earn at
// least 3% of redkitchen's frame time (docs/slam-eval.md "SSE paths": the measurement, and the
// five SSE paths deleted for earning less). With simd = false every one of them runs the kernel
// body instead (the code the CUDA path runs), so the kernels are the code that is tested: the
// end-to-end tests run in both modes. simd_off names single paths to run through their kernels.
// Process-wide: the Mapper sets it from its [compute] section.

#include <mrpt/config/CLoadableOptions.h>

#include <string>
#include <vector>

namespace rasm {

namespace compute {
/// The CPU launchers that have an SSE path (the kernel bodies it stands for in parentheses).
enum class SimdPath : int {
  BilateralFilter,  ///< bilateral_filter (BilateralDepthKernel): core, depth smoothing
  Fusion,           ///< fusion (AssociateKernel, UpdateKernel, CoverageKernel, CarveKernel): II-D
  Splat,            ///< splat (SplatKernel, ResolveKernel): surfel_map, renders and resolve
  kCount
};
/// The INI name of a path (simd_off).
const char* simdPathName(SimdPath path);
/// All paths, in enum order.
std::vector<SimdPath> simdPaths();

/// Whether `path` may use its SSE code ([compute] simd and not in simd_off; default true).
bool simdEnabled(SimdPath path);
/// Sets every path (simd) ...
void setSimdEnabled(bool enabled);
/// ... or one.
void setSimdEnabled(SimdPath path, bool enabled);
}  // namespace compute

struct TComputeParams : mrpt::config::CLoadableOptions {
  bool simd = true;  ///< false: kernel bodies only (no SSE path at all)
  /// Comma-separated paths that run their kernel body although simd = true (simdPathName names);
  /// empty = none. An unknown name is an InputError naming it.
  std::string simd_off;

  /// The paths of simd_off (InputError naming an unknown one).
  std::vector<compute::SimdPath> simdOff() const;
  /// Sets the process-wide switches (compute::setSimdEnabled) from simd and simd_off.
  void apply() const;

  void loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s) override;
  void saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const override;
};

}  // namespace rasm
