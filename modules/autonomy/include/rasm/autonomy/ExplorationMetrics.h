#pragma once
// One row of an exploration's metrics over time (ExplorationLoop.h "metrics"): what
// exploration.json "metrics" holds and what the run plots in exploration.png (run/RunPlots.h).

#include <cstddef>

namespace rasm::autonomy {

struct ExplorationMetricsRow {
  double t = 0;                ///< s since the first frame (simulated time on the simulator)
  double path_m = 0;           ///< path driven so far
  double coverage = 0;         ///< fraction of the world's surface seen (ground truth)
  double objects_correct = 0;  ///< fraction of the detectable objects carrying their class
  double entropy = 0;          ///< of the occupancy octree (nats)
  std::size_t frames = 0, surfels = 0;
  std::size_t objects_total = 0, objects_ok = 0;  ///< detectable objects; of them, named right
};

}  // namespace rasm::autonomy
