// Cost of a map snapshot (issue 13, 3): copying a SurfelStore (arrays and spatial index: what
// pipeline::Mapper::snapshot() copies) of 0.5, 1 and 3 M surfels spread over a 10 x 10 x 3 m
// room, default layout (class evidence, view bins). Prints one JSON line with, per size, the
// medians over 5 copies of a full copy, of the arrays into a reused store (the part of a snapshot
// under the map lock) and of the index rebuild after it.
//   bench_snapshot   (the copy is single-threaded)
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <random>
#include <vector>

#include "rasm/surfel_map/SurfelStore.h"

using namespace rasm;

int main() {
  std::printf("{\"bench\":\"snapshot\",\"sizes\":[");
  bool first = true;
  for (const int n : {500000, 1000000, 3000000}) {
    maps::SurfelStore store;
    const int i0 = store.allocate(n);
    maps::SurfelArrays a = store.arrays();
    std::mt19937 rng(1);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    for (int i = i0; i < i0 + n; ++i) {
      a.pos_conf[i] = Vec4f(10 * u(rng), 10 * u(rng), 3 * u(rng), 1.0f);
      a.normal_radius[i] = Vec4f(0, 0, 1, 0.005f);
    }
    store.indexAppended();
    // A full copy (arrays and index) into fresh memory, and what Mapper::snapshotInto does: the
    // arrays into a reused store (under the map lock), then the index rebuilt (no lock).
    std::vector<double> full, arrays, index;
    maps::SurfelStore reused;
    const auto ms = [](auto t0) {
      return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0)
          .count();
    };
    for (int k = 0; k < 5; ++k) {
      auto t0 = std::chrono::steady_clock::now();
      {
        const maps::SurfelStore copy = store;
        full.push_back(ms(t0));
        if (copy.size() != store.size()) return 1;
      }
      t0 = std::chrono::steady_clock::now();
      reused.copySurfelsFrom(store);
      arrays.push_back(ms(t0));
      t0 = std::chrono::steady_clock::now();
      reused.rebuildIndex();
      index.push_back(ms(t0));
    }
    for (auto* v : {&full, &arrays, &index}) std::sort(v->begin(), v->end());
    const double bytes = double(store.memoryBytes());
    std::printf(
        "%s{\"surfels\":%d,\"bytes\":%.0f,\"full_copy_ms\":%.2f,\"arrays_into_reused_ms\":%.2f,"
        "\"index_rebuild_ms\":%.2f}",
        first ? "" : ",", n, bytes, full[2], arrays[2], index[2]);
    first = false;
  }
  std::printf("]}\n");
  return 0;
}
