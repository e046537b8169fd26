#pragma once
// Distance thresholds that let the CPU update skip the view-information exponential (V-B) where
// it cannot raise a bin. Plain data (SurfelFusion keeps one); built in FusionCpu.cpp.

namespace rasm::fusion {

/// updateViewBinAt's exponential, skipped: IC(d) (ViewBins.h) does not increase with the distance
/// d and quantizeUnit does not decrease, so for each bin value v < 255 the quantised IC exceeds v
/// exactly below one distance, below[v] (the smallest float d whose quantised IC is <= v, found by
/// bisection over the floats with the same expf). A bin of value v is then raised only when
/// d < below[v]; otherwise, the common case, the bin stays and no exponential is computed.
struct ViewInfoThresholds {
  float lambda1 = -1.0f, d_min_m = -1.0f;  ///< the IC parameters `below` was built for
  float below[255] = {};
  /// (Re)builds `below` for these parameters (255 bisections; a no-op when they are unchanged).
  void build(float lambda1, float d_min_m);
  bool builtFor(float l1, float dm) const { return l1 == lambda1 && dm == d_min_m; }
};

}  // namespace rasm::fusion
