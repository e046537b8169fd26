#pragma once
// CPU launchers: run a kernel functor over a 1-D or 2-D range with OpenMP. The functor is the same
// struct the CUDA launchers (ParallelCuda.cuh) run, with `RASM_HD void operator()(int i) const` or
// `(int x, int y) const`. Reductions take `RASM_HD void operator()(int i, Acc& acc) const`
// and need `Acc::operator+=`: the range is cut into a fixed number of contiguous chunks that
// does not depend on the thread count, each chunk accumulates privately and the partials are
// summed in chunk order, so results are deterministic and the same for any thread count.
//
// Scheduling is dynamic (threads take the next chunk of indices / rows when they finish one):
// on a robot laptop or a 2-core VM the kernels share the cores with the frame reader and other
// processes, and with static scheduling every parallel region waited for its slowest,
// descheduled thread (measured: the level-0 normal map took 7 ms instead of 3.5 whenever the
// reader thread decoded a frame at the same time). The kernels are per-element independent (the
// CUDA launchers run them in any order), so the outputs do not depend on the schedule.

#include <algorithm>
#include <vector>

#ifdef _OPENMP
#include <omp.h>
#endif

namespace rasm::compute {

enum class Backend { Cpu, Cuda };

inline int maxThreads() {
#ifdef _OPENMP
  return omp_get_max_threads();
#else
  return 1;
#endif
}

/// Chunk of a dynamically scheduled 1-D loop: ~16 chunks per thread, at least 1 index.
inline int dynamicChunk(int n) {
  return std::max(1, n / (16 * maxThreads()));
}

template <typename F>
void forEach1D(int n, const F& f) {
  const int chunk = dynamicChunk(n);
#pragma omp parallel for schedule(dynamic, chunk)
  for (int i = 0; i < n; ++i) f(i);
}

/// Rows are distributed over threads; x runs innermost (cache friendly for pitched images).
template <typename F>
void forEach2D(int width, int height, const F& f) {
  const int chunk = dynamicChunk(height);
#pragma omp parallel for schedule(dynamic, chunk)
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) f(x, y);
}

/// Number of chunks of a reduction over n items: fixed (not the thread count), so that the
/// summation order, and with it the floating-point result, is the same on any machine.
inline int reduceChunks(int n) {
  return std::max(1, std::min(64, n / 32));
}

template <typename Acc, typename F>
Acc reduce1D(int n, const F& f, const Acc& zero = Acc()) {
  const int nc = reduceChunks(n);
  std::vector<Acc> partial(nc, zero);
  const int nt = std::max(1, std::min(maxThreads(), nc));
#pragma omp parallel for schedule(dynamic, 1) num_threads(nt)
  for (int c = 0; c < nc; ++c) {
    const int begin = static_cast<int>(static_cast<long long>(n) * c / nc);
    const int end = static_cast<int>(static_cast<long long>(n) * (c + 1) / nc);
    Acc& acc = partial[c];
    for (int i = begin; i < end; ++i) f(i, acc);
  }
  Acc total = zero;
  for (const Acc& p : partial) total += p;
  return total;
}

}  // namespace rasm::compute
